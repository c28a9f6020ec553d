// The face's muscles beyond their pull: a linear muscle's belly thickening as it contracts (its
// bulge) pushes the tissue over it off the skull, on a user's mesh and in reel's own smile.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "face_scene.h"
#include "helpers.h"
#include "sim/face/face_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// How far the skin over muscle m's nodes has moved off its bone point since `x0`, weighted as its
// pull (the skin's height over the bone node, so a jaw's rigid turn does not count; the head is
// unturned, and the jaw turns a few degrees at most, so the rest outward direction serves).
double rise(const FaceBody& f, const FaceMuscle& m, const std::vector<Vec3>& x0) {
  const std::size_t n = f.surface().size();
  const auto& x = f.network().state.x;
  double r = 0.0;
  for (std::size_t j = 0; j < m.nodes.size(); ++j) {
    const auto k = static_cast<std::size_t>(m.nodes[j]);
    r += m.weight[j] * ((x[k] - x[2 * n + k]) - (x0[k] - x0[2 * n + k])).dot(f.tissue().out[k]);
  }
  return r;
}

}  // namespace

TEST_CASE("face: a muscle's bulge pushes the tissue over it off the skull, and it still pulls") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "reel_test_face_bulge";
  fs::create_directories(dir);
  writeBallObj((dir / "ball.obj").string());
  const Vec3 att = 0.092 * Vec3(0, 0.5, 1).normalized(), ins = 0.096 * Vec3(0, -0.3, 1).normalized();
  auto num = [](const Vec3& p) { return "[" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) + "]"; };
  auto scene = [&](const std::string& bulge) {
    return R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 2, "integrator": "implicit_euler", "gravity": [0, 0, 0],
      "implicit": {"cg_tolerance": 1e-6},
      "bodies": [{"type": "face", "name": "f", "mesh": "ball.obj", "inset": 0.008,
                  "muscles": [{"name": "lift", "attachment": )" + num(att) + R"(, "insertion": )" + num(ins) + R"(, "strength": 5)" + bulge + R"(}],
                  "activations": [{"time": 0, "muscles": {"lift": 0}}, {"time": 0.3, "muscles": {"lift": 1}}]}]})";
  };
  double rises[2] = {0, 0}, pulls[2] = {0, 0};
  for (int b = 0; b < 2; ++b) {
    World w = worldFromText(scene(b ? R"(, "bulge": 1)" : ""), (dir / "scene.json").string());
    const FaceBody& f = face(w);
    const FaceMuscle& m = f.muscles().at(0);
    CHECK(m.desc.bulge == (b ? 1.0 : 0.0));
    const std::vector<Vec3> x0 = f.network().state.x;
    auto centre = [&] {
      Vec3 c = Vec3::Zero();
      for (std::size_t j = 0; j < m.nodes.size(); ++j) c += m.weight[j] * f.network().state.x[static_cast<std::size_t>(m.nodes[j])];
      return c;
    };
    const double d0 = (centre() - att).norm();
    run(w, 20);
    rises[b] = rise(f, m, x0), pulls[b] = d0 - (centre() - att).norm();
  }
  MESSAGE("the skin over the muscle off the skull: " << rises[0] * 1e3 << " mm without its bulge, " << rises[1] * 1e3 << " mm with");
  MESSAGE("toward the attachment: " << pulls[0] * 1e3 << " mm, " << pulls[1] * 1e3 << " mm");
  CHECK(rises[1] > rises[0] + 0.0001);
  CHECK(rises[1] < 0.003);  // a thickening belly, not a balloon
  CHECK(pulls[1] > 0.5 * pulls[0]);
  CHECK(pulls[0] > 0.001);
  // 0 and 2 are taken, on a sphincter too (its ring thickening pushes out what it squeezes, as
  // puckered lips); a bulge below 0 or past 2 is refused, naming it.
  CHECK(app::parseScene(faceSceneText(R"(, "muscles": [{"name": "m", "type": "sphincter", "center": [0, 0, 0.09], "bulge": 1}])", 1.0, "[48, 32]", "1e-5"),
                        "s.json")
            .ok());
  for (const char* fine : {"0", "2"})
    CHECK(app::parseScene(faceSceneText(std::string(R"(, "muscles": [{"name": "m", "attachment": [0, 0, 0.05], "insertion": [0, 0, 0.09], "bulge": )") + fine + "}]",
                                        1.0, "[48, 32]", "1e-5"),
                          "s.json")
              .ok());
  checkHas(badInputErrors(faceSceneText(R"(, "muscles": [{"name": "m", "type": "sphincter", "center": [0, 0, 0.09], "bulge": 2.5}])", 1.0, "[48, 32]", "1e-5")),
           "/bodies/0/muscles/0/bulge");
  for (const char* bad : {"-0.5", "3"})
    checkHas(badInputErrors(faceSceneText(std::string(R"(, "muscles": [{"name": "m", "attachment": [0, 0, 0.05], "insertion": [0, 0, 0.09], "bulge": )") + bad + "}]",
                                          1.0, "[48, 32]", "1e-5")),
             "/bodies/0/muscles/0/bulge");
}

TEST_CASE("face: a smile bunches the cheek over the zygomatic major, off the skull") {
  World w = worldFromText(faceSceneText(R"(, "activations": [{"time": 0, "preset": "happiness", "amount": 0}, {"time": 0.4, "preset": "happiness"}])",
                                        1.0, "[48, 32]", "1e-5"));
  const FaceBody& f = face(w);
  const FaceMuscle* zyg = nullptr;
  for (const FaceMuscle& m : f.muscles())
    if (m.desc.name == "zygomatic_major_left") zyg = &m;
  REQUIRE(zyg != nullptr);
  CHECK(zyg->desc.bulge > 0.0);
  const std::vector<Vec3> x0 = f.network().state.x;
  run(w, 24);
  const double r = rise(f, *zyg, x0);
  MESSAGE("the cheek over the zygomatic major off the skull: " << r * 1e3 << " mm");
  CHECK(r > 0.0005);  // (without the bulge it sank 0.57 mm: the skin slid over the bone, stretching)
}
