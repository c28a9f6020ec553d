// Golden-image testing as a product: the metrics (SSIM against its closed form, FLIP against the
// published implementation's values), the suite format's bad input, and `reel test` end to end:
// exit codes, --update, the HTML report in a real browser, JUnit XML.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "core/image_metrics.h"
#include "helpers.h"
#include "io/png.h"
#include "io/test_suite.h"

using namespace reel;
namespace fs = std::filesystem;

namespace {

// The image pairs of the FLIP check (x the column, y the row from the top).
Image gradient() {
  Image im(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      std::uint8_t* p = im.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(4 * x);
      p[1] = static_cast<std::uint8_t>(5 * y);
      p[2] = 128;
    }
  return im;
}
Image checker(int shift) {
  Image im(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const int sx = x >= shift ? x - shift : x;
      const std::uint8_t v = ((sx / 8 + y / 8) % 2 == 0) ? 255 : 0;
      std::uint8_t* p = im.pixel(x, y);
      p[0] = p[1] = p[2] = v;
    }
  return im;
}

void writeText(const fs::path& p, const std::string& s) {
  std::ofstream f(p);
  f << s;
}

const std::string kLights = std::string(REEL_SOURCE_DIR) + "/tests/scenes/lights.json";

// A folder holding lights.json, a copy with the crate's colour changed, and a suite of both at
// frame 10 whose goldens are the unchanged scene's.
fs::path suiteFolder(const std::string& name) {
  const fs::path d = test::freshDir(name);
  fs::copy_file(kLights, d / "lights.json");
  std::string text = test::fileBytes(kLights);
  const std::string from = "\"color\": [0.7, 0.5, 0.3]";
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), "\"color\": [0.3, 0.5, 0.7]");
  writeText(d / "recoloured.json", text);
  writeText(d / "s.json", R"({ "format": "reel-test/1", "name": "demo",
    "cases": [ {"name": "same", "scene": "lights.json", "frames": [10]},
               {"name": "crate", "scene": "recoloured.json", "times": [1.0]} ] })");
  return d;
}

}  // namespace

TEST_CASE("SSIM: 1 for identical images, the closed form for flat ones, lower for a shifted pattern") {
  const Image a = gradient();
  CHECK(ssim(a, a) == doctest::Approx(1.0).epsilon(1e-12));
  // Two flat images of luma 100 and 110: σ = 0, so SSIM = (2·μx·μy + C1)/(μx² + μy² + C1).
  Image f(40, 30), g(40, 30);
  std::fill(f.rgb.begin(), f.rgb.end(), std::uint8_t{100});
  std::fill(g.rgb.begin(), g.rgb.end(), std::uint8_t{110});
  const double c1 = (0.01 * 255) * (0.01 * 255);
  CHECK(ssim(f, g) == doctest::Approx((2.0 * 100 * 110 + c1) / (100.0 * 100 + 110.0 * 110 + c1)).epsilon(1e-9));
  // Symmetric, and a pattern moved by a pixel is less alike than one a level brighter.
  const Image c0 = checker(0), c1s = checker(1);
  CHECK(ssim(c0, c1s) == doctest::Approx(ssim(c1s, c0)).epsilon(1e-12));
  Image brighter = c0;
  for (auto& v : brighter.rgb) v = static_cast<std::uint8_t>(std::min(255, v + 1));
  CHECK(ssim(c0, brighter) > 0.999);
  CHECK(ssim(c0, c1s) < 0.9);
}

TEST_CASE("FLIP matches the published implementation (NVlabs/flip v1.6) on three image pairs") {
  // Reference values from NVIDIA's FLIP.h (float32; the float64 evaluation of the same method in
  // parentheses where they differ) at its default 67.02 pixels per degree.
  const Image a = gradient();
  Image square = a;  // pair A: a red square over the gradient
  for (int y = 16; y < 32; ++y)
    for (int x = 20; x < 36; ++x) {
      std::uint8_t* p = square.pixel(x, y);
      p[0] = 255, p[1] = 32, p[2] = 32;
    }
  std::vector<float> map;
  const FlipResult fa = flip(a, square, kFlipPpd, &map);
  CHECK(fa.mean == doctest::Approx(0.1048633588).epsilon(1e-5));
  CHECK(map[24 * 64 + 28] == doctest::Approx(0.963021219).epsilon(1e-5));
  CHECK(map[16 * 64 + 20] == doctest::Approx(0.713817537).epsilon(1e-5));
  CHECK(map[0] == 0.0f);
  CHECK(fa.max == doctest::Approx(0.963392913).epsilon(1e-5));
  // Pair B: every channel 8 levels brighter.
  Image bright = a;
  for (auto& v : bright.rgb) v = static_cast<std::uint8_t>(std::min(255, v + 8));
  CHECK(flip(a, bright).mean == doctest::Approx(0.1763271340).epsilon(1e-5));
  // Pair C: a checkerboard moved one pixel right (edges and points).
  const FlipResult fc = flip(checker(0), checker(1), kFlipPpd, &map);
  CHECK(fc.mean == doctest::Approx(0.2925254395).epsilon(1e-4));
  CHECK(map[4 * 64 + 8] == doctest::Approx(0.59825623).epsilon(1e-4));
  // Pair D: identical.
  const FlipResult fd = flip(a, a);
  CHECK(fd.mean == 0.0);
  CHECK(fd.max == 0.0);
}

TEST_CASE("a test suite's bad input: every error at once, with its JSON path") {
  const fs::path d = test::freshDir("suite_bad");
  fs::copy_file(kLights, d / "lights.json");
  writeText(d / "s.json", R"({ "format": "reel-test/1", "tolerence": {},
    "tolerance": {"max_flip": 2, "min_sim": 0.9},
    "cases": [ {"name": "a", "scene": "lights.json", "frames": [10], "size": "10x10"},
               {"name": "a", "scene": "nowhere.json", "frames": [1]},
               {"name": "../b", "scene": "lights.json", "frames": [1], "times": [0]},
               {"name": "c", "scene": "lights.json", "frames": []},
               {"name": "e", "scene": "lights.json", "frames": [-1], "samples": 3} ] })");
  auto s = io::loadTestSuite((d / "s.json").string());
  REQUIRE(!s.ok());
  std::string all;
  for (const std::string& m : s.error().messages) all += m + "\n";
  CAPTURE(all);
  CHECK(all.find("/tolerence: unknown key") != std::string::npos);
  CHECK(all.find("did you mean \"tolerance\"") != std::string::npos);
  CHECK(all.find("/tolerance/max_flip") != std::string::npos);
  CHECK(all.find("/tolerance/min_sim: unknown key") != std::string::npos);
  CHECK(all.find("/cases/0/size") != std::string::npos);
  CHECK(all.find("/cases/1/name: a second case named \"a\"") != std::string::npos);
  CHECK(all.find("/cases/1/scene: no such file: " + (d / "nowhere.json").string()) != std::string::npos);
  CHECK(all.find("/cases/2/name") != std::string::npos);
  CHECK(all.find("/cases/2: give \"frames\" or \"times\", not both") != std::string::npos);
  CHECK(all.find("/cases/3/frames: expected a list of 1 to") != std::string::npos);
  CHECK(all.find("/cases/4/frames/0") != std::string::npos);
  CHECK(all.find("/cases/4/samples") != std::string::npos);
  // Not a suite at all, or another format.
  writeText(d / "t.json", R"({"format": "reel/1", "cases": []})");
  auto t = io::loadTestSuite((d / "t.json").string());
  REQUIRE(!t.ok());
  CHECK(t.error().messages.front().find("unsupported format \"reel/1\"") != std::string::npos);
  CHECK(!io::loadTestSuite((d / "missing.json").string()).ok());
  CHECK(!io::loadTestSuite(d.string()).ok());
}

TEST_CASE("reel test: a changed scene fails (exit 1), an unchanged one passes, a one-level change passes") {
  const fs::path d = suiteFolder("suite_run");
  const std::string suite = (d / "s.json").string();
  // No goldens yet: exit 1, each named; --update writes them and exits 0.
  auto first = test::runReel("test " + suite);
  CHECK(first.code == 1);
  CHECK(first.out.find("MISSING  same, frame 10: no golden " + (d / "s" / "same_f0010.png").string()) != std::string::npos);
  auto update = test::runReel("test " + suite + " --update -q");
  CHECK(update.code == 0);
  REQUIRE(fs::exists(d / "s" / "same_f0010.png"));
  REQUIRE(fs::exists(d / "s" / "crate_f0010.png"));  // times [1.0] at 10 fps: frame 10
  // The crate's golden becomes the unchanged scene's: now that case differs.
  fs::copy_file(d / "s" / "same_f0010.png", d / "s" / "crate_f0010.png", fs::copy_options::overwrite_existing);
  // One level more in the red channel of the unchanged golden: still within tolerance.
  auto golden = io::readPng((d / "s" / "same_f0010.png").string());
  REQUIRE(golden.ok());
  Image level = golden.value();
  for (std::size_t i = 0; i < level.rgb.size(); i += 3) level.rgb[i] = static_cast<std::uint8_t>(std::min(255, level.rgb[i] + 1));
  REQUIRE(io::writePng((d / "s" / "same_f0010.png").string(), level).ok());
  const auto kept = fs::last_write_time(d / "s" / "same_f0010.png");
  const fs::path report = d / "report";
  auto run = test::runReel("test " + suite + " --report " + report.string() + " --junit " + (d / "j.xml").string() + " -j 2");
  CAPTURE(run.out);
  CHECK(run.code == 1);
  CHECK(run.out.find("pass     same, frame 10") != std::string::npos);
  CHECK(run.out.find("FAIL     crate, frame 10") != std::string::npos);
  CHECK(run.out.find("1 passed, 1 differ") != std::string::npos);
  // The report names the failing case and shows its three pictures; the passing one a thumbnail.
  const std::string html = test::fileBytes(report / "index.html");
  CHECK(html.find("crate, frame 10") != std::string::npos);
  for (const char* f : {"crate_f0010.expected.png", "crate_f0010.actual.png", "crate_f0010.diff.png", "same_f0010.thumb.png"}) {
    CAPTURE(f);
    CHECK(html.find(std::string("images/") + f) != std::string::npos);
    CHECK(io::readPng((report / "images" / f).string()).ok());
  }
  CHECK(html.find("http") == std::string::npos);  // nothing from the network
  CHECK(html.find("<script src") == std::string::npos);
  // JUnit: a testcase per case and frame, the failure with its metrics.
  const std::string xml = test::fileBytes(d / "j.xml");
  CHECK(xml.find("<testsuite name=\"demo\" tests=\"2\" failures=\"1\" errors=\"0\"") != std::string::npos);
  CHECK(std::regex_search(xml, std::regex("<testcase classname=\"demo.crate\" name=\"frame 10\"[^>]*>\\s*<failure type=\"differs\" message=\"mean")));
  CHECK(std::regex_search(xml, std::regex("<testcase classname=\"demo.same\" name=\"frame 10\"[^>]*></testcase>")));
  // --update rewrites the differing golden, never the one that passes.
  auto again = test::runReel("test " + suite + " --update -q");
  CHECK(again.code == 0);
  CHECK(again.out.find("updated  crate, frame 10") != std::string::npos);
  CHECK(fs::last_write_time(d / "s" / "same_f0010.png") == kept);
  CHECK(test::runReel("test " + suite + " -q").code == 0);
  // --case: only the case named runs; a name not in the suite is exit 2 with the nearest one.
  auto one = test::runReel("test " + suite + " --case crate");
  CHECK(one.code == 0);
  CHECK(one.out.find("1 frames of 1 cases") != std::string::npos);
  CHECK(one.out.find("same, frame") == std::string::npos);
  auto typo = test::runReel("test " + suite + " --case crat");
  CHECK(typo.code == 2);
  CHECK(typo.out.find("--case crat: no such case; did you mean \"crate\"?") != std::string::npos);
}

TEST_CASE("reel test: a missing scene or a frame outside the film is exit 2 before anything renders; outputs exit 4") {
  const fs::path d = suiteFolder("suite_exit");
  writeText(d / "bad.json", R"({ "format": "reel-test/1",
    "cases": [ {"name": "gone", "scene": "gone.json", "frames": [0]},
               {"name": "late", "scene": "lights.json", "frames": [5, 999]} ] })");
  auto gone = test::runReel("test " + (d / "bad.json").string());
  CAPTURE(gone.out);
  CHECK(gone.code == 2);
  CHECK(gone.out.find("/cases/0/scene: no such file: " + (d / "gone.json").string()) != std::string::npos);
  writeText(d / "late.json", R"({ "format": "reel-test/1",
    "cases": [ {"name": "late", "scene": "lights.json", "frames": [5, 999]}, {"name": "t", "scene": "lights.json", "times": [99]} ] })");
  auto late = test::runReel("test " + (d / "late.json").string());
  CAPTURE(late.out);
  CHECK(late.code == 2);
  CHECK(late.out.find("/cases/0/frames/1: frame 999 is outside the film") != std::string::npos);
  CHECK(late.out.find("/cases/1/times/0: 99 s is outside the film") != std::string::npos);
  CHECK(!fs::exists(d / "late"));
  // A case whose simulation goes unstable fails alone (exit 1, even with --update); the rest run.
  writeText(d / "boom.json", R"({"format": "reel/1", "duration": 200, "fps": 1, "substeps": 1, "gravity": [0, 0, 0],
     "render": {"width": 32, "height": 24},
     "bodies": [{"type": "mass_spring", "name": "probe", "nodes": [{"position": [0,0,0], "mass": 1, "velocity": [9000, 0, 0]}]}]})");
  writeText(d / "boom_suite.json", R"({ "format": "reel-test/1",
    "cases": [ {"name": "boom", "scene": "boom.json", "frames": [150]}, {"name": "same", "scene": "lights.json", "frames": [10]} ] })");
  auto boom = test::runReel("test " + (d / "boom_suite.json").string() + " --update --junit " + (d / "boom.xml").string());
  CAPTURE(boom.out);
  CHECK(boom.code == 1);
  CHECK(boom.out.find("ERROR    boom, frame 150:") != std::string::npos);
  CHECK(boom.out.find("position ran away") != std::string::npos);
  CHECK(fs::exists(d / "boom_suite" / "same_f0010.png"));
  CHECK(!fs::exists(d / "boom_suite" / "boom_f0150.png"));
  CHECK(test::fileBytes(d / "boom.xml").find("<error type=\"render\" message=\"") != std::string::npos);
  // A report folder under a regular file: exit 4, naming it.
  writeText(d / "file", "x");
  auto out = test::runReel("test " + (d / "s.json").string() + " --update --report " + (d / "file" / "r").string());
  CHECK(out.code == 4);
  CHECK(out.out.find((d / "file").string()) != std::string::npos);
}

TEST_CASE("the HTML report in a real browser: every picture decodes and the slider moves") {
  const fs::path d = suiteFolder("suite_browser");
  const std::string suite = (d / "s.json").string();
  REQUIRE(test::runReel("test " + suite + " --update -q").code == 0);
  fs::copy_file(d / "s" / "same_f0010.png", d / "s" / "crate_f0010.png", fs::copy_options::overwrite_existing);
  const fs::path report = d / "report";
  REQUIRE(test::runReel("test " + suite + " --report " + report.string()).code == 1);
  // Headless Chromium (Debian's chromium-headless-shell, scripts/install-deps.sh) loads the page
  // with #selftest: its script checks each <img> decoded and drags the slider, then marks <body>.
  const char* browser = "chromium-headless-shell";
  REQUIRE_MESSAGE(std::system((std::string("command -v ") + browser + " >/dev/null").c_str()) == 0,
                  "no chromium-headless-shell: run scripts/install-deps.sh");
  const std::string cmd = std::string("HOME=") + d.string() + " timeout 120 " + browser +
                          " --headless --no-sandbox --disable-gpu --no-first-run --virtual-time-budget=5000 --dump-dom 'file://" +
                          (report / "index.html").string() + "#selftest' 2>/dev/null";
  std::string dom;
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p);
  char buf[4096];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) dom.append(buf, n);
  pclose(p);
  std::smatch m;
  REQUIRE_MESSAGE(std::regex_search(dom, m, std::regex("data-selftest=\"([^\"]*)\"")), dom.substr(0, 2000));
  CHECK(m[1].str() == "pass");
  // The failing case's three pictures, twice more in the slider and flicker views, and a thumbnail.
  REQUIRE(std::regex_search(dom, m, std::regex("data-images=\"(\\d+)\"")));
  CHECK(std::stoi(m[1].str()) == 3 + 4 + 1);
}
