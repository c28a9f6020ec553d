// One world, convex parts: rigid bodies and figures' links meet the surfaces of the bodies with
// points (a sheet's triangles, a fish's skin, a lattice's skin) through the contact layer's
// triangle–convex handler, not only by those bodies' nodes: a ball smaller than a sheet's mesh
// rests on it. Contact happens, momentum is kept in zero gravity, 1 and 2 threads give the same
// bits, a resumed run the same bits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "helpers.h"
#include "contact_helpers.h"
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

// With a floor 1 m down under gravity; in zero gravity, nothing else.
std::string scene(const std::string& bodies, const std::string& gravity = "[0, -9.78, 0]", double duration = 2) {
  const bool floor = gravity != "[0, 0, 0]";
  return R"({"format": "reel/1", "duration": )" + std::to_string(duration) +
         R"(, "fps": 30, "substeps": 40, "auto_substeps": true, "gravity": )" + gravity +
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
    double s0 = 0.0;
    const Vec3 p0 = momentum(w, s0);
    run(w, 14);
    double s1 = 0.0;
    const Vec3 p1 = momentum(w, s1);
    CHECK(w.contacts().total().triangle_convex > 0);
    CAPTURE(p0.transpose());
    CAPTURE(p1.transpose());
    CHECK((p1 - p0).norm() < 1e-12 * std::max(s0, s1));
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
