// What makes films fast to make (issue: every demo film in minutes): the simulation cache of
// stills, `reel bench film`, progress in logs, the defaults films run at, tears that run.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "helpers.h"
#include "sim/cloth/cloth.h"
#include "sim/cloth/cloth_body.h"
#include "sim/world.h"

using namespace reel;
using reel::test::Run;
using reel::test::runReel;
namespace fs = std::filesystem;

namespace {

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

const std::string kDrape = std::string(REEL_SOURCE_DIR) + "/tests/scenes/drape.json";

}  // namespace

TEST_CASE("a still reuses the simulation a still or render of the same scene left: the same bytes") {
  const fs::path d = test::freshDir("films_cache");
  const std::string cd = "cd " + d.string() + " && ";
  // Frame 8 without the cache, then with it (written), then read back from it.
  REQUIRE(runReel("still " + kDrape + " --frame 8 --size 64x48 --no-cache -o plain.png", cd).code == 0);
  CHECK_FALSE(fs::exists(d / "render_out" / ".cache"));
  REQUIRE(runReel("still " + kDrape + " --frame 8 --size 64x48 -o first.png", cd).code == 0);
  int files = 0;
  fs::path some;
  for (const auto& scene : fs::directory_iterator(d / "render_out" / ".cache"))
    for (const auto& f : fs::directory_iterator(scene.path())) {
      ++files;
      some = f.path();
    }
  CHECK(files == 8);  // frames 1..8: this small scene's checkpoints all fit
  REQUIRE(runReel("still " + kDrape + " --frame 8 --size 64x48 -o second.png", cd).code == 0);
  CHECK(test::fileBytes(d / "plain.png") == test::fileBytes(d / "first.png"));
  CHECK(test::fileBytes(d / "plain.png") == test::fileBytes(d / "second.png"));
  // A later frame continues from the cache, a render of a range starts from it: the same bytes.
  REQUIRE(runReel("still " + kDrape + " --frame 9 --size 64x48 -o nine.png", cd).code == 0);
  REQUIRE(runReel("still " + kDrape + " --frame 9 --size 64x48 --no-cache -o nine_plain.png", cd).code == 0);
  CHECK(test::fileBytes(d / "nine.png") == test::fileBytes(d / "nine_plain.png"));
  REQUIRE(runReel("render " + kDrape + " --frames 8-9 --size 64x48 -o r_#.png", cd).code == 0);
  CHECK(test::fileBytes(d / "r_9.png") == test::fileBytes(d / "second.png"));
  CHECK(test::fileBytes(d / "r_10.png") == test::fileBytes(d / "nine.png"));
  // Damaged checkpoints (every one) are ignored, never trusted.
  for (const auto& scene : fs::directory_iterator(d / "render_out" / ".cache"))
    for (const auto& f : fs::directory_iterator(scene.path())) {
      std::string b = test::fileBytes(f.path());
      b[b.size() / 2] = static_cast<char>(b[b.size() / 2] ^ 0x5a);
      std::ofstream(f.path(), std::ios::binary) << b;
    }
  REQUIRE(runReel("still " + kDrape + " --frame 8 --size 64x48 -o damaged.png", cd).code == 0);
  CHECK(test::fileBytes(d / "plain.png") == test::fileBytes(d / "damaged.png"));
  // Another seed is another simulation: not read from this one's cache.
  REQUIRE(runReel("still " + kDrape + " --frame 8 --size 64x48 --seed 5 -o seeded.png", cd).code == 0);
  REQUIRE(runReel("still " + kDrape + " --frame 8 --size 64x48 --seed 5 --no-cache -o seeded_plain.png", cd).code == 0);
  CHECK(test::fileBytes(d / "seeded.png") == test::fileBytes(d / "seeded_plain.png"));
}

TEST_CASE("bench film: one JSON line per scene, seconds per frame by stage, adding up") {
  const Run r = runReel("bench film " + kDrape + " --frames 0-4 --threads 1");
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["name"] == "film");
  CHECK(j["frames"] == 5);
  const double sim = j["simulate_s_per_frame"].get<double>();
  CHECK(sim > 0);
  double stages = 0;
  for (const auto& [k, v] : j["simulate_stages_s_per_frame"].items()) stages += v.get<double>();
  CHECK(j["simulate_stages_s_per_frame"].contains("integration"));
  CHECK(j["simulate_stages_s_per_frame"].contains("contacts"));
  CHECK(stages == doctest::Approx(sim).epsilon(0.05));
  CHECK(j["draw_s_per_frame"].get<double>() > 0);
  CHECK(j["end_to_end_s"].get<double>() >= j["end_to_end_s_per_frame"].get<double>() * 5 * 0.999);
  CHECK(runReel("bench springs --frames 0-4").code == 2);  // --frames is the film's
}

TEST_CASE("progress: plain lines when stderr is not a terminal, nothing with --quiet") {
  const fs::path d = test::freshDir("films_progress");
  const std::string out = (d / "f_#.png").string();
  Run r = runReel("render " + kDrape + " --size 32x24 --no-cache -o " + out);
  REQUIRE(r.code == 0);
  CHECK(has(r.out, "reel: frame 10/10 (100%)"));
  CHECK(has(r.out, "s left\n"));
  CHECK_FALSE(has(r.out, "\r"));
  r = runReel("render " + kDrape + " --size 32x24 --no-cache --quiet -o " + out);
  REQUIRE(r.code == 0);
  CHECK(r.out.empty());
  r = runReel("simulate " + kDrape + " -q");
  CHECK_FALSE(has(r.out, "reel: frame"));
}

TEST_CASE("film defaults: implicit Euler at 5 steps a frame, each kind's CG tolerance unless the scene sets one") {
  const std::string base = R"({"format": "reel/1", "duration": 1, "integrator": "implicit_euler")";
  CHECK(test::sceneFromText(base + "}").substeps == kImplicitSubsteps);
  CHECK(test::sceneFromText(base + R"(, "substeps": 12})").substeps == 12);
  CHECK(test::sceneFromText(R"({"format": "reel/1", "duration": 1})").substeps == 10);
  const SceneDesc plain = test::sceneFromText(base + "}");
  CHECK(plain.implicit.cg_tolerance == kFilmTolerance);
  CHECK_FALSE(plain.implicit.tolerance_given);
  const SceneDesc set = test::sceneFromText(base + R"(, "implicit": {"cg_tolerance": 1e-6}})");
  CHECK(set.implicit.tolerance_given);
  CHECK(set.implicit.cg_tolerance == 1e-6);
  // A sheet solves to 1e-2 by default and to the scene's tolerance when given: the last step's
  // residual shows which.
  const std::string sheet = R"(, "bodies": [{"type": "cloth", "name": "s", "resolution": [12, 12], "velocity": [0, 0, 1],
      "pinned": ["corner_00"]}]})";
  World a = test::worldFromText(base + sheet), b = test::worldFromText(base + R"(, "implicit": {"cg_tolerance": 1e-9})" + sheet);
  test::run(a, 3);
  test::run(b, 3);
  CHECK(a.lastStepStats().cg_relative_residual <= 1e-2);
  CHECK(a.lastStepStats().cg_relative_residual > 1e-9);
  CHECK(b.lastStepStats().cg_relative_residual <= 1e-9);
  CHECK(a.lastStepStats().cg_iterations < b.lastStepStats().cg_iterations);
}

TEST_CASE("a tear under a slow pull runs from its tip over several frames, ending in two pieces") {
  // The ripping_cloth sheet's setting on implicit Euler's long steps (5 a frame): every thread at
  // a clamp is past its threshold within a few steps of each other.
  const std::string scene = R"({"format": "reel/1", "duration": 3, "fps": 30, "integrator": "implicit_euler",
    "seed": 7, "gravity": [0, 0, 0],
    "bodies": [{"type": "cloth", "name": "s", "rotation_deg": [90, 0, 0], "size": [1.2, 1.2], "resolution": [24, 24],
                "mass": 0.25, "stiffness": 4000, "damping": 0.3, "shear_stiffness": 1000, "node_damping": 0.001,
                "tear": {"strain": 0.12, "variation": 0.15},
                "grips": [{"nodes": ["edge_x0"], "velocity": [-0.12, 0, 0]},
                          {"nodes": ["edge_x1"], "velocity": [0.12, 0, 0]}]}]})";
  World w = test::worldFromText(scene);
  const ClothBody& b = *w.first<ClothBody>();
  int most_in_a_step = 0, steps_tearing = 0;  // springs broken in a frame, frames with any
  long long before = 0;
  for (int f = 0; f < 60; ++f) {
    REQUIRE(w.advanceFrame());
    const long long now = b.cloth().springs_broken;
    if (now > before) ++steps_tearing;
    most_in_a_step = std::max(most_in_a_step, static_cast<int>(now - before));
    before = now;
  }
  CHECK(clothPieces(b.network().model.nodes(), b.network().model.springs) == 2);
  // Breaking every thread past its threshold at once opened holes all over the evenly stretched
  // sheet: 419 springs in one frame. Now 49 (a thread takes up to 2 shear and 2 bend springs).
  CHECK(most_in_a_step <= 100);
  CHECK(steps_tearing >= 3);
  CHECK(test::runHash(scene, 1, 30) == test::runHash(scene, 2, 30));
}

TEST_CASE("the simulation cache knows the meshes a scene loads: an edited mesh is a new simulation") {
  const fs::path d = test::freshDir("films_cache_mesh");
  const std::string cd = "cd " + d.string() + " && ";
  auto box = [&](double top) {
    std::ofstream(d / "block.obj") << "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv -1 " << top << " -1\nv 1 " << top
                                   << " -1\nv 1 " << top << " 1\nv -1 " << top << " 1\n"
                                   << "f 1 2 3\nf 1 3 4\nf 5 7 6\nf 5 8 7\nf 1 5 6\nf 1 6 2\nf 2 6 7\nf 2 7 3\n"
                                   << "f 3 7 8\nf 3 8 4\nf 4 8 5\nf 4 5 1\n";
  };
  std::ofstream(d / "drop.json") << R"({"format": "reel/1", "duration": 1, "fps": 10, "integrator": "implicit_euler",
    "render": {"width": 48, "height": 32}, "camera": {"position": [0, 1, 3], "target": [0, 0.3, 0]},
    "objects": [{"type": "mesh", "name": "block", "file": "block.obj"}],
    "bodies": [{"type": "cloth", "name": "s", "position": [0, 0.8, 0], "size": [1, 1], "resolution": [8, 8]}]})";
  box(0.2);
  REQUIRE(runReel("still drop.json --frame 8 -o low.png", cd).code == 0);
  box(0.6);  // a taller block: the sheet lands on it earlier and higher
  REQUIRE(runReel("still drop.json --frame 8 -o high.png", cd).code == 0);
  REQUIRE(runReel("still drop.json --frame 8 --no-cache -o high_plain.png", cd).code == 0);
  CHECK(test::fileBytes(d / "high.png") == test::fileBytes(d / "high_plain.png"));
  CHECK(test::fileBytes(d / "high.png") != test::fileBytes(d / "low.png"));
}
