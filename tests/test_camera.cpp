// Cameras that follow and frame a body (scene keys camera.follow and camera.frame): the damped
// trail against its closed form, the camera a falling body gives, the rig through snapshots and
// the caches' byte encoding, and bad input.
#include <doctest/doctest.h>

#include <cmath>

#include "app/sim_cache.h"
#include "core/camera.h"
#include "core/scene_view.h"
#include "helpers.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// Two free nodes 0.2 m apart, falling from rest at y = 2 (no springs, no air): their centre falls
// as ½gt², their extent is the 0.25 m floor.
std::string fallingScene(const std::string& camera_rig) {
  return std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 10, "gravity": [0, -9.8, 0],
    "render": {"width": 320, "height": 180},
    "camera": {"position": [0, 2, 5], "target": [0, 2, 0], "fov_deg": 40, )") + camera_rig + R"(},
    "bodies": [{"type": "mass_spring", "name": "pair",
      "nodes": [{"position": [-0.1, 2, 0], "mass": 1}, {"position": [0.1, 2, 0], "mass": 1}], "springs": []}]})";
}

DrawCamera cameraOf(const World& w, const SceneDesc& s) {
  DrawList list;
  setSceneView(s, w.time(), list, w.cameraRig());
  return list.camera;
}

// The exact fall of the pair's centre after t seconds.
double fallen(double t) { return 0.5 * 9.8 * t * t; }

}  // namespace

TEST_CASE("camera keys: two keys 0.001 s apart are a cut, and the shot before it does not swing toward the next") {
  CameraDesc c;
  auto key = [](double t, const Vec3& p) {
    CameraKey k;
    k.time = t, k.position = p, k.target = p + Vec3(0, 0, -1);
    return k;
  };
  // A dolly along x at 1 m/s, then a cut to a camera 100 m away.
  c.keys = {key(0, Vec3(0, 1, 5)), key(1, Vec3(1, 1, 5)), key(2, Vec3(2, 1, 5)), key(2.001, Vec3(100, 1, 50)), key(3, Vec3(100, 1, 51))};
  for (double t : {1.25, 1.5, 1.75}) {
    CAPTURE(t);
    const DrawCamera d = cameraAt(c, t);
    CHECK(std::abs(d.position.x() - t) < 0.1);  // on the dolly, easing into its last key (through the cut: 6 m off)
    CHECK(std::abs(d.position.z() - 5.0) < 1e-12);  // not pulled toward the next shot's z = 50
  }
  // After the cut, the next shot's path is its own.
  CHECK(std::abs(cameraAt(c, 2.5).position.x() - 100.0) < 1e-12);
}

TEST_CASE("camera rig: a critically damped trail, exact at any step, trailing a steady body by its lag") {
  const double lag = 0.5, w = 2.0 / lag;
  // From 1 m off a still body: e(t) = (1 + ωt)·exp(−ωt), whatever the step.
  for (int steps : {1, 3, 30, 240}) {
    CameraRig r = startRig(Vec3(1, 0, 0), 1.0);
    double worst = 0.0, lowest = 1.0;
    for (int k = 1; k <= steps; ++k) {
      advanceRig(r, Vec3::Zero(), 0.5, 1.0 / steps, lag);
      const double t = static_cast<double>(k) / steps, exact = (1 + w * t) * std::exp(-w * t);
      worst = std::max(worst, std::abs(r.centre.x() - exact));
      lowest = std::min(lowest, r.centre.x());
      CHECK(r.radius - 0.5 == doctest::Approx(0.5 * exact).epsilon(1e-12));
    }
    CAPTURE(steps);
    CHECK(worst < 1e-12);
    CHECK(lowest > 0.0);  // critically damped: it never swings past the body
  }
  // A body at 3 m/s, followed for 20 lags at 30 frames a second: the camera runs 3 × 0.5 m behind.
  CameraRig r = startRig(Vec3::Zero(), 1.0);
  const double h = 1.0 / 30;
  int k = 0;
  for (; k < 300; ++k) advanceRig(r, Vec3(3.0 * (k + 1) * h, 0, 0), 1.0, h, lag);
  CHECK(3.0 * k * h - r.centre.x() == doctest::Approx(3.0 * lag).epsilon(0.02));
  CHECK(r.velocity.x() == doctest::Approx(3.0).epsilon(0.01));  // the body moves in jumps of a frame
  // A lag so short that exp(−ωh) underflows: rigid, not NaN.
  CameraRig tiny = startRig(Vec3::Zero(), 1.0);
  advanceRig(tiny, Vec3(1, 2, 3), 0.5, h, 1e-300);
  CHECK((tiny.centre - Vec3(1, 2, 3)).norm() == 0.0);
  // Lag 0: on the body at every frame.
  advanceRig(r, Vec3(7, 1, 2), 2.0, h, 0.0);
  CHECK((r.centre - Vec3(7, 1, 2)).norm() == 0.0);
  CHECK(r.radius == 2.0);
}

TEST_CASE("camera follow and frame: the camera a falling body gives") {
  const double t = 0.5;
  SUBCASE("follow, track, lag 0: the authored camera carried by the body's fall") {
    const SceneDesc s = sceneFromText(fallingScene(R"("follow": {"body": "pair", "lag": 0})"));
    World w = worldFromText(fallingScene(R"("follow": {"body": "pair", "lag": 0})"));
    run(w, 15);
    const DrawCamera c = cameraOf(w, s);
    // Symplectic Euler's fall differs from ½gt² by ½g·h·t at step h = 1/300 s.
    const double drop = fallen(t), tol = 0.5 * 9.8 * t / 300 + 1e-9;
    CHECK(c.position.y() == doctest::Approx(2.0 - drop).epsilon(tol / drop));
    CHECK(c.target.y() == doctest::Approx(2.0 - drop).epsilon(tol / drop));
    CHECK(c.position.z() == 5.0);
    CHECK(c.target.x() == doctest::Approx(0.0).epsilon(1e-12));
  }
  SUBCASE("follow, pan: the camera stays and turns, its aim trailing the body") {
    const std::string text = fallingScene(R"("follow": {"body": "pair", "mode": "pan", "lag": 0.2})");
    const SceneDesc s = sceneFromText(text);
    World w = worldFromText(text);
    run(w, 15);
    const DrawCamera c = cameraOf(w, s);
    CHECK(c.position == Vec3(0, 2, 5));
    const double aim = 2.0 - c.target.y();
    CHECK(aim > 0.0);
    CHECK(aim < fallen(t));                                       // trails the body
    CHECK(aim == doctest::Approx(fallen(t - 0.2)).epsilon(0.15));  // by about its lag
  }
  SUBCASE("frame: aims at the centre from the distance that fits margin × radius") {
    const std::string text = fallingScene(R"("frame": {"body": "pair", "lag": 0, "margin": 2})");
    const SceneDesc s = sceneFromText(text);
    World w = worldFromText(text);
    run(w, 15);
    const DrawCamera c = cameraOf(w, s);
    CHECK(c.target.y() == doctest::Approx(2.0 - fallen(t)).epsilon(0.01));
    // 320x180 at 40° vertical: the vertical field is the narrower; the pair's radius is the 0.25 m floor.
    const double distance = 2.0 * 0.25 / std::sin(20.0 * kPi / 180.0);
    CHECK((c.position - c.target).norm() == doctest::Approx(distance).epsilon(1e-9));
    CHECK((c.target - c.position).normalized().isApprox(Vec3(0, 0, -1), 1e-12));
  }
}

TEST_CASE("camera rig: a snapshot and the caches' encoding carry it, so a resumed render sees the same camera") {
  const std::string text = fallingScene(R"("frame": {"body": "pair", "lag": 0.7})");
  const SceneDesc s = sceneFromText(text);
  World a = worldFromText(text);
  run(a, 10);
  WorldSnapshot snap;
  const std::vector<std::byte> bytes = app::encodeSnapshot(a.snapshot());
  REQUIRE(app::decodeSnapshot(bytes.data(), bytes.size(), snap));
  run(a, 10);
  World b = worldFromText(text);
  REQUIRE(b.restore(snap).ok());
  REQUIRE(b.cameraRig() != nullptr);
  run(b, 10);
  const DrawCamera ca = cameraOf(a, s), cb = cameraOf(b, s);
  CHECK(ca.position == cb.position);
  CHECK(ca.target == cb.target);
  // A world that starts fresh at frame 10's state without the rig would aim elsewhere: the rig is state.
  World c = worldFromText(text);
  snap.camera = CameraRig{};
  REQUIRE(c.restore(snap).ok());
  run(c, 10);
  CHECK((cameraOf(c, s).position - ca.position).norm() > 1e-3);
}

TEST_CASE("camera follow and frame: bad input names the path") {
  checkHas(badInputError(fallingScene(R"("follow": "nobody")")), "/camera/follow: no body named 'nobody'");
  checkHas(badInputError(fallingScene(R"("frame": {"body": "ghost"})")), "/camera/frame/body: no body named 'ghost'");
  checkHas(badInputError(fallingScene(R"("follow": "pairr")")), "did you mean \"pair\"?");
  checkHas(badInputError(fallingScene(R"("follow": "")")), "/camera/follow: must name a body");
  checkHas(badInputError(fallingScene(R"("keys": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 1]}])")),
           "/camera/keys/0/target: must differ from the camera position");
  checkHas(badInputError(fallingScene(R"("follow": "pair", "frame": "pair")")), "give follow or frame, not both");
  checkHas(badInputError(fallingScene(R"("follow": {"body": "pair", "mode": "zoom"})")), "/camera/follow/mode");
  checkHas(badInputError(fallingScene(R"("follow": {"body": "pair", "lag": -1})")), "/camera/follow/lag");
  checkHas(badInputError(fallingScene(R"("frame": {"body": "pair", "margin": 0})")), "/camera/frame/margin");
  checkHas(badInputError(fallingScene(R"("follow": 3)")), "/camera/follow: expected a body's name");
  checkHas(badInputError(fallingScene(R"("frame": {"lag": 1})")), "/camera/frame/body");
}
