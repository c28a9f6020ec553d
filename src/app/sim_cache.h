// The simulation cache of stills and renders (docs/rendering.md): World snapshots of a scene's
// frames under render_out/.cache/<key>/, so that `reel still --time T` after a render or another
// still of the same scene restores the nearest frame at or before T instead of simulating from 0.
// The key hashes the scene file's bytes, the seed, the assets the scene loaded (path, size and
// modification time) and the reel binary itself (its size and modification time: a rebuilt reel
// never reads an older one's states). Built after the scene is loaded. A checkpoint file is
// versioned and checksummed; one that does not read back whole is ignored, never trusted.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "sim/world.h"

namespace reel::app {

// A World snapshot as bytes (its fields in one fixed order) and back; `decode` is false for bytes
// that are not one whole snapshot. Shared by this cache and the farm cache (app/farm_cache.h).
std::vector<std::byte> encodeSnapshot(const WorldSnapshot& snap);
bool decodeSnapshot(const std::byte* bytes, std::size_t n, WorldSnapshot& snap);

class SimCache {
 public:
  // Per scene, checkpoints take at most about this much disk (every frame when they fit, else
  // evenly spaced), and at most this many scenes are kept (the least recently used go).
  static constexpr double kBudgetBytes = 64.0 * 1024 * 1024;
  static constexpr int kScenes = 8;

  // A cache for the scene file (with the --seed in force, if any) under `root`
  // (render_out/.cache). Off when the scene file cannot be read.
  SimCache(const std::string& root, const std::string& scene_file, std::optional<std::uint64_t> seed, int frames);
  bool on() const { return !dir_.empty(); }
  const std::string& dir() const { return dir_; }

  // Restores into `world` the latest good checkpoint at or before frame `k` (none: the world
  // stays at frame 0). Returns the frame restored.
  int restoreNearest(World& world, int k) const;
  // Writes the world's current frame when it is one to keep (every `interval` frames, or
  // `always`); failures are reported once on stderr and turn the cache off, never the run.
  void offer(const World& world, bool always = false);

 private:
  std::string path(int frame) const;
  std::string dir_;
  std::uint64_t key_ = 0;
  int frames_ = 0;
  int interval_ = 0;  // 0: not decided yet (from the first snapshot's size)
};

}  // namespace reel::app
