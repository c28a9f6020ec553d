// End to end: the reel binary on real scenes, its dump format and its exit codes (DESIGN 3, 5, 9).
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "helpers.h"
#include "sim/world.h"

using namespace reel;
namespace fs = std::filesystem;

namespace {

struct Run {
  int code = -1;
  std::string out;  // stdout and stderr together
};

Run runReel(const std::string& args) {
  Run r;
  const std::string cmd = std::string(REEL_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p);
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

fs::path tmpDir() {
  const fs::path d = fs::temp_directory_path() / "reel_cli_test";
  fs::create_directories(d);
  return d;
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = tmpDir() / name;
  std::ofstream(p) << text;
  return p.string();
}

const std::string kRope = std::string(REEL_SOURCE_DIR) + "/scenes/rope.json";

}  // namespace

TEST_CASE("simulate writes the reel-dump/1 format: frames 0, every K-th and the last") {
  const std::string out = (tmpDir() / "rope_dump.json").string();
  const Run r = runReel("simulate " + kRope + " --dump " + out + " --dump-every 7 --threads 2");
  REQUIRE(r.code == 0);
  CHECK(!fs::exists(out + ".part"));
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  CHECK(j["format"] == "reel-dump/1");
  CHECK(j["scene"] == "rope");
  CHECK(j["fps"] == 30);
  CHECK(j["substeps"] == 40);
  const auto& frames = j["frames"];
  // 6 s at 30 fps: frames 0..179; every 7th plus the last.
  std::vector<int> want;
  for (int k = 0; k < 180; k += 7) want.push_back(k);
  want.push_back(179);
  REQUIRE(frames.size() == want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    CHECK(frames[i]["frame"] == want[i]);
    CHECK(frames[i]["time"].get<double>() == want[i] / 30.0);
  }
  const auto& b = frames.back()["bodies"][0];
  CHECK(b["name"] == "rope");
  CHECK(b["type"] == "mass_spring");
  CHECK(b["positions"].size() == 31);
  CHECK(b["velocities"].size() == 31);
  CHECK(b["springs"].size() == 30);
  CHECK(b["springs"][3] == nlohmann::json::array({3, 4}));
  // Numbers round-trip exactly: the dump equals the state simulated in this process.
  auto scene = io::loadScene(kRope);
  REQUIRE(scene.ok());
  auto w = World::create(scene.value());
  REQUIRE(w.ok());
  for (int k = 0; k < 179; ++k) REQUIRE(w.value().advanceFrame().ok());
  const auto& x = w.value().bodies()[0]->state.x;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(b["positions"][i][c].get<double>() == x[i][c]);
}

TEST_CASE("dumps are byte-identical for 1 and 2 threads") {
  const std::string a = (tmpDir() / "t1.json").string(), b = (tmpDir() / "t2.json").string();
  // 4096 nodes and 16000 springs: above the size at which loops run in parallel.
  const std::string net = write("bignet.json", R"({"format": "reel/1", "duration": 0.2, "substeps": 5,
    "auto_substeps": true, "objects": [{"type": "sphere", "center": [0, -0.6, 0], "radius": 0.5}],
    "bodies": [{"type": "net", "name": "net", "size": [2, 2], "resolution": [64, 64], "mass": 1,
                "stiffness": 100, "damping": 0.02, "velocity": [0.3, 0, 0.1], "pinned": ["corner_00"]}]})");
  REQUIRE(runReel("simulate " + net + " --dump " + a + " --threads 1").code == 0);
  REQUIRE(runReel("simulate " + net + " --dump " + b + " --threads 2").code == 0);
  std::ifstream fa(a), fb(b);
  const std::string sa((std::istreambuf_iterator<char>(fa)), {}), sb((std::istreambuf_iterator<char>(fb)), {});
  CHECK(sa.size() > 1000);
  CHECK(sa == sb);
}

TEST_CASE("exit codes: 0 done, 2 bad input, 3 unstable, 4 unwritable output") {
  CHECK(runReel("info").code == 0);
  CHECK(runReel("check " + kRope).code == 0);
  // Usage errors.
  CHECK(runReel("").code == 2);
  CHECK(runReel("frobnicate").code == 2);
  CHECK(runReel("simulate").code == 2);
  CHECK(runReel("simulate " + kRope + " --threads 0").code == 2);
  CHECK(runReel("bench nothing").code == 2);
  // Bad scenes: first line is one clear error.
  Run r = runReel("simulate /nonexistent.json");
  CHECK(r.code == 2);
  CHECK(r.out.rfind("reel: /nonexistent.json: no such file", 0) == 0);
  const std::string bad = write("bad.json", "{\"format\": \"reel/1\",\n \"duration\": }");
  r = runReel("check " + bad);
  CHECK(r.code == 2);
  CHECK(r.out.find("bad.json:2:14: syntax error") != std::string::npos);
  const std::string typo = write("typo.json", R"({"format": "reel/1", "duration": 1, "substep": 3, "fps": -1})");
  r = runReel("check " + typo);
  CHECK(r.code == 2);
  CHECK(r.out.find("/substep: unknown key; did you mean \"substeps\"?") != std::string::npos);
  CHECK(r.out.find("/fps: must be an integer in [1, 1000]") != std::string::npos);
  CHECK(r.out.find("reel: 2 errors") != std::string::npos);
  // Unstable: exit 3, and the dump keeps the good frames.
  const std::string boom = write("boom.json", R"({"format": "reel/1", "duration": 200, "fps": 1, "substeps": 1, "gravity": [0, 0, 0],
     "bodies": [{"type": "mass_spring", "name": "probe",
       "nodes": [{"position": [0,0,0], "mass": 1, "velocity": [9000, 0, 0]}]}]})");
  const std::string boom_dump = (tmpDir() / "boom_dump.json").string();
  r = runReel("simulate " + boom + " --dump " + boom_dump + " --dump-every 7");
  CHECK(r.code == 3);
  CHECK(r.out.find("body 'probe' node 0 position ran away") != std::string::npos);
  CHECK(r.out.find("unstable at frame 112") != std::string::npos);
  std::ifstream in(boom_dump);
  const auto j = nlohmann::json::parse(in);  // valid JSON, ending with the last good frame
  REQUIRE(j["frames"].size() == 17);          // 0, 7, ..., 105 and 111
  CHECK(j["frames"].back()["frame"] == 111);
  CHECK(j["frames"].back()["bodies"][0]["positions"][0][0].get<double>() == 9000.0 * 111);
  // A huge unterminated string is a syntax error, not a crash.
  r = runReel("check " + write("long.json", "{\"format\": \"reel/1\", \"a\": \"" + std::string(200000, 'x')));
  CHECK(r.code == 2);
  CHECK(r.out.find("long.json:1:") != std::string::npos);
  // Unwritable output: exit 4 and no file left behind.
  r = runReel("simulate " + kRope + " --dump /nonexistent_dir/out.json");
  CHECK(r.code == 4);
  CHECK(r.out.find("/nonexistent_dir/out.json.part: cannot write") != std::string::npos);
  if (fs::exists("/dev/full")) {
    // A full disk: the final name never appears.
    const fs::path link = tmpDir() / "full.json.part";
    fs::remove(link);
    fs::create_symlink("/dev/full", link);
    r = runReel("simulate " + kRope + " --dump " + (tmpDir() / "full.json").string());
    CHECK(r.code == 4);
    CHECK(!fs::exists(tmpDir() / "full.json"));
    fs::remove(link);
  }
}

TEST_CASE("bench prints one JSON line per integrator") {
  const Run r = runReel("bench springs --seconds 0.02 --threads 1");
  REQUIRE(r.code == 0);
  int lines = 0;
  std::size_t pos = 0;
  while (pos < r.out.size()) {
    const std::size_t end = r.out.find('\n', pos);
    const auto j = nlohmann::json::parse(r.out.substr(pos, end - pos));
    CHECK(j["name"] == "springs");
    CHECK(j["nodes"] == 65536);
    CHECK(j["spring_updates_per_s"].get<double>() > 0);
    ++lines;
    pos = end + 1;
  }
  CHECK(lines == 5);
}
