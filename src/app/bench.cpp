// reel bench: one JSON line per measurement (DESIGN 8).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/body_kinds.h"
#include "app/bench.h"
#include "app/commands.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/patterns.h"
#include "core/random.h"
#include "core/scene_view.h"
#include "io/video.h"
#include "render/renderer.h"
#include "sim/world.h"
#include "core/parallel.h"

namespace reel::app {
namespace {

using Clock = std::chrono::steady_clock;

// A wavy sheet of about `tris` triangles filling the view of the bench camera.
TriMesh wavySheet(int tris) {
  const int n = static_cast<int>(std::sqrt(tris / 2.0));
  TriMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double u = double(i) / n, v = double(j) / n;
      const double x = 4.0 * (u - 0.5), z = 3.0 * (v - 0.5);
      const double y = 0.15 * std::sin(9 * u) * std::cos(7 * v);
      const Vec3 nrm = Vec3(-0.15 * 9 / 4.0 * std::cos(9 * u) * std::cos(7 * v), 1.0,
                            0.15 * 7 / 3.0 * std::sin(9 * u) * std::sin(7 * v)).normalized();
      m.addVertex(Vec3(x, y, z), nrm, u, v);
    }
  const auto row = static_cast<std::uint32_t>(n + 1);
  for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
      const std::uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  return m;
}

// Frames per second of a draw list, drawn for `seconds` after one warm-up frame.
double framesPerSecond(Renderer& r, const DrawList& list, double seconds) {
  Image img;
  (void)r.draw(list, img);  // warm-up: upload, compile
  int frames = 0;
  const auto t0 = Clock::now();
  double el = 0;
  do {
    (void)r.draw(list, img);
    ++frames;
    el = std::chrono::duration<double>(Clock::now() - t0).count();
  } while (el < seconds);
  return frames / el;
}

// A school: 10,000 copies of the fish mesh (0.35 m long, random headings, tints and wave
// phases) in a 16 x 6 x 26 m box in front of the camera, over a sand floor; copies beyond 7 m
// drawn with the 64-triangle far mesh. Frames per second at 1280x720 with 4 samples, with and
// without shadows, beside the bare draw of the same triangles.
int benchInstances(gl::Context& ctx, double seconds) {
  const int n = 10000;
  const double scale = 0.35;
  DrawList list;
  list.camera.position = Vec3(0, 2.0, 0);
  list.camera.target = Vec3(0, 1.2, -10);
  list.camera.fov_deg = 50;
  DrawInstances d;
  d.mesh = std::make_shared<const TriMesh>(makeFishMesh(1));
  d.far_mesh = std::make_shared<const TriMesh>(makeFishMesh(0));
  d.far_distance = 7.0;
  d.wave_amplitude = 0.08f;
  d.wave_number = 5.0f;
  d.wave_start = -0.15f;
  d.material.color = Vec3(0.75, 0.78, 0.8);
  d.material.specular = 0.3;
  TriMesh bare;  // the same triangles placed on the CPU, each copy at its level of detail
  for (int i = 0; i < n; ++i) {
    auto u = [&](int stream) { return uniformAt(1, static_cast<std::uint64_t>(stream), static_cast<std::uint64_t>(i)); };
    const Vec3 origin(16 * (u(0) - 0.5), 6 * u(1), -4 - 26 * u(2));
    const Mat3 R = Eigen::AngleAxisd(2 * kPi * u(3), Vec3::UnitY()).toRotationMatrix();
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) d.transforms.push_back(static_cast<float>(scale * R(k, a)));
    for (int k = 0; k < 3; ++k) d.transforms.push_back(static_cast<float>(origin[k]));
    for (int k = 0; k < 3; ++k) d.colors.push_back(static_cast<float>(0.6 + 0.4 * u(4 + k)));
    d.phases.push_back(static_cast<float>(2 * kPi * u(7)));
    TriMesh copy = (origin - list.camera.position).norm() > d.far_distance ? *d.far_mesh : *d.mesh;
    copy.transform(scale * R, origin);
    const auto base = static_cast<std::uint32_t>(bare.vertexCount());
    bare.positions.insert(bare.positions.end(), copy.positions.begin(), copy.positions.end());
    for (std::uint32_t v : copy.indices) bare.indices.push_back(base + v);
  }
  list.instances.push_back(d);
  DrawMesh floor;
  floor.mesh = std::make_shared<const TriMesh>(makeQuad(400, 400, 4));
  floor.material.texture = std::make_shared<const Image>(makePattern("sand", 512));
  list.meshes.push_back(floor);
  RenderSettings rs;  // 1280x720, 4 samples
  auto r = Renderer::create(ctx, rs, findShaderDir());
  if (!r.ok()) return report(r.error());
  LightDesc key, amb;
  key.direction = Vec3(-0.3, -1.0, -0.2);
  amb.kind = LightKind::Ambient;
  amb.intensity = 0.4;
  list.lights = {key, amb};
  const double lit = framesPerSecond(*r.value(), list, seconds);
  list.lights[0].shadows = true;
  const double shadowed = framesPerSecond(*r.value(), list, seconds);
  auto bare_s = r.value()->bareDrawSeconds(bare, list.camera, std::max(3, static_cast<int>(lit * seconds)));
  if (!bare_s.ok()) return report(bare_s.error());
  nlohmann::ordered_json j = {{"name", "render_instances"},
                              {"width", rs.width},
                              {"height", rs.height},
                              {"samples", rs.samples},
                              {"copies", n},
                              {"triangles", bare.triangleCount()},
                              {"gl", std::string(ctx.backend())},
                              {"bare_draw_fps", 1.0 / bare_s.value()},
                              {"reel_fps", lit},
                              {"reel_shadows_fps", shadowed},
                              {"reel_vs_bare", (1.0 / lit) / bare_s.value()}};
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  return 0;
}

// Frames per second of reel's renderer beside the bare draw of the same triangles: a wavy sheet,
// then a school of instanced copies.
int benchRender(double seconds) {
  auto ctx = gl::createContext(gl::Backend::Auto);
  if (!ctx.ok()) return report(ctx.error());
  if (int rc = benchInstances(*ctx.value(), seconds); rc != 0) return rc;
  DrawCamera cam;
  cam.position = Vec3(0, 2.6, 2.6);
  cam.target = Vec3(0, 0, 0);
  cam.fov_deg = 50;
  for (auto [w, h] : {std::pair{1280, 720}, std::pair{1920, 1080}})
    for (int tris : {100000, 1000000}) {
      auto mesh = std::make_shared<const TriMesh>(wavySheet(tris));
      for (int samples : {1, 4}) {
        RenderSettings rs;
        rs.width = w;
        rs.height = h;
        rs.samples = samples;
        auto r = Renderer::create(*ctx.value(), rs, findShaderDir());
        if (!r.ok()) return report(r.error());
        DrawList list;
        list.camera = cam;
        DrawMesh dm;
        dm.mesh = mesh;
        dm.material.color = Vec3(0.7, 0.6, 0.5);
        list.meshes.push_back(dm);
        auto timeFrames = [&](const std::vector<LightDesc>& lights) -> double {
          list.lights = lights;
          return framesPerSecond(*r.value(), list, seconds);
        };
        LightDesc key, amb;
        key.direction = Vec3(-0.45, -1.0, -0.35);
        amb.kind = LightKind::Ambient;
        amb.intensity = 0.4;
        LightDesc key_shadow = key;
        key_shadow.shadows = true;
        const double lit = timeFrames({key, amb});
        const double shadowed = timeFrames({key_shadow, amb});
        const int bare_frames = std::max(3, static_cast<int>(lit * seconds));
        auto bare = r.value()->bareDrawSeconds(*mesh, cam, bare_frames);
        if (!bare.ok()) return report(bare.error());
        nlohmann::ordered_json j = {{"name", "render"},
                                    {"width", w},
                                    {"height", h},
                                    {"triangles", mesh->triangleCount()},
                                    {"samples", samples},
                                    {"gl", std::string(ctx.value()->backend())},
                                    {"bare_draw_fps", 1.0 / bare.value()},
                                    {"reel_fps", lit},
                                    {"reel_shadows_fps", shadowed},
                                    {"reel_vs_bare", (1.0 / lit) / bare.value()}};
        std::printf("%s\n", j.dump().c_str());
        std::fflush(stdout);
      }
    }
  return 0;
}

// A film end to end beside each stage alone: simulation, drawing, encoding (first 60 frames).
int benchFilm(const std::string& scene_path) {
  auto scene = loadScene(scene_path);
  if (!scene.ok()) return report(scene.error());
  const SceneDesc& s = scene.value();
  const int frames = std::min(60, s.frameCount());
  auto world = makeWorld(s);
  if (!world.ok()) return report(world.error());
  // Stage 1: simulate and fill the draw lists.
  std::vector<DrawList> lists(static_cast<std::size_t>(frames));
  auto t0 = Clock::now();
  for (int k = 0; k < frames; ++k) {
    if (k > 0)
      if (Status st = world.value().advanceFrame(); !st) return report(st.error());
    DrawList& list = lists[static_cast<std::size_t>(k)];
    setSceneView(s, world.value().time(), list);
    world.value().draw(list);
  }
  const double sim = std::chrono::duration<double>(Clock::now() - t0).count();
  // Stage 2: draw.
  auto ctx = gl::createContext(gl::Backend::Auto);
  if (!ctx.ok()) return report(ctx.error());
  RenderSettings rs;
  rs.width = s.render.width;
  rs.height = s.render.height;
  rs.samples = s.render.samples;
  auto r = Renderer::create(*ctx.value(), rs, findShaderDir());
  if (!r.ok()) return report(r.error());
  std::vector<Image> images(static_cast<std::size_t>(frames));
  t0 = Clock::now();
  for (int k = 0; k < frames; ++k)
    if (Status st = r.value()->draw(lists[static_cast<std::size_t>(k)], images[static_cast<std::size_t>(k)]); !st)
      return report(st.error());
  const double draw = std::chrono::duration<double>(Clock::now() - t0).count();
  // Stage 3: encode.
  const std::string out = "/tmp/reel_bench_film.mp4";
  io::VideoWriter v;
  t0 = Clock::now();
  if (Status st = v.open(out, rs.width, rs.height, s.fps); !st) return report(st.error());
  for (const Image& img : images)
    if (Status st = v.write(img); !st) return report(st.error());
  if (Status st = v.finish(); !st) return report(st.error());
  const double enc = std::chrono::duration<double>(Clock::now() - t0).count();
  std::remove(out.c_str());
  // All three overlapped, as `reel render` runs them.
  RenderOptions ro;
  ro.scene = scene_path;
  ro.outputs = {out};
  ro.quiet = true;
  t0 = Clock::now();
  std::fflush(stdout);
  if (int rc = render(ro, "0-" + std::to_string(frames - 1), false); rc != 0) return rc;
  const double total = std::chrono::duration<double>(Clock::now() - t0).count();
  std::remove(out.c_str());
  const double slowest = std::max({sim, draw, enc});
  nlohmann::ordered_json j = {{"name", "film"},
                              {"scene", s.name},
                              {"frames", frames},
                              {"width", rs.width},
                              {"height", rs.height},
                              {"simulate_fps", frames / sim},
                              {"draw_fps", frames / draw},
                              {"encode_fps", frames / enc},
                              {"end_to_end_fps", frames / total},
                              {"end_to_end_vs_slowest_stage", total / slowest}};
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace

int bench(const std::vector<std::string>& names, double seconds) {
  const std::vector<std::string> all = {"springs", "render", "film", "cloth", "fluid", "school", "fish", "rigid", "cloth_liquid", "face"};
  const std::vector<std::string>& run = names.empty() ? all : names;
  for (const auto& n : run) {
    if (std::find(all.begin(), all.end(), n) == all.end()) {
      std::string names_list;
      for (const auto& a : all) names_list += (names_list.empty() ? "" : ", ") + a;
      std::fprintf(stderr, "reel: unknown benchmark \"%s\" (available: %s)\n", n.c_str(), names_list.c_str());
      return 2;
    }
  }
  for (const auto& n : run) {
    int rc = 0;
    if (n == "springs") benchSprings(seconds);
    if (n == "render") rc = benchRender(seconds);
    if (n == "film") rc = benchFilm(REEL_SOURCE_DIR "/scenes/jelly.json");
    if (n == "cloth") rc = benchCloth(std::max(1.0 / 30.0, seconds));
    if (n == "fluid") rc = benchFluid(std::max(4.0 / 30.0, 0.1 * seconds));
    if (n == "school") rc = benchSchool(seconds);
    if (n == "fish") rc = benchFish(seconds);
    if (n == "rigid") rc = benchRigid();
    if (n == "cloth_liquid") rc = benchClothLiquid();
    if (n == "face") rc = benchFace();
    if (rc != 0) return rc;
  }
  return 0;
}

}  // namespace reel::app
