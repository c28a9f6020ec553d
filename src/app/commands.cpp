#include "app/commands.h"
#include "app/body_kinds.h"
#include "app/farm_cache.h"
#include "app/progress.h"

#include <unistd.h>

#include <CLI/Version.hpp>
#include <Eigen/Core>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "core/mass_properties.h"
#include "core/parallel.h"
#include "io/dump.h"
#include "io/mesh_import.h"
#include "io/stats.h"
#include "io/video.h"
#include "render/gl/context.h"
#include "sim/world.h"

namespace reel::app {

int report(const Error& e) {
  for (const auto& line : e.messages) std::fprintf(stderr, "reel: %s\n", line.c_str());
  if (e.messages.size() > 1) std::fprintf(stderr, "reel: %zu errors\n", e.messages.size());
  return static_cast<int>(e.kind);
}

// The world's current frame in the stats file: each body that reports quantities, in world order.
Status writeStats(io::StatsWriter& w, const World& world, int fps) {
  std::vector<std::pair<std::string, std::vector<Statistic>>> rows;
  for (const auto& b : world.bodies()) {
    rows.emplace_back(b->name(), std::vector<Statistic>{});
    b->statistics(rows.back().second);
  }
  return w.write(world.frame(), world.frame() / static_cast<double>(fps), rows);
}

int simulate(const SimulateOptions& opt) {
  if (opt.resume && (!opt.dump.empty() || !opt.stats.empty()))
    return report(Error(ErrorKind::BadInput, "--resume continues a cache only; a --dump or --stats file starts at frame 0 "
                                             "(simulate without --resume to write one)"));
  auto scene = loadScene(opt.scene);
  if (!scene.ok()) return report(scene.error());
  if (opt.seed) scene.value().seed = *opt.seed;
  const SceneDesc& s = scene.value();
  auto world_r = makeWorld(s);
  if (!world_r.ok()) return report(world_r.error());
  World& world = world_r.value();

  io::DumpWriter dump;
  FrameView snap;
  const bool dumping = !opt.dump.empty();
  // The last good frame not yet in the dump, copied so that it can still be written when the
  // next frame goes unstable (DESIGN 5: the last frame is always written).
  int pending = -1;
  FrameCopy pending_snap;
  auto keepPending = [&] {
    world.view(snap);
    pending_snap.take(snap);
    pending = world.frame();
  };
  io::StatsWriter stats;
  const bool counting = !opt.stats.empty();
  if (counting)
    if (Status st = stats.open(opt.stats); !st || !(st = writeStats(stats, world, s.fps))) return report(st.error());
  if (dumping) {
    if (Status st = dump.open(opt.dump, s.name, s.fps, s.substeps); !st) return report(st.error());
    world.view(snap);
    if (Status st = dump.write(snap); !st) return report(st.error());
  }
  // Frames 0..N-1 show times k/fps, as in a film of the scene (DESIGN 3).
  const int last = s.frameCount() - 1;
  // --cache: every frame's state into DIR; --resume: from its last good frame.
  std::optional<CacheWriter> cache;
  if (!opt.cache.empty()) {
    auto want = CacheManifest::of(opt.scene, s);
    if (!want.ok()) return report(want.error());
    cache.emplace();
    if (Status st = cache->open(opt.cache, want.value(), opt.resume); !st) return report(st.error());
    if (cache->frames() > last) {
      std::printf("%s: complete (%d frames)\n", opt.cache.c_str(), cache->frames());
      return 0;
    }
    if (Status st = cache->restoreLast(world); !st) return report(st.error());
    if (cache->frames() == 0)
      if (Status st = cache->append(world); !st) return report(st.error());
  }
  const int first = world.frame() + 1;
  const auto t0 = std::chrono::steady_clock::now();
  Progress progress(last - first + 1, opt.quiet);
  for (int k = first; k <= last; ++k) {
    if (Status st = world.advanceFrame(); !st) {
      if (cache) (void)cache->finish();  // the frames before stay good
      if (counting) (void)stats.finish();  // the statistics of the good frames
      if (dumping) {
        // Keep what was simulated: the dump ends with the last good frame.
        Status w = pending >= 0 ? dump.write(pending_snap.view()) : Status{};
        if (Status fin = dump.finish(); w && fin)
          std::fprintf(stderr, "reel: the dump %s holds frames up to %d\n", opt.dump.c_str(), k - 1);
      }
      return report(st.error());
    }
    if (dumping) {
      if (k % opt.dump_every == 0 || k == last) {
        world.view(snap);
        if (Status st = dump.write(snap); !st) return report(st.error());
        pending = -1;
      } else if (opt.dump_every > 1) {
        keepPending();
      }
    }
    if (counting)
      if (Status st = writeStats(stats, world, s.fps); !st) return report(st.error());
    if (cache)
      if (Status st = cache->append(world); !st) return report(st.error());
    progress.update(k - first + 1);
  }
  if (cache)
    if (Status st = cache->finish(); !st) return report(st.error());
  if (counting)
    if (Status st = stats.finish(); !st) return report(st.error());
  if (dumping)
    if (Status st = dump.finish(); !st) return report(st.error());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %d frames (%.3f s of scene time, %lld steps of %.3g s) in %.3f s%s%s\n",
              s.name.c_str(), last + 1, last / static_cast<double>(s.fps),
              static_cast<long long>(last) * world.stepsPerFrame(), world.stepSize(), secs,
              dumping ? ", dump: " : "", dumping ? opt.dump.c_str() : "");
  if (cache) {
    const std::string resumed = first > 1 ? ", resumed after frame " + std::to_string(first - 1) : "";
    std::printf("cache: %s (%d frames%s)\n", opt.cache.c_str(), last + 1, resumed.c_str());
  }
  if (world.unconvergedSteps() > 0)
    std::fprintf(stderr,
                 "reel: warning: in %lld implicit steps the conjugate-gradient solve stopped at "
                 "implicit.cg_max_iterations = %d (worst relative residual %.3g, tolerance %.3g)\n",
                 world.unconvergedSteps(), s.implicit.cg_max_iterations, world.worstResidual(),
                 s.implicit.cg_tolerance);
  return 0;
}

int check(const std::vector<std::string>& scenes) {
  int worst = 0;
  for (const auto& path : scenes) {
    auto scene = loadScene(path);
    Error err;
    if (scene.ok()) {
      auto world = makeWorld(scene.value(), /*check_only=*/true);  // also refuses unstable steps
      if (world.ok()) {
        std::printf("%s: ok (%zu bodies, %zu objects, %d frames)\n", path.c_str(),
                    scene.value().bodies.size(), scene.value().objects.size(), scene.value().frameCount());
        // What each body's parameters mean in practice (a liquid's rest distance, stable step).
        const World& w = world.value();
        for (const auto& b : w.bodies())
          for (const std::string& line : b->notes(w.stepSize())) std::printf("  %s\n", line.c_str());
        continue;
      }
      err = world.error();
    } else {
      err = scene.error();
    }
    worst = std::max(worst, report(err));
  }
  return worst;
}

int meshMass(const std::string& file, double density) {
  auto mesh = io::importMesh(file);
  if (!mesh.ok()) return report(mesh.error());
  auto m = solidMassProperties(mesh.value(), density);
  if (!m.ok()) {
    Error e = m.error();
    for (std::string& line : e.messages) line = file + ": " + line;
    return report(e);
  }
  const MassProperties& p = m.value();
  auto vec = [](const auto& v) { return nlohmann::json::array({v[0], v[1], v[2]}); };
  const nlohmann::json out = {{"file", file},
                              {"density", density},
                              {"volume", p.volume},
                              {"mass", p.mass},
                              {"center_of_mass", vec(p.center_of_mass)},
                              {"inertia", {vec(p.inertia.row(0)), vec(p.inertia.row(1)), vec(p.inertia.row(2))}}};
  std::printf("%s\n", out.dump().c_str());
  return 0;
}

int info() {
  std::printf("reel %s (%s build)\n", REEL_VERSION, REEL_BUILD_TYPE);
  std::printf("compiler: g++ %d.%d.%d, C++%ld\n", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__,
              __cplusplus / 100 % 100);
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const char* spins = std::getenv("GOMP_SPINCOUNT");
  const std::string wait = policy ? std::string(policy) + (spins ? std::string(", ") + spins + " spins" : "")
                           : spins ? std::string(spins) + " spins, then sleep"
                                   : "runtime default";
  std::printf("threads: %d (OpenMP %d, waiting: %s)\n", threadCount(), _OPENMP, wait.c_str());
  std::printf("libraries: Eigen %d.%d.%d, nlohmann-json %d.%d.%d, CLI11 %s\n", EIGEN_WORLD_VERSION,
              EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION, NLOHMANN_JSON_VERSION_MAJOR,
              NLOHMANN_JSON_VERSION_MINOR, NLOHMANN_JSON_VERSION_PATCH, CLI11_VERSION);
  std::printf("integrators:");
  for (auto n : kIntegratorNames) std::printf(" %.*s", static_cast<int>(n.size()), n.data());
  std::printf("\nbodies:");
  for (const BodyKind& k : bodyKinds()) std::printf(" %s", k.type);
  std::printf("\nobjects: plane sphere box capsule mesh container\n");
  for (const auto& b : gl::probeBackends())
    std::printf("gl %s: %s\n", b.name.c_str(), b.ok ? b.detail.c_str() : ("unavailable: " + b.detail).c_str());
  std::printf("encoders:");
  for (const auto& e : io::availableEncoders()) std::printf(" [%s]", e.c_str());
  std::printf("\n");
  return 0;
}

}  // namespace reel::app
