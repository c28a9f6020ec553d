// One world, scene objects: the static and keyed objects (spheres, boxes, capsules, containers,
// meshes; not planes) thinner than a sheet's edges are convex parts of the contact layer, so its
// triangles meet them and not only its nodes: a sheet dropped on a rail or a post thinner than its mesh rests on it, a
// thin keyed paddle sweeping through a hanging sheet carries it; a sheet pinned on an object
// (a flag on its pole) is left apart from it. 1 and 2 threads give the same bits, a resumed run
// the same bits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "contact_helpers.h"
#include "helpers.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// A floor 1 m down, the objects given, the bodies given.
std::string scene(const std::string& objects, const std::string& bodies, const std::string& gravity = "[0, -9.78, 0]") {
  return R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 40, "auto_substeps": true, "gravity": )" +
         gravity + R"(, "objects": [{"type": "plane", "name": "floor", "point": [0, -1, 0]})" +
         (objects.empty() ? "" : ", " + objects) + R"(], "bodies": [)" + bodies + "]}";
}

// A free 1 m sheet 0.3 m up, its nodes 11.1 cm apart (rows at z = ±0.056, ±0.167, …, ±0.5).
const std::string kSheet = R"({"type": "cloth", "name": "sheet", "position": [0, 0.3, 0], "size": [1, 1], "resolution": [10, 10],
    "mass": 0.3, "stiffness": 600, "damping": 0.2, "node_damping": 0.01, "thickness": 0.01})";

// A 2 cm rail along x under the sheet's middle, between two rows of nodes, and a 2 cm post under
// the middle of its middle square: no node of the sheet comes down on either.
const std::string kRail = R"({"type": "capsule", "name": "rail", "start": [-0.8, 0, 0], "end": [0.8, 0, 0], "radius": 0.01})";
const std::string kPost = R"({"type": "capsule", "name": "post", "start": [0, -1, 0], "end": [0, 0, 0], "radius": 0.01})";

double highest(const World& w, const std::string& name) {
  double y = -1e300;
  for (const Vec3& p : viewOf(w, name).positions) y = std::max(y, p.y());
  return y;
}

}  // namespace

TEST_CASE("scene objects: a sheet dropped on a rail or a post thinner than its mesh rests on it") {
  // Without the objects as convex parts both fell between the nodes to the floor.
  for (const std::string& object : {kRail, kPost}) {
    CAPTURE(object);
    World w = worldFromText(scene(object, kSheet));
    CHECK(w.contacts().active());
    run(w, 90);
    CHECK(w.contacts().total().triangle_convex > 0);
    // Draped over it: its top a plate's thickness above the object's top (y = 0.01), its hems
    // hanging, off the floor, and settling (the hems' last swings).
    CHECK(highest(w, "sheet") > 0.015);
    CHECK(highest(w, "sheet") < 0.03);
    CHECK(lowest(w, "sheet") > -0.9);
    CHECK(lowest(w, "sheet") < -0.2);
    double vmax = 0.0;
    for (const Vec3& v : viewOf(w, "sheet").velocities) vmax = std::max(vmax, v.norm());
    CHECK(vmax < 0.3);
  }
}

TEST_CASE("scene objects: an object no thinner than a sheet's edges is left to its nodes") {
  // A 0.4 m box under the sheet: its nodes' own contacts hold the sheet off it (a triangle dips
  // into it by no more than one edge's sag), so the layer has nothing to do; the sheet rests on it.
  // (With every solid object a convex part, a fold jammed between two such objects was pushed back
  // and forth by them and by the sheet's self-collision: the flying carpet took 2.8 times as long.)
  const std::string box = R"({"type": "box", "name": "crate", "center": [0, -0.2, 0], "size": [0.4, 0.4, 0.4]})";
  World w = worldFromText(scene(box, kSheet));
  CHECK(!w.contacts().active());
  run(w, 45);
  CHECK(w.contacts().total().triangle_convex == 0);
  CHECK(highest(w, "sheet") > 0.005);  // the box's top at y = 0; the nodes a contact distance above it
  CHECK(highest(w, "sheet") < 0.04);
  CHECK(lowest(w, "sheet") > -0.9);
  // The rail under the same sheet is thinner than its edges: met by its triangles.
  CHECK(worldFromText(scene(kRail, kSheet)).contacts().active());
}

TEST_CASE("scene objects: a thin keyed paddle sweeping through a hanging sheet carries it") {
  // A sheet hung by its top corners in the x–y plane; a 1 cm thick paddle (a box) moving along z
  // at 1.5 m/s through it, between its nodes' rows and columns.
  const std::string hung = R"({"type": "cloth", "name": "sheet", "position": [0, 0, 0], "rotation_deg": [90, 0, 0], "size": [1, 1],
      "resolution": [9, 9], "mass": 0.3, "stiffness": 600, "damping": 0.2, "node_damping": 0.01, "thickness": 0.01,
      "pinned": ["corner_00", "corner_10"]})";
  const std::string paddle = R"({"type": "box", "name": "paddle", "center": [0.0625, -0.0625, -0.3], "size": [0.06, 0.06, 0.01],
      "motion": {"keys": [{"time": 0, "position": [0.0625, -0.0625, -0.3]}, {"time": 0.6, "position": [0.0625, -0.0625, 0.6]}]}})";
  World w = worldFromText(scene(paddle, hung, "[0, 0, 0]"));
  run(w, 12);  // 0.4 s: the paddle at z = 0.3
  CHECK(w.contacts().total().triangle_convex > 0);
  double zmax = -1e300;
  for (const Vec3& p : viewOf(w, "sheet").positions) zmax = std::max(zmax, p.z());
  CHECK(zmax > 0.2);  // the sheet is carried ahead of the paddle, not passed through
}

TEST_CASE("scene objects: a sheet pinned on an object is left apart from it (a flag on its pole)") {
  // A flag whose pinned edge lies inside its pole, the pole's surface past the first free column
  // of nodes, in zero gravity and still air: it stays at rest (the pole does not push the
  // triangles beside the pins off itself; without the rule they move at 0.47 m/s).
  const std::string pole = R"({"type": "capsule", "name": "pole", "start": [-0.03, -1, 0], "end": [-0.03, 1, 0], "radius": 0.05})";
  const std::string flag = R"({"type": "cloth", "name": "flag", "position": [0.5, 0, 0], "rotation_deg": [90, 0, 0], "size": [1, 0.6],
      "resolution": [30, 18], "mass": 0.1, "stiffness": 600, "damping": 0.2, "thickness": 0.006, "pinned": ["edge_x0"]})";
  World w = worldFromText(scene(pole, flag, "[0, 0, 0]"));
  CHECK(!w.contacts().active());  // held there from the start: the layer has nothing to do
  run(w, 15);
  CHECK(w.contacts().total().triangle_convex == 0);
  double vmax = 0.0;
  for (const Vec3& v : viewOf(w, "flag").velocities) vmax = std::max(vmax, v.norm());
  CHECK(vmax < 1e-9);
}

TEST_CASE("scene objects: 1 and 2 threads give the same bits; a resumed run gives the same bits") {
  const std::string text = scene(kRail + ", " + kPost, kSheet);
  const World a = sameBitsThreadsAndResume(text, 20);
  CHECK(a.contacts().total().triangle_convex > 0);
}
