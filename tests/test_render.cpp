// The renderer against analytic images, itself (determinism, OSMesa = EGL), PNG and video files.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/image_compare.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/patterns.h"
#include "core/scene_view.h"
#include "helpers.h"
#include "render_helpers.h"
#include "io/files.h"
#include "io/png.h"
#include "io/video.h"
#include "render/projection.h"
#include "render/renderer.h"
#include "render/uploads.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;
namespace fs = std::filesystem;

namespace {

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
  for (const auto& row : {std::tuple{0.5, 60.0, 0.0}, std::tuple{0.8, 0.0, 0.0}, std::tuple{0.3, 45.0, 0.2},
                          std::tuple{0.6, 100.0, 0.25}}) {
    const double rho = std::get<0>(row), theta = std::get<1>(row), amb = std::get<2>(row);
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
  // The films' look too: environment, occlusion, soft shadows' noise, ACES.
  auto look = io::readFile(std::string(REEL_SOURCE_DIR) + "/tests/scenes/film_look.json", 1 << 20);
  REQUIRE(look.ok());
  const Image la = renderScene(look.value(), gl::Backend::OSMesa, 3);
  CHECK(la.rgb == renderScene(look.value(), gl::Backend::OSMesa, 3).rgb);
  CHECK(la.rgb == renderScene(look.value(), gl::Backend::Egl, 3).rgb);
  // The picture is not trivially uniform: the net, objects and shadows are there.
  const ImageDiff d = compareImages(a, renderScene(kShadowScene, gl::Backend::OSMesa, 0), 16);
  CHECK(d.over > 100);
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

TEST_CASE("videos: BT.709 throughout, so saturated colours come back (a BT.601 matrix under BT.709 tags would not)") {
  // Four flat 32-pixel blocks: red, green, blue, grey (4:2:0 chroma is exact inside a block).
  const std::uint8_t colours[4][3] = {{230, 20, 20}, {20, 220, 30}, {25, 30, 235}, {128, 128, 128}};
  Image img(128, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 128; ++x) std::copy(colours[x / 32], colours[x / 32] + 3, img.pixel(x, y));
  for (const char* ext : {".mp4", ".webm"}) {
    CAPTURE(ext);
    const std::string path = (fs::temp_directory_path() / (std::string("reel_video_709") + ext)).string();
    io::VideoWriter v;
    REQUIRE(v.open(path, 128, 32, 10).ok());
    for (int k = 0; k < 3; ++k) REQUIRE(v.write(img).ok());
    REQUIRE(v.finish().ok());
    auto info = io::probeVideo(path);
    REQUIRE(info.ok());
    CHECK(info.value().color == "bt709/bt709");
    auto dec = io::decodeVideo(path, 128, 32);
    REQUIRE(dec.ok());
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 3; ++c) {
        CAPTURE(b);
        CAPTURE(c);
        CHECK(std::abs(dec.value()[1].pixel(16 + 32 * b, 16)[c] - colours[b][c]) <= 8);
      }
  }
}

namespace {

// The pixel where world point p appears (column, row from the top).
std::pair<int, int> pixelOf(const DrawList& list, int W, int H, const Vec3& p) {
  const DrawCamera& c = list.camera;
  const Mat4f vp = perspective(c.fov_deg, double(W) / H, 0.5, 100) * lookAt(c.position, c.target, c.up);
  const Eigen::Vector4f q = vp * Eigen::Vector4f(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  return {int((q.x() / q.w() * 0.5 + 0.5) * W), int((0.5 - q.y() / q.w() * 0.5) * H)};
}

// A mesh of one flat colour (per-vertex colours), to tell meshes apart in a picture.
std::shared_ptr<const TriMesh> colouredMesh(TriMesh m, const Vec3& c) {
  m.colors.clear();
  for (std::size_t i = 0; i < m.vertexCount(); ++i)
    for (int k = 0; k < 3; ++k) m.colors.push_back(static_cast<float>(c[k]));
  return std::make_shared<const TriMesh>(std::move(m));
}

}  // namespace

TEST_CASE("an instanced copy draws the pixels of the same mesh placed by a DrawMesh") {
  DirectRenderer dr(96, 72, 4);
  auto fish = std::make_shared<const TriMesh>(makeFishMesh(1));
  const Mat3 R = rotationFromEulerDeg(Vec3(10, 35, 0));
  const Vec3 t(0.1, 0.05, 0.4);
  DrawList list = ambientList(Vec3(0.9, 0.6, 1.4), Vec3(0, 0, -0.1));
  LightDesc key;
  key.direction = Vec3(-0.4, -1.0, -0.3);
  list.lights.push_back(key);
  list.lights[0].intensity = 0.3;
  DrawMaterial mat;
  mat.color = Vec3(0.9, 0.6, 0.3);
  mat.specular = 0.3;
  // As a mesh, transformed on the CPU.
  DrawList as_mesh = list;
  TriMesh placed = *fish;
  placed.transform(R, t);
  as_mesh.meshes.push_back({std::make_shared<const TriMesh>(placed), false, mat});
  // As one instanced copy.
  DrawList as_copy = list;
  DrawInstances d;
  d.mesh = fish;
  d.material = mat;
  addCopy(d, R, 1.0, t);
  as_copy.instances.push_back(d);
  const Image a = dr.draw(as_mesh), b = dr.draw(as_copy);
  const ImageDiff diff = compareImages(a, b, 8);
  CHECK(diff.mean_abs < 0.2);
  CHECK(diff.over <= 3);
  CHECK(compareImages(a, dr.draw(list), 16).over > 100);  // the fish is there at all
}

TEST_CASE("instanced copies: per-copy colours, shadows, the far level of detail") {
  const int W = 96, H = 48;
  DirectRenderer dr(W, H, 1);
  auto box = std::make_shared<const TriMesh>(makeBox(Vec3(0.4, 0.4, 0.4)));
  // Two white boxes tinted red and blue, side by side, seen from the front.
  DrawList list = ambientList(Vec3(0, 0, 2.5), Vec3(0, 0, 0));
  DrawInstances d;
  d.mesh = box;
  d.material.color = Vec3(1, 1, 1);
  addCopy(d, Mat3::Identity(), 1.0, Vec3(-0.6, 0, 0));
  addCopy(d, Mat3::Identity(), 1.0, Vec3(0.6, 0, 0));
  d.colors = {1.0f, 0.1f, 0.1f, 0.1f, 0.1f, 1.0f};
  list.instances.push_back(d);
  Image img = dr.draw(list);
  const auto [lx, ly] = pixelOf(list, W, H, Vec3(-0.6, 0, 0.2));
  const auto [rx, ry] = pixelOf(list, W, H, Vec3(0.6, 0, 0.2));
  CHECK(img.pixel(lx, ly)[0] == 255);
  CHECK(img.pixel(lx, ly)[2] < 100);
  CHECK(img.pixel(rx, ry)[2] == 255);
  CHECK(img.pixel(rx, ry)[0] < 100);
  // Without colours both are white.
  list.instances[0].colors.clear();
  img = dr.draw(list);
  CHECK(img.pixel(lx, ly)[2] == 255);
  CHECK(img.pixel(rx, ry)[0] == 255);

  // Level of detail: red near meshes, green far ones, switched at 2.5 m from the camera.
  DrawInstances lod;
  lod.mesh = colouredMesh(makeBox(Vec3(0.4, 0.4, 0.4)), Vec3(1, 0, 0));
  lod.far_mesh = colouredMesh(makeBox(Vec3(0.4, 0.4, 0.4)), Vec3(0, 1, 0));
  lod.far_distance = 2.5;
  lod.material.color = Vec3(1, 1, 1);
  addCopy(lod, Mat3::Identity(), 1.0, Vec3(-0.6, 0, 0.5));  // 2.09 m away
  addCopy(lod, Mat3::Identity(), 1.0, Vec3(0.6, 0, -0.5));  // 3.06 m away
  list.instances = {lod};
  img = dr.draw(list);
  const auto [nx, ny] = pixelOf(list, W, H, Vec3(-0.6, 0, 0.7));
  const auto [fx, fy] = pixelOf(list, W, H, Vec3(0.6, 0, -0.3));
  CHECK(img.pixel(nx, ny)[0] == 255);
  CHECK(img.pixel(nx, ny)[1] == 0);
  CHECK(img.pixel(fx, fy)[1] == 255);
  CHECK(img.pixel(fx, fy)[0] == 0);
  // The split keeps each part in the list's order.
  DrawInstances many;
  for (int i = 0; i < 6; ++i) addCopy(many, Mat3::Identity(), 1.0, Vec3(i, 0, 0));
  std::array<std::vector<float>, 2> parts;
  packInstances(many, Vec3(0, 0, 0), 2.5, parts);
  REQUIRE(parts[0].size() == 3 * kInstanceFloats);
  REQUIRE(parts[1].size() == 3 * kInstanceFloats);
  for (int i = 0; i < 3; ++i) {
    CHECK(parts[0][kInstanceFloats * i + 9] == float(i));
    CHECK(parts[1][kInstanceFloats * i + 9] == float(i + 3));
    CHECK(parts[0][kInstanceFloats * i + 12] == 1.0f);  // white without colours
    CHECK(parts[0][kInstanceFloats * i + 15] == 0.0f);  // no phase without phases
  }
  packInstances(many, Vec3(0, 0, 0), 0.0, parts);
  CHECK(parts[0].size() == 6 * kInstanceFloats);
  CHECK(parts[1].empty());
}

TEST_CASE("instanced copies cast shadows") {
  // A floor lit from straight above, a box held over it: the floor below the box is dark, the
  // floor as far to the other side is not.
  const int W = 96, H = 48;
  DirectRenderer dr(W, H, 1);
  DrawList lit = ambientList(Vec3(0, 4, 4), Vec3(0, 0, 0));
  lit.lights[0].intensity = 0.2;
  LightDesc sun;
  sun.direction = Vec3(0, -1, 0);
  sun.shadows = true;
  lit.lights.push_back(sun);
  lit.meshes.push_back({std::make_shared<const TriMesh>(makeQuad(6, 6)), false, DrawMaterial{}});
  DrawInstances above;
  above.mesh = std::make_shared<const TriMesh>(makeBox(Vec3(0.4, 0.4, 0.4)));
  addCopy(above, Mat3::Identity(), 2.0, Vec3(1.2, 1.0, -0.8));
  const Image bare = dr.draw(lit);
  lit.instances.push_back(above);
  const Image shadowed = dr.draw(lit);
  const auto [sx, sy] = pixelOf(lit, W, H, Vec3(1.2, 0, -0.8));
  const auto [ox, oy] = pixelOf(lit, W, H, Vec3(-1.2, 0, -0.8));
  CHECK(shadowed.pixel(sx, sy)[0] + 40 < bare.pixel(sx, sy)[0]);
  CHECK(std::abs(shadowed.pixel(ox, oy)[0] - bare.pixel(ox, oy)[0]) <= 1);
}

TEST_CASE("the travelling wave bends copies sideways: phase π mirrors phase 0") {
  // A fish along z seen from straight above: image columns run along world x (mirrored), rows
  // along z. Ambient light only, so the picture of a mirrored shape is the mirrored picture.
  const int W = 80, H = 96;
  DirectRenderer dr(W, H, 4);
  DrawList list = ambientList(Vec3(0, 2.6, -0.5), Vec3(0, 0, -0.5), Vec3(0, 0, 1));
  DrawInstances d;
  d.mesh = std::make_shared<const TriMesh>(makeFishMesh(1));
  d.material.color = Vec3(1, 1, 1);
  addCopy(d, Mat3::Identity(), 1.0, Vec3(0, 0, 0));
  d.wave_amplitude = 0.12f;
  d.wave_number = float(kPi / 2);  // the tail tip is a quarter wave behind the start
  d.wave_start = -0.2f;
  d.wave_end = -1.0f;
  list.instances.push_back(d);
  const Image straight = dr.draw(list);
  list.instances[0].phases = {0.0f};
  const Image bent = dr.draw(list);
  list.instances[0].phases = {float(kPi)};
  const Image other = dr.draw(list);
  CHECK(compareImages(straight, bent, 16).over > 40);
  // Phase π displaces every point by minus what phase 0 does: the mirror image, row by row the
  // same coverage about the mirrored centre (to a fraction of a pixel: the samples of a pixel are
  // not placed symmetrically).
  double total0 = 0, total1 = 0, worst = 0, mean = 0;
  int rows = 0;
  for (int y = 0; y < H; ++y) {
    double s0 = 0, c0 = 0, s1 = 0, c1 = 0;
    for (int x = 0; x < W; ++x) {
      s0 += bent.pixel(x, y)[0];
      c0 += bent.pixel(x, y)[0] * (x + 0.5);
      s1 += other.pixel(x, y)[0];
      c1 += other.pixel(x, y)[0] * (x + 0.5);
    }
    total0 += s0;
    total1 += s1;
    if (s0 < 255 || s1 < 255) continue;
    ++rows;
    worst = std::max(worst, std::abs(c0 / s0 + c1 / s1 - W));
    mean += std::abs(c0 / s0 + c1 / s1 - W);
  }
  CHECK(rows > 30);
  CHECK(total1 == doctest::Approx(total0).epsilon(0.01));
  CHECK(mean / rows < 0.2);
  CHECK(worst < 1.0);
  // At phase 0 the tail fin (z from −0.9 to −1) moves by a(z)·sin(−k·(start − z)): −0.082 m to
  // −0.114 m along x, to the right in the picture (the camera's right is −x).
  auto tailCentre = [&](const Image& img) {
    double sum = 0, weight = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        // Rows of the tail: z from −0.9 to −1.0, the bottom of the picture (+z is up).
        const double z = -0.5 - (y + 0.5 - H / 2.0) / (H / 2.0) * 2.6 * std::tan(20 * kPi / 180);
        if (z > -0.9) continue;
        sum += img.pixel(x, y)[0] * (x + 0.5);
        weight += img.pixel(x, y)[0];
      }
    return sum / std::max(weight, 1.0);
  };
  const double px_per_m = (H / 2.0) / (2.6 * std::tan(20 * kPi / 180));
  const double shift = tailCentre(bent) - tailCentre(straight);
  CHECK(shift > 0.08 * px_per_m);
  CHECK(shift < 0.115 * px_per_m);
}

TEST_CASE("the ground patterns: pale warm sand, warm wood, neutral concrete; varied and tileable") {
  for (const char* name : {"sand", "wood", "concrete"}) {
    CAPTURE(name);
    const Image img = makePattern(name, 128);
    REQUIRE(img.width == 128);
    REQUIRE(img.height == 128);
    double mean[3] = {0, 0, 0}, sq = 0;
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x)
        for (int c = 0; c < 3; ++c) {
          mean[c] += img.pixel(x, y)[c] / (128.0 * 128.0);
          sq += img.pixel(x, y)[c] * img.pixel(x, y)[c] / (3 * 128.0 * 128.0);
        }
    const std::string n = name;
    if (n == "sand") CHECK(mean[0] > 170);  // pale
    if (n != "concrete") {                   // warm
      CHECK(mean[0] > mean[1] + 5);
      CHECK(mean[1] > mean[2] + 5);
    } else {
      CHECK(std::abs(mean[0] - mean[2]) < 8);  // grey
    }
    const double m = (mean[0] + mean[1] + mean[2]) / 3;
    CHECK(std::sqrt(sq - m * m) > 4);  // not a flat colour
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
  }
  CHECK(makePattern("no such pattern", 16).width == 0);
}

TEST_CASE("per-vertex gloss adds a wet sheen where it is 1 and changes nothing where it is 0") {
  const int W = 64, H = 48;
  DirectRenderer dr(W, H, 1);
  // The sun mirrored about the quad's normal into the camera: the highlight at its centre.
  DrawList list = sunlit(Vec3(0, 1, 1.2), Vec3(0, -1, 1.2).normalized());
  TriMesh quad = makeQuad(2, 2);
  auto drawWith = [&](const std::vector<float>& gloss) {
    TriMesh m = quad;
    m.gloss = gloss;
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(std::move(m));
    d.material.color = Vec3(0.3, 0.3, 0.3);
    d.material.specular = 1e-3;
    list.meshes = {d};
    return dr.draw(list);
  };
  const Image dry = drawWith({});
  const Image zero = drawWith(std::vector<float>(quad.vertexCount(), 0.0f));
  const Image wet = drawWith(std::vector<float>(quad.vertexCount(), 1.0f));
  CHECK(zero.rgb == dry.rgb);
  const auto [cx, cy] = pixelOf(list, W, H, Vec3::Zero());
  CHECK(int(wet.pixel(cx, cy)[0]) > int(dry.pixel(cx, cy)[0]) + 60);
}

TEST_CASE("per-vertex gloss below 0 dulls a surface: at grazing its highlight is faint and in its own colour, not white") {
  const int W = 64, H = 48;
  DirectRenderer dr(W, H, 1);
  // Seen at 80 degrees from the normal, a sun mirrored into the camera: a Fresnel rim's angle.
  const double a = 80.0 * kPi / 180.0;
  DrawList list = sunlit(Vec3(0, std::cos(a), std::sin(a)) * 2.0, Vec3(0, -std::cos(a), std::sin(a)));
  TriMesh quad = makeQuad(4, 4);
  const Vec3 brown(0.2, 0.1, 0.05);
  auto drawWith = [&](float gloss) {
    TriMesh m = quad;
    m.gloss.assign(m.vertexCount(), gloss);
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(std::move(m));
    d.material.color = brown;
    d.material.specular = 0.5;
    list.meshes = {d};
    return dr.draw(list);
  };
  const Image plain = drawWith(0.0f), dull = drawWith(-1.0f);
  const auto [cx, cy] = pixelOf(list, W, H, Vec3::Zero());
  auto linear = [](const std::uint8_t* px) {
    Vec3 v;
    for (int c = 0; c < 3; ++c) v[c] = std::pow(px[c] / 255.0, 2.2);
    return v;
  };
  // The diffuse term alone (no specular): what each highlight is measured over.
  DrawList bare = list;
  const Vec3 p = linear(plain.pixel(cx, cy)), q = linear(dull.pixel(cx, cy));
  Vec3 base;
  {
    TriMesh m = quad;
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(std::move(m));
    d.material.color = brown;
    bare.meshes = {d};
    base = linear(dr.draw(bare).pixel(cx, cy));
  }
  const Vec3 hp = p - base, hq = q - base;  // the highlights
  MESSAGE("highlight, gloss 0: " << hp.transpose() << "; gloss -1: " << hq.transpose() << " over " << base.transpose());
  // The plain surface's grazing highlight is white and strong; the dulled one's is there, far
  // fainter, and in the brown's own colour (blue well under red, as the albedo's 0.25).
  CHECK(hp[2] > 0.8 * hp[0]);
  CHECK(hq[0] > 0.005);
  CHECK(hq[0] < 0.3 * hp[0]);
  CHECK(hq[2] < 0.5 * hq[0]);
}

TEST_CASE("a fading solid drawn front_only blends its nearest surface alone: a ball inside it does not show through") {
  DirectRenderer dr(64, 64, 1);
  const DrawList base = ambientList(Vec3(0, 0, 3), Vec3::Zero());
  auto ball = [](double r, const Vec3& color, bool front_only) {
    DrawMaterial m;
    m.color = color;
    m.opacity = 0.5;
    m.front_only = front_only;
    return DrawMesh{std::make_shared<const TriMesh>(makeUvSphere(r, 32, 16)), false, m};
  };
  auto draw = [&](bool front_only, bool inner, bool inner_front_only) {
    DrawList list = base;
    list.meshes.push_back(ball(0.5, Vec3(0.9, 0.9, 0.9), front_only));  // the skin, fading
    if (inner) list.meshes.push_back(ball(0.3, Vec3(0.9, 0.05, 0.05), inner_front_only));  // what lies inside it
    return dr.draw(list);
  };
  const Image alone = draw(true, false, true), front = draw(true, true, true), every = draw(false, true, false);
  // A ball blended whole inside the fading one still shows through it (drawn before it).
  const Image mixed = draw(true, true, false);
  CHECK(int(mixed.pixel(32, 32)[0]) > int(alone.pixel(32, 32)[0]) + 20);  // (over a black background: redder)
  const std::uint8_t *a = alone.pixel(32, 32), *f = front.pixel(32, 32), *e = every.pixel(32, 32);
  MESSAGE("the middle: white alone " << int(a[0]) << " " << int(a[1]) << ", front only " << int(f[0]) << " " << int(f[1])
                                      << ", every surface " << int(e[0]) << " " << int(e[1]));
  CHECK(std::abs(int(f[1]) - int(a[1])) <= 1);  // the inner ball hidden
  CHECK(std::abs(int(f[0]) - int(a[0])) <= 1);
  CHECK(int(e[1]) < int(a[1]) - 20);  // blended through without it
  CHECK(compareImages(alone, dr.draw(base), 16).over > 100);  // the fading ball is there at all
}
