// reel bench: one JSON line per measurement (DESIGN 8).
#include <unistd.h>

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
#include "core/environment.h"
#include "render/renderer.h"
#include "sim/world.h"
#include "core/parallel.h"
#include "core/profile.h"

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

// What each pass costs: a 100k-triangle wavy sheet on a floor at 1280x720, 4 samples, drawn bare,
// then with a plain Lambert material and two lights, then with each pass added alone (GGX
// specular, filtered shadows, soft shadows, the environment's light, ambient occlusion, ACES,
// transmission: the sheet as see-through water over a floor, the liquids' pass; motion blur: five
// pictures of a moving sheet), then with all of them but those two (a film's look).
int benchPasses(gl::Context& ctx, double seconds) {
  RenderSettings rs;
  auto r = Renderer::create(ctx, rs, findShaderDir());
  if (!r.ok()) return report(r.error());
  DrawCamera cam;
  cam.position = Vec3(0, 2.6, 2.6);
  cam.target = Vec3(0, 0, 0);
  cam.fov_deg = 50;
  auto mesh = std::make_shared<const TriMesh>(wavySheet(100000));
  const auto sky = prefilterEnvironment(proceduralSky(Vec3(0.3, 0.4, 0.6), Vec3(0.8, 0.8, 0.8), Vec3(0.3, 0.28, 0.25)), 0.7, 0);
  // The process's first two seconds of drawing run at half speed (the allocator's threshold for
  // mapping large blocks rises only as llvmpipe frees them): drawn once untimed.
  if (auto warm = r.value()->bareDrawSeconds(*mesh, cam, 30); !warm.ok()) return report(warm.error());
  auto bare = r.value()->bareDrawSeconds(*mesh, cam, std::max(3, static_cast<int>(20 * seconds)));
  if (!bare.ok()) return report(bare.error());
  struct Variant {
    const char* pass;
    bool specular, shadows, soft, environment, ao, aces, transmission = false, motion_blur = false;
  };
  const Variant variants[] = {{"plain", false, false, false, false, false, false},
                              {"ggx_specular", true, false, false, false, false, false},
                              {"shadows", false, true, false, false, false, false},
                              {"soft_shadows", false, true, true, false, false, false},
                              {"environment", false, false, false, true, false, false},
                              {"ao", false, false, false, false, true, false},
                              {"aces", false, false, false, false, false, true},
                              {"transmission", false, false, false, false, false, false, true},
                              {"motion_blur", false, false, false, false, false, false, false, true},
                              {"film_look", true, true, true, true, true, true}};
  for (const Variant& v : variants) {
    DrawList list;
    list.camera = cam;
    DrawMesh dm;
    dm.mesh = mesh;
    dm.material.color = Vec3(0.7, 0.6, 0.5);
    if (v.specular) dm.material.specular = 0.5, dm.material.roughness = 0.4;
    if (v.transmission) {  // see-through water over a floor: the liquid pass
      dm.material.transmission = 0.9;
      dm.material.absorption_depth = 0.2;
      DrawMesh floor;
      TriMesh quad = makeQuad(8, 8);
      quad.transform(Mat3::Identity(), Vec3(0, -0.5, 0));
      floor.mesh = std::make_shared<const TriMesh>(std::move(quad));
      list.meshes.push_back(floor);
    }
    list.meshes.push_back(dm);
    LightDesc key, amb;
    key.direction = Vec3(-0.45, -1.0, -0.35);
    key.shadows = v.shadows;
    key.size = v.soft ? 2.5 : 0.0;
    amb.kind = LightKind::Ambient;
    amb.intensity = 0.4;
    list.lights = {key};
    if (!v.environment) list.lights.push_back(amb);
    if (v.environment) list.environment = sky;
    if (v.ao) list.ao_radius = 0.3;
    if (v.aces) list.tonemap = "aces";
    if (v.motion_blur) {  // the scene's default shutter: 180°, 5 pictures, over a sheet that moved
      list.shutter_deg = 180;
      list.shutter_samples = 5;
      auto before = std::make_shared<DrawList>(list);
      TriMesh moved = *mesh;
      moved.transform(Mat3::Identity(), Vec3(0.1, 0, 0));
      before->meshes.back().mesh = std::make_shared<const TriMesh>(std::move(moved));
      for (DrawList* l : {before.get(), &list}) l->meshes.back().per_frame = true;
      list.previous = before;
    }
    const double fps = framesPerSecond(*r.value(), list, seconds);
    nlohmann::ordered_json j = {{"name", "render_pass"},
                                {"pass", v.pass},
                                {"width", rs.width},
                                {"height", rs.height},
                                {"triangles", mesh->triangleCount()},
                                {"samples", rs.samples},
                                {"gl", std::string(ctx.backend())},
                                {"bare_draw_fps", 1.0 / bare.value()},
                                {"reel_fps", fps},
                                {"reel_vs_bare", (1.0 / fps) / bare.value()}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
  return 0;
}

// Frames per second of reel's renderer beside the bare draw of the same triangles: each pass's
// cost, a school of instanced copies, then wavy sheets of several sizes.
int benchRender(double seconds) {
  auto ctx = gl::createContext(gl::Backend::Auto);
  if (!ctx.ok()) return report(ctx.error());
  if (int rc = benchPasses(*ctx.value(), seconds); rc != 0) return rc;
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

// A film rendered as `reel render` renders it (three threads: simulation, drawing, encoding),
// with each thread's busy time and the simulation split by stage (core/profile.h), in seconds
// per frame; `range`: the frames (all by default). The video goes to a temporary file.
int benchFilm(const std::string& scene_path, const std::string& range) {
  const std::string out = "/tmp/reel_bench_film_" + std::to_string(::getpid()) + ".mp4";
  RenderOptions ro;
  ro.scene = scene_path;
  ro.outputs = {out};
  ro.quiet = true;
  ro.cache.clear();  // the simulation is what is measured
  FilmTimes t;
  std::fflush(stdout);
  const int rc = render(ro, range, false, &t);
  std::remove(out.c_str());
  if (rc != 0) return rc;
  const double n = std::max(1, t.frames);
  nlohmann::ordered_json stages;
  // "other": the simulation thread's busy time no stage claims (the stepping loop, setting up the
  // views); the profile's own "other" also counts its waits on the queue, so it is not used.
  double claimed = 0;
  for (std::size_t k = 1; k < t.stages.size(); ++k) {
    claimed += t.stages[k];
    if (t.stages[k] > 0) stages[std::string(profile::kStageNames[k])] = t.stages[k] / n;
  }
  stages["other"] = std::max(0.0, t.simulate - claimed) / n;
  nlohmann::ordered_json j = {{"name", "film"},
                              {"scene", t.scene},
                              {"frames", t.frames},
                              {"width", t.width},
                              {"height", t.height},
                              {"samples", t.samples},
                              {"threads", threadCount()},
                              {"setup_s", t.setup},
                              {"simulate_s_per_frame", t.simulate / n},
                              {"simulate_stages_s_per_frame", stages},
                              {"draw_s_per_frame", t.draw / n},
                              {"encode_s_per_frame", t.encode / n},
                              {"end_to_end_s_per_frame", t.total / n},
                              {"end_to_end_s", t.total}};
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  return 0;
}

}  // namespace

int bench(const std::vector<std::string>& given, double seconds, const std::string& frames) {
  const std::vector<std::string> all = {"springs", "render", "film", "cloth", "fluid", "school", "fish", "rigid", "articulated", "cloth_liquid", "face", "cache"};
  // Scene files name the films `film` renders (jelly by default).
  std::vector<std::string> names, films;
  for (const auto& n : given) (n.size() > 5 && n.ends_with(".json") ? films : names).push_back(n);
  if (!films.empty() && std::find(names.begin(), names.end(), "film") == names.end()) names.push_back("film");
  if (films.empty()) films.push_back(REEL_SOURCE_DIR "/scenes/jelly.json");
  if (!frames.empty() && (names.size() != 1 || names[0] != "film")) {
    std::fprintf(stderr, "reel: --frames applies to the film benchmark only: reel bench film SCENE.json --frames A-B\n");
    return 2;
  }
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
    if (n == "film")
      for (const auto& f : films)
        if (rc == 0) rc = benchFilm(f, frames);
    if (n == "cloth") rc = benchCloth(std::max(1.0 / 30.0, seconds));
    if (n == "fluid") rc = benchFluid(std::max(4.0 / 30.0, 0.1 * seconds));
    if (n == "school") rc = benchSchool(seconds);
    if (n == "fish") rc = benchFish(seconds);
    if (n == "rigid") rc = benchRigid();
    if (n == "articulated") rc = benchArticulated();
    if (n == "cloth_liquid") rc = benchClothLiquid();
    if (n == "face") rc = benchFace();
    if (n == "cache") rc = benchCache(30);
    if (rc != 0) return rc;
  }
  return 0;
}

}  // namespace reel::app
