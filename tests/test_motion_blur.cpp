// Motion blur by sub-frame accumulation (core/motion.*, render.motion_blur): the shutter's sample
// times, the interpolated draw list, and a moving ball smeared along its path, the same through
// `still`, `render`, a range that starts mid-film and the farm cache.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "core/motion.h"
#include "helpers.h"
#include "io/png.h"

using namespace reel;
using namespace reel::test;

TEST_CASE("motion blur: the shutter's sample times are the midpoints of its open part") {
  const std::vector<double> half = shutterTimes(180, 4);
  REQUIRE(half.size() == 4);
  CHECK(half[0] == doctest::Approx(0.5625));
  CHECK(half[3] == doctest::Approx(0.9375));
  const std::vector<double> whole = shutterTimes(360, 2);
  CHECK(whole[0] == doctest::Approx(0.25));
  CHECK(whole[1] == doctest::Approx(0.75));
}

TEST_CASE("motion blur: a draw list between two frames moves what both frames drew alike") {
  DrawList a, b;
  a.camera.position = Vec3(0, 0, 0), b.camera.position = Vec3(4, 0, 0);
  a.camera.fov_deg = 40, b.camera.fov_deg = 60;
  auto tri = [](float x) {
    auto m = std::make_shared<TriMesh>();
    m->addVertex(Vec3(x, 0, 0), Vec3(0, 0, 1));
    m->addVertex(Vec3(x + 1, 0, 0), Vec3(0, 0, 1));
    m->addVertex(Vec3(x, 1, 0), Vec3(1, 0, 0));
    m->indices = {0, 1, 2};
    return m;
  };
  a.meshes.push_back({tri(0), true, {}});
  b.meshes.push_back({tri(2), true, {}});
  a.spheres.push_back({{0, 0, 0, 1, 1, 1}, {}, 0.1f, {}});
  b.spheres.push_back({{4, 0, 0, 1, 1, 5}, {}, 0.1f, {}});
  a.spheres.push_back({{0, 0, 0}, {}, 0.1f, {}});  // one more sphere emitted by frame k: not alike
  b.spheres.push_back({{7, 7, 7, 8, 8, 8}, {}, 0.1f, {}});
  a.tubes.push_back({{0, 0, 0, 0, 0, 2}, 0.01f, {}});
  b.tubes.push_back({{2, 0, 0, 2, 0, 2}, 0.01f, {}});
  DrawInstances ia, ib;
  ia.transforms = std::vector<float>(12, 0.0f);
  ib.transforms = std::vector<float>(12, 1.0f);
  ia.phases = {3.0f};
  ib.phases = {-3.0f};  // 0.28 rad on, the short way across ±π
  a.instances.push_back(ia);
  b.instances.push_back(ib);
  b.previous = std::make_shared<const DrawList>(a);
  const DrawList h = shutterSample(a, b, 0.25);
  CHECK(h.previous == nullptr);
  CHECK(h.camera.position.x() == doctest::Approx(1.0));
  CHECK(h.camera.fov_deg == doctest::Approx(45.0));
  CHECK(h.meshes[0].mesh->positions[0] == doctest::Approx(0.5f));
  CHECK(h.meshes[0].mesh->positions[3] == doctest::Approx(1.5f));
  const float* n = &h.meshes[0].mesh->normals[6];  // (1,0,0) then (1,0,0): unit
  CHECK(std::hypot(n[0], n[1], n[2]) == doctest::Approx(1.0f));
  CHECK(h.spheres[0].centers[0] == doctest::Approx(1.0f));
  CHECK(h.spheres[0].centers[5] == doctest::Approx(2.0f));
  CHECK(h.spheres[1].centers == b.spheres[1].centers);
  CHECK(h.tubes[0].ends[0] == doctest::Approx(0.5f));
  CHECK(h.instances[0].transforms[4] == doctest::Approx(0.25f));
  CHECK(h.instances[0].phases[0] == doctest::Approx(3.0 + 0.25 * (2 * kPi - 6.0)).epsilon(1e-5));
  // Items pair by the body that drew them: when body 0's mesh is gone at frame k, body 1's mesh
  // moves from body 1's, not from the mesh that was first in the list.
  DrawList c = a, e = b;
  c.meshes = {{tri(0), true, {}, 0}, {tri(5), true, {}, 1}};
  e.meshes = {{tri(7), true, {}, 1}};
  CHECK(shutterSample(c, e, 0.5).meshes[0].mesh->positions[0] == doctest::Approx(6.0f));
  // A mesh remeshed between the frames (a liquid's surface) is drawn as at frame k.
  b.meshes[0].mesh = std::make_shared<TriMesh>(makeBox(Vec3(1, 1, 1)));
  CHECK(shutterSample(a, b, 0.25).meshes[0].mesh == b.meshes[0].mesh);
}

TEST_CASE("motion blur: a fast ball is smeared along its path, the same through still, render and a range") {
  namespace fs = std::filesystem;
  const fs::path d = freshDir("motion_blur");
  // A white ball crossing a dark picture at 12 m/s (0.4 m a frame at 30 fps), seen side on.
  auto write = [&](const std::string& name, const std::string& blur) {
    std::ofstream(d / name) << R"({"format": "reel/1", "duration": 0.5, "fps": 30,
      "render": {"width": 320, "height": 180, "samples": 1, "background": {"top": [0, 0, 0], "bottom": [0, 0, 0]})"
                            << blur << R"(},
      "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "fov_deg": 40},
      "lights": [{"type": "ambient", "color": [1, 1, 1], "intensity": 1}],
      "objects": [{"type": "sphere", "name": "ball", "center": [-1.5, 0, 0], "radius": 0.1, "color": [1, 1, 1],
                   "motion": {"keys": [{"time": 0, "position": [-1.5, 0, 0]}, {"time": 0.25, "position": [1.5, 0, 0]}]}}]})";
    return (d / name).string();
  };
  const std::string sharp = write("sharp.json", ""), blurred = write("blurred.json", R"(, "motion_blur": {"shutter_deg": 180, "samples": 8})");
  auto still = [&](const std::string& scene, const std::string& out) {
    REQUIRE(runReel("still --no-cache " + scene + " --frame 7 -o " + (d / out).string()).code == 0);
    auto img = io::readPng((d / out).string());
    REQUIRE(img.ok());
    return img.value();
  };
  const Image a = still(sharp, "sharp.png"), b = still(blurred, "blurred.png");
  // Lit pixels on the ball's row: the sharp ball is about 2·0.1 m wide, the smear adds half a
  // frame's travel (0.2 m); its middle is as bright as the ball, its ends fade.
  auto row = [](const Image& img, int& lit, int& partial, long& ink) {
    lit = partial = 0;
    ink = 0;
    for (int x = 0; x < img.width; ++x) {
      const int v = img.pixel(x, img.height / 2)[0];
      ink += v;
      if (v > 8) ++lit;
      if (v > 8 && v < 200) ++partial;
    }
  };
  int lit_a, part_a, lit_b, part_b;
  long ink_a, ink_b;
  row(a, lit_a, part_a, ink_a);
  row(b, lit_b, part_b, ink_b);
  const double px_per_m = 180 / (2 * 3 * std::tan(20 * kPi / 180));
  CAPTURE(lit_a);
  CAPTURE(lit_b);
  CHECK(lit_a == doctest::Approx(0.2 * px_per_m).epsilon(0.25));
  CHECK(lit_b - lit_a == doctest::Approx(0.2 * px_per_m).epsilon(0.3));
  CHECK(part_b > part_a + 8);
  // The smear's centre lags the ball at frame 7 by a quarter of a frame's travel (0.1 m).
  auto centre = [](const Image& img) {
    double w = 0, s = 0;
    for (int x = 0; x < img.width; ++x) {
      const double v = img.pixel(x, img.height / 2)[0];
      w += v;
      s += v * x;
    }
    return s / w;
  };
  CHECK(centre(a) - centre(b) == doctest::Approx(0.1 * px_per_m).epsilon(0.3));
  // The same frame from a render of the film and from a render of frames 7-8 only.
  REQUIRE(runReel("render --no-cache " + blurred + " -o " + (d / "all_###.png").string()).code == 0);
  REQUIRE(runReel("render --no-cache " + blurred + " --frames 7-8 -o " + (d / "part_###.png").string()).code == 0);
  CHECK(fileBytes(d / "all_008.png") == fileBytes(d / "blurred.png"));
  CHECK(fileBytes(d / "part_008.png") == fileBytes(d / "blurred.png"));
  // And from the farm cache: a chunk starting at frame 7 restores frame 6 for its shutter.
  REQUIRE(runReel("simulate -q " + blurred + " --cache " + (d / "farm").string()).code == 0);
  REQUIRE(runReel("render -q --cache " + (d / "farm").string() + " " + blurred + " --frames 7-8 -o " + (d / "farm_###.png").string()).code == 0);
  CHECK(io::readPng((d / "farm_008.png").string()).value().rgb == b.rgb);
  // Frame 0 has no frame before it: drawn sharp.
  REQUIRE(runReel("render --no-cache " + sharp + " --frames 0-0 -o " + (d / "sharp_###.png").string()).code == 0);
  auto pixels = [&](const std::string& f) { return io::readPng((d / f).string()).value().rgb; };
  CHECK(pixels("all_001.png") == pixels("sharp_001.png"));
  // Bad input.
  checkHas(badInputError(std::string(R"({"format": "reel/1", "duration": 1, "render": {"motion_blur": {"shutter_deg": 400}}})")),
           "/render/motion_blur/shutter_deg");
  checkHas(badInputError(std::string(R"({"format": "reel/1", "duration": 1, "render": {"motion_blur": {"samples": 1}}})")),
           "/render/motion_blur/samples");
}

TEST_CASE("depth of field: the lens' points spread over the aperture, also looking straight down") {
  DrawList list;
  list.camera.position = Vec3(0, 3, 0);
  list.camera.target = Vec3(0, 0, 0);  // along the default up (0, 1, 0)
  list.camera.aperture = 0.2;
  list.camera.lens_samples = 8;
  REQUIRE(picturesPerFrame(list) == 8);
  Vec3 mean = Vec3::Zero();
  double widest = 0;
  for (int j = 0; j < 8; ++j) {
    const DrawCamera c = picture(list, j, 8).camera;
    CHECK(c.position.y() == doctest::Approx(3.0));  // on the lens' plane
    CHECK(c.target == Vec3(0, 0, 0));                // all looking at the point in focus
    widest = std::max(widest, (c.position - list.camera.position).norm());
    mean += c.position / 8;
  }
  CHECK(widest > 0.07);
  CHECK(widest <= 0.1);
  CHECK((mean - list.camera.position).norm() < 0.03);
}

TEST_CASE("depth of field: what is in focus stays sharp, what lies behind spreads over its circle of confusion") {
  namespace fs = std::filesystem;
  const fs::path d = freshDir("depth_of_field");
  // A white ball in focus 3 m away on the left, a white ball 9 m away on the right, black behind.
  auto write = [&](const std::string& name, const std::string& lens) {
    std::ofstream(d / name) << R"({"format": "reel/1", "duration": 0.1, "fps": 30,
      "render": {"width": 320, "height": 180, "samples": 1, "background": {"top": [0, 0, 0], "bottom": [0, 0, 0]}},
      "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "fov_deg": 40)" << lens << R"(},
      "lights": [{"type": "ambient", "color": [1, 1, 1], "intensity": 1}],
      "objects": [{"type": "sphere", "name": "near", "center": [-0.5, 0, 0], "radius": 0.25, "color": [1, 1, 1]},
                  {"type": "sphere", "name": "far", "center": [2.0, 0, -6], "radius": 0.75, "color": [1, 1, 1]}]})";
    return (d / name).string();
  };
  auto still = [&](const std::string& scene, const std::string& out) {
    REQUIRE(runReel("still --no-cache " + scene + " --frame 0 -o " + (d / out).string()).code == 0);
    return io::readPng((d / out).string()).value();
  };
  const Image pin = still(write("pin.json", ""), "pin.png");
  const Image lens = still(write("lens.json", R"(, "depth_of_field": {"aperture": 0.1, "samples": 32})"), "lens.png");
  // The width of the ramp from 10% to 90% white where the middle row crosses each ball's left edge.
  auto edge = [](const Image& img, int from, int to) {
    int lo = -1, hi = -1;
    for (int x = from; x < to; ++x) {
      const int v = img.pixel(x, img.height / 2)[0];
      if (lo < 0 && v > 0.1 * 255) lo = x;
      if (hi < 0 && v > 0.9 * 255) hi = x;
    }
    return hi - lo;
  };
  const int mid = 160;  // the near ball lies left of the middle, the far one right of it
  CHECK(edge(pin, 0, mid) <= 2);
  CHECK(edge(pin, mid, 320) <= 2);
  CHECK(edge(lens, 0, mid) <= 2);  // in focus
  // Behind: the circle of confusion on the plane in focus is A·(d − f)/d = 0.1·6/9 m; in pixels
  // there, 180 / (2·3·tan 20°) px/m. The 10–90% ramp across a disc's edge spans about 80% of it.
  const double coc_px = 0.1 * 6.0 / 9.0 * 180 / (2 * 3 * std::tan(20 * kPi / 180));
  CAPTURE(coc_px);
  CHECK(edge(lens, mid, 320) == doctest::Approx(0.8 * coc_px).epsilon(0.35));
  checkHas(badInputError(std::string(R"({"format": "reel/1", "duration": 1, "camera": {"depth_of_field": {"focus_distance": 2}}})")),
           "/camera/depth_of_field/aperture");
  checkHas(badInputError(std::string(R"({"format": "reel/1", "duration": 1, "camera": {"depth_of_field": {"aperture": 0.1, "samples": 1}}})")),
           "/camera/depth_of_field/samples");
}
