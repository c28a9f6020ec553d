// libFuzzer target: what a simulation cache holds, against a World built from one of the small
// scenes of the snapshot tests (tests/body_scenes.h: every body kind). The first byte picks the
// scene and what the rest is:
//   0: a frame's snapshot bytes (what a record holds once its checksum passes: a checksum is no
//      defence against a crafted file): decoded, restored into the world, drawn, and advanced a
//      frame; the world must take its own snapshot back afterwards;
//   1: a frame store (2 bytes: the index's length, then frames.idx, then frames.bin): opened,
//      every frame read (at most 4), and resumed by a writer that cuts off what does not check out;
//   2: a cache's cache.json beside that scene's good cache: read, compared, its frame 0 restored.
// A refusal is the expected answer; a crash, sanitizer report, leak, hang or blow-up is a finding.
#include <sys/stat.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "../body_scenes.h"
#include "app/body_kinds.h"
#include "app/farm_cache.h"
#include "app/sim_cache.h"
#include "core/drawlist.h"
#include "fuzz_files.h"
#include "io/frame_store.h"

namespace {

using reel::fuzz::privateDir;
using reel::fuzz::put;

struct Case {
  std::string name, scene_file;
  std::unique_ptr<reel::World> world;
  reel::WorldSnapshot start;        // frame 0
  reel::app::CacheManifest want;    // what this scene's cache must say
  std::string cache_dir, store_dir; // a good cache; a folder for mutated stores
};

std::vector<Case>& cases() {
  static std::vector<Case> all = [] {
    std::vector<Case> out;
    for (const auto& [name, text] : reel::test::kScenes) {
      Case c;
      c.name = name;
      for (char& ch : c.name)
        if (ch == '+') ch = '_';
      c.scene_file = put(c.name + ".json", text);
      auto scene = reel::app::loadScene(c.scene_file);
      if (!scene.ok()) std::abort();
      auto world = reel::app::makeWorld(scene.value());
      if (!world.ok()) std::abort();
      c.world = std::make_unique<reel::World>(std::move(world.value()));
      c.start = c.world->snapshot();
      auto want = reel::app::CacheManifest::of(c.scene_file, scene.value());
      if (!want.ok()) std::abort();
      c.want = want.value();
      c.cache_dir = privateDir() + "/cache_" + c.name;
      c.store_dir = privateDir() + "/store_" + c.name;
      if (mkdir(c.store_dir.c_str(), 0700) != 0) std::abort();
      // A good cache of two frames.
      reel::app::CacheWriter w;
      if (!w.open(c.cache_dir, c.want, false) || !w.append(*c.world) || !c.world->advanceFrame() || !w.append(*c.world) ||
          !w.finish())
        std::abort();
      if (!c.world->restore(c.start)) std::abort();
      out.push_back(std::move(c));
    }
    return out;
  }();
  return all;
}

std::string bytesOf(const std::vector<std::byte>& b) { return {reinterpret_cast<const char*>(b.data()), b.size()}; }

void writeSeeds() {
  using reel::fuzz::seed;
  using reel::fuzz::slurp;
  std::uint8_t k = 0;
  for (Case& c : cases()) {
    const auto kind = [&](int mode) { return static_cast<std::uint8_t>(3 * k + mode); };
    if (!c.world->advanceFrame()) std::abort();
    seed(c.name + ".snapshot", kind(0), bytesOf(reel::app::encodeSnapshot(c.world->snapshot())));
    const std::string idx = slurp(c.cache_dir + "/frames.idx");
    std::string store;
    store += static_cast<char>(idx.size() & 0xff);
    store += static_cast<char>(idx.size() >> 8);
    store += idx + slurp(c.cache_dir + "/frames.bin");
    seed(c.name + ".store", kind(1), store);
    seed(c.name + ".manifest", kind(2), slurp(c.cache_dir + "/cache.json"));
    ++k;
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (reel::fuzz::seedDir()) {
    writeSeeds();
    std::exit(0);
  }
  (void)cases();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  std::vector<Case>& all = cases();
  Case& c = all[(data[0] / 3) % all.size()];
  const int mode = data[0] % 3;
  const auto* rest = reinterpret_cast<const std::byte*>(data + 1);
  const std::size_t n = size - 1;
  reel::World& world = *c.world;
  if (mode == 0) {
    reel::WorldSnapshot snap;
    if (reel::app::decodeSnapshot(rest, n, snap) && world.restore(snap)) {
      // What `reel render --cache` does with a frame: draw it (liquid surfaces, skins, meshes
      // at their poses), then what `simulate --resume` does: step on from it.
      reel::DrawList list;
      world.draw(list);
      (void)world.advanceFrame();
    }
  } else if (mode == 1) {
    if (n < 2) return 0;
    const std::size_t idx = std::min<std::size_t>(n - 2, static_cast<std::size_t>(data[1]) | (static_cast<std::size_t>(data[2]) << 8));
    const char* p = reinterpret_cast<const char*>(data + 3);
    reel::fuzz::writeBytes(c.store_dir + "/frames.idx", p, idx);
    reel::fuzz::writeBytes(c.store_dir + "/frames.bin", p + idx, n - 2 - idx);
    if (auto r = reel::io::FrameStoreReader::open(c.store_dir); r.ok()) {
      for (int k = 0; k < std::min(r.value().frames(), 4); ++k) {
        auto bytes = r.value().read(k);
        reel::WorldSnapshot snap;
        if (bytes.ok() && reel::app::decodeSnapshot(bytes.value().data(), bytes.value().size(), snap)) (void)world.restore(snap);
      }
    }
    reel::io::FrameStoreWriter w;
    if (w.resume(c.store_dir).ok()) w.close();
  } else {
    reel::fuzz::writeBytes(c.cache_dir + "/cache.json", rest, n);
    reel::app::CacheReader r;
    if (r.open(c.cache_dir, c.want)) (void)r.restore(world, 0);
  }
  // Whatever the input did, the world takes its own frame 0 back.
  if (!world.restore(c.start)) std::abort();
  return 0;
}
