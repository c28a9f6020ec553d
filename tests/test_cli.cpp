// End to end: the reel binary on real scenes, its dump format and its exit codes (DESIGN 3, 5, 9).
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/image_compare.h"
#include "core/scene.h"
#include "helpers.h"
#include "sim/springs/springs_body.h"
#include "io/png.h"
#include "io/video.h"
#include "sim/world.h"

using namespace reel;
using reel::test::Run;
using reel::test::runReel;
namespace fs = std::filesystem;

namespace {

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
  auto scene = app::loadScene(kRope);
  REQUIRE(scene.ok());
  auto w = app::makeWorld(scene.value());
  REQUIRE(w.ok());
  for (int k = 0; k < 179; ++k) REQUIRE(w.value().advanceFrame().ok());
  const auto& x = w.value().first<SpringsBody>()->network().state.x;
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
  REQUIRE(runReel("simulate " + net + " --dump " + a + " --threads 1", "REEL_PARALLEL_MIN=2 ").code == 0);
  REQUIRE(runReel("simulate " + net + " --dump " + b + " --threads 2", "REEL_PARALLEL_MIN=2 ").code == 0);
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
  // Unwritable output (its folder would be under a regular file): exit 4 and no file left behind.
  const std::string blocker = write("blocker", "a file, not a folder");
  r = runReel("simulate " + kRope + " --dump " + blocker + "/out.json");
  CHECK(r.code == 4);
  CHECK(r.out.find(blocker + "/out.json: cannot create the folder " + blocker) != std::string::npos);
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
    CHECK(j["integrator"] == std::string(kIntegratorNames[static_cast<std::size_t>(lines)]));
    ++lines;
    pos = end + 1;
  }
  CHECK(lines == 6);  // symplectic_euler, explicit_euler, verlet, rk4, implicit_euler, bdf2
}

TEST_CASE("render: PNG frames numbered from 1 and a video from one simulation") {
  const fs::path dir = tmpDir() / "film";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string drape = std::string(REEL_SOURCE_DIR) + "/tests/scenes/drape.json";
  const std::string pattern = (dir / "f_###.png").string(), video = (dir / "film.mp4").string();
  Run r = runReel("render " + drape + " -o " + pattern + " -o " + video + " --size 96x64");
  REQUIRE(r.code == 0);
  // 1 s at 10 fps: 10 frames, f_001.png .. f_010.png, and no part files.
  for (int k = 1; k <= 10; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "f_%03d.png", k);
    CHECK(fs::exists(dir / name));
  }
  CHECK(!fs::exists(dir / "f_011.png"));
  CHECK(!fs::exists(dir / "f_000.png"));
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().extension() != ".part");
  auto info = io::probeVideo(video);
  REQUIRE(info.ok());
  CHECK(info.value().frames == 10);
  CHECK(info.value().width == 96);
  CHECK(info.value().height == 64);
  CHECK(info.value().codec == "h264");
  CHECK(info.value().pix_fmt == "yuv420p");
  CHECK(info.value().fps == doctest::Approx(10.0));
  auto text = io::readPngText((dir / "f_004.png").string());
  REQUIRE(text.ok());
  CHECK(std::find(text.value().begin(), text.value().end(), std::pair<std::string, std::string>{"reel:frame", "3"}) !=
        text.value().end());
  // The video's frames are close to the PNGs.
  auto frames = io::decodeVideo(video, 96, 64);
  REQUIRE(frames.ok());
  auto png = io::readPng((dir / "f_006.png").string());
  REQUIRE(png.ok());
  CHECK(compareImages(frames.value()[5], png.value(), 255).mean_abs < 4.0);
  // The still of frame 5 equals the film's frame 6.
  const std::string still = (dir / "still.png").string();
  REQUIRE(runReel("still " + drape + " --frame 5 -o " + still + " --size 96x64").code == 0);
  auto s = io::readPng(still);
  REQUIRE(s.ok());
  CHECK(s.value().rgb == png.value().rgb);
  REQUIRE(runReel("still " + drape + " --time 0.5 -o " + still + " --size 96x64 --gl egl").code == 0);
  CHECK(io::readPng(still).value().rgb == png.value().rgb);
  // reel compare: identical within tolerance (0), different not (1), missing file (2).
  CHECK(runReel("compare " + still + " " + (dir / "f_006.png").string()).code == 0);
  r = runReel("compare " + still + " " + (dir / "f_001.png").string() + " --diff " + (dir / "diff.png").string());
  CHECK(r.code == 1);
  CHECK(r.out.find("NOT within tolerance") != std::string::npos);
  CHECK(fs::exists(dir / "diff.png"));
  CHECK(runReel("compare " + still + " /nonexistent.png").code == 2);
}

TEST_CASE("render: --frames, --no-overwrite resumes, bad outputs and paths") {
  const fs::path dir = tmpDir() / "resume";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string drape = std::string(REEL_SOURCE_DIR) + "/tests/scenes/drape.json";
  const std::string pattern = (dir / "r_####.png").string();
  REQUIRE(runReel("render " + drape + " -o " + pattern + " --size 64x48 --frames 2-5").code == 0);
  CHECK(!fs::exists(dir / "r_0002.png"));
  CHECK(fs::exists(dir / "r_0003.png"));
  CHECK(fs::exists(dir / "r_0006.png"));
  CHECK(!fs::exists(dir / "r_0007.png"));
  // Resume: a missing frame and a corrupt one are redrawn, valid ones are left alone.
  const auto kept = fs::last_write_time(dir / "r_0004.png");
  fs::remove(dir / "r_0003.png");
  { std::ofstream(dir / "r_0005.png") << "not a png"; }
  REQUIRE(runReel("render " + drape + " -o " + pattern + " --size 64x48 --frames 2-5 --no-overwrite").code == 0);
  CHECK(io::readPng((dir / "r_0003.png").string()).ok());
  CHECK(io::readPng((dir / "r_0005.png").string()).ok());
  CHECK(fs::last_write_time(dir / "r_0004.png") == kept);
  // Bad requests: exit 2.
  CHECK(runReel("render " + drape + " -o " + (dir / "x.avi").string()).code == 2);
  CHECK(runReel("render " + drape + " -o " + (dir / "x.png").string()).code == 2);
  CHECK(runReel("render " + drape + " --frames 5-2 -o " + pattern).code == 2);
  CHECK(runReel("render " + drape + " --frames 0-10 -o " + pattern).code == 2);
  CHECK(runReel("render " + drape + " --frames 0-5xyz -o " + pattern).code == 2);
  CHECK(runReel("render " + drape + " --gl vulkan -o " + pattern).code == 2);
  CHECK(runReel("render " + drape + " --size 10x10 -o " + pattern).code == 2);
  CHECK(runReel("still " + drape + " --frame 10 -o " + (dir / "s.png").string()).code == 2);
  CHECK(runReel("still " + drape + " -o " + (dir / "s.png").string()).code == 2);
}

TEST_CASE("outputs: missing folders are created, and one that cannot be is exit 4") {
  const fs::path dir = tmpDir() / "new_folders";
  fs::remove_all(dir);
  const std::string drape = std::string(REEL_SOURCE_DIR) + "/tests/scenes/drape.json";
  const std::string pattern = (dir / "a/b/f_##.png").string(), video = (dir / "c/d/film.mp4").string();
  REQUIRE(runReel("render " + drape + " -o " + pattern + " -o " + video + " --size 64x36 --frames 0-1").code == 0);
  CHECK(io::readPng((dir / "a/b/f_01.png").string()).ok());
  CHECK(io::readPng((dir / "a/b/f_02.png").string()).ok());
  auto info = io::probeVideo(video);
  REQUIRE(info.ok());
  CHECK(info.value().frames == 2);
  REQUIRE(runReel("still " + drape + " --frame 1 -o " + (dir / "e/s.png").string() + " --size 64x36").code == 0);
  CHECK(io::readPng((dir / "e/s.png").string()).ok());
  REQUIRE(runReel("simulate " + drape + " --dump " + (dir / "f/g/d.json").string()).code == 0);
  CHECK(fs::is_regular_file(dir / "f/g/d.json"));

  // Under a regular file no folder can be made: exit 4, the message names the path, no file appears.
  const std::string blocker = write("not_a_folder", "a file");
  Run r = runReel("render " + drape + " -o " + blocker + "/v.mp4 --size 64x36 --frames 0-1");
  CHECK(r.code == 4);
  CHECK(r.out.find("reel: " + blocker + "/v.mp4: cannot create the folder " + blocker) == 0);
  r = runReel("render " + drape + " -o " + blocker + "/sub/f_##.png --size 64x36 --frames 0-1");
  CHECK(r.code == 4);
  CHECK(r.out.find("cannot create the folder " + blocker + "/sub") != std::string::npos);
  r = runReel("still " + drape + " --frame 1 -o " + blocker + "/s.png --size 64x36");
  CHECK(r.code == 4);
  CHECK(r.out.find(blocker + "/s.png") != std::string::npos);
  CHECK(fs::is_regular_file(blocker));
}

TEST_CASE("--seed replaces the scene's seed in simulate, still and render") {
  // A jittered block of liquid: its first frame's positions come from the seed.
  const std::string body = R"("duration": 0.2, "fps": 10, "substeps": 20, "auto_substeps": true,
    "objects": [{"type": "container", "center": [0, 0.1, 0], "size": [0.2, 0.2, 0.2], "wall": 0.02}],
    "bodies": [{"type": "fluid", "name": "water", "species": [{"name": "water", "mass": 0.008, "alpha": 212.6,
      "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}],
      "blocks": [{"min": [-0.04, 0.02, -0.04], "max": [0.04, 0.1, 0.04], "spacing": 0.02, "jitter": 0.3}]}]})";
  const std::string plain = write("seed_plain.json", R"({"format": "reel/1", "name": "jitter", )" + body);
  const std::string seeded = write("seed_7.json", R"({"format": "reel/1", "name": "jitter", "seed": 7, )" + body);
  const auto dump = [&](const std::string& scene, const std::string& args) {
    const fs::path out = tmpDir() / "seed.dump.json";
    fs::remove(out);
    const Run r = runReel("simulate " + scene + " --dump " + out.string() + " " + args);
    REQUIRE(r.code == 0);
    std::ifstream in(out);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string d0 = dump(plain, ""), d7 = dump(plain, "--seed 7"), d8 = dump(plain, "--seed 8");
  CHECK(d0.size() > 1000);
  CHECK(d7 != d0);
  CHECK(d8 != d7);
  CHECK(dump(seeded, "") == d7);           // the scene's seed 7 and --seed 7 are the same film
  CHECK(dump(seeded, "--seed 0") == d0);   // the command line wins
  CHECK(dump(plain, "--seed 9007199254740991") != d0);  // 2^53 - 1, the largest

  // The PNG says which seed drew it.
  const std::string drape = std::string(REEL_SOURCE_DIR) + "/tests/scenes/drape.json";
  const std::string png = (tmpDir() / "seed_still.png").string();
  REQUIRE(runReel("still " + drape + " --frame 0 -o " + png + " --size 64x36 --seed 42").code == 0);
  auto text = io::readPngText(png);
  REQUIRE(text.ok());
  CHECK(std::find(text.value().begin(), text.value().end(), std::pair<std::string, std::string>{"reel:seed", "42"}) !=
        text.value().end());

  // Not an integer 0..2^53-1: exit 2 with one clear line, before anything is simulated.
  for (const char* bad : {"-1", "abc", "1.5", "9007199254740992", "99999999999999999999999", "7x", "\"\""}) {
    CAPTURE(bad);
    const Run r = runReel("simulate " + plain + " --seed " + bad);
    CHECK(r.code == 2);
    CHECK(r.out.find("reel: --seed must be an integer 0..9007199254740991") == 0);
  }
  CHECK(runReel("render " + drape + " --seed -3 -o " + (tmpDir() / "never/f_#.png").string()).code == 2);
  CHECK(!fs::exists(tmpDir() / "never"));
  CHECK(runReel("still " + drape + " --frame 0 --seed abc -o " + png).code == 2);
}

TEST_CASE("cloth bad input exits 2 naming the JSON path; a cloth film renders and dumps only intact springs") {
  const std::string bad = write("bad_cloth.json", R"({"format": "reel/1", "duration": 1,
    "bodies": [{"type": "cloth", "resolution": [1, 8], "size": [1, -1], "tear": {"strain": 0},
                "pinned": ["edge_q0"]}],
    "objects": [{"type": "mesh", "file": "missing.obj"}]})");
  const Run r = runReel("check " + bad);
  CHECK(r.code == 2);
  CHECK(r.out.find("/bodies/0/resolution/0") != std::string::npos);
  CHECK(r.out.find("/bodies/0/size/1") != std::string::npos);
  CHECK(r.out.find("/bodies/0/tear/strain") != std::string::npos);
  CHECK(r.out.find("/bodies/0/pinned/0") != std::string::npos);
  CHECK(r.out.find("/objects/0/file") != std::string::npos);
  // The golden tear scene: its dump lists fewer springs at the end than at the start.
  const std::string dump = (tmpDir() / "tear.dump.json").string();
  REQUIRE(runReel("simulate " + std::string(REEL_SOURCE_DIR) + "/tests/scenes/cloth_tear.json --dump " + dump +
                  " --dump-every 100").code == 0);
  std::ifstream in(dump);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto first = text.find("\"springs\""), last = text.rfind("\"springs\"");
  REQUIRE(first != last);
  const auto count = [&](std::size_t at) {
    const std::size_t end = text.find("]]", at);
    return std::count(text.begin() + static_cast<std::ptrdiff_t>(at), text.begin() + static_cast<std::ptrdiff_t>(end), '[');
  };
  CHECK(count(last) < count(first));
  // --dump-every K > 1 when the next frame goes unstable: the last good frame is written with its
  // own springs, not the model's after the sheet tore on (a probe runs away at t = 0.4999 s, just
  // after tears in frame 5, so frame 4 is the last dumped).
  std::string boom = test::fileBytes(std::string(REEL_SOURCE_DIR) + "/tests/scenes/cloth_tear.json");
  boom.replace(boom.find("\"bodies\": ["), 11, R"("bodies": [{"type": "mass_spring", "name": "probe",
      "nodes": [{"position": [995500.9, 0, 0], "mass": 1, "velocity": [9000, 0, 0]}]},)");
  const std::string scene = write("tear_boom.json", boom);
  const std::string every = (tmpDir() / "tear_every.json").string(), sparse = (tmpDir() / "tear_sparse.json").string();
  CHECK(runReel("simulate " + scene + " -q --dump " + every).code == 3);
  CHECK(runReel("simulate " + scene + " -q --dump " + sparse + " --dump-every 50").code == 3);
  std::ifstream ea(every), sa(sparse);
  const auto je = nlohmann::json::parse(ea), js = nlohmann::json::parse(sa);
  REQUIRE(je["frames"].back()["frame"] == 4);
  REQUIRE(js["frames"].back()["frame"] == 4);
  CHECK(je["frames"].back()["bodies"][1]["springs"] == js["frames"].back()["bodies"][1]["springs"]);
  CHECK(je["frames"].back()["bodies"][1]["positions"] == js["frames"].back()["bodies"][1]["positions"]);
}

TEST_CASE("fluid on the command line: dumps list species, bad input exits 2, a blow-up exits 3") {
  const std::string species = R"({"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6})";
  const std::string good = write("fluid_ok.json", R"({"format": "reel/1", "duration": 0.2, "fps": 10, "substeps": 80,
    "objects": [{"type": "container", "center": [0, 0.1, 0], "size": [0.3, 0.2, 0.3], "wall": 0.02}],
    "bodies": [{"type": "fluid", "name": "water", "species": [)" + species + R"(, {"name": "oil", "mass": 0.005, "alpha": 320, "beta": 0.128, "cutoff": 0.02725, "viscosity": 6}],
      "blocks": [{"min": [-0.1, 0.02, -0.1], "max": [0.0, 0.1, 0.1], "spacing": 0.02},
                 {"species": "oil", "min": [0.0, 0.02, -0.1], "max": [0.1, 0.1, 0.1], "spacing": 0.02}]}]})");
  const std::string dump = (tmpDir() / "fluid.dump.json").string();
  REQUIRE(runReel("simulate " + good + " --dump " + dump).code == 0);
  std::ifstream in(dump);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text.find("\"type\":\"particles\"") != std::string::npos);
  CHECK(text.find("\"generator\":\"fluid\"") != std::string::npos);
  CHECK(text.find("\"species_names\":[\"water\",\"oil\"]") != std::string::npos);
  CHECK(text.find("\"species\":[0,0,") != std::string::npos);
  const Run check = runReel("check " + good);
  CHECK(check.code == 0);
  CHECK(check.out.find("species 'water': rest distance 0.02 m") != std::string::npos);

  const std::string bad = write("fluid_bad.json", R"({"format": "reel/1", "duration": 1,
    "bodies": [{"type": "fluid", "species": [{"name": "w", "mass": -1, "cutoff": 0.03}],
                "emitters": [{"position": [0, 1, 0], "rate": 0}]}]})");
  const Run r = runReel("check " + bad);
  CHECK(r.code == 2);
  CHECK(r.out.find("/bodies/0/species/0/mass") != std::string::npos);
  CHECK(r.out.find("/bodies/0/emitters/0/rate") != std::string::npos);

  // A particle thrown faster than anything physical (20 km/s): it runs away.
  const std::string boom = write("fluid_boom.json", R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 1, "auto_substeps": true,
    "bodies": [{"type": "fluid", "name": "goo", "species": [{"name": "w", "mass": 0.01, "alpha": 200, "beta": 0.1, "cutoff": 0.05}],
                "particles": [{"positions": [[0, 0, 0], [0.05, 0, 0]], "velocities": [[20000, 0, 0], [0, 0, 0]]}]}]})");
  const Run u = runReel("simulate " + boom);
  CHECK(u.code == 3);
  CHECK(u.out.find("body 'goo' particle") != std::string::npos);
}

TEST_CASE("simulate --stats writes a school's order parameters per frame (CSV); its dump lists agents") {
  const std::string scene = write("stats_school.json", R"({"format": "reel/1", "name": "stats", "fps": 10, "substeps": 1, "duration": 2,
      "bodies": [{"type": "rope", "name": "r", "start": [0, 0, 0], "end": [1, 0, 0], "segments": 4, "stiffness": 1, "mass": 1},
                 {"type": "school", "name": "fish, small", "count": 20, "heading": [1, 0, 0], "noise": 0}]})");
  const std::string csv = (tmpDir() / "stats.csv").string(), dump = (tmpDir() / "stats_dump.json").string();
  fs::remove(csv);
  const Run r = runReel("simulate " + scene + " --stats " + csv + " --dump " + dump);
  REQUIRE(r.code == 0);
  CHECK(!fs::exists(csv + ".part"));
  std::ifstream in(csv);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) lines.push_back(line);
  REQUIRE(lines.size() == 21);  // the header, frames 0..19 of the one body with statistics
  CHECK(lines[0] == "frame,time,body,polarization,milling,centroid_x,centroid_y,centroid_z,nearest_neighbour");
  CHECK(lines[1].rfind("0,0,\"fish, small\",1,", 0) == 0);  // all heading +x at frame 0: p = 1
  CHECK(lines[20].rfind("19,1.9,\"fish, small\",", 0) == 0);
  const auto j = nlohmann::json::parse(std::ifstream(dump));
  const auto& fish = j["frames"][0]["bodies"][1];
  CHECK(fish["type"] == "agents");
  CHECK(fish["generator"] == "school");
  CHECK(fish["positions"].size() == 20);
  CHECK(fish["velocities"].size() == 20);
  CHECK(!fish.contains("springs"));
  // An unwritable statistics file: exit 4 before anything is simulated.
  CHECK(runReel("simulate " + scene + " --stats /proc/no/such/stats.csv").code == 4);
}

TEST_CASE("a fish body's dump lists its nodes' masses, muscles and mental state; a bad fish scene exits 2") {
  const std::string scene = write("dump_fish.json", R"({"format": "reel/1", "name": "fish", "fps": 10, "substeps": 4, "duration": 0.3,
      "integrator": "implicit_euler", "bodies": [{"type": "fish", "name": "f", "count": 2, "start": {"center": [0, 0, 0], "radius": 1},
      "mental": {"hunger": 0.4, "libido": 0.1, "fear": 0}}]})");
  const std::string dump = (tmpDir() / "fish_dump.json").string(), csv = (tmpDir() / "fish.csv").string();
  const Run r = runReel("simulate " + scene + " --dump " + dump + " --stats " + csv);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(std::ifstream(dump));
  const auto& f = j["frames"][0]["bodies"][0];
  CHECK(f["generator"] == "fish");
  CHECK(f["positions"].size() == 46);
  CHECK(f["masses"].size() == 46);
  CHECK(f["springs"].size() == 182);
  REQUIRE(f["muscles"].size() == 2);
  CHECK(f["muscles"][0].size() == 12);
  REQUIRE(f["mental"].size() == 2);
  CHECK(f["mental"][1][0].get<double>() == doctest::Approx(0.4));
  CHECK(f["mental"][1][1].get<double>() == doctest::Approx(0.1));
  CHECK(f["intention"].size() == 2);
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  CHECK(header == "frame,time,body,hunger,libido,fear,speed,meals");
  const std::string bad = write("bad_fish.json", R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "fish", "name": "f", "species": "shark"}]})");
  const Run b = runReel("check " + bad);
  CHECK(b.code == 2);
  CHECK(b.out.find("/bodies/0/species") != std::string::npos);
}

TEST_CASE("info --mass prints a closed mesh's mass properties as JSON and refuses an open one") {
  // A 2 × 1 × 1 box from (1, 0, 0): the centre at (2, 0.5, 0.5), I = m (b² + c²)/12 and so on.
  const std::string box = write("box.obj", "v 1 0 0\nv 3 0 0\nv 3 1 0\nv 1 1 0\nv 1 0 1\nv 3 0 1\nv 3 1 1\nv 1 1 1\n"
                                           "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                           "f 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n");
  const Run r = runReel("info --mass " + box + " --density 3");
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["volume"].get<double>() == doctest::Approx(2.0).epsilon(1e-12));
  CHECK(j["mass"].get<double>() == doctest::Approx(6.0).epsilon(1e-12));
  CHECK(j["center_of_mass"][0].get<double>() == doctest::Approx(2.0).epsilon(1e-12));
  CHECK(j["inertia"][0][0].get<double>() == doctest::Approx(6.0 * 2 / 12).epsilon(1e-12));
  CHECK(j["inertia"][1][1].get<double>() == doctest::Approx(6.0 * 5 / 12).epsilon(1e-12));
  CHECK(std::abs(j["inertia"][0][1].get<double>()) < 1e-12);
  const std::string open = write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");
  const Run bad = runReel("info --mass " + open);
  CHECK(bad.code == 2);
  CHECK(bad.out.find("not closed") != std::string::npos);
}
