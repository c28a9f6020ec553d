// reel bench cache: what the farm cache (app/farm_cache.h) costs per frame for each body kind, in
// bytes per node, particle, agent or body, raw and as stored (compressed), and how fast frames pack
// and unpack. Measured on the demo films after a second of simulation, when things move.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "app/bench.h"
#include "app/body_kinds.h"
#include "app/commands.h"
#include "app/sim_cache.h"
#include "io/frame_store.h"
#include "sim/world.h"

namespace reel::app {

int benchCache(int frames) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  std::vector<std::string> scenes;
  for (const auto& e : std::filesystem::directory_iterator(REEL_SOURCE_DIR "/scenes"))
    if (e.path().extension() == ".json") scenes.push_back(e.path().string());
  std::sort(scenes.begin(), scenes.end());
  struct Kind {
    std::string unit;
    long long elements = 0, raw = 0, stored = 0;
    std::vector<std::string> scenes;
  };
  std::map<std::string, Kind> kinds;
  for (const std::string& path : scenes) {
    auto scene = loadScene(path);
    if (!scene.ok()) return report(scene.error());
    auto world = makeWorld(scene.value());
    if (!world.ok()) return report(world.error());
    World& w = world.value();
    const int k = std::min(frames, scene.value().frameCount() - 1);
    for (int f = 0; f < k; ++f)
      if (Status st = w.advanceFrame(); !st) return report(st.error());
    const WorldSnapshot snap = w.snapshot();
    FrameView view;
    w.view(view);
    // The whole frame as the cache stores it, and the time to pack and unpack it.
    const io::Bytes raw = encodeSnapshot(snap);
    auto t0 = Clock::now();
    const io::Bytes packed = io::packFrame(raw);
    const double pack = since(t0);
    t0 = Clock::now();
    auto back = io::unpackFrame(packed.data(), packed.size(), raw.size());
    const double unpack = since(t0);
    if (!back.ok() || back.value() != raw) return report(Error(ErrorKind::Internal, path + ": the cache does not round-trip"));
    nlohmann::ordered_json j = {{"name", "cache_frame"},
                                {"scene", scene.value().name},
                                {"frame", k},
                                {"raw_bytes", raw.size()},
                                {"cache_bytes", packed.size() + 48},  // + record header and index entry
                                {"ratio", static_cast<double>(raw.size()) / static_cast<double>(packed.size())},
                                {"pack_mb_per_s", static_cast<double>(raw.size()) / 1e6 / std::max(pack, 1e-9)},
                                {"unpack_mb_per_s", static_cast<double>(raw.size()) / 1e6 / std::max(unpack, 1e-9)}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
    // Each body alone, by the kind that built it.
    for (std::size_t b = 0; b < view.bodies.size() && b < snap.bodies.size(); ++b) {
      const BodyView& v = view.bodies[b];
      const std::string kind = v.generator.empty() ? v.type : v.generator;
      Kind& acc = kinds[kind];
      acc.unit = v.type == "particles" ? "particle" : v.type == "agents" ? "agent" : v.type == "rigid" ? "body" : "node";
      acc.elements += static_cast<long long>(v.positions.size());
      acc.raw += static_cast<long long>(snap.bodies[b].bytes.size());
      acc.stored += static_cast<long long>(io::packFrame(snap.bodies[b].bytes).size());
      if (std::find(acc.scenes.begin(), acc.scenes.end(), scene.value().name) == acc.scenes.end())
        acc.scenes.push_back(scene.value().name);
    }
  }
  for (const auto& [kind, acc] : kinds) {
    const double n = static_cast<double>(std::max(acc.elements, 1LL));
    nlohmann::ordered_json j = {{"name", "cache_kind"},
                                {"kind", kind},
                                {"unit", acc.unit},
                                {"count", acc.elements},
                                {"raw_bytes_per_" + acc.unit, static_cast<double>(acc.raw) / n},
                                {"cache_bytes_per_" + acc.unit, static_cast<double>(acc.stored) / n},
                                {"scenes", acc.scenes}};
    std::printf("%s\n", j.dump().c_str());
  }
  return 0;
}

}  // namespace reel::app
