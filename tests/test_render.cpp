// The renderer against analytic images, itself (determinism, OSMesa = EGL), PNG and video files.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/image_compare.h"
#include "core/math.h"
#include "core/patterns.h"
#include "core/scene_view.h"
#include "helpers.h"
#include "io/files.h"
#include "io/png.h"
#include "io/video.h"
#include "render/renderer.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;
namespace fs = std::filesystem;

namespace {

// Renders frame `frame` of a scene in this process with the given backend.
Image renderScene(const std::string& text, gl::Backend backend = gl::Backend::OSMesa, int frame = 0,
                  const std::string& file = "test.json") {
  const SceneDesc scene = sceneFromText(text, file);
  auto w = app::makeWorld(scene);
  REQUIRE(w.ok());
  for (int k = 0; k < frame; ++k) REQUIRE(w.value().advanceFrame().ok());
  auto ctx = gl::createContext(backend);
  REQUIRE_MESSAGE(ctx.ok(), (ctx.ok() ? "" : ctx.error().headline()));
  RenderSettings rs;
  rs.width = scene.render.width;
  rs.height = scene.render.height;
  rs.samples = scene.render.samples;
  auto r = Renderer::create(*ctx.value(), rs, findShaderDir());
  REQUIRE_MESSAGE(r.ok(), (r.ok() ? "" : r.error().headline()));
  DrawList list;
  setSceneView(scene, w.value().time(), list);
  w.value().draw(list);
  Image img;
  REQUIRE(r.value()->draw(list, img).ok());
  return img;
}

double srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055; }

// A camera looking straight down at a floor of albedo ρ lit by one directional light at angle θ
// from the normal, plus an optional ambient light.
std::string litPlane(double rho, double theta_deg, double ambient) {
  const double t = theta_deg * kPi / 180.0;
  char buf[1024];
  std::snprintf(buf, sizeof buf, R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 64, "height": 48, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 3, 0.001], "target": [0, 0, 0], "fov_deg": 40},
    "lights": [{"type": "directional", "direction": [%.17g, %.17g, 0], "intensity": 1},
               {"type": "ambient", "intensity": %.17g}],
    "objects": [{"type": "plane", "color": [%.17g, %.17g, %.17g]}]})",
                std::sin(t), -std::cos(t), ambient, rho, rho, rho);
  return buf;
}

}  // namespace

TEST_CASE("a lit Lambertian plane has the value sRGB(ρ·cos θ + ρ·ambient)") {
  for (auto [rho, theta, amb] : {std::tuple{0.5, 60.0, 0.0}, std::tuple{0.8, 0.0, 0.0}, std::tuple{0.3, 45.0, 0.2},
                                 std::tuple{0.6, 100.0, 0.25}}) {
    CAPTURE(rho);
    CAPTURE(theta);
    const Image img = renderScene(litPlane(rho, theta, amb));
    const double lin = rho * std::max(0.0, std::cos(theta * kPi / 180.0)) + rho * amb;
    const int want = static_cast<int>(std::lround(255.0 * srgb(lin)));
    for (auto [x, y] : {std::pair{32, 24}, std::pair{5, 5}, std::pair{60, 40}}) {
      const std::uint8_t* p = img.pixel(x, y);
      for (int c = 0; c < 3; ++c) CHECK(std::abs(int(p[c]) - want) <= 1);
    }
  }
}

TEST_CASE("a texture multiplies the albedo, decoded from sRGB, mapped by the UVs") {
  const fs::path dir = fs::temp_directory_path() / "reel_tex_test";
  fs::create_directories(dir);
  Image tex(2, 2);
  const std::uint8_t colours[4][3] = {{200, 30, 30}, {30, 200, 30}, {30, 30, 200}, {240, 240, 240}};
  for (int i = 0; i < 4; ++i) std::copy(colours[i], colours[i] + 3, tex.pixel(i % 2, i / 2));
  REQUIRE(io::writePng((dir / "t.png").string(), tex).ok());
  const std::string scene = R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 64, "height": 48, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 3.139974, 0.000001], "target": [0, 0, 0], "fov_deg": 40},
    "lights": [{"type": "ambient", "intensity": 1}],
    "objects": [{"type": "plane", "size": [2, 2], "color": [1, 1, 1], "texture": "t.png"}]})";
  std::ofstream((dir / "s.json").string()) << scene;
  auto s = app::loadScene((dir / "s.json").string());
  REQUIRE(s.ok());
  REQUIRE(s.value().objects[0].material.texture_image);
  const Image img = renderScene(scene, gl::Backend::OSMesa, 0, (dir / "s.json").string());
  // The camera height puts the texel centres (world x, z = ±0.5) on the centres of pixels 10.5
  // pixels from the image centre; each shows one texel's colour (sRGB decoded, lit by 1,
  // encoded again).
  std::vector<std::array<int, 3>> seen;
  for (int y : {13, 34})
    for (int x : {21, 42}) {
      const std::uint8_t* p = img.pixel(x, y);
      seen.push_back({p[0], p[1], p[2]});
    }
  for (const auto& c : colours) {
    bool found = false;
    for (const auto& q : seen)
      found = found || (std::abs(q[0] - c[0]) <= 2 && std::abs(q[1] - c[1]) <= 2 && std::abs(q[2] - c[2]) <= 2);
    CHECK_MESSAGE(found, int(c[0]) << "," << int(c[1]) << "," << int(c[2]));
  }
  fs::remove_all(dir);
}

TEST_CASE("a sphere's silhouette has the size the camera implies") {
  // Sphere of radius r at distance d: angular radius asin(r/d); on screen
  // R = (H/2)·tan(asin(r/d)) / tan(fov/2) pixels.
  const double r = 0.5, d = 4.0, fov = 30.0;
  const int W = 320, H = 240;
  char buf[1024];
  std::snprintf(buf, sizeof buf, R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": %d, "height": %d, "samples": 4, "background": [0, 0, 0]},
    "camera": {"position": [0, 0, %g], "target": [0, 0, 0], "fov_deg": %g},
    "lights": [{"type": "ambient", "intensity": 1}],
    "objects": [{"type": "sphere", "radius": %g, "color": [1, 1, 1]}]})", W, H, d, fov, r);
  const Image img = renderScene(buf);
  double covered = 0;  // anti-aliased coverage
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) covered += img.pixel(x, y)[0] / 255.0;
  const double want = 0.5 * H * std::tan(std::asin(r / d)) / std::tan(fov * kPi / 360.0);
  CHECK(std::sqrt(covered / kPi) == doctest::Approx(want).epsilon(0.01));
  CHECK(img.pixel(W / 2, H / 2)[0] == 255);
  CHECK(img.pixel(2, 2)[0] == 0);
}

namespace {

const char* kShadowScene = R"({"format": "reel/1", "duration": 1, "fps": 10, "substeps": 20, "auto_substeps": true,
  "render": {"width": 160, "height": 120, "samples": 4, "background": {"top": [0.5, 0.6, 0.8], "bottom": [0.9, 0.9, 0.85]}},
  "camera": {"position": [1.5, 1.2, 2.5], "target": [0, 0.2, 0], "fov_deg": 45},
  "objects": [{"type": "plane", "checker": true},
              {"type": "box", "center": [0.6, 0.15, -0.3], "size": [0.3, 0.3, 0.3], "rotation_deg": [0, 30, 0], "color": [0.8, 0.5, 0.2]},
              {"type": "capsule", "start": [-0.6, 0.1, 0], "end": [-0.6, 0.5, -0.2], "radius": 0.1, "color": [0.3, 0.7, 0.4]}],
  "bodies": [{"type": "net", "name": "net", "position": [0, 0.8, 0], "size": [0.8, 0.8], "resolution": [9, 9],
              "mass": 0.2, "stiffness": 200, "damping": 0.05, "pinned": ["corner_00", "corner_10"],
              "node_radius": 0.02, "color": [0.2, 0.4, 0.9]}]})";

}  // namespace

TEST_CASE("renders are byte-identical run to run, and OSMesa equals EGL") {
  const Image a = renderScene(kShadowScene, gl::Backend::OSMesa, 5);
  const Image b = renderScene(kShadowScene, gl::Backend::OSMesa, 5);
  CHECK(a.rgb == b.rgb);
  auto egl = gl::createContext(gl::Backend::Egl);
  if (!egl.ok()) {
    MESSAGE("EGL unavailable here: " << egl.error().headline());
    return;
  }
  egl = Error();  // release it before the helper makes its own
  const Image c = renderScene(kShadowScene, gl::Backend::Egl, 5);
  CHECK(a.rgb == c.rgb);
  // The picture is not trivially uniform: the net, objects and shadows are there.
  const ImageDiff d = compareImages(a, renderScene(kShadowScene, gl::Backend::OSMesa, 0), 16);
  CHECK(d.over > 100);
}

TEST_CASE("golden images of the test scenes, within tolerance") {
  // REEL_UPDATE_GOLDEN=1 rewrites the goldens; otherwise a failing comparison writes a diff image.
  const bool update = std::getenv("REEL_UPDATE_GOLDEN") != nullptr;
  const fs::path dir = fs::path(REEL_SOURCE_DIR) / "tests";
  int compared = 0;
  for (const auto& e : fs::directory_iterator(dir / "scenes")) {
    if (e.path().extension() != ".json") continue;
    CAPTURE(e.path().string());
    auto text = io::readFile(e.path().string(), 1 << 20);
    REQUIRE(text.ok());
    const int frame = 10;  // a frame where things have moved
    const Image img = renderScene(text.value(), gl::Backend::OSMesa, frame);
    const fs::path golden = dir / "golden" / (e.path().stem().string() + ".png");
    if (update) {
      REQUIRE(io::writePng(golden.string(), img, {}, 9).ok());
      continue;
    }
    auto want = io::readPng(golden.string());
    REQUIRE_MESSAGE(want.ok(), "missing golden " << golden << "; run with REEL_UPDATE_GOLDEN=1");
    REQUIRE(want.value().width == img.width);
    Image diff;
    const ImageDiff d = compareImages(img, want.value(), 16, &diff);
    const bool ok = d.mean_abs <= 1.0 && d.over_fraction <= 0.005;
    if (!ok) {
      const fs::path out = fs::temp_directory_path() / (e.path().stem().string() + "_diff.png");
      (void)io::writePng(out.string(), diff);
      (void)io::writePng((fs::temp_directory_path() / (e.path().stem().string() + "_got.png")).string(), img);
      MESSAGE("diff image: " << out.string());
    }
    CHECK_MESSAGE(ok, "mean " << d.mean_abs << ", max " << d.max_abs << ", " << d.over << " pixels over 16");
    ++compared;
  }
  if (!update) CHECK(compared >= 2);
}

TEST_CASE("PNG files round-trip with their text chunks") {
  Image img(7, 5);  // odd size
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = static_cast<std::uint8_t>(i * 37);
  const std::string path = (fs::temp_directory_path() / "reel_png_test.png").string();
  REQUIRE(io::writePng(path, img, {{"reel:scene", "t"}, {"reel:frame", "3"}}).ok());
  CHECK(!fs::exists(path + ".part"));
  auto back = io::readPng(path);
  REQUIRE(back.ok());
  CHECK(back.value().rgb == img.rgb);
  auto text = io::readPngText(path);
  REQUIRE(text.ok());
  CHECK(text.value() == io::TextChunks{{"reel:scene", "t"}, {"reel:frame", "3"}});
  // Not a PNG, or truncated: clean errors.
  CHECK(!io::readPng(REEL_SOURCE_DIR "/README.md").ok());
  fs::resize_file(path, 60);
  CHECK(!io::readPng(path).ok());
  // Unwritable (its folder would be under a regular file): an Output error and nothing left behind.
  auto st = io::writePng(path + "/x.png", img);
  REQUIRE(!st.ok());
  CHECK(st.error().kind == ErrorKind::Output);
  CHECK(fs::is_regular_file(path));
}

TEST_CASE("videos: frame count, size, rate, codec and pixel format; frames close to the images") {
  // Frames of a moving gradient, at an odd size.
  const int W = 81, H = 47, N = 12;
  std::vector<Image> frames;
  for (int k = 0; k < N; ++k) {
    Image img(W, H);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        std::uint8_t* p = img.pixel(x, y);
        p[0] = static_cast<std::uint8_t>(40 + 2 * x + 5 * k);
        p[1] = static_cast<std::uint8_t>(60 + 3 * y);
        p[2] = static_cast<std::uint8_t>(200 - 2 * x);
      }
    frames.push_back(img);
  }
  struct Want {
    const char* ext;
    const char* codec;
    const char* pix;
    double mean;  // allowed mean absolute error of decoded frames
  };
  for (const Want& w : {Want{".mp4", "h264", "yuv420p", 3.0}, Want{".webm", "vp9", "yuv420p", 4.0},
                        Want{".gif", "gif", "pal8", 20.0}}) {
    CAPTURE(w.ext);
    const std::string path = (fs::temp_directory_path() / (std::string("reel_video_test") + w.ext)).string();
    io::VideoWriter v;
    REQUIRE(v.open(path, W, H, 24).ok());
    for (const Image& f : frames) REQUIRE(v.write(f).ok());
    REQUIRE(v.finish().ok());
    CHECK(!fs::exists(path + ".part"));
    auto info = io::probeVideo(path);
    REQUIRE(info.ok());
    CHECK(info.value().codec == w.codec);
    if (std::string(w.ext) != ".gif") CHECK(info.value().pix_fmt == w.pix);  // FFmpeg decodes GIF to bgra
    CHECK(info.value().frames == N);
    if (std::string(w.ext) != ".gif") CHECK(info.value().fps == doctest::Approx(24.0));
    CHECK(info.value().width >= W);
    CHECK(info.value().width <= W + 1);
    auto dec = io::decodeVideo(path, W, H);
    REQUIRE(dec.ok());
    REQUIRE(dec.value().size() == frames.size());
    for (int k = 0; k < N; k += 5) CHECK(compareImages(dec.value()[k], frames[k], 255).mean_abs < w.mean);
  }
}

TEST_CASE("the sand pattern: pale warm sand, varied, tileable") {
  const Image img = makePattern("sand", 128);
  REQUIRE(img.width == 128);
  REQUIRE(img.height == 128);
  double mean[3] = {0, 0, 0}, sq = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      for (int c = 0; c < 3; ++c) {
        mean[c] += img.pixel(x, y)[c] / (128.0 * 128.0);
        sq += img.pixel(x, y)[c] * img.pixel(x, y)[c] / (3 * 128.0 * 128.0);
      }
  CHECK(mean[0] > 170);  // pale
  CHECK(mean[0] > mean[1]);  // warm
  CHECK(mean[1] > mean[2]);
  const double m = (mean[0] + mean[1] + mean[2]) / 3;
  CHECK(std::sqrt(sq - m * m) > 5);  // not a flat colour
  // Tileable: the last column runs on into the first as any column into the next (rows alike).
  auto step = [&](int x0, int y0, int x1, int y1, bool cols) {
    double s = 0;
    for (int i = 0; i < 128; ++i)
      for (int c = 0; c < 3; ++c)
        s += std::abs(int(img.pixel(cols ? x0 : i, cols ? i : y0)[c]) - int(img.pixel(cols ? x1 : i, cols ? i : y1)[c]));
    return s / (3 * 128);
  };
  double inner_x = 0, inner_y = 0;
  for (int k = 0; k < 127; ++k) {
    inner_x += step(k, 0, k + 1, 0, true) / 127;
    inner_y += step(0, k, 0, k + 1, false) / 127;
  }
  CHECK(step(127, 0, 0, 0, true) < 1.3 * inner_x + 0.5);
  CHECK(step(0, 127, 0, 0, false) < 1.3 * inner_y + 0.5);
  CHECK(makePattern("no such pattern", 16).width == 0);
}
