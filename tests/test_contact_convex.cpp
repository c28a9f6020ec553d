// One world, convex parts: rigid bodies and figures' links meet the points of every body (nodes,
// particles) through the contact layer's point–convex handler, and the surfaces of the bodies
// with points (a sheet's triangles, a fish's skin, a lattice's skin) through its triangle–convex
// handler: a ball smaller than a sheet's mesh rests on it. Contact happens, momentum is kept in
// zero gravity, nothing passes through at speed, a liquid's species meet a part by their own
// surfaces, 1 and 2 threads give the same bits, a resumed run the same bits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "helpers.h"
#include "contact_helpers.h"
#include "sim/fluid/fluid_body.h"
#include "sim/springs/springs_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// Momentum of every body (nodes, rigid bodies' and links' centres of mass), and the sum of |m·v|
// (the scale of rounding).
Vec3 momentum(const World& w, double& scale) {
  Vec3 p = Vec3::Zero();
  scale = 0.0;
  for (const auto& b : w.bodies()) {
    if (const auto* f = dynamic_cast<const FluidBody*>(b.get())) {
      const Fluid& fl = f->fluid();
      for (std::size_t i = 0; i < fl.size(); ++i) p += fl.m[i] * fl.v[i], scale += fl.m[i] * fl.v[i].norm();
      continue;
    }
    BodyView v;
    if (!b->view(v)) continue;
    std::vector<double> m(v.masses.begin(), v.masses.end());
    if (const auto* n = dynamic_cast<const SpringNetworkBody*>(b.get()); n && m.empty()) m = n->network().model.mass;
    REQUIRE(m.size() == v.velocities.size());
    for (std::size_t i = 0; i < v.velocities.size(); ++i) {
      p += m[i] * v.velocities[i];
      scale += m[i] * v.velocities[i].norm();
    }
  }
  return p;
}

// Runs `frames` frames and checks that momentum was kept to rounding (1e-12 of Σ|m·v|).
void runKeepingMomentum(World& w, int frames) {
  double s0 = 0.0;
  const Vec3 p0 = momentum(w, s0);
  run(w, frames);
  double s1 = 0.0;
  const Vec3 p1 = momentum(w, s1);
  CAPTURE(p0.transpose());
  CAPTURE(p1.transpose());
  CHECK((p1 - p0).norm() < 1e-12 * std::max(s0, s1));
}

// With a floor 1 m down under gravity; in zero gravity, nothing else.
std::string scene(const std::string& bodies, const std::string& gravity = "[0, -9.78, 0]", double duration = 2,
                  const std::string& extra = "") {
  const bool floor = gravity != "[0, 0, 0]";
  return R"({"format": "reel/1", "duration": )" + std::to_string(duration) +
         R"(, "fps": 30, "substeps": 40, "auto_substeps": true, "gravity": )" + gravity + extra +
         (floor ? R"(, "objects": [{"type": "plane", "name": "floor", "point": [0, -1, 0]}])" : "") +
         R"(, "bodies": [)" + bodies + "]}";
}

// A 1 m sheet held at its corners at y = 0, its nodes 12.5 cm apart.
const std::string kCoarse = R"({"type": "cloth", "name": "held", "position": [0, 0, 0], "size": [1, 1], "resolution": [9, 9],
    "mass": 0.3, "stiffness": 600, "damping": 0.2, "node_damping": 0.01, "thickness": 0.01,
    "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"]})";

}  // namespace

TEST_CASE("convex parts: a ball and a flat box smaller than a sheet's mesh rest on it") {
  // An 8 cm ball dropped between four nodes, a 15 x 5 x 15 cm box across one square: without the
  // triangle–convex handler both fell through to the floor.
  const std::string ball = R"({"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.04, "mass": 0.2, "position": [0.06, 0.3, 0.06]})";
  const std::string box = R"({"type": "rigid", "name": "box", "shape": "box", "size": [0.15, 0.05, 0.15], "mass": 0.2, "position": [-0.25, 0.3, -0.25]})";
  World w = worldFromText(scene(kCoarse + "," + ball + "," + box));
  CHECK(w.contacts().active());
  run(w, 45);
  CHECK(w.contacts().total().triangle_convex > 0);
  const double sheet = lowest(w, "held");
  CHECK(sheet < -0.02);  // it sags under them
  for (const char* name : {"ball", "box"}) {
    CAPTURE(name);
    const BodyView v = viewOf(w, name);
    CHECK(v.positions[0].y() > sheet);
    CHECK(v.positions[0].y() > -0.3);
    CHECK(v.velocities[0].norm() < 0.2);  // at rest on it
  }
}

TEST_CASE("convex parts: a figure's link rests on a sheet") {
  const std::string figure = R"({"type": "articulated", "name": "a", "position": [0.06, 0.3, 0.06],
      "links": [{"name": "block", "shape": "box", "size": [0.1, 0.04, 0.1], "mass": 0.3}]})";
  World w = worldFromText(scene(kCoarse + "," + figure));
  run(w, 45);
  CHECK(w.contacts().total().triangle_convex > 0);
  const BodyView v = viewOf(w, "a");
  CHECK(v.positions[0].y() > lowest(w, "held"));
  CHECK(v.positions[0].y() > -0.3);
}

TEST_CASE("convex parts: a box thrown at a free sheet or a lattice in zero gravity keeps momentum and does not pass") {
  // Each target's mesh is coarser than what is thrown at it (a sheet's nodes 12.5 cm apart, a
  // lattice's 20 cm): only its faces can stop it.
  const std::string sheet = R"({"type": "cloth", "name": "target", "position": [0, 0, 0], "size": [1, 1], "resolution": [9, 9],
      "mass": 0.3, "stiffness": 600, "damping": 0.2, "thickness": 0.01})";
  const std::string lattice = R"({"type": "lattice", "name": "target", "position": [0, -0.1, 0], "size": [0.4, 0.2, 0.4],
      "resolution": [3, 2, 3], "mass": 0.5, "stiffness": 300, "damping": 0.5, "node_radius": 0.01})";
  const std::string box = R"({"type": "rigid", "name": "box", "shape": "box", "size": [0.12, 0.06, 0.12], "mass": 0.5,
      "position": [0.06, 0.2, 0.06], "rotation_deg": [10, 20, 5], "velocity": [0.5, -3, 0], "angular_velocity": [0, 2, 1]})";
  // (A figure's link is left out here: the figure's own step keeps a spinning link's linear
  // momentum only to O(h·ω²·r), whatever pushes it; what the layer hands it is the same code.)
  for (const std::string& bodies : {sheet + "," + box, lattice + "," + box}) {
    CAPTURE(bodies);
    World w = worldFromText(scene(bodies, "[0, 0, 0]", 1));
    auto mean = [](const World& world) {
      const BodyView v = viewOf(world, "target");
      Vec3 m = Vec3::Zero();
      for (const Vec3& p : v.positions) m += p / static_cast<double>(v.positions.size());
      return m;
    };
    const Vec3 start = mean(w);
    runKeepingMomentum(w, 14);
    CHECK(w.contacts().total().triangle_convex > 0);
    // The target was carried along (its mean 5 cm lower at least), the box still on its side.
    CHECK(mean(w).y() < start.y() - 0.05);
    CHECK(viewOf(w, "box").positions[0].y() > mean(w).y());
  }
}

TEST_CASE("convex parts: 1 and 2 threads give the same bits; a resumed run gives the same bits") {
  const std::string text = scene(kCoarse + R"(, {"type": "rigid", "name": "box", "shape": "box", "size": [0.15, 0.05, 0.15],
      "mass": 0.2, "position": [0.05, 0.1, 0.0], "rotation_deg": [0, 30, 0]})");
  const World a = sameBitsThreadsAndResume(text, 12);
  CHECK(a.contacts().total().triangle_convex > 0);
}

TEST_CASE("point–convex: a rigid box thrown at a rope, a sheet, a lattice, water or fish in zero gravity, momentum kept") {
  // The box is larger than every mesh here: its faces meet the targets' points (nodes, particles).
  const std::string rope = R"({"type": "rope", "name": "target", "start": [-0.3, 0, 0.05], "end": [0.3, 0, -0.05],
      "segments": 24, "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_damping": 0, "node_radius": 0.01})";
  const std::string sheet = R"({"type": "cloth", "name": "target", "position": [0, 0, 0], "size": [0.6, 0.6], "resolution": [13, 13],
      "mass": 0.3, "stiffness": 600, "damping": 0.2, "thickness": 0.01})";
  const std::string lattice = R"({"type": "lattice", "name": "target", "position": [0, -0.1, 0], "size": [0.4, 0.2, 0.4],
      "resolution": [5, 3, 5], "mass": 0.5, "stiffness": 300, "damping": 0.5, "node_radius": 0.01})";
  const std::string water = R"({"type": "fluid", "name": "target", "radius": 0.01, "species": [{"name": "water", "mass": 0.008,
      "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}],
      "blocks": [{"min": [-0.1, -0.05, -0.1], "max": [0.1, 0.0, 0.1], "spacing": 0.02}]})";
  const std::string box = R"({"type": "rigid", "name": "box", "shape": "box", "size": [0.3, 0.1, 0.3], "mass": 0.5,
      "position": [0.02, 0.2, 0.01], "rotation_deg": [5, 20, 3], "velocity": [0.3, -3, 0], "angular_velocity": [0, 2, 1]})";
  const std::string fish = R"({"type": "fish", "name": "target", "behaviour": "none", "length": 1.0, "count": 2,
      "start": {"min": [-0.05, -0.1, -0.05], "max": [0.05, 0.0, 0.05]}, "heading": [0, 0, 1]})";
  for (const std::string& target : {rope, sheet, lattice, water, fish}) {
    CAPTURE(target);
    // (no water around the fish: its drag would be an outside force)
    World w = worldFromText(scene(target + "," + box, "[0, 0, 0]", 1, R"(, "water": {"density": 0})"));
    runKeepingMomentum(w, 8);
    CHECK(w.contacts().total().point_convex > 0);
    // The box was slowed (0.5 kg into 0.1–0.5 kg of target) and stayed above every point it met.
    const BodyView b = viewOf(w, "box");
    CHECK(b.velocities[0].y() > -2.5);
    CHECK(b.positions[0].y() - 0.05 > lowest(w, "target") - 0.02);
  }
}

TEST_CASE("point–convex: nothing passes through a thin rigid plate at speed") {
  // A 2 cm plate of 100 kg; a rope and a block of water thrown at it at 60 m/s: each point moves
  // 5 cm a step, more than the plate and its radius together (4 cm).
  const std::string plate = R"({"type": "rigid", "name": "plate", "shape": "box", "size": [0.8, 0.02, 0.8], "mass": 100,
      "position": [0, 0, 0]})";
  const std::string rope = R"({"type": "rope", "name": "shot", "start": [-0.3, 0.12, 0.05], "end": [0.3, 0.12, -0.05],
      "segments": 24, "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_damping": 0.001, "node_radius": 0.01,
      "velocity": [0, -60, 0]})";
  const std::string water = R"({"type": "fluid", "name": "shot", "radius": 0.01, "species": [{"name": "water", "mass": 0.008,
      "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}],
      "blocks": [{"min": [-0.1, 0.1, -0.1], "max": [0.1, 0.14, 0.1], "spacing": 0.02, "velocity": [0, -60, 0]}]})";
  for (const std::string& shot : {rope, water}) {
    CAPTURE(shot);
    World w = worldFromText(scene(plate + "," + shot, "[0, 0, 0]", 1));
    run(w, 3);
    CHECK(w.contacts().total().point_convex > 0);
    CHECK(lowest(w, "shot") > viewOf(w, "plate").positions[0].y());
  }
}

TEST_CASE("point–convex: a liquid's species meet a rigid body by their own surfaces") {
  // Two lone drops fall 10 cm onto a heavy box resting on the floor: the box bounces "rubber"
  // (restitution 0.8 for that species) and stops "honey" (restitution 0, and its own friction).
  const std::string box = R"({"type": "rigid", "name": "box", "shape": "box", "size": [0.6, 0.2, 0.6], "mass": 50,
      "position": [0, -0.9, 0], "surface": {"restitution": 0.0, "species": {"rubber": {"restitution": 0.8}}}})";
  const std::string drops = R"({"type": "fluid", "name": "drops", "radius": 0.01,
      "species": [{"name": "honey", "mass": 0.008, "alpha": 0, "beta": 0, "cutoff": 0.02},
                  {"name": "rubber", "mass": 0.008, "alpha": 0, "beta": 0, "cutoff": 0.02}],
      "particles": [{"species": "honey", "positions": [[-0.15, -0.69, 0]]}, {"species": "rubber", "positions": [[0.15, -0.69, 0]]}]})";
  World w = worldFromText(scene(box + "," + drops));
  double top_honey = -1e9, top_rubber = -1e9;
  for (int f = 0; f < 20; ++f) {
    run(w, 1);
    const BodyView v = viewOf(w, "drops");
    if (f >= 8) {
      top_honey = std::max(top_honey, v.positions[0].y());
      top_rubber = std::max(top_rubber, v.positions[1].y());
    }
  }
  CHECK(w.contacts().total().point_convex > 0);
  // The box's top is at -0.8; a drop resting on it sits at -0.79.
  CHECK(top_honey < -0.785);
  CHECK(top_rubber > -0.77);  // it bounced back up by a few centimetres at least
  CHECK(viewOf(w, "drops").positions[0].y() > -0.8);
}

TEST_CASE("point–convex: 1 and 2 threads give the same bits; a resumed run gives the same bits") {
  const std::string text = scene(R"({"type": "rope", "name": "rope", "start": [-0.3, -0.8, 0.05], "end": [0.3, -0.8, -0.05],
      "segments": 24, "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_damping": 0.001, "node_radius": 0.01},
      {"type": "fluid", "name": "water", "radius": 0.01, "species": [{"name": "water", "mass": 0.008, "alpha": 212.6,
      "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}], "blocks": [{"min": [0.0, -0.85, -0.05], "max": [0.1, -0.75, 0.05], "spacing": 0.02}]},
      {"type": "rigid", "name": "box", "shape": "box", "size": [0.5, 0.1, 0.5], "mass": 2, "position": [0, -0.95, 0], "rotation_deg": [0, 30, 0]})");
  const World a = sameBitsThreadsAndResume(text, 12);
  CHECK(a.contacts().total().point_convex > 0);
}
