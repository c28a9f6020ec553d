// One world: bodies of every kind that has points meet through the World's contact layer
// (sim/contact_layer.h). For each cell of docs/coupling.md: contact happens, momentum is kept in
// zero gravity, nothing passes through at speed, 1 and 2 threads give the same bits, and a run
// resumed from a snapshot gives the same bits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "helpers.h"
#include "contact_helpers.h"
#include "articulated_helpers.h"
#include "sim/cloth/cloth_body.h"
#include "sim/face/face_body.h"
#include "sim/fish/fish_body.h"
#include "sim/fluid/fluid_body.h"
#include "sim/springs/springs_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// Momentum of every point of every body with points (nodes and particles), and the sum of |m·v|
// (the scale of rounding).
Vec3 momentum(const World& w, double& scale) {
  Vec3 p = Vec3::Zero();
  scale = 0.0;
  for (const auto& b : w.bodies()) {
    if (const auto* n = dynamic_cast<const SpringNetworkBody*>(b.get())) {
      const auto& net = n->network();
      for (std::size_t i = 0; i < net.model.nodes(); ++i) {
        p += net.model.mass[i] * net.state.v[i];
        scale += net.model.mass[i] * net.state.v[i].norm();
      }
    } else if (const auto* f = dynamic_cast<const FluidBody*>(b.get())) {
      const Fluid& fl = f->fluid();
      for (std::size_t i = 0; i < fl.size(); ++i) {
        p += fl.m[i] * fl.v[i];
        scale += fl.m[i] * fl.v[i].norm();
      }
    }
  }
  return p;
}

std::string scene(const std::string& bodies, const std::string& gravity = "[0, -9.78, 0]", double duration = 2,
                  const std::string& extra = "") {
  return R"({"format": "reel/1", "duration": )" + std::to_string(duration) +
         R"(, "fps": 30, "substeps": 40, "auto_substeps": true, "gravity": )" + gravity + extra +
         R"(, "objects": [{"type": "plane", "name": "floor", "point": [0, -1, 0]}], "bodies": [)" + bodies + "]}";
}

// A 1 m sheet held at its corners at y = 0.
const std::string kHeld = R"({"type": "cloth", "name": "held", "position": [0, 0, 0], "size": [1, 1], "resolution": [17, 17],
    "mass": 0.3, "stiffness": 600, "damping": 0.2, "node_damping": 0.01, "thickness": 0.01,
    "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"]})";

std::string sheet(const std::string& name, const Vec3& at, double size, const std::string& velocity = "[0, 0, 0]",
                  const std::string& rotation = "[0, 0, 0]") {
  auto num = [](double x) { return std::to_string(x); };
  return R"({"type": "cloth", "name": ")" + name + R"(", "position": [)" + num(at.x()) + ", " + num(at.y()) + ", " +
         num(at.z()) + R"(], "size": [)" + num(size) + ", " + num(size) + R"(], "resolution": [11, 11],
    "mass": 0.1, "stiffness": 400, "damping": 0.2, "node_damping": 0.01, "thickness": 0.01, "rotation_deg": )" +
         rotation + R"(, "velocity": )" + velocity + "}";
}

const std::string kRope = R"({"type": "rope", "name": "rope", "start": [-0.3, 0.25, 0.05], "end": [0.3, 0.25, -0.05],
    "segments": 24, "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_damping": 0.001, "node_radius": 0.01})";

const std::string kWater = R"("species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}])";

}  // namespace

TEST_CASE("contact layer: a sheet dropped on a held sheet rests on it") {
  World w = worldFromText(scene(kHeld + "," + sheet("top", {0, 0.3, 0}, 0.5)));
  CHECK(w.contacts().active());
  run(w, 45);
  // The held sheet sags under it; the dropped one lies above it, not on the floor.
  CHECK(lowest(w, "held") < -0.02);
  CHECK(lowest(w, "top") > lowest(w, "held") - 0.005);
  CHECK(lowest(w, "top") > -0.5);
  // At rest, not sliding through.
  for (const Vec3& v : viewOf(w, "top").velocities) CHECK(v.norm() < 0.5);
}

TEST_CASE("contact layer: a rope dropped on a held sheet rests on it") {
  World w = worldFromText(scene(kHeld + "," + kRope));
  run(w, 45);
  CHECK(lowest(w, "rope") > lowest(w, "held") - 0.005);
  CHECK(lowest(w, "rope") > -0.5);
}

TEST_CASE("contact layer: a lattice (jelly) dropped on a held sheet rests on it") {
  const std::string jelly = R"({"type": "lattice", "name": "jelly", "position": [0, 0.3, 0], "size": [0.2, 0.2, 0.2],
      "resolution": [3, 3, 3], "mass": 0.2, "stiffness": 300, "damping": 0.5, "node_radius": 0.01})";
  World w = worldFromText(scene(kHeld + "," + jelly));
  run(w, 45);
  CHECK(lowest(w, "jelly") > lowest(w, "held") - 0.005);
  CHECK(lowest(w, "jelly") > -0.5);
}

TEST_CASE("contact layer: water poured on a resting fish splashes off it") {
  // A 1 m fish lying still (behaviour none, no drive) in the way of a column of water.
  const std::string bodies = R"({"type": "fish", "name": "fish", "behaviour": "none", "length": 1.0, "position": [0, 0, 0]},
      {"type": "fluid", "name": "water", "radius": 0.01, )" + kWater + R"(,
       "blocks": [{"min": [-0.04, 0.3, -0.2], "max": [0.04, 0.6, 0.2], "spacing": 0.02}]})";
  World w = worldFromText(scene(bodies, "[0, -9.78, 0]", 1, R"(, "integrator": "implicit_euler")"));
  run(w, 15);
  CHECK(w.contacts().total().point_triangle > 0);
  // Particles over the fish's back at the start: none has gone through its body to below it.
  const BodyView fish = viewOf(w, "fish");
  double belly = 1e300, x0 = 1e300, x1 = -1e300, z0 = 1e300, z1 = -1e300;
  for (const Vec3& p : fish.positions) {
    belly = std::min(belly, p.y());
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
    z0 = std::min(z0, p.z()), z1 = std::max(z1, p.z());
  }
  int under = 0, total = 0;
  for (const Vec3& p : viewOf(w, "water").positions) {
    ++total;
    if (p.y() < belly && p.x() > x0 + 0.02 && p.x() < x1 - 0.02 && p.z() > z0 + 0.1 && p.z() < z1 - 0.1) ++under;
  }
  CHECK(total > 50);
  CHECK(under == 0);
  // And the water pushed the fish down.
  double vy = 0.0;
  for (const Vec3& v : fish.velocities) vy += v.y();
  CHECK(vy < 0.0);
}

TEST_CASE("contact layer: two free sheets thrown at each other collide, momentum kept") {
  // Zero gravity; facing each other across x, each turned upright (normal along x).
  const std::string a = sheet("a", {-0.15, 0, 0}, 0.4, "[2, 0, 0]", "[0, 0, 90]");
  const std::string b = sheet("b", {0.15, 0.05, 0.05}, 0.4, "[-2, 0, 0]", "[0, 0, 90]");
  World w = worldFromText(scene(a + "," + b, "[0, 0, 0]"));
  double s0 = 0.0;
  const Vec3 p0 = momentum(w, s0);
  run(w, 20);
  double s1 = 0.0;
  const Vec3 p1 = momentum(w, s1);
  CHECK((p1 - p0).norm() < 1e-12 * s0);
  // They met and did not pass (without contacts they would be 2.3 m apart, a beyond b): a stays
  // on the −x side of b, the two thicknesses apart.
  double amean = 0.0, bmean = 0.0;
  const BodyView va = viewOf(w, "a"), vb = viewOf(w, "b");
  for (const Vec3& p : va.positions) amean += p.x() / static_cast<double>(va.positions.size());
  for (const Vec3& p : vb.positions) bmean += p.x() / static_cast<double>(vb.positions.size());
  CHECK(amean < bmean - 0.01);
}

TEST_CASE("contact layer: momentum is kept in zero gravity for every pair of proxy kinds") {
  const std::string held_free = R"({"type": "cloth", "name": "held", "position": [0, 0, 0], "size": [1, 1], "resolution": [13, 13],
      "mass": 0.3, "stiffness": 600, "damping": 0.2, "thickness": 0.01})";
  const std::string rope = R"({"type": "rope", "name": "rope", "start": [-0.3, 0.1, 0], "end": [0.3, 0.1, 0], "segments": 20,
      "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_radius": 0.01, "velocity": [0, -2, 0]})";
  const std::string water = R"({"type": "fluid", "name": "water", "radius": 0.01, )" + kWater +
                            R"(, "blocks": [{"min": [-0.05, 0.25, -0.05], "max": [0.05, 0.35, 0.05], "spacing": 0.02, "velocity": [0, -3, 0]}]})";
  const std::string fish = R"({"type": "fish", "name": "fish", "behaviour": "none", "length": 1.0, "count": 2,
      "start": {"min": [-0.05, -0.1, -0.05], "max": [0.05, 0.1, 0.05]}, "heading": [0, 0, 1]})";
  const std::string jelly = R"({"type": "lattice", "name": "jelly", "position": [0, 0.2, 0], "size": [0.2, 0.2, 0.2],
      "resolution": [3, 3, 3], "mass": 0.2, "stiffness": 300, "damping": 0.5, "node_radius": 0.01, "velocity": [0, -2, 0]})";
  const std::string rope_water = R"({"type": "fluid", "name": "drops", "radius": 0.01, )" + kWater +
                                 R"(, "blocks": [{"min": [-0.05, 0.2, -0.05], "max": [0.05, 0.3, 0.05], "spacing": 0.02, "velocity": [0, -3, 0]}]})";
  // The divergence-free SPH model's water (docs/fluids.md) meets the others the same way.
  const std::string sph_water = R"({"type": "fluid", "name": "sph", "model": "dfsph", "radius": 0.0095,
      "species": [{"name": "water", "mass": 0.008, "density": 1000, "viscosity": 1}],
      "blocks": [{"min": [-0.05, 0.25, -0.05], "max": [0.05, 0.35, 0.05], "spacing": 0.02, "velocity": [0, -3, 0]}]})";
  for (const std::string& pair : {held_free + "," + rope, held_free + "," + jelly, held_free + "," + fish, rope + "," + jelly,
                                  rope + "," + fish, jelly + "," + fish, fish + "," + water, fish, jelly + "," + water,
                                  rope + "," + rope_water, jelly + "," + sph_water, fish + "," + sph_water}) {
    CAPTURE(pair);
    // (no water around the fish: its drag would be an outside force)
    World w = worldFromText(scene(pair, "[0, 0, 0]", 2, R"(, "water": {"density": 0})"));
    double s0 = 0.0;
    const Vec3 p0 = momentum(w, s0);
    run(w, 8);
    CHECK(w.contacts().active());
    double s1 = 0.0;
    const Vec3 p1 = momentum(w, s1);
    CHECK((p1 - p0).norm() < 1e-12 * std::max(s0, s1));
    // They met.
    CHECK(w.contacts().total().point_triangle + w.contacts().total().point_point > 0);
  }
}

TEST_CASE("contact layer: kelp meets a rope and a fish") {
  // A stalk of kelp (nodes 0.12 m apart); a rope thrown across it at the height of its fifth node,
  // and a fish lying against it.
  const std::string kelp = R"({"type": "seaweed", "name": "kelp", "bases": [[0, -1, 0]], "height": 1.2, "segments": 10})";
  const std::string rope = R"({"type": "rope", "name": "rope", "start": [-0.4, -0.52, 0.3], "end": [0.4, -0.52, 0.3], "segments": 20,
      "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_radius": 0.01, "velocity": [0, 0, -2]})";
  const std::string fish = R"({"type": "fish", "name": "fish", "behaviour": "none", "length": 0.6, "position": [0, -0.3, 0.05], "heading": [1, 0, 0]})";
  for (const std::string& other : {rope, fish}) {
    CAPTURE(other);
    World w = worldFromText(scene(kelp + "," + other, "[0, 0, 0]", 1, R"(, "water": {"density": 0})"));
    const BodyView start = viewOf(w, "kelp");  // (a view: spans into the live state)
    const std::vector<Vec3> before(start.positions.begin(), start.positions.end());
    run(w, 11);
    const ContactCounts& c = w.contacts().total();
    CHECK(c.point_triangle + c.point_point + c.edge_edge > 0);
    const BodyView after = viewOf(w, "kelp");
    double moved = 0.0;
    for (std::size_t i = 0; i < after.positions.size(); ++i) moved = std::max(moved, (after.positions[i] - before[i]).norm());
    CHECK(moved > 0.005);
    // The rope did not slip through the stalk between its nodes (edge against edge).
    if (other == rope) CHECK(viewOf(w, "rope").positions[10].z() > after.positions[4].z() - 0.05);
  }
}

TEST_CASE("contact layer: two ropes thrown across each other do not pass through, momentum kept") {
  // Crossed at right angles, their nodes out of line (no node meets a node), 4 m/s apart.
  const std::string a = R"({"type": "rope", "name": "a", "start": [-0.3, 0.05, 0], "end": [0.3, 0.05, 0], "segments": 20,
      "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_radius": 0.005, "velocity": [0, -2, 0]})";
  const std::string b = R"({"type": "rope", "name": "b", "start": [0.0, -0.05, -0.315], "end": [0.0, -0.05, 0.285], "segments": 20,
      "mass": 0.1, "stiffness": 2000, "damping": 0.2, "node_radius": 0.005, "velocity": [0, 2, 0]})";
  World w = worldFromText(scene(a + "," + b, "[0, 0, 0]", 1));
  double s0 = 0.0;
  const Vec3 p0 = momentum(w, s0);
  run(w, 6);
  double s1 = 0.0;
  CHECK((momentum(w, s1) - p0).norm() < 1e-12 * s0);
  CHECK(w.contacts().total().edge_edge > 0);
  CHECK(viewOf(w, "a").positions[10].y() > viewOf(w, "b").positions[10].y());
}

TEST_CASE("contact layer: nothing passes through a sheet or a fish's skin at speed") {
  // A rope fired at 40 m/s (over 3 cm a step, three times the contact distance) at a held sheet,
  // and light particles at a fish, in zero gravity.
  const std::string target = R"({"type": "cloth", "name": "held", "position": [0, 0, 0], "size": [1, 1], "resolution": [9, 9],
      "mass": 0.3, "stiffness": 600, "damping": 0.2, "thickness": 0.005,
      "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"]})";
  const std::string rope = R"({"type": "rope", "name": "shot", "start": [-0.3, 0.1, 0.02], "end": [0.3, 0.1, -0.02],
      "segments": 30, "mass": 0.02, "stiffness": 500, "damping": 0.1, "node_radius": 0.005, "velocity": [0, -40, 0]})";
  const std::string fish = R"({"type": "fish", "name": "fish", "behaviour": "none", "length": 1.0, "position": [0, 0, 0]})";
  const std::string shot = R"({"type": "fluid", "name": "shot", "radius": 0.005,
      "species": [{"name": "lead", "mass": 0.0002, "alpha": 0.01, "beta": 0.00001, "cutoff": 0.02}],
      "blocks": [{"min": [-0.02, 0.15, -0.2], "max": [0.02, 0.17, 0.2], "spacing": 0.02, "velocity": [0, -40, 0]}]})";
  for (const std::string& bodies : {target + "," + rope, fish + "," + shot}) {
    CAPTURE(bodies);
    World w = worldFromText(scene(bodies, "[0, 0, 0]", 1, R"(, "water": {"density": 0})"));
    const std::string hit = bodies == target + "," + rope ? "held" : "fish";
    run(w, 6);
    // Above the target's lowest point, every one, after bouncing off it.
    const double under = lowest(w, hit);
    for (const Vec3& p : viewOf(w, "shot").positions) CHECK(p.y() > under);
    CHECK(w.contacts().total().point_triangle > 20);
  }
}

TEST_CASE("contact layer: 1 and 2 threads give the same bits; a resumed run gives the same bits") {
  const std::string text = scene(kHeld + "," + sheet("top", {0, 0.3, 0}, 0.5) + "," + kRope +
                                 R"(, {"type": "fluid", "name": "water", "radius": 0.01, )" + kWater +
                                 R"(, "blocks": [{"min": [0.2, 0.3, 0.2], "max": [0.3, 0.4, 0.3], "spacing": 0.02}]})");
  sameBitsThreadsAndResume(text, 12);
}

// The exchange is exact (the layer hands the link the opposite of every impulse it gives a
// particle, in the same step); what remains is the figure's own integration of a spinning body: its
// floating base moves by a spatial velocity at the world origin (semi-implicit Euler), which turns
// the momentum of a body spinning at ω by about h·ω·|p| a step. The sequential contacts give the
// block a slight spin (~1e-3 rad/s), so each frame is allowed that much and no more: an impulse
// that reached the figure a step late, or not at all, is ~1e-2 of the momentum in the first frame
// of contact, where the block does not spin yet.
TEST_CASE("water thrown at a figure in zero gravity pushes it in the same step: momentum kept but what its spin turns") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 30, "gravity": [0, 0, 0],
    "bodies": [{"type": "articulated", "name": "a", "position": [0, 1, 0],
                "links": [{"name": "block", "shape": "box", "size": [0.4, 0.4, 0.4], "mass": 20}]},
               {"type": "fluid", "name": "water", "radius": 0.01, )" + kWater +
                         R"(, "blocks": [{"min": [-0.5, 0.95, -0.05], "max": [-0.4, 1.05, 0.05], "spacing": 0.02, "velocity": [3, 0, 0]}]}]})");
  ArticulatedBody& a = figure(w);
  Vec3 c, v;
  auto total = [&] {
    double s = 0;
    centreOfMass(a.model(), a.kinematics(), c, v);
    return Vec3(momentum(w, s) + 20 * v);
  };
  auto spin = [&] { return a.kinematics().vel[0].head<3>().norm(); };
  const Vec3 p0 = total();
  int contact_frames = 0;
  for (int f = 0; f < 15; ++f) {
    const Vec3 before = total();
    const double w0 = spin(), v0 = v.norm();
    const std::size_t hits = w.contacts().total().point_convex;
    run(w, 1);
    const Vec3 after = total();
    const double allowed = 2.0 * 20.0 * (1.0 / 30.0) * std::max(w0, spin()) * std::max(v0, v.norm());
    CAPTURE(f);
    CAPTURE(spin());
    CHECK((after - before).norm() <= allowed + 1e-12 * p0.norm());
    if (w.contacts().total().point_convex > hits) ++contact_frames;
  }
  CAPTURE(v.transpose());
  CHECK(contact_frames >= 2);
  CHECK(v.x() > 0.1);  // the block was pushed (3 N·s of water at 20 kg)
  CHECK(spin() < 1e-2);
  CHECK((total() - p0).norm() < 1e-5 * p0.norm());
}

// Two figures meet: the first in scene order solves the contact (each side's effective mass) and
// hands the second the opposite, which the second takes in the same step (it steps after the first
// when their reach overlaps) and leaves that contact alone. Face to face, so neither block spins
// (a spinning one's own step turns its momentum, above): each frame keeps momentum to 1e-9 of
// Σ|m·v| (when each figure solved its own side against the other as a free body, the frame of
// contact lost 2.5e-9 of it; 2e-11 now).
TEST_CASE("two figures thrown at each other in zero gravity: equal and opposite in the same step") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 30, "gravity": [0, 0, 0],
    "bodies": [{"type": "articulated", "name": "a", "position": [-0.3, 1, 0], "velocity": [1.5, 0, 0],
                "links": [{"name": "block", "shape": "box", "size": [0.4, 0.4, 0.4], "mass": 20}]},
               {"type": "articulated", "name": "b", "position": [0.3, 1, 0], "velocity": [-1.5, 0, 0],
                "links": [{"name": "block", "shape": "box", "size": [0.4, 0.4, 0.4], "mass": 10}]}]})");
  Vec3 c, va, vb;
  auto total = [&] {
    centreOfMass(figure(w, 0).model(), figure(w, 0).kinematics(), c, va);
    centreOfMass(figure(w, 1).model(), figure(w, 1).kinematics(), c, vb);
    return Vec3(20 * va + 10 * vb);
  };
  const double scale = 20 * 1.5 + 10 * 1.5;  // Σ|m·v| at the start, N·s
  for (int f = 0; f < 12; ++f) {
    const Vec3 before = total();
    run(w, 1);
    CAPTURE(f);
    CHECK((total() - before).norm() < 1e-9 * scale);
  }
  CAPTURE(va.transpose());
  CAPTURE(vb.transpose());
  CHECK(va.x() < 0.6);  // they met: 15 N·s shared by 30 kg moves both at 0.5 m/s
  CHECK(vb.x() > 0.4);
  CHECK(viewOf(w, "b").positions[0].x() - viewOf(w, "a").positions[0].x() > 0.39);  // face to face, not through
}

TEST_CASE("contact layer: two sheets whose rims cross between their nodes catch edge on edge") {
  // Zero gravity. Sheet a stands in the plane z = 0 with its top rim along x at y = 0.2; sheet b
  // stands in the plane x = 0 with its bottom rim along z at y = 0.25; thrown at each other at
  // 4 m/s. Ten nodes a side: no node of either lies in the other's plane, so only the rims
  // (threads of the sheets' borders) can catch; without them b passes through a.
  auto strip = [](const std::string& name, double y, const std::string& v, const std::string& rot) {
    return R"({"type": "cloth", "name": ")" + name + R"(", "position": [0, )" + std::to_string(y) +
           R"(, 0], "size": [0.4, 0.4], "resolution": [10, 10], "mass": 0.1, "stiffness": 400, "damping": 0.2,
        "node_damping": 0.01, "thickness": 0.01, "rotation_deg": )" + rot + R"(, "velocity": )" + v + "}";
  };
  const std::string a = strip("a", 0.0, "[0, 2, 0]", "[90, 0, 0]");
  const std::string b = strip("b", 0.45, "[0, -2, 0]", "[0, 0, 90]");
  World w = worldFromText(scene(a + "," + b, "[0, 0, 0]", 1));
  double ytop = -1e300;
  for (const Vec3& p : viewOf(w, "a").positions) ytop = std::max(ytop, p.y());
  CHECK(ytop == doctest::Approx(0.2).epsilon(1e-9));
  CHECK(lowest(w, "b") == doctest::Approx(0.25).epsilon(1e-9));
  double s0 = 0.0;
  const Vec3 p0 = momentum(w, s0);
  run(w, 6);  // 0.2 s: free, the rims would have passed each other by 0.75 m
  double s1 = 0.0;
  CHECK((momentum(w, s1) - p0).norm() < 1e-12 * s0);
  CHECK(w.contacts().total().edge_edge > 0);
  double amean = 0.0, bmean = 0.0;
  const BodyView va = viewOf(w, "a"), vb = viewOf(w, "b");
  for (const Vec3& p : va.positions) amean += p.y() / static_cast<double>(va.positions.size());
  for (const Vec3& p : vb.positions) bmean += p.y() / static_cast<double>(vb.positions.size());
  CHECK(bmean - amean > 0.3);
}

namespace {

// A face at a test resolution with other bodies, under implicit Euler (the face's own tests').
std::string faceWith(const std::string& others, const std::string& gravity) {
  return R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 4, "auto_substeps": true, "integrator": "implicit_euler",
      "implicit": {"cg_tolerance": 1e-5}, "gravity": )" + gravity + R"(, "bodies": [
      {"type": "face", "name": "face", "resolution": [48, 32]}, )" + others + "]}";
}

// How far p lies outside the face's skin (`layer` 0) or its skull (`layer` 2): along the normal
// of the layer's nearest vertex (the mean of its triangles' normals, counter-clockwise from
// outside), m; negative inside.
double outside(const FaceBody& f, const Vec3& p, std::size_t layer) {
  const auto& x = f.network().state.x;
  const std::size_t n = f.surface().size(), o = layer * n;
  std::size_t best = 0;
  for (std::size_t k = 0; k < n; ++k)
    if ((x[o + k] - p).squaredNorm() < (x[o + best] - p).squaredNorm()) best = k;
  Vec3 normal = Vec3::Zero();
  const auto& t = f.surface().tris;
  for (std::size_t k = 0; k + 2 < t.size(); k += 3)
    if (t[k] == best || t[k + 1] == best || t[k + 2] == best)
      normal += (x[o + t[k + 1]] - x[o + t[k]]).cross(x[o + t[k + 2]] - x[o + t[k]]);
  return (p - x[o + best]).dot(normal.normalized());
}

}  // namespace

TEST_CASE("contact layer: a face's skin meets a rope and water") {
  // Zero gravity; thrown at the face (it looks along +z, its nose 0.11 m out) at 3 m/s, across
  // the nose and cheeks (the eye sockets hold no eyeball to stop it: docs/face.md, limits).
  auto across = [](const std::string& thrown) {
    World w = worldFromText(faceWith(thrown, "[0, 0, 0]"));
    const FaceBody& f = *w.first<FaceBody>();
    const std::string name = w.bodies()[1]->name();
    const std::vector<Vec3> rest = f.network().state.x;
    double skin = 1e300, skull = 1e300, dent = 0.0;
    Vec3 deepest = Vec3::Zero(), deep_skin = Vec3::Zero();
    for (int frame = 0; frame < 6; ++frame) {
      run(w, 1);
      for (const Vec3& p : viewOf(w, name).positions) {
        if (p.y() < -0.1) continue;  // splashed down past the chin (the nearest vertex's normal misleads at the neck's cut)
        // (Over the face's middle; beside the cheeks and round the jaw's sides, where the rope's
        // ends wrap, the dented skin's nearest normal leans and misleads: there the skull alone
        // is measured.)
        if (p.z() > 0.03 && std::abs(p.x()) < 0.04 && outside(f, p, 0) < skin) skin = outside(f, p, 0), deep_skin = p;
        if (outside(f, p, 2) < skull) skull = outside(f, p, 2), deepest = p;
      }
      // The skin took the push: how far back (−z) an epidermis node was driven.
      for (std::size_t k = 0; k < f.surface().size(); ++k)
        dent = std::max(dent, rest[k].z() - f.network().state.x[k].z());
    }
    MESSAGE("deepest: " << -skin << " m under the skin (at " << deep_skin.transpose() << "), " << skull
                         << " m over the skull (at " << deepest.transpose() << "); skin dented " << dent << " m");
    CHECK(w.contacts().total().point_triangle > 0);
    CHECK(skull > 0.0);         // nothing reaches the skull
    CHECK(skin > -0.012);       // the skin dents no deeper than its tissue
    CHECK(dent > 0.002);
    // Stopped by the face, not flying on at 3 m/s.
    const BodyView v = viewOf(w, name);
    double vz = 0.0;
    for (const Vec3& u : v.velocities) vz += u.z() / static_cast<double>(v.velocities.size());
    CHECK(vz > -1.0);
  };
  SUBCASE("a rope") {
    across(R"({"type": "rope", "name": "rope", "start": [-0.12, -0.03, 0.2], "end": [0.12, -0.03, 0.2], "segments": 24,
        "mass": 0.05, "stiffness": 2000, "damping": 0.2, "node_radius": 0.005, "velocity": [0, 0, -3]})");
  }
  SUBCASE("water") {
    across(R"({"type": "fluid", "name": "water", "radius": 0.005, "species": [{"name": "water", "mass": 0.001,
        "alpha": 212.6, "beta": 0.085, "cutoff": 0.0136, "viscosity": 6}],
        "blocks": [{"min": [-0.03, -0.02, 0.2], "max": [0.03, 0.04, 0.23], "spacing": 0.01, "velocity": [0, 0, -3]}]})");
  }
}
