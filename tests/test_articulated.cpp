// Articulated bodies: a hinge pendulum's period, a double pendulum's energy, joints that never
// come apart, servos with gravity compensation, the human figure's masses and balance, the dump,
// determinism, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "capture.h"
#include "core/figure.h"
#include "core/math.h"
#include "app/body_kinds.h"
#include "articulated_helpers.h"
#include "helpers.h"
#include "sim/articulated/articulated_body.h"
#include "sim/rigid/rigid_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

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

// The period of a pendulum scene's first joint, from its downward zero crossings over 5 s.
double pendulumPeriod(const std::string& scene) {
  World w = worldFromText(scene);
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
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

TEST_CASE("a hinge pendulum swings with the period 2π√(I/(m g d)) (3°, semi-implicit, film step)") {
  // The rod about its end: I = m(L² + w²)/12 + m(L/2)², d = L/2.
  const double m = 0.02 * 0.02 * 1.0 * 1000, I = m * (1.0 + 0.0004) / 12 + m * 0.25;
  const double period = pendulumPeriod(kPendulum), expected = 2 * kPi * std::sqrt(I / (m * 9.78 * 0.5));
  CAPTURE(period);
  CAPTURE(expected);
  CHECK(std::abs(period / expected - 1) < 0.005);
  // A rotor's armature a on the hinge adds to its inertia alone: 2π√((I + a)/(m g d)).
  std::string geared = kPendulum;
  geared.replace(geared.find(R"("angle_deg": 3)"), 14, R"("angle_deg": 3, "armature": 0.05)");
  const double slower = pendulumPeriod(geared), expected_geared = 2 * kPi * std::sqrt((I + 0.05) / (m * 9.78 * 0.5));
  CAPTURE(slower);
  CHECK(std::abs(slower / expected_geared - 1) < 0.005);
  CHECK(slower > 1.1 * period);
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

TEST_CASE("a figure lying on its back gets up (curl, sit, tuck, rock, squat, rise), stands a push, gets up again after a harder one; face down, it rolls over first") {
  // Lying on its back, still: the stand-up's pre-condition holds after `wait`.
  const std::string lying = R"(, "position": [0, 0.1, 0], "rotation_deg": [-90, 0, 0])";
  World w = worldFromText(human(lying + R"(, "stand_up": true, "protect": true)"));
  ArticulatedBody& b = figure(w);
  std::vector<int> phases{0};
  double worst_gap = 0;
  for (int f = 0; f < 270; ++f) {  // 9 s
    REQUIRE(w.advanceFrame());
    if (b.standUpState().phase != phases.back()) phases.push_back(b.standUpState().phase);
    worst_gap = std::max(worst_gap, jointGap(b));
  }
  CAPTURE(phases.size());
  // Every phase in its order, each once (no retry needed here), ending standing under balance.
  CHECK(phases == std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7});
  CHECK(b.activeController() == ControllerKind::StandUp);
  const double head = b.kinematics().x[3].y(), pelvis = b.kinematics().x[0].y();
  CAPTURE(head);
  CHECK(head > 0.85 * 0.905 * 1.75);  // the head's standing height is 0.905 H
  CHECK(pelvis > 0.85 * 0.575 * 1.75);
  CHECK(worst_gap < 1e-9);
  // Standing, it keeps its feet under a 15 N·s push from the side; a 40 N·s push from the front
  // throws it on its back, arms out (protect), and it gets up again.
  for (const char* push : {R"([15, 0, 0])", R"([0, 0, -40])"}) {
    World pushed = worldFromText(human(lying + R"(, "stand_up": true, "protect": true,
      "pushes": [{"time": 5, "link": "chest", "impulse": )" + std::string(push) + "}]"));
    ArticulatedBody& p = figure(pushed);
    bool protect = false, again = false;
    for (int f = 0; f < 360; ++f) {  // 12 s
      REQUIRE(pushed.advanceFrame());
      if (f < 150) continue;
      protect = protect || p.activeController() == ControllerKind::Protect;
      again = again || (protect && p.standUpState().phase >= static_cast<int>(StandUpPhase::Squat));
    }
    CAPTURE(push);
    if (push[1] == '1') {
      CHECK(p.standUpState().phase == static_cast<int>(StandUpPhase::Stand));
      CHECK(!protect);
    } else {
      CHECK(protect);
      CHECK(again);  // on its feet again after the fall
    }
  }
  // Without the controller it stays down.
  World still = worldFromText(human(lying));
  run(still, 270);
  CHECK(figure(still).kinematics().x[3].y() < 0.3);
  // Standing, the pre-condition does not hold: the stand-up never acts.
  World standing = worldFromText(human(R"(, "stand_up": true)"));
  for (int f = 0; f < 60; ++f) {
    REQUIRE(standing.advanceFrame());
    CHECK(figure(standing).standUpState().phase == 0);
  }
  // Face down, it rolls onto its back first, then gets up.
  World prone = worldFromText(human(R"(, "position": [0, 0.1, 0], "rotation_deg": [90, 0, 0], "stand_up": true)"));
  std::vector<int> seen{0};
  for (int f = 0; f < 270; ++f) {
    REQUIRE(prone.advanceFrame());
    if (figure(prone).standUpState().phase != seen.back()) seen.push_back(figure(prone).standUpState().phase);
  }
  CHECK(seen == std::vector<int>{0, 8, 0, 1, 2, 3, 4, 5, 6, 7});
  CHECK(figure(prone).kinematics().x[3].y() > 0.85 * 0.905 * 1.75);
}

TEST_CASE("the stand-up gets up figures its tuning never saw: other strengths, frictions, sizes, headings, steps") {
  struct Case {
    std::string keys;
    double friction, height;
    int substeps;
  };
  const std::vector<Case> cases = {
      {R"("strength": 0.72)", 0.8, 1.75, 8},         {R"("strength": 1.4)", 0.8, 1.75, 8},
      {"", 0.55, 1.75, 8},                             {"", 1.3, 1.75, 8},
      {R"("height": 1.5, "mass": 45)", 0.8, 1.5, 8},  {R"("height": 2.0, "mass": 100)", 0.8, 2.0, 8},
      {R"("rotation_deg": [-90, 135, 0])", 0.8, 1.75, 8}, {R"("rotation_deg": [-90, 0, -10])", 0.8, 1.75, 8},
      {"", 0.8, 1.75, 4},                              {"", 0.8, 1.75, 12}};
  for (const Case& c : cases) {
    const std::string f = std::to_string(c.friction);
    std::string keys = c.keys.find("rotation_deg") == std::string::npos ? R"("rotation_deg": [-90, 0, 0])" : c.keys;
    if (keys != c.keys && !c.keys.empty()) keys += ", " + c.keys;
    World w = worldFromText(R"({"format": "reel/1", "duration": 11, "fps": 30, "substeps": )" + std::to_string(c.substeps) +
                            R"(, "objects": [{"type": "plane", "surface": {"friction": )" + f + R"(}}],
      "bodies": [{"type": "articulated", "name": "man", "figure": "human", "position": [0, 0.1, 0], "stand_up": true,
                  "surface": {"friction": )" + f + "}, " + keys + "}]}");
    run(w, 330);
    const ArticulatedBody& b = figure(w);
    CAPTURE(c.keys);
    CAPTURE(c.friction);
    CAPTURE(c.substeps);
    CHECK(b.standUpState().phase == static_cast<int>(StandUpPhase::Stand));
    CHECK(b.kinematics().x[3].y() > 0.85 * 0.905 * c.height);
  }
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
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"armature": -0.1}})")), "/bodies/0/links/1/joint/armature");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {}, "mass": 1e9})")), "/bodies/0/links/1/mass");
  checkHas(badInputError(links(R"({"name": "base", "parent": "base", "joint": {}})")), "/bodies/0/links/1/name");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"type": "ball", "lower_deg": 1, "upper_deg": 2}})")),
           "/bodies/0/links/1/joint/lower_deg");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"type": "hinge"}})", R"(, "balance": true)")),
           "/bodies/0/balance");
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"type": "hinge"}})", R"(, "stand_up": true)")),
           "/bodies/0/stand_up");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "stand_up": {"wait": -1}}]})"), "/bodies/0/stand_up/wait");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "joints": {"knee": {"angle_deg": 10}}}]})"), "/bodies/0/joints/knee");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "pushes": [{"time": 1, "link": "chst", "impulse": [1, 0, 0]}]}]})"), "/bodies/0/pushes/0/link");
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "articulated", "name": "m", "figure": "human",
    "poses": [{"time": 1, "joints": {"shin_l": [1, 2]}}]}]})"), "/bodies/0/poses/0/joints/shin_l");
  // An angle past the cap is named as such, not as "not finite".
  checkHas(badInputError(links(R"({"name": "x", "parent": "base", "joint": {"angle_deg": 1e200}})")),
           "/bodies/0/links/1/joint/angle_deg: an angle of 1e+200 degrees is beyond the limit of ±1e6");
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
  CAPTURE_BINDING(coarse.transpose());
  CAPTURE_BINDING(fine.transpose());
  CHECK(gap < 1e-9);
  CHECK(coarse.y() < 0.3);  // it fell
  CHECK((coarse - fine).norm() < 0.1);
}
