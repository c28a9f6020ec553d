// Articulated bodies: a hinge pendulum's period, a double pendulum's energy, joints that never
// come apart, servos with gravity compensation, the human figure's masses and balance, the dump,
// determinism, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/figure.h"
#include "core/math.h"
#include "app/body_kinds.h"
#include "helpers.h"
#include "sim/articulated/articulated_body.h"
#include "sim/rigid/rigid_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

ArticulatedBody& figure(World& w, std::size_t k = 0) {
  std::size_t seen = 0;
  for (const auto& b : w.bodies())
    if (auto* a = dynamic_cast<ArticulatedBody*>(b.get()))
      if (seen++ == k) return *a;
  throw std::runtime_error("no articulated body");
}

// The farthest a joint's point on the parent is from the same point on the child, m.
double jointGap(const ArticulatedBody& b) {
  const ArtKinematics& k = b.kinematics();
  double worst = 0;
  for (std::size_t i = 0; i < b.model().joints.size(); ++i) {
    const ArtJoint& j = b.model().joints[i];
    if (j.parent < 0) continue;
    const auto p = static_cast<std::size_t>(j.parent);
    const Vec3 on_parent = k.x[p] + k.R[p] * j.parent_anchor, on_child = k.x[i] + k.R[i] * j.anchor;
    worst = std::max(worst, (on_parent - on_child).norm());
  }
  return worst;
}

double energy(const ArticulatedBody& b) {
  return kineticEnergy(b.model(), b.kinematics()) + potentialEnergy(b.model(), b.kinematics(), Vec3(0, -9.78, 0));
}

const std::string kPendulum = R"({"format": "reel/1", "duration": 5, "fps": 100, "substeps": 10,
  "bodies": [{"type": "articulated", "name": "p", "fixed_base": true,
    "links": [{"name": "base", "shape": "sphere", "radius": 0.01, "density": 1000},
              {"name": "rod", "shape": "box", "size": [0.02, 1, 0.02], "density": 1000, "parent": "base",
               "joint": {"type": "hinge", "axis": [0, 0, 1], "anchor": [0, 0.5, 0], "angle_deg": 3}}]}]})";

std::string human(const std::string& keys) {
  return R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 8,
    "objects": [{"type": "plane", "surface": {"friction": 0.9}}],
    "bodies": [{"type": "articulated", "name": "man", "figure": "human", "surface": {"friction": 0.9})" + keys + "}]}";
}

}  // namespace

TEST_CASE("a hinge pendulum swings with the period 2π√(I/(m g d)) (3°, semi-implicit, film step)") {
  World w = worldFromText(kPendulum);
  ArticulatedBody& b = figure(w);
  std::vector<double> crossings;
  double last = b.state().q[0], t_last = 0;
  for (int f = 1; f <= 500; ++f) {
    REQUIRE(w.advanceFrame());
    const double a = b.state().q[0], t = f / 100.0;
    if (last > 0 && a <= 0) crossings.push_back(t_last + (t - t_last) * last / (last - a));
    last = a;
    t_last = t;
  }
  REQUIRE(crossings.size() >= 3);
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  // The rod about its end: I = m(L² + w²)/12 + m(L/2)², d = L/2.
  const double m = 0.02 * 0.02 * 1.0 * 1000, I = m * (1.0 + 0.0004) / 12 + m * 0.25;
  const double expected = 2 * kPi * std::sqrt(I / (m * 9.78 * 0.5));
  CAPTURE(period);
  CAPTURE(expected);
  CHECK(std::abs(period / expected - 1) < 0.005);
}

TEST_CASE("a chaotic double pendulum keeps its energy within 1e-4 over 10 s (rk4, 1 ms)") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 10, "fps": 100, "substeps": 10, "integrator": "rk4",
    "bodies": [{"type": "articulated", "name": "dp", "fixed_base": true,
      "links": [{"name": "base", "shape": "sphere", "radius": 0.01},
                {"name": "upper", "shape": "capsule", "radius": 0.03, "length": 0.5, "parent": "base",
                 "joint": {"type": "hinge", "anchor": [0, 0.25, 0], "angle_deg": 120}},
                {"name": "lower", "shape": "capsule", "radius": 0.03, "length": 0.5, "parent": "upper",
                 "joint": {"type": "hinge", "anchor": [0, 0.25, 0], "parent_anchor": [0, -0.25, 0], "angle_deg": -50}}]}]})");
  ArticulatedBody& b = figure(w);
  const double E0 = energy(b);
  double worst = 0, swing = 0;
  for (int f = 0; f < 1000; ++f) {
    REQUIRE(w.advanceFrame());
    worst = std::max(worst, std::abs(energy(b) - E0));
    swing = std::max(swing, kineticEnergy(b.model(), b.kinematics()));
  }
  // Relative to the energy that moves about (the kinetic energy's peak), not the arbitrary zero of the potential.
  CAPTURE(worst / swing);
  CHECK(swing > 1.0);
  CHECK(worst / swing < 1e-4);
}

TEST_CASE("a tumbling figure's joints never come apart (reduced coordinates: under 1e-9 m)") {
  World w = worldFromText(human(R"(, "strength": 0, "velocity": [0, 3, 2], "angular_velocity": [4, 1, 2])"));
  ArticulatedBody& b = figure(w);
  double worst = 0;
  for (int f = 0; f < 60; ++f) {
    REQUIRE(w.advanceFrame());
    worst = std::max(worst, jointGap(b));
  }
  CHECK(b.contacts() > 0);  // it landed
  CHECK(worst < 1e-9);
}

TEST_CASE("a PD servo with gravity compensation holds an arm's pose within 1°; without it, the arm sags") {
  auto arm = [](bool compensate) {
    return std::string(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 8,
      "bodies": [{"type": "articulated", "name": "arm", "fixed_base": true, "gravity_compensation": )") +
           (compensate ? "true" : "false") + R"(, "servo": {"kp": 40, "kd": 4},
        "links": [{"name": "base", "shape": "sphere", "radius": 0.05},
                  {"name": "upper", "shape": "capsule", "radius": 0.04, "length": 0.3, "parent": "base",
                   "joint": {"type": "hinge", "anchor": [0, 0.19, 0], "target_deg": 60}},
                  {"name": "fore", "shape": "capsule", "radius": 0.03, "length": 0.25, "parent": "upper",
                   "joint": {"type": "hinge", "anchor": [0, 0.15, 0], "parent_anchor": [0, -0.19, 0], "target_deg": -45}}]}]})";
  };
  for (bool compensate : {true, false}) {
    World w = worldFromText(arm(compensate));
    run(w, 60);
    const ArticulatedBody& b = figure(w);
    const double e1 = std::abs(b.state().q[0] - 60 * kPi / 180), e2 = std::abs(b.state().q[1] + 45 * kPi / 180);
    CAPTURE(compensate);
    CAPTURE(e1 * 180 / kPi);
    CAPTURE(e2 * 180 / kPi);
    if (compensate) CHECK(std::max(e1, e2) < kPi / 180);
    else CHECK(std::max(e1, e2) > 3 * kPi / 180);
  }
}

TEST_CASE("the human figure: Winter's segment masses, 16 links, 33 joint degrees of freedom") {
  const auto links = humanFigure(1.75, 70.0, 1.0);
  CHECK(links.size() == 16);
  double mass = 0;
  int dofs = 0;
  for (const auto& l : links) {
    mass += l.mass.mass;
    if (l.parent >= 0) dofs += jointDofs(l.joint.type);
    CHECK(l.mass.inertia.diagonal().minCoeff() > 0);
  }
  CHECK(mass == doctest::Approx(70.0).epsilon(1e-9));
  CHECK(dofs == 33);
  auto find = [&](const std::string& n) {
    for (const auto& l : links)
      if (l.name == n) return l.mass.mass;
    return -1.0;
  };
  CHECK(find("thigh_l") == doctest::Approx(0.100 * 70));
  CHECK(find("hand_r") == doctest::Approx(0.006 * 70));
  CHECK(find("head") == doctest::Approx(0.081 * 70));
  // It stands on its soles: the feet's lowest points at y = 0.
  World w = worldFromText(human(""));
  const ArticulatedBody& b = figure(w);
  CHECK(b.kinematics().x[0].y() == doctest::Approx(humanRootHeight(1.75)));
}

TEST_CASE("the standing figure balances after a 15 N·s push to the chest and falls from a 40 N·s one") {
  for (double push : {15.0, 40.0}) {
    World w = worldFromText(human(R"(, "balance": true, "protect": true,
      "pushes": [{"time": 0.5, "link": "chest", "impulse": [0, 0, )" + std::to_string(push) + "]}]"));
    ArticulatedBody& b = figure(w);
    bool protected_fall = false;
    for (int f = 0; f < 90; ++f) {
      REQUIRE(w.advanceFrame());
      protected_fall = protected_fall || b.activeController() == ControllerKind::Protect;
    }
    const double pelvis = b.kinematics().x[0].y();
    CAPTURE(push);
    CAPTURE(pelvis);
    if (push < 20) {
      CHECK(pelvis > 0.95);
      CHECK(b.activeController() == ControllerKind::Balance);
    } else {
      CHECK(pelvis < 0.4);
      CHECK(protected_fall);  // the arms went out on the way down
    }
  }
  // Without the balance controller the smaller push already topples it.
  World w = worldFromText(human(R"(, "pushes": [{"time": 0.5, "link": "chest", "impulse": [0, 0, 25]}])"));
  run(w, 90);
  CHECK(figure(w).kinematics().x[0].y() < 0.9);
}

TEST_CASE("articulated: the same state for 1 and 2 threads, and a dump of links and joints") {
  const std::string text = human(R"(, "strength": 0.3, "velocity": [0, 0, 1.5], "protect": true)");
  CHECK(runHash(text, 1, 30) == runHash(text, 2, 30));
  // Two figures running into each other and a crate falling on them: the figures step in parallel.
  const std::string crowd = R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 8,
    "objects": [{"type": "plane", "surface": {"friction": 0.9}}],
    "bodies": [{"type": "articulated", "name": "a", "figure": "human", "strength": 0.3, "velocity": [0, 0, 2]},
               {"type": "articulated", "name": "b", "figure": "human", "strength": 0.3, "position": [0, 0, 1.6],
                "rotation_deg": [0, 180, 0], "velocity": [0, 0, -1]},
               {"type": "rigid", "name": "crate", "shape": "box", "size": [0.4, 0.4, 0.4], "mass": 10, "position": [0.1, 2.4, 0.8]}]})";
  CHECK(runHash(crowd, 1, 45) == runHash(crowd, 2, 45));
  const auto dir = freshDir("articulated_dump");
  const std::string scene = (dir / "s.json").string();
  std::ofstream(scene) << kPendulum;
  const Run r = runReel("simulate " + scene + " --dump " + (dir / "d.json").string());
  REQUIRE(r.code == 0);
  const std::string dump = fileBytes(dir / "d.json");
  for (const char* key : {"\"links\":", "\"name\":\"rod\"", "\"orientation\":", "\"angular_velocity\":", "\"joints\":", "\"angles\":"})
    CHECK(dump.find(key) != std::string::npos);
}

TEST_CASE("a push at time 0 acts in the first step, and a push acts once") {
  auto speed = [](const std::string& time) {
    World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 24, "substeps": 10, "gravity": [0, 0, 0],
      "bodies": [{"type": "articulated", "name": "a", "links": [{"name": "block", "shape": "box", "size": [0.2, 0.2, 0.2], "mass": 2}],
                  "pushes": [{"time": )" + time + R"(, "link": "block", "impulse": [1, 0, 0]}]}]})");
    run(w, 23);
    Vec3 c, v;
    centreOfMass(figure(w).model(), figure(w).kinematics(), c, v);
    return v.x();
  };
  CHECK(speed("0") == doctest::Approx(0.5));
  CHECK(speed("0.925") == doctest::Approx(0.5));
}

TEST_CASE("articulated: bad input is refused with its JSON path") {
  auto links = [](const std::string& second, const std::string& extra = "") {
    return R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "a")" + extra + R"(,
      "links": [{"name": "base"}, )" + second + "]}]}";
  };
  checkHas(badInputError(links(R"({"name": "x", "parent": "bse", "joint": {}})")), "/bodies/0/links/1/parent");
  checkHas(badInputError(links(R"({"name": "x", "parent": "bse", "joint": {}})")), "nearest: 'base'");
  checkHas(badInputError(links(R"({"name": "x", "parent": "y", "joint": {}}, {"name": "y", "parent": "x", "joint": {}})")), "cycle");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"axis": [0, 0, 0]}})")), "/bodies/0/links/1/joint/axis");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"lower_deg": 10, "upper_deg": -10}})")),
           "/bodies/0/links/1/joint/lower_deg");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"kp": -1}})")), "/bodies/0/links/1/joint/kp");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base"})")), "/bodies/0/links/1/joint");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {}, "mass": 1e9})")), "/bodies/0/links/1/mass");
  checkHas(badInputError(links(R"({"name": "base", "parent": "base", "joint": {}})")), "/bodies/0/links/1/name");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"type": "ball", "lower_deg": 1, "upper_deg": 2}})")),
           "/bodies/0/links/1/joint/lower_deg");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"type": "hinge"}})", R"(, "balance": true)")),
           "/bodies/0/balance");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "joints": {"knee": {"angle_deg": 10}}}]})"), "/bodies/0/joints/knee");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "pushes": [{"time": 1, "link": "chst", "impulse": [1, 0, 0]}]}]})"), "/bodies/0/pushes/0/link");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "poses": [{"time": 1, "joints": {"shin_l": [1, 2]}}]}]})"), "/bodies/0/poses/0/joints/shin_l");
}

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

// Writes `urdf` beside a scene that loads it; the scene's path.
std::string robotScene(const std::string& dir_name, const std::string& urdf) {
  const auto dir = freshDir(dir_name);
  std::ofstream(dir / "arm.urdf") << urdf;
  std::ofstream(dir / "s.json") << R"({"format": "reel/1", "duration": 1,
    "bodies": [{"type": "articulated", "name": "arm", "urdf": "arm.urdf", "fixed_base": true, "rotation_deg": [-90, 0, 0]}]})";
  return (dir / "s.json").string();
}

}  // namespace

TEST_CASE("URDF: a small arm's links, masses, inertias and joints match the hand-computed ones") {
  auto s = app::loadScene(robotScene("urdf_arm", kArm));
  REQUIRE_MESSAGE(s.ok(), (s.ok() ? "" : s.error().headline()));
  const auto& d = s.value().bodies[0].as<ArticulatedDesc>();
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
  auto w = app::makeWorld(s.value());
  REQUIRE(w.ok());
  const double y0 = figure(w.value()).kinematics().x[2].y();
  run(w.value(), 10);
  CHECK(jointGap(figure(w.value())) < 1e-9);
  CHECK(figure(w.value()).kinematics().x[2].y() < y0 - 0.2);
}

TEST_CASE("URDF: a mesh link is drawn as its mesh and met as its convex hull") {
  std::string urdf = kArm;
  const std::string capsule = R"(<capsule radius="0.04" length="0.32"/>)";
  urdf.replace(urdf.find(capsule), capsule.size(), R"(<mesh filename="parts/fore.obj" scale="0.08 0.4 0.08"/>)");
  const std::string scene = robotScene("urdf_mesh", urdf);
  const auto dir = std::filesystem::path(scene).parent_path();
  std::filesystem::create_directories(dir / "parts");
  // A unit cube about its centre.
  std::ofstream(dir / "parts" / "fore.obj") << "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
                                               "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
                                               "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                               "f 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";
  auto s = app::loadScene(scene);
  REQUIRE_MESSAGE(s.ok(), (s.ok() ? "" : s.error().headline()));
  const auto& d = s.value().bodies[0].as<ArticulatedDesc>();
  CHECK(d.links[2].shape.kind == LinkShape::Kind::Mesh);
  CHECK(d.links[2].mass.mass == 1.0);  // the inertial's, not the mesh's
  auto w = app::makeWorld(s.value());
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
  auto refused = [](const std::string& urdf, const std::string& part) {
    auto s = app::loadScene(robotScene("urdf_bad", urdf));
    REQUIRE_FALSE(s.ok());
    CAPTURE(s.error().headline());
    CHECK(s.error().headline().find("/bodies/0/urdf") != std::string::npos);
    CHECK(s.error().headline().find(part) != std::string::npos);
  };
  auto replace = [](std::string s, const std::string& a, const std::string& b) {
    const auto p = s.find(a);
    REQUIRE(p != std::string::npos);
    return s.replace(p, a.size(), b);
  };
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
}

TEST_CASE("a figure and a rigid body trade momentum at their contact (equal and opposite, both masses counted)") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 8, "gravity": [0, 0, 0],
    "bodies": [{"type": "articulated", "name": "a", "position": [0, 1, 0],
                "links": [{"name": "block", "shape": "box", "size": [0.4, 0.4, 0.4], "mass": 20}]},
               {"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.15, "mass": 5, "position": [-1, 1, 0], "velocity": [3, 0, 0]}]})");
  ArticulatedBody& a = figure(w);
  const RigidBody* ball = w.first<RigidBody>();
  REQUIRE(ball);
  auto momentum = [&] {
    Vec3 c, v;
    centreOfMass(a.model(), a.kinematics(), c, v);
    return Vec3(20 * v + 5 * ball->states()[0].v);
  };
  const Vec3 p0 = momentum();
  run(w, 30);
  const Vec3 p1 = momentum();
  CAPTURE(p1.transpose());
  CHECK(a.kinematics().vel[0].tail<3>().norm() > 0.5);  // the block was hit
  CHECK(ball->states()[0].v.x() < 1.5);                   // the ball lost most of its speed
  CHECK((p1 - p0).norm() < 0.01 * p0.norm());
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
        <joint name="j1" type="hinge" axis="0 1 0" range="-120 120" damping="0.01"/>
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

std::string mjcfScene(const std::string& xml) {
  const auto dir = freshDir("mjcf");
  std::ofstream(dir / "dp.xml") << xml;
  std::ofstream(dir / "s.json") << R"({"format": "reel/1", "duration": 1,
    "bodies": [{"type": "articulated", "name": "dp", "mjcf": "dp.xml", "rotation_deg": [-90, 0, 0]}]})";
  return (dir / "s.json").string();
}

}  // namespace

TEST_CASE("MJCF: a double pendulum's masses (from density and given), joints and limits, welded to the world") {
  auto s = app::loadScene(mjcfScene(kPendulumMjcf));
  REQUIRE_MESSAGE(s.ok(), (s.ok() ? "" : s.error().headline()));
  const auto& d = s.value().bodies[0].as<ArticulatedDesc>();
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
  CHECK((j1.anchor - Vec3(-0.25, 0, 0)).norm() < 1e-9);     // the joint at the capsule's end
  CHECK((d.links[2].joint.anchor - Vec3(0, 0, 0.2)).norm() < 1e-9);  // and at the box's top
  CHECK(d.links[2].joint.lower.empty());
  auto w = app::makeWorld(s.value());
  REQUIRE(w.ok());
  run(w.value(), 10);
  CHECK(jointGap(figure(w.value())) < 1e-9);
}

TEST_CASE("MJCF: what is outside the subset is refused with its line") {
  auto refused = [](const std::string& xml, const std::string& part) {
    auto s = app::loadScene(mjcfScene(xml));
    REQUIRE_FALSE(s.ok());
    CAPTURE(s.error().headline());
    CHECK(s.error().headline().find("/bodies/0/mjcf") != std::string::npos);
    CHECK(s.error().headline().find(part) != std::string::npos);
  };
  auto replace = [](std::string s, const std::string& a, const std::string& b) {
    const auto p = s.find(a);
    REQUIRE(p != std::string::npos);
    return s.replace(p, a.size(), b);
  };
  refused(replace(kPendulumMjcf, R"(type="hinge" axis="0 1 0"/>)", R"(type="slide" axis="0 1 0"/>)"), "line 12: joint type \"slide\"");
  refused(replace(kPendulumMjcf, "<option timestep=\"0.002\"/>", "<default><geom density=\"500\"/></default>"), "line 3: <default>");
  refused(replace(kPendulumMjcf, R"(<geom type="sphere" size="0.05" mass="1"/>)", R"(<geom type="mesh" mesh="m"/>)"), "line 7: geom type \"mesh\"");
  refused(replace(kPendulumMjcf, R"(range="-120 120")", R"(range="120 -120")"), "line 9: the range");
  refused(replace(kPendulumMjcf, R"(<actuator>)", R"(<tendon/><actuator>)"), "line 18: <tendon>");
  refused(replace(kPendulumMjcf, R"(size="0.03 0.03 0.2" mass="0.5"/>)", R"(size="0.03 0.03 0.2" mass="0.5"/><geom type="sphere" size="0.1"/>)"),
          "line 13: a second <geom>");
}

TEST_CASE("a cloth held by a link (a cape's grip) hangs its weight on the figure: the servo sags by m·g·L/kp") {
  auto scene = [](bool cloth) {
    return std::string(R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 10, "integrator": "implicit_euler",
      "bodies": [{"type": "articulated", "name": "arm", "fixed_base": true, "gravity_compensation": true, "servo": {"kp": 100, "kd": 20},
        "links": [{"name": "base", "shape": "sphere", "radius": 0.05},
                  {"name": "rod", "parent": "base", "shape": "box", "size": [0.04, 0.5, 0.04], "mass": 1,
                   "joint": {"type": "hinge", "axis": [0, 0, 1], "anchor": [0, 0.25, 0], "angle_deg": 90, "target_deg": 90}}]})") +
           (cloth ? R"(, {"type": "cloth", "name": "flag", "position": [0.5, -0.2, 0], "rotation_deg": [90, 0, 0], "size": [0.1, 0.4],
                      "resolution": [3, 9], "mass": 1.0, "stiffness": 5000, "damping": 5, "node_damping": 0.05,
                      "grips": [{"nodes": ["edge_z0"], "object": "arm/rod"}]})"
                  : "") +
           "]}";
  };
  for (bool cloth : {false, true}) {
    World w = worldFromText(scene(cloth));
    run(w, 90);
    const double angle = figure(w).state().q[0] * 180 / kPi;
    // 1 kg hanging from the rod's tip 0.5 m out: 4.89 N·m against kp = 100 N·m/rad, 2.8°.
    const double expected = cloth ? 90 - 9.78 * 0.5 / 100 * 180 / kPi : 90;
    CAPTURE(cloth);
    CAPTURE(angle);
    CHECK(std::abs(angle - expected) < 0.25);
  }
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "cloth", "name": "c",
    "grips": [{"nodes": ["edge_z0"], "object": "x", "velocity": [1, 0, 0]}]}]})"), "/bodies/0/grips/0/velocity");
}

TEST_CASE("film step sizes: a figure falling over a box at one step a frame (33 ms) is stable and lands as at 8") {
  auto fall = [](int substeps) {
    World w = worldFromText(R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": )" + std::to_string(substeps) + R"(,
      "objects": [{"type": "plane", "surface": {"friction": 0.9}}, {"type": "box", "center": [0, 0.15, 0.6], "size": [2, 0.3, 0.4]}],
      "bodies": [{"type": "articulated", "name": "man", "figure": "human", "strength": 0.3, "velocity": [0, 0, 1.5],
                  "surface": {"friction": 0.9}}]})");
    run(w, 89);
    return std::pair<Vec3, double>(figure(w).kinematics().x[0], jointGap(figure(w)));
  };
  const auto [coarse, gap] = fall(1);
  const auto [fine, gap8] = fall(8);
  CAPTURE(coarse.transpose());
  CAPTURE(fine.transpose());
  CHECK(gap < 1e-9);
  CHECK(coarse.y() < 0.3);  // it fell
  CHECK((coarse - fine).norm() < 0.1);
}
