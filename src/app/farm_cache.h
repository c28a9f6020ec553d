// The farm's simulation cache (docs/farm.md): `reel simulate SCENE --cache DIR` writes every
// frame's World snapshot into DIR (io/frame_store.h: compressed, checksummed, indexed records),
// beside DIR/cache.json, which says what made it, and DIR/scene.json, the scene file's bytes.
// `reel render SCENE --cache DIR --frames A-B` draws those frames from it without simulating.
// A cache is only used by the scene, seed, assets and reel build that made it (byte-identical
// frames need all four); any other is refused, naming what differs.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/scene.h"
#include "io/frame_store.h"
#include "sim/world.h"

namespace reel::app {

// What made a cache (DIR/cache.json).
struct CacheManifest {
  std::string reel;        // version
  std::string build;       // a hash of the reel binary's bytes
  std::string scene_file;  // as given to simulate (for messages)
  std::string scene_name;
  std::string scene_hash;  // of the scene file's bytes
  std::string scene_text;  // the bytes (DIR/scene.json), not in cache.json
  std::uint64_t seed = 0;
  int fps = 0, frames = 0;
  std::vector<std::pair<std::string, std::string>> assets;  // file name, hash of its bytes

  // What this process would write for `scene_file`, loaded as `scene` (after loading: its assets).
  static Result<CacheManifest> of(const std::string& scene_file, const SceneDesc& scene);
  // "" when `other` may use this cache, else what differs, in words.
  std::string mismatch(const CacheManifest& other) const;
};

// Writing a cache (reel simulate --cache).
class CacheWriter {
 public:
  // Opens DIR for `want`: a new or empty folder is made a cache (as is one whose start was cut
  // short: cache files but no cache.json); one holding a cache of the same manifest is continued
  // after its last good frame when `resume` (else refused); one holding a cache of something else,
  // anything else, or a cache another reel is writing now is refused (exit 2). A folder that cannot
  // be written is an exit-4 error, leaving nothing of this run behind.
  Status open(const std::string& dir, const CacheManifest& want, bool resume);
  // Frames already in the cache (when resumed).
  int frames() const { return store_.frames(); }
  // Restores the world to the cache's last frame (resumed; nothing to do when there is none).
  Status restoreLast(World& world) const;
  // Appends the world's current frame (frames arrive in order, from frame 0).
  Status append(const World& world);
  Status finish() { return store_.finish(); }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  io::FrameStoreWriter store_;
};

// Reading a cache (reel render --cache).
class CacheReader {
 public:
  // Opens DIR for `want` (exit 2 when it is not a cache or another's).
  Status open(const std::string& dir, const CacheManifest& want);
  int frames() const { return store_->frames(); }
  // Puts the world in frame k's state (exit 2 when the frame is damaged or missing).
  Status restore(World& world, int k) const;

 private:
  std::string dir_;
  std::unique_ptr<io::FrameStoreReader> store_;
};

// Reads DIR/cache.json; exit 2 when DIR holds no reel cache.
Result<CacheManifest> readManifest(const std::string& dir);

}  // namespace reel::app
