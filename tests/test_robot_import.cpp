// Robots made for other tools: URDF and MJCF files loaded as articulated bodies (masses, inertias,
// joints, limits, meshes, MJCF default classes) and what is outside the subset refused with its line.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/body_kinds.h"
#include "articulated_helpers.h"
#include "core/math.h"
#include "helpers.h"
#include "sim/articulated/articulated_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// s with the first a replaced by b (a must be there).
std::string replaced(std::string s, const std::string& a, const std::string& b) {
  const auto p = s.find(a);
  REQUIRE(p != std::string::npos);
  return s.replace(p, a.size(), b);
}

// The scene, loaded (it must load).
SceneDesc loadedScene(const std::string& path) {
  auto s = app::loadScene(path);
  REQUIRE_MESSAGE(s.ok(), (s.ok() ? "" : s.error().headline()));
  return s.value();
}

// The scene is refused, naming the body's robot key and `part` (a line and what is wrong).
void checkRefused(const std::string& scene, const std::string& key, const std::string& part) {
  auto s = app::loadScene(scene);
  REQUIRE_FALSE(s.ok());
  CAPTURE(s.error().headline());
  CHECK(s.error().headline().find("/bodies/0/" + key) != std::string::npos);
  CHECK(s.error().headline().find(part) != std::string::npos);
}

}  // namespace

namespace {

// A two-link arm on a box base (URDF: z up, the shoulder turned 90° about y, so the arm starts
// along +x), and a scene that loads it.
const std::string kArm = R"(<?xml version="1.0"?>
<robot name="arm">
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base">
    <inertial><mass value="5"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial>
    <collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision>
  </link>
  <link name="upper">
    <inertial><origin xyz="0 0 0.25"/><mass value="2"/><inertia ixx="0.0425" iyy="0.0425" izz="0.0025"/></inertial>
    <collision><origin xyz="0 0 0.25"/><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision>
  </link>
  <link name="fore">
    <inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.0137" iyy="0.0137" izz="0.0008"/></inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><capsule radius="0.04" length="0.32"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.05" rpy="0 1.5707963267948966 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="3"/><dynamics damping="0.1"/>
  </joint>
  <joint name="elbow" type="continuous">
    <parent link="upper"/><child link="fore"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
  </joint>
</robot>
)";

// Writes a robot file `file` (read by the body's `key`, urdf or mjcf) beside a scene that loads
// it, in a folder of its own per test (tests run in parallel); the scene's path.
std::string modelScene(const std::string& dir_name, const std::string& key, const std::string& file, const std::string& text,
                       const std::string& extra = "") {
  const auto dir = freshDir(dir_name);
  std::ofstream(dir / file) << text;
  std::ofstream(dir / "s.json") << R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "robot", ")" +
                                       key + R"(": ")" + file + R"(")" + extra + R"(, "rotation_deg": [-90, 0, 0]}]})";
  return (dir / "s.json").string();
}

std::string robotScene(const std::string& dir_name, const std::string& urdf) {
  return modelScene(dir_name, "urdf", "arm.urdf", urdf, R"(, "fixed_base": true)");
}

}  // namespace

TEST_CASE("URDF: a small arm's links, masses, inertias and joints match the hand-computed ones") {
  const SceneDesc loaded = loadedScene(robotScene("urdf_arm", kArm));
  const auto& d = loaded.bodies[0].as<ArticulatedDesc>();
  REQUIRE(d.links.size() == 3);
  CHECK(d.links[0].name == "base");
  CHECK(d.links[1].mass.mass == 2.0);
  CHECK(d.links[2].mass.mass == 1.0);
  // In the robot's frame (z up): the upper arm's inertia turned by the shoulder's 90° about y, its
  // long axis (z) now along x.
  const Mat3 I = d.links[1].mass.inertia;
  CHECK(I(0, 0) == doctest::Approx(0.0025));
  CHECK(I(1, 1) == doctest::Approx(0.0425));
  CHECK(I(2, 2) == doctest::Approx(0.0425));
  CHECK(std::abs(I(0, 2)) < 1e-12);
  // The shoulder's point (0, 0, 0.05) in the base; the upper arm's centre 0.25 m along the turned z (+x).
  const ArticulatedJointDesc& sh = d.links[1].joint;
  CHECK(sh.type == JointType::Hinge);
  CHECK((sh.parent_anchor - Vec3(0, 0, 0.05)).norm() < 1e-9);
  CHECK((sh.anchor - Vec3(-0.25, 0, 0)).norm() < 1e-9);
  CHECK((sh.axis - Vec3(0, 1, 0)).norm() < 1e-9);
  CHECK(sh.lower == std::vector<double>{-2.0});
  CHECK(sh.upper == std::vector<double>{2.0});
  CHECK(sh.damping == 0.1);
  const ArticulatedJointDesc& el = d.links[2].joint;
  CHECK(el.lower.empty());
  CHECK((el.parent_anchor - Vec3(0.25, 0, 0)).norm() < 1e-9);
  CHECK((el.anchor - Vec3(-0.2, 0, 0)).norm() < 1e-9);
  // The cylinder stands along the arm (reel's y turned onto the URDF's z, turned onto x).
  CHECK((d.links[1].shape.rotation * Vec3::UnitY() - Vec3(1, 0, 0)).norm() < 1e-9);
  CHECK(d.links[1].shape.kind == LinkShape::Kind::Cylinder);
  // It simulates (turned z up → y up): the arm swings down under gravity, joints together.
  auto w = app::makeWorld(loaded);
  REQUIRE(w.ok());
  const double y0 = figure(w.value()).kinematics().x[2].y();
  run(w.value(), 10);
  CHECK(jointGap(figure(w.value())) < 1e-9);
  CHECK(figure(w.value()).kinematics().x[2].y() < y0 - 0.2);
}

namespace {

// A unit cube about its centre, wound outward.
const char* kUnitCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
    "f 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";

// The scene loaded with kUnitCubeObj written as parts/<name> beside it.
SceneDesc loadWithCube(const std::string& scene, const std::string& name) {
  const auto dir = std::filesystem::path(scene).parent_path();
  std::filesystem::create_directories(dir / "parts");
  std::ofstream(dir / "parts" / name) << kUnitCubeObj;
  return loadedScene(scene);
}

}  // namespace

TEST_CASE("URDF: a mesh link is drawn as its mesh and met as its convex hull") {
  std::string urdf = kArm;
  const std::string capsule = R"(<capsule radius="0.04" length="0.32"/>)";
  urdf.replace(urdf.find(capsule), capsule.size(), R"(<mesh filename="parts/fore.obj" scale="0.08 0.4 0.08"/>)");
  const SceneDesc loaded = loadWithCube(robotScene("urdf_mesh", urdf), "fore.obj");
  const auto& d = loaded.bodies[0].as<ArticulatedDesc>();
  CHECK(d.links[2].shape.kind == LinkShape::Kind::Mesh);
  CHECK(d.links[2].mass.mass == 1.0);  // the inertial's, not the mesh's
  auto w = app::makeWorld(loaded);
  REQUIRE(w.ok());
  const ArtLink& fore = figure(w.value()).model().links[2];
  REQUIRE(fore.shape.kind == CoreKind::Polytope);
  CHECK(fore.shape.poly->vertices.size() == 8);  // the cube's hull
  run(w.value(), 5);
  CHECK(jointGap(figure(w.value())) < 1e-9);
  urdf.replace(urdf.find("parts/fore.obj"), 14, "package://arm/fore.obj");
  auto bad = app::loadScene(robotScene("urdf_mesh", urdf));
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().headline().find("package://") != std::string::npos);
}

TEST_CASE("URDF: what is outside the subset, or broken, is refused with its line") {
  auto refused = [](const std::string& urdf, const std::string& part) { checkRefused(robotScene("urdf_bad", urdf), "urdf", part); };
  const auto replace = &replaced;
  refused(replace(kArm, R"(type="continuous")", R"(type="prismatic")"), "line 20: joint type \"prismatic\"");
  refused(replace(kArm, R"(<capsule radius="0.04" length="0.32"/>)", R"(<cone radius="0.04"/>)"), "line 14: <cone>");
  refused(replace(kArm, R"(<parent link="upper"/>)", R"(<parent link="uper"/>)"), "line 21: no link \"uper\"");
  refused(replace(kArm, R"(<child link="upper"/>)", R"(<child link="base"/>)"), "cycle");
  refused(replace(kArm, R"(<mass value="2"/>)", R"(<mass value="-2"/>)"), "line 9: <mass> value must be > 0");
  refused(replace(kArm, R"(lower="-2" upper="2")", R"(lower="2" upper="-2")"), "line 18: the lower limit");
  refused(replace(kArm, R"(</robot>)", R"(<link name="tip"/><joint name="x" type="fixed"><parent link="fore"/><child link="tip"/><mimic joint="elbow"/></joint></robot>)"),
          "line 23: <mimic>");
  refused(replace(kArm, "  </link>\n  <link name=\"upper\">", "  </lnk>\n  <link name=\"upper\">"), "line 7: </lnk> closes <link>");
  refused(replace(kArm, R"(<axis xyz="0 1 0"/><limit)", R"(<axis xyz="0 0 0"/><limit)"), "line 18: an axis of zero length");
  refused(replace(kArm, R"(<mass value="5"/>)", R"(<mass value="5e7"/>)"), "line 5: <inertial> gives no usable mass and inertia (mass 5e+07 kg");
  refused(replace(kArm, R"(<mass value="5"/>)", R"(<mass value="5e10"/>)"), "line 5: <mass> value: 5e+10 is beyond the limit of ±1e9");
}

namespace {

const std::string kPendulumMjcf = R"(<mujoco model="double pendulum">
  <compiler angle="degree"/>
  <option timestep="0.002"/>
  <worldbody>
    <geom type="plane" size="2 2 0.1"/>
    <body name="base" pos="0 0 2">
      <geom type="sphere" size="0.05" mass="1"/>
      <body name="upper">
        <joint name="j1" type="hinge" axis="0 1 0" range="-120 120" damping="0.01" armature="0.02"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.04" density="1000"/>
        <body name="lower" pos="0.5 0 0">
          <joint name="j2" type="hinge" axis="0 1 0"/>
          <geom type="box" pos="0 0 -0.2" size="0.03 0.03 0.2" mass="0.5"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j1"/></actuator>
</mujoco>
)";

std::string mjcfScene(const std::string& dir_name, const std::string& xml) { return modelScene(dir_name, "mjcf", "dp.xml", xml); }

}  // namespace

TEST_CASE("MJCF: a double pendulum's masses (from density and given), joints and limits, welded to the world") {
  const SceneDesc loaded = loadedScene(mjcfScene("mjcf_pendulum", kPendulumMjcf));
  const auto& d = loaded.bodies[0].as<ArticulatedDesc>();
  REQUIRE(d.links.size() == 3);
  CHECK(d.fixed_base);  // no free joint on the root
  // The capsule: a 0.5 m cylinder of radius 0.04 and a ball of it, at 1000 kg/m³.
  const double r = 0.04, L = 0.5, capsule = 1000 * (kPi * r * r * L + 4.0 / 3.0 * kPi * r * r * r);
  CHECK(d.links[1].mass.mass == doctest::Approx(capsule));
  CHECK(d.links[2].mass.mass == doctest::Approx(0.5));
  // The box's inertia about its centre: m(b² + c²)/12 with its full sizes 0.06, 0.06, 0.4.
  CHECK(d.links[2].mass.inertia(0, 0) == doctest::Approx(0.5 * (0.06 * 0.06 + 0.4 * 0.4) / 12));
  const ArticulatedJointDesc& j1 = d.links[1].joint;
  CHECK(j1.type == JointType::Hinge);
  CHECK((j1.axis - Vec3(0, 1, 0)).norm() < 1e-12);
  REQUIRE(j1.lower.size() == 1);
  CHECK(j1.lower[0] == doctest::Approx(-120 * kPi / 180));
  CHECK(j1.damping == 0.01);
  CHECK(j1.armature == 0.02);
  CHECK((j1.anchor - Vec3(-0.25, 0, 0)).norm() < 1e-9);     // the joint at the capsule's end
  CHECK((d.links[2].joint.anchor - Vec3(0, 0, 0.2)).norm() < 1e-9);  // and at the box's top
  CHECK(d.links[2].joint.lower.empty());
  auto w = app::makeWorld(loaded);
  REQUIRE(w.ok());
  run(w.value(), 10);
  CHECK(jointGap(figure(w.value())) < 1e-9);
}

TEST_CASE("MJCF: what is outside the subset is refused with its line") {
  auto refused = [](const std::string& xml, const std::string& part) { checkRefused(mjcfScene("mjcf_bad", xml), "mjcf", part); };
  const auto replace = &replaced;
  refused(replace(kPendulumMjcf, R"(type="hinge" axis="0 1 0"/>)", R"(type="slide" axis="0 1 0"/>)"), "line 12: joint type \"slide\"");
  refused(replace(kPendulumMjcf, R"(<geom type="sphere" size="0.05" mass="1"/>)", R"(<geom type="ellipsoid" size="0.05 0.1 0.1"/>)"),
          "line 7: geom type \"ellipsoid\"");
  refused(replace(kPendulumMjcf, R"(<geom type="sphere" size="0.05" mass="1"/>)", R"(<geom type="mesh" mesh="m"/>)"), "line 7: no <mesh> named \"m\"");
  refused(replace(kPendulumMjcf, R"(<joint name="j2" type="hinge")", R"(<joint name="j2" class="stiff" type="hinge")"),
          "line 12: no default class \"stiff\"");
  refused(replace(kPendulumMjcf, R"(<body name="upper">)", R"(<body name="upper" childclass="arm">)"), "line 8: no default class \"arm\"");
  refused(replace(kPendulumMjcf, "<option timestep=\"0.002\"/>", "<default><default><geom density=\"500\"/></default></default>"),
          "line 3: a nested <default> needs a class");
  refused(replace(replace(kPendulumMjcf, "<option timestep=\"0.002\"/>", "<asset><mesh name=\"m\" file=\"gone.obj\"/></asset>"),
                  R"(<geom type="sphere" size="0.05" mass="1"/>)", R"(<geom type="mesh" mesh="m"/>)"),
          "line 3: <mesh> \"gone.obj\"");
  refused(replace(kPendulumMjcf, R"(range="-120 120")", R"(range="120 -120")"), "line 9: the range");
  refused(replace(kPendulumMjcf, R"(<actuator>)", R"(<tendon/><actuator>)"), "line 18: <tendon>");
  refused(replace(kPendulumMjcf, R"(size="0.03 0.03 0.2" mass="0.5"/>)", R"(size="0.03 0.03 0.2" mass="0.5"/><geom type="sphere" size="0.1"/>)"),
          "line 13: a second <geom>");
  // Sizes and masses at the edges, each named with its line: a cap is not "not finite".
  refused(replace(kPendulumMjcf, R"(size="0.03 0.03 0.2" mass="0.5")", R"(size="0.03 1e-300 0.2" mass="0.5")"),
          "line 13: <geom> size must be at least 1e-6 m");
  refused(replace(kPendulumMjcf, R"(size="0.03 0.03 0.2" mass="0.5")", R"(size="0.03 1e200 0.2" mass="0.5")"),
          "line 13: <geom> size: 1e+200 is beyond the limit of ±1e9");
  refused(replace(kPendulumMjcf, R"(size="0.03 0.03 0.2" mass="0.5")", R"(size="0.03 0.03 0.2" mass="1e8")"),
          "line 13: <geom> gives no usable mass and inertia (mass 1e+08 kg");
  refused(replace(kPendulumMjcf, "<option timestep=\"0.002\"/>", "<default class=\"main\"><default class=\"a\"><default class=\"a\"/></default></default>"),
          "line 3: a second default class \"a\"");
}

TEST_CASE("MJCF: default classes cascade onto joints and geoms; a mesh geom's mass comes from its volume") {
  const std::string xml = R"(<mujoco model="classes">
  <compiler angle="degree" meshdir="parts"/>
  <default>
    <geom density="500"/>
    <joint damping="0.2" axis="0 1 0"/>
    <default class="limb">
      <joint range="-90 90"/>
      <geom type="capsule" size="0.04"/>
      <default class="heavy"><geom density="2000"/></default>
    </default>
  </default>
  <asset><mesh name="block" file="cube.obj" scale="0.2 0.1 0.4"/></asset>
  <worldbody>
    <body name="base" pos="0 0 2">
      <geom type="mesh" mesh="block"/>
      <body name="upper" childclass="limb">
        <joint name="j1"/>
        <geom fromto="0 0 0 0.5 0 0"/>
        <body name="lower" pos="0.5 0 0">
          <joint name="j2" class="main" axis="1 0 0"/>
          <geom class="heavy" fromto="0 0 0 0.4 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
)";
  const SceneDesc loaded = loadWithCube(mjcfScene("mjcf_classes", xml), "cube.obj");
  const auto& d = loaded.bodies[0].as<ArticulatedDesc>();
  REQUIRE(d.links.size() == 3);
  // The base: the unit cube scaled to 0.2 × 0.1 × 0.4 m at the main class's 500 kg/m³.
  CHECK(d.links[0].shape.kind == LinkShape::Kind::Mesh);
  CHECK(d.links[0].mass.mass == doctest::Approx(500 * 0.2 * 0.1 * 0.4));
  CHECK(d.links[0].mass.inertia(0, 0) == doctest::Approx(4.0 * (0.1 * 0.1 + 0.4 * 0.4) / 12));
  // upper: a capsule (limb's type and radius) at main's density; lower: heavy's density.
  auto capsule = [](double L, double density) { return density * kPi * 0.04 * 0.04 * (L + 4.0 / 3.0 * 0.04); };
  CHECK(d.links[1].shape.kind == LinkShape::Kind::Capsule);
  CHECK(d.links[1].mass.mass == doctest::Approx(capsule(0.5, 500)));
  CHECK(d.links[2].mass.mass == doctest::Approx(capsule(0.4, 2000)));
  // j1 takes limb's range and main's damping and axis; j2 (class main) no range, its own axis.
  const ArticulatedJointDesc& j1 = d.links[1].joint;
  REQUIRE(j1.lower.size() == 1);
  CHECK(j1.lower[0] == doctest::Approx(-kPi / 2));
  CHECK(j1.damping == 0.2);
  CHECK((j1.axis - Vec3(0, 1, 0)).norm() < 1e-12);
  const ArticulatedJointDesc& j2 = d.links[2].joint;
  CHECK(j2.lower.empty());
  CHECK(j2.damping == 0.2);
  CHECK((j2.axis - Vec3(1, 0, 0)).norm() < 1e-12);
  auto w = app::makeWorld(loaded);
  REQUIRE(w.ok());
  REQUIRE(figure(w.value()).model().links[0].shape.kind == CoreKind::Polytope);
  CHECK(figure(w.value()).model().links[0].shape.poly->vertices.size() == 8);  // met as the cube's hull
  run(w.value(), 10);
  CHECK(jointGap(figure(w.value())) < 1e-9);
}
