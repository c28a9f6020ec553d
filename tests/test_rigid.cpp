// Rigid bodies: free tumbling (angular momentum kept, the intermediate axis flips), friction on
// an incline, bouncing, stacking, sleeping, momentum exchanged with cloth and liquids, schools
// steering around them, determinism, the dump, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/format.h"
#include "core/math.h"
#include "core/state_blob.h"
#include "helpers.h"
#include "sim/cloth/cloth_body.h"
#include "sim/rigid/rigid_body.h"
#include "sim/school/school_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;
namespace fs = std::filesystem;

namespace {

const RigidBody& rigid(const World& w, std::size_t k = 0) {
  std::size_t seen = 0;
  for (const auto& b : w.bodies())
    if (const auto* r = dynamic_cast<const RigidBody*>(b.get()))
      if (seen++ == k) return *r;
  throw std::runtime_error("no such rigid body");
}

// A body of principal moments (1, 2, 3) kg·m² spinning at ω (world = body frame at the start).
RigidModel tumbler() {
  RigidModel m;
  m.mass = m.inv_mass = 1.0;
  m.moments = Vec3(1, 2, 3);
  m.inertia = m.moments.asDiagonal();
  return m;
}

// A heavy slab (3 × 0.2 × 1 m, 60 t) on the floor and a 10 cm cube resting on it at x, with its
// own keys (μ = 0.5 everywhere; sleeping off).
std::string slabScene(double x, const std::string& keys) {
  return R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 10, "gravity": [0, -9.81, 0],
    "objects": [{"type": "plane", "name": "floor", "surface": {"friction": 0.5}}],
    "bodies": [{"type": "rigid", "name": "slab", "shape": "box", "size": [3, 0.2, 1], "position": [0, 0.1, 0], "density": 100000,
                "sleep_time": 0, "surface": {"friction": 0.5}},
               {"type": "rigid", "name": "block", "shape": "box", "size": [0.1, 0.1, 0.1], "position": [)" +
         formatNumber(x, 17) + R"(, 0.25, 0], "sleep_time": 0, )" + keys + R"(, "surface": {"friction": 0.5}}]})";
}

}  // namespace

TEST_CASE("torque-free tumbling keeps angular momentum; the intermediate axis flips, the others stay") {
  const RigidModel m = tumbler();
  const double h = 1e-3;
  for (int axis = 0; axis < 3; ++axis) {
    RigidState s;
    s.w = Vec3::Constant(0.01);
    s.w[axis] = 2.0;
    const Vec3 L0 = angularMomentum(m, s);
    const double E0 = kineticEnergy(m, s);
    double lowest = 1e300, worst_L = 0, worst_E = 0;
    for (int i = 0; i < 20000; ++i) {  // 20 s
      rotateFree(m, s, h);
      const Vec3 body_w = s.q.conjugate() * s.w;
      lowest = std::min(lowest, body_w[axis] / 2.0);
      worst_L = std::max(worst_L, (angularMomentum(m, s) - L0).norm() / L0.norm());
      worst_E = std::max(worst_E, std::abs(kineticEnergy(m, s) - E0) / E0);
    }
    CAPTURE(axis);
    CHECK(worst_L < 1e-9);  // exactly kept, up to rounding
    CHECK(worst_E < 1e-4);  // O(h²), no drift
    if (axis == 1) CHECK(lowest < -0.9);  // flipped over (Dzhanibekov)
    else CHECK(lowest > 0.99);            // stable
  }
}

TEST_CASE("a constant force and torque accelerate a free body by F/m and τ/I; damping slows it as exp(−c t)") {
  // A 2 × 1 × 1 m box of 10 kg without gravity: I_xx = m (1 + 1)/12, a torque about x.
  World w = worldFromText(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 10, "gravity": [0, 0, 0],
    "bodies": [{"type": "rigid", "name": "pushed", "shape": "box", "size": [2, 1, 1], "mass": 10,
                "force": [5, 0, 0], "torque": [0.5, 0, 0], "sleep_time": 0},
               {"type": "rigid", "name": "damped", "shape": "sphere", "radius": 0.5, "position": [0, 5, 0],
                "velocity": [2, 0, 0], "angular_velocity": [0, 3, 0], "linear_damping": 0.5, "angular_damping": 1}]})");
  run(w, 30);  // 1 s
  const RigidState& s = rigid(w, 0).states()[0];
  CHECK(s.v.x() == doctest::Approx(0.5).epsilon(1e-9));
  CHECK(s.x.x() == doctest::Approx(0.25).epsilon(1e-2));
  CHECK(s.w.x() == doctest::Approx(0.5 / (10.0 * 2 / 12)).epsilon(1e-9));
  const RigidState& d = rigid(w, 1).states()[0];
  CHECK(d.v.x() == doctest::Approx(2 * std::exp(-0.5)).epsilon(1e-3));
  CHECK(d.w.y() == doctest::Approx(3 * std::exp(-1.0)).epsilon(1e-3));
}

TEST_CASE("a box on an incline stays when tan θ < μ and slides with g (sin θ − μ cos θ) otherwise") {
  for (double deg : {20.0, 35.0}) {
    const double th = deg * kPi / 180.0;
    const Vec3 n(-std::sin(th), std::cos(th), 0), down(-std::cos(th), -std::sin(th), 0);
    const Vec3 start = 0.05 * n;  // a 10 cm cube resting on the plane
    World w = worldFromText(R"({"format": "reel/1", "duration": 1.2, "fps": 30, "substeps": 10, "gravity": [0, -9.81, 0],
      "objects": [{"type": "plane", "name": "ramp", "normal": [)" + formatNumber(n.x(), 17) + ", " + formatNumber(n.y(), 17) +
                            R"(, 0], "surface": {"friction": 0.5}}],
      "bodies": [{"type": "rigid", "name": "block", "shape": "box", "size": [0.1, 0.1, 0.1], "sleep_time": 0,
                  "position": [)" + formatNumber(start.x(), 17) + ", " + formatNumber(start.y(), 17) +
                            R"(, 0], "rotation_deg": [0, 0, )" + formatNumber(deg, 17) + R"(], "surface": {"friction": 0.5}}]})");
    run(w, 6);  // settled on the plane
    const Vec3 x0 = rigid(w).states()[0].x;
    const double v0 = rigid(w).states()[0].v.dot(down);
    run(w, 30);  // one second more
    const double slid = (rigid(w).states()[0].x - x0).dot(down);
    CAPTURE(deg);
    if (deg < 26.0) {
      CHECK(std::abs(slid) < 1e-3);
    } else {
      const double a = 9.81 * (std::sin(th) - 0.5 * std::cos(th));
      CHECK(slid == doctest::Approx(v0 + 0.5 * a).epsilon(0.02));
    }
  }
}

TEST_CASE("a box sliding across another slows at μg and stays on its face (a pair's kept manifold moves with it)") {
  // A 10 cm cube thrown at 2 m/s along the top of a heavy slab (a body, not an object: their
  // manifold is kept while they barely move against each other and computed again when they have).
  // Thrown along the slab's face it rests on: friction μ·g = 4.905 m/s² stops it after 0.408 s
  // and 0.408 m.
  World thrown = worldFromText(slabScene(-1, R"("velocity": [2, 0, 0])"));
  const double top = 0.2 + 0.05;
  double lowest = 1.0;
  for (int f = 0; f < 6; ++f) {  // 0.2 s
    run(thrown, 1);
    lowest = std::min(lowest, rigid(thrown, 1).states()[0].x.y());
  }
  CHECK(rigid(thrown, 1).states()[0].v.x() == doctest::Approx(2.0 - 4.905 * 0.2).epsilon(0.02));
  run(thrown, 24);  // 1 s: stopped
  const RigidState& end = rigid(thrown, 1).states()[0];
  MESSAGE("slid " << end.x.x() + 1.0 << " m, lowest centre " << lowest << " m (face + half size " << top << " m)");
  CHECK(end.v.norm() < 0.01);
  CHECK(end.x.x() + 1.0 == doctest::Approx(0.408).epsilon(0.02));
  CHECK(lowest > top - 0.0065);  // into its slop and the soft push's give, no farther
  CHECK(std::abs(end.x.y() - top) < 0.006);
  // Thrown at 3 m/s half a metre from the slab's end, it slides off and falls to the floor.
  World off = worldFromText(slabScene(1, R"("velocity": [3, 0, 0])"));
  run(off, 30);
  CHECK(rigid(off, 1).states()[0].x.x() > 1.5);
  CHECK(rigid(off, 1).states()[0].x.y() < 0.1);
}

TEST_CASE("a box pushed slowly across another creeps at (F − μmg)/m: kept and fresh manifolds take turns") {
  // A 10 cm cube (1 kg) on a heavy slab, pushed by 5 N against friction μmg = 4.905 N: it creeps
  // at 0.095 m/s², 0.3–0.5 mm a step, so its manifold is kept for a few steps and computed again
  // in between. (The first 0.1 s, while the contact takes the block's weight, it gains more.)
  World w = worldFromText(slabScene(-1, R"("mass": 1, "force": [5, 0, 0])"));
  run(w, 6);  // 0.2 s
  const double v0 = rigid(w, 1).states()[0].v.x();
  double lowest = 1.0;
  for (int f = 0; f < 18; ++f) {  // 0.6 s more
    run(w, 1);
    lowest = std::min(lowest, rigid(w, 1).states()[0].x.y());
  }
  const double a = (rigid(w, 1).states()[0].v.x() - v0) / 0.6;
  MESSAGE("crept at " << a << " m/s², from " << v0 << " m/s; lowest centre " << lowest << " m");
  CHECK(v0 < 0.15);  // under half a millimetre a step (h = 1/300 s)
  CHECK(a == doctest::Approx(5.0 - 0.5 * 9.81).epsilon(0.02));
  CHECK(lowest > 0.25 - 0.0065);  // into its slop and the soft push's give, no farther
}

TEST_CASE("a ball dropped with restitution e bounces back to e² of its drop height") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 20,
    "objects": [{"type": "plane", "name": "floor", "surface": {"restitution": 0.8}}],
    "bodies": [{"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.1, "position": [0, 1.1, 0],
                "surface": {"restitution": 0.8}}]})");
  double peak = 0.0, prev_vy = 0.0;
  bool bounced = false;
  for (int f = 0; f < 60 && peak == 0.0; ++f) {
    run(w, 1);
    const RigidState& s = rigid(w).states()[0];
    if (s.v.y() > 0) bounced = true;
    if (bounced && prev_vy > 0 && s.v.y() <= 0) peak = s.x.y() - 0.1;
    prev_vy = s.v.y();
  }
  CHECK(peak == doctest::Approx(0.64).epsilon(0.03));
}

TEST_CASE("a stack of ten boxes stands still for ten seconds, asleep or awake") {
  for (const char* sleep : {"0.5", "0"}) {
    World w = worldFromText(R"({"format": "reel/1", "duration": 11, "fps": 30, "substeps": 4,
      "objects": [{"type": "plane", "name": "floor"}],
      "bodies": [{"type": "rigid", "name": "stack", "shape": "box", "size": [0.5, 0.5, 0.5], "position": [0, 0.25, 0],
                  "array": {"count": [1, 10, 1], "spacing": [0, 0.5, 0]}, "sleep_time": )" + std::string(sleep) + "}]}");
    run(w, 30);  // a second to settle into contact
    std::vector<Vec3> x0;
    for (const RigidState& s : rigid(w).states()) x0.push_back(s.x);
    run(w, 300);
    double drift = 0.0;
    for (std::size_t i = 0; i < x0.size(); ++i) drift = std::max(drift, (rigid(w).states()[i].x - x0[i]).norm());
    MESSAGE("sleep_time " << sleep << ": largest drift " << drift << " m, top box at " << rigid(w).states()[9].x.y() << " m, "
                          << rigid(w).solverStats().asleep << " boxes asleep");
    CHECK(drift < 1e-3);
    CHECK(rigid(w).states()[9].x.y() > 4.75 - 0.06);  // each contact settles into its 4.3 mm slop and a little more
    CHECK(rigid(w).solverStats().asleep == (std::string(sleep) == "0" ? 0 : 10));
  }
}

TEST_CASE("a ball and a box dropped into a concave mesh (a bowl) come to rest inside it") {
  const std::string scene = R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 8,
    "objects": [{"type": "mesh", "name": "bowl", "file": ")" + std::string(REEL_SOURCE_DIR) + R"(/scenes/meshes/bowl.obj"}],
    "bodies": [{"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.05, "position": [0.12, 0.5, 0.03],
                "surface": {"friction": 0.4}},
               {"type": "rigid", "name": "box", "shape": "box", "size": [0.08, 0.08, 0.08], "position": [-0.1, 0.7, 0],
                "rotation_deg": [30, 20, 10]}]})";
  World w = worldFromText(scene, std::string(REEL_SOURCE_DIR) + "/scenes/test.json");
  run(w, 90);
  const RigidState& ball = rigid(w, 0).states()[0];
  const RigidState& box = rigid(w, 1).states()[0];
  MESSAGE("ball at " << ball.x.transpose() << ", box at " << box.x.transpose());
  // The bowl's inner floor is at y = 0.04, its rim 0.4 m across: both end inside, at rest.
  CHECK(ball.x.y() == doctest::Approx(0.04 + 0.05).epsilon(0.1));
  CHECK(std::hypot(ball.x.x(), ball.x.z()) < 0.3);
  CHECK(box.x.y() > 0.04);
  CHECK(box.x.y() < 0.2);
  CHECK(std::hypot(box.x.x(), box.x.z()) < 0.3);
  CHECK(ball.v.norm() < 0.05);
  CHECK(box.v.norm() < 0.05);
}

TEST_CASE("a crate thrown into a free cloth: cloth and crate exchange momentum, the total is kept") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 20, "auto_substeps": true, "gravity": [0, 0, 0],
    "bodies": [{"type": "cloth", "name": "sheet", "size": [1, 1], "resolution": [12, 12], "position": [0, 0, 0], "mass": 0.5},
               {"type": "rigid", "name": "crate", "shape": "box", "size": [0.3, 0.3, 0.3], "density": 100,
                "position": [0, 0.4, 0], "velocity": [0, -2, 0]}]})");
  auto momentum = [&] {
    const SpringNetwork& cloth = w.first<ClothBody>()->network();
    Vec3 p = Vec3::Zero();
    for (std::size_t i = 0; i < cloth.state.v.size(); ++i) p += cloth.model.mass[i] * cloth.state.v[i];
    const RigidBody& r = rigid(w);
    return Vec3(p + r.models()[0].mass * r.states()[0].v);
  };
  const Vec3 p0 = momentum();
  run(w, 15);
  const RigidState& crate = rigid(w).states()[0];
  CHECK(crate.v.y() > -1.9);  // slowed by the cloth
  CHECK((momentum() - p0).norm() < 1e-9 * p0.norm());
}

TEST_CASE("a crate lands on a cloth held at its corners and is held up by it") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 7, "fps": 30, "substeps": 40, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "trampoline", "size": [1.2, 1.2], "resolution": [16, 16], "position": [0, 0.5, 0],
                "mass": 0.8, "node_damping": 0.05, "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"]},
               {"type": "rigid", "name": "crate", "shape": "box", "size": [0.25, 0.25, 0.25], "density": 200,
                "position": [0, 1.0, 0]}]})");
  for (int f = 0; f < 180; f += 30) {
    run(w, 30);
    MESSAGE("t = " << (f + 10) / 30.0 << " s: crate at y = " << rigid(w).states()[0].x.y() << ", v = " << rigid(w).states()[0].v.transpose());
  }
  const RigidState& crate = rigid(w).states()[0];
  const double bottom = crate.x.y() - 0.125;
  CHECK(bottom > 0.1);          // held up (the cloth sags under it)
  CHECK(bottom < 0.5);          // having landed on it
  CHECK(crate.v.norm() < 0.2);  // at rest
}

TEST_CASE("a school steers around a rigid ball that falls through it") {
  World w = worldFromText(R"({"format": "reel/1", "duration": 2, "fps": 30, "gravity": [0, -2, 0],
    "bodies": [{"type": "school", "name": "s", "count": 60, "model": "couzin", "start": {"center": [0, 0, 0], "radius": 1.5},
                "avoid": {"margin": 0.3}},
               {"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.5, "position": [0, 2, 0]}]})");
  double closest = 1e300;
  for (int f = 0; f < 60; ++f) {
    run(w, 1);
    const Vec3 c = rigid(w).states()[0].x;
    for (const Vec3& x : w.first<SchoolBody>()->school().x) closest = std::min(closest, (x - c).norm());
  }
  MESSAGE("closest agent " << closest << " m from the ball's centre (radius 0.5)");
  CHECK(closest > 0.45);
}

TEST_CASE("rigid bodies: the same state for 1 and 2 threads, and the dump lists pose and mass") {
  const std::string scene = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 4,
    "objects": [{"type": "plane", "name": "floor"}],
    "bodies": [{"type": "rigid", "name": "crates", "shape": "box", "size": [0.3, 0.2, 0.4], "position": [0, 0.5, 0],
                "rotation_deg": [10, 20, 30], "angular_velocity": [1, 2, 3], "array": {"count": [3, 3, 3], "spacing": [0.35, 0.3, 0.45]}},
               {"type": "rigid", "name": "ball", "shape": "capsule", "radius": 0.1, "length": 0.3, "position": [0.3, 2, 0.3]}]})";
  CHECK(runHash(scene, 1, 20) == runHash(scene, 2, 20));
  // A pile large enough that its colours of contacts are shared between the threads (64 contacts
  // or more each), wide contacts with lanes of boxes and of the floor, and kept manifolds.
  const std::string pile = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 4,
    "objects": [{"type": "plane", "name": "floor"}],
    "bodies": [{"type": "rigid", "name": "pile", "shape": "box", "size": [0.3, 0.3, 0.3], "position": [0, 0.2, 0],
                "rotation_deg": [0, 10, 0], "sleep_time": 0, "array": {"count": [8, 3, 8], "spacing": [0.31, 0.32, 0.31]}}]})";
  CHECK(runHash(pile, 1, 15) == runHash(pile, 2, 15));
  {
    ParallelForTest parallel(2);
    World w = worldFromText(pile);
    run(w, 8);
    CHECK(rigid(w).solverStats().shared_colours > 0);
    // Resumed in the middle: the broad phase's kept candidates are made afresh, the same pairs found.
    const WorldSnapshot snap = w.snapshot();
    run(w, 7);
    World again = worldFromText(pile);
    REQUIRE(again.restore(snap).ok());
    run(again, 7);
    CHECK(again.stateHash() == w.stateHash());
  }
  World w = worldFromText(scene);
  FrameView fv;
  w.view(fv);
  REQUIRE(fv.bodies.size() == 2);
  const BodyView& b = fv.bodies[0];
  CHECK(b.type == "rigid");
  CHECK(b.positions.size() == 27);
  REQUIRE(b.fields.size() == 3);
  CHECK(b.fields[0].name == "orientation");
  const Eigen::Quaterniond q(b.fields[0].values[0], b.fields[0].values[1], b.fields[0].values[2], b.fields[0].values[3]);
  CHECK((q.toRotationMatrix() - rotationFromEulerDeg(Vec3(10, 20, 30))).norm() < 1e-12);
  CHECK(b.masses[0] == doctest::Approx(1000 * 0.3 * 0.2 * 0.4));
  CHECK(b.fields[2].values[0] == doctest::Approx(b.masses[0] * (0.2 * 0.2 + 0.4 * 0.4) / 12));  // I_xx, body frame
}

TEST_CASE("rigid bodies are one system of the World: entries apart in the scene meet, and its cache resumes bit for bit") {
  // A ball entry after a cloth lands on a crate entry before it: the system steps both together.
  const std::string scene = R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 4, "integrator": "implicit_euler",
    "objects": [{"type": "plane", "name": "floor"}],
    "bodies": [{"type": "rigid", "name": "crate", "shape": "box", "size": [0.4, 0.4, 0.4], "position": [0, 0.2, 0]},
               {"type": "cloth", "name": "flag", "size": [0.3, 0.3], "resolution": [4, 4], "position": [3, 0.01, 0]},
               {"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.1, "position": [0, 0.6, 0]}]})";
  World w = worldFromText(scene);
  run(w, 12);  // 0.4 s: landed, not yet asleep
  CHECK(rigid(w, 1).states()[0].x.y() == doctest::Approx(0.5).epsilon(0.02));  // resting on the crate
  CHECK(rigid(w, 0).solverStats().contacts > 0);
  CHECK(&rigid(w, 0).solverStats() == &rigid(w, 1).solverStats());  // one joint step
  // The warm-start cache is the system's: resuming from a snapshot gives the same bits.
  const WorldSnapshot snap = w.snapshot();
  REQUIRE(snap.systems.size() == 1);
  std::vector<CachedImpulse> impulses;
  std::vector<CachedManifold> manifolds;
  {
    StateReader r(snap.systems[0]);
    r.get(impulses);
    r.get(manifolds);
    CHECK(r.done());
  }
  CHECK(!impulses.empty());  // the warm start
  CHECK(manifolds.size() == 1);  // the ball on the crate keeps its manifold
  run(w, 10);
  World again = worldFromText(scene);
  REQUIRE(again.restore(snap).ok());
  run(again, 10);
  CHECK(again.stateHash() == w.stateHash());
  // A snapshot whose system state does not parse is refused, and the world stays as it was.
  WorldSnapshot bad = snap;
  bad.systems[0].bytes.push_back(std::byte{1});
  const std::uint64_t before = again.stateHash();
  CHECK_FALSE(again.restore(bad).ok());
  CHECK(again.stateHash() == before);
  bad.systems.clear();
  CHECK_FALSE(again.restore(bad).ok());
  // Kept manifolds that are not whole are refused: no points, a normal or a turn not of unit
  // length, a coordinate not finite, a negative margin.
  for (int k = 0; k < 5; ++k) {
    std::vector<CachedManifold> m = manifolds;
    if (k == 0) m[0].count = 0;
    if (k == 1) m[0].normal = {0, 0, 0};
    if (k == 2) m[0].q = {2, 0, 0, 0};
    if (k == 3) m[0].on_b[0][1] = std::nan("");
    if (k == 4) m[0].margin = -1;
    WorldSnapshot broken = snap;
    broken.systems[0].bytes.clear();
    StateWriter writer(broken.systems[0]);
    writer.put(impulses);
    writer.put(m);
    CAPTURE(k);
    CHECK_FALSE(again.restore(broken).ok());
    CHECK(again.stateHash() == before);
  }
}

TEST_CASE("rigid bodies: bad input is refused with its JSON path") {
  auto scene = [](const std::string& keys) {
    return R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "rigid", "name": "b", "shape": "box", )" + keys + "}]}";
  };
  checkHas(badInputError(scene(R"("density": 0)")), "/bodies/0/density");
  checkHas(badInputError(scene(R"("mass": -1)")), "/bodies/0/mass");
  checkHas(badInputError(scene(R"("orientation": [0, 0, 0, 0])")), "/bodies/0/orientation");
  checkHas(badInputError(scene(R"("surface": {"friction": -0.1})")), "/bodies/0/surface/friction");
  checkHas(badInputError(scene(R"("surface": {"restitution": 1.5})")), "/bodies/0/surface/restitution");
  checkHas(badInputError(scene(R"("mass": 1, "density": 2)")), "/bodies/0/mass");
  checkHas(badInputError(scene(R"("fixed": true, "velocity": [1, 0, 0])")), "/bodies/0/velocity");
  checkHas(badInputError(scene(R"("fixed": true, "torque": [1, 0, 0])")), "/bodies/0/torque");
  checkHas(badInputError(scene(R"("linear_damping": -1)")), "/bodies/0/linear_damping");
  checkHas(badInputError(scene(R"("size": [1, 0, 1])")), "/bodies/0/size");
  // Meshes that bound no solid.
  const fs::path dir = fs::temp_directory_path() / "reel_rigid_test";
  fs::create_directories(dir);
  const std::string cube_v = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
  const std::string faces[] = {"f 1 4 3\nf 1 3 2\n", "f 5 6 7\nf 5 7 8\n", "f 1 2 6\nf 1 6 5\n",
                               "f 4 8 7\nf 4 7 3\n", "f 1 5 8\nf 1 8 4\n", "f 2 3 7\nf 2 7 6\n"};
  std::string closed = cube_v, open = cube_v, inside_out = cube_v;
  for (int k = 0; k < 6; ++k) {
    closed += faces[k];
    if (k > 0) open += faces[k];
  }
  for (int k = 0; k < 6; ++k) {
    std::string f = faces[k];
    for (std::size_t p = 0; (p = f.find("f ", p)) != std::string::npos; p += 2) {
      // Swap the last two indices of each face line.
      const std::size_t e = f.find('\n', p);
      std::string line = f.substr(p + 2, e - p - 2);
      const std::size_t s1 = line.find(' '), s2 = line.rfind(' ');
      line = line.substr(0, s1) + " " + line.substr(s2 + 1) + " " + line.substr(s1 + 1, s2 - s1 - 1);
      f.replace(p + 2, e - p - 2, line);
    }
    inside_out += f;
  }
  std::string shifted;  // the cube moved by (0.5, 0.25, 0.4): it crosses the first
  for (int k = 0; k < 8; ++k)
    shifted += "v " + formatNumber((k == 1 || k == 2 || k == 5 || k == 6) + 0.5, 3) + " " + formatNumber((k == 2 || k == 3 || k == 6 || k == 7) + 0.25, 3) +
               " " + formatNumber((k >= 4) + 0.4, 3) + "\n";
  const std::string both = closed + shifted +
                           [&] {
                             std::string s;
                             for (const std::string& f : faces) {
                               std::string g;
                               for (std::size_t i = 0; i < f.size(); ++i) {
                                 if (std::isdigit(static_cast<unsigned char>(f[i])) && (i == 0 || !std::isdigit(static_cast<unsigned char>(f[i - 1])))) {
                                   std::size_t j = i;
                                   while (j < f.size() && std::isdigit(static_cast<unsigned char>(f[j]))) ++j;
                                   g += std::to_string(std::stoi(f.substr(i, j - i)) + 8);
                                   i = j - 1;
                                 } else {
                                   g += f[i];
                                 }
                               }
                               s += g;
                             }
                             return s;
                           }();
  const std::pair<std::string, std::string> meshes[] = {{"open.obj", open}, {"inside_out.obj", inside_out}, {"both.obj", both}};
  const char* reasons[] = {"not closed", "inside out", "intersects itself"};
  for (int k = 0; k < 3; ++k) {
    std::ofstream(dir / meshes[k].first) << meshes[k].second;
    const std::string file = (dir / "s.json").string();
    std::ofstream(file) << R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "rigid", "name": "b", "shape": "mesh", "file": ")" +
                               meshes[k].first + R"("}]})";
    auto r = app::loadScene(file);
    REQUIRE(!r.ok());
    CHECK(r.error().kind == ErrorKind::BadInput);
    checkHas(r.error().messages.front(), "/bodies/0/file");
    checkHas(r.error().messages.front(), reasons[k]);
  }
  std::ofstream(dir / "closed.obj") << closed;
  std::ofstream(dir / "s.json") << R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "rigid", "name": "b", "shape": "mesh", "file": "closed.obj"}]})";
  auto ok = app::loadScene((dir / "s.json").string());
  REQUIRE(ok.ok());
  CHECK(ok.value().bodies[0].as<RigidDesc>().items[0].mass.mass == doctest::Approx(1000.0));
}
