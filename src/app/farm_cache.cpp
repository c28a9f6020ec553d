#include "app/farm_cache.h"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <system_error>

#include "app/sim_cache.h"
#include "core/hash.h"
#include "io/files.h"

namespace reel::app {
namespace {

namespace fs = std::filesystem;
constexpr const char* kFormat = "reel-cache/1";
constexpr std::size_t kMaxSceneBytes = 64u << 20;

std::string hashOf(const std::string& bytes) { return hashBytes(bytes.data(), bytes.size()).hex(); }

// The running reel binary's bytes, hashed once per process.
std::string buildHash() {
  static const std::string id = [] {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    auto bytes = ec ? Result<std::string>(Error(ErrorKind::Internal, "")) : io::readFile(exe.string(), 1u << 30);
    return bytes.ok() ? hashOf(bytes.value()) : std::string("unknown");
  }();
  return id;
}

std::string manifestPath(const std::string& dir) { return (fs::path(dir) / "cache.json").string(); }
std::string scenePath(const std::string& dir) { return (fs::path(dir) / "scene.json").string(); }

Status writeWhole(const std::string& path, const std::string& bytes) {
  io::AtomicFile f;
  Status st = f.open(path);
  if (st) st = f.write(bytes);
  if (st) st = f.commit();
  return st;
}

}  // namespace

Result<CacheManifest> CacheManifest::of(const std::string& scene_file, const SceneDesc& scene) {
  CacheManifest m;
  auto text = io::readFile(scene_file, kMaxSceneBytes);
  if (!text.ok()) return text.error();
  m.reel = REEL_VERSION;
  m.build = buildHash();
  m.scene_file = scene_file;
  m.scene_name = scene.name;
  m.scene_text = text.value();
  m.scene_hash = hashOf(m.scene_text);
  m.seed = scene.seed;
  m.fps = scene.fps;
  m.frames = scene.frameCount();
  for (const std::string& a : io::resolvedAssets()) {
    auto bytes = io::readFile(a, std::size_t{1} << 31);
    if (!bytes.ok()) return bytes.error();
    m.assets.push_back({fs::path(a).filename().string(), hashOf(bytes.value())});
  }
  return m;
}

std::string CacheManifest::mismatch(const CacheManifest& o) const {
  if (reel != o.reel) return "it was made by reel " + reel + ", this is reel " + o.reel;
  if (build != o.build) return "it was made by another build of reel " + reel + " (binary " + build + ", this one " + o.build + ")";
  if (scene_hash != o.scene_hash)
    return "it was simulated from another scene (" + scene_file + ", \"" + scene_name + "\"; its bytes are in scene.json)";
  if (seed != o.seed) return "it was simulated with seed " + std::to_string(seed) + ", not " + std::to_string(o.seed);
  if (assets != o.assets) {
    for (std::size_t i = 0; i < std::max(assets.size(), o.assets.size()); ++i)
      if (i >= assets.size() || i >= o.assets.size() || assets[i] != o.assets[i])
        return "the scene's asset " + (i < o.assets.size() ? o.assets[i].first : assets[i].first) + " has changed since";
  }
  if (fps != o.fps || frames != o.frames) return "its film has another frame rate or length";
  return "";
}

Result<CacheManifest> readManifest(const std::string& dir) {
  auto text = io::readFile(manifestPath(dir), 1u << 20);
  if (!text.ok()) return Error(ErrorKind::BadInput, dir + ": not a reel simulation cache (no readable cache.json)");
  CacheManifest m;
  try {
    const auto j = nlohmann::json::parse(text.value());
    if (j.at("format").get<std::string>() != kFormat)
      return Error(ErrorKind::BadInput, manifestPath(dir) + ": format " + j.at("format").dump() + ", expected " + kFormat);
    m.reel = j.at("reel").get<std::string>();
    m.build = j.at("build").get<std::string>();
    m.scene_file = j.at("scene").get<std::string>();
    m.scene_name = j.at("scene_name").get<std::string>();
    m.scene_hash = j.at("scene_hash").get<std::string>();
    m.seed = j.at("seed").get<std::uint64_t>();
    m.fps = j.at("fps").get<int>();
    m.frames = j.at("frames").get<int>();
    for (const auto& a : j.at("assets")) m.assets.push_back({a.at(0).get<std::string>(), a.at(1).get<std::string>()});
  } catch (const nlohmann::json::exception& e) {
    // In plain words (nlohmann's own text names its exception types, not the file's fault).
    const char* why = dynamic_cast<const nlohmann::json::parse_error*>(&e)    ? "it is not JSON"
                      : dynamic_cast<const nlohmann::json::out_of_range*>(&e) ? "a field reel writes is missing"
                                                                              : "a field has the wrong type";
    return Error(ErrorKind::BadInput, manifestPath(dir) + ": damaged (" + why +
                                          "): not the cache.json reel writes; `reel simulate --cache` makes the cache anew");
  }
  return m;
}

// The files a cache is made of: a folder holding only these (and their part files) but no
// cache.json is a cache whose start was cut short, started again.
static bool onlyCacheFiles(const std::string& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    std::string n = e.path().filename().string();
    if (n.ends_with(".part")) n.resize(n.size() - 5);
    if (n != "cache.json" && n != "scene.json" && n != "frames.bin" && n != "frames.idx") return false;
  }
  return !ec;
}

Status CacheWriter::open(const std::string& dir, const CacheManifest& want, bool resume) {
  dir_ = dir;
  std::error_code ec;
  const bool existed = fs::exists(dir, ec);
  if (existed && !fs::is_directory(dir, ec)) return Error(ErrorKind::BadInput, dir + ": not a folder");
  if (existed && fs::exists(manifestPath(dir), ec)) {
    auto have = readManifest(dir);
    if (!have.ok()) return have.error();
    if (!resume)
      return Error(ErrorKind::BadInput, dir + ": already holds a cache of \"" + have.value().scene_name +
                                            "\"; add --resume to continue it, or remove the folder");
    if (const std::string why = have.value().mismatch(want); !why.empty())
      return Error(ErrorKind::BadInput, dir + ": cannot resume this cache: " + why);
    auto kept = store_.resume(dir);  // (locks the folder, then checks every frame)
    if (!kept.ok()) return kept.error();
    return {};
  }
  if (existed && !onlyCacheFiles(dir))
    return Error(ErrorKind::BadInput, dir + ": holds something else (no cache.json); give an empty or new folder");
  // A new cache: the store first, which locks the folder (a second writer stops there, touching
  // nothing), then the scene and, last, the manifest that makes it a cache. A failure takes back
  // what this run made.
  // The outermost folder this run creates, to take back on failure.
  fs::path made = fs::absolute(dir, ec);
  while (made.has_parent_path() && made.parent_path() != made && !fs::exists(made.parent_path(), ec)) made = made.parent_path();
  fs::create_directories(dir, ec);
  if (ec) {
    const std::string why = ec.message();
    if (!existed) fs::remove_all(made, ec);
    return Error(ErrorKind::Output, dir + ": cannot create the cache folder: " + why);
  }
  if (Status st = store_.create(dir); !st) {
    if (st.error().kind != ErrorKind::Output) return st;  // another writer's folder
    if (!existed) fs::remove_all(made, ec);
    return st;
  }
  auto undo = [&](const Status& st) {
    store_.close();
    if (!existed) fs::remove_all(made, ec);
    else
      for (const char* f : {"cache.json", "scene.json", "frames.bin", "frames.idx"}) fs::remove(fs::path(dir) / f, ec);
    return st;
  };
  nlohmann::json assets = nlohmann::json::array();
  for (const auto& [name, hash] : want.assets) assets.push_back({name, hash});
  const nlohmann::json j = {{"format", kFormat},       {"reel", want.reel},
                            {"build", want.build},     {"scene", want.scene_file},
                            {"scene_name", want.scene_name}, {"scene_hash", want.scene_hash},
                            {"seed", want.seed},       {"fps", want.fps},
                            {"frames", want.frames},   {"assets", assets}};
  if (Status st = writeWhole(scenePath(dir), want.scene_text); !st) return undo(st);
  const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  if (Status st = writeWhole(manifestPath(dir), text); !st) return undo(st);
  return {};
}

Status CacheWriter::restoreLast(World& world) const {
  if (store_.frames() == 0) return {};
  auto reader = io::FrameStoreReader::open(dir_);
  if (!reader.ok()) return reader.error();
  auto bytes = reader.value().read(store_.frames() - 1);
  if (!bytes.ok()) return bytes.error();
  WorldSnapshot snap;
  if (!decodeSnapshot(bytes.value().data(), bytes.value().size(), snap))
    return Error(ErrorKind::BadInput, dir_ + ": frame " + std::to_string(store_.frames() - 1) + " does not decode");
  return world.restore(snap);
}

Status CacheWriter::append(const World& world) {
  if (world.frame() != store_.frames())
    return Error(ErrorKind::Internal, dir_ + ": frame " + std::to_string(world.frame()) + " out of order");
  return store_.append(encodeSnapshot(world.snapshot()));
}

Status CacheReader::open(const std::string& dir, const CacheManifest& want) {
  dir_ = dir;
  auto have = readManifest(dir);
  if (!have.ok()) return have.error();
  if (const std::string why = have.value().mismatch(want); !why.empty())
    return Error(ErrorKind::BadInput, dir + ": this cache is not for this render: " + why);
  auto store = io::FrameStoreReader::open(dir);
  if (!store.ok()) return store.error();
  store_ = std::make_unique<io::FrameStoreReader>(std::move(store.value()));
  return {};
}

Status CacheReader::restore(World& world, int k) const {
  auto bytes = store_->read(k);
  if (!bytes.ok()) return bytes.error();
  WorldSnapshot snap;
  if (!decodeSnapshot(bytes.value().data(), bytes.value().size(), snap) || snap.frame != k)
    return Error(ErrorKind::BadInput, dir_ + ": frame " + std::to_string(k) + " does not decode into this scene's world");
  if (Status st = world.restore(snap); !st) {
    Error e = st.error();
    e.kind = ErrorKind::BadInput;
    e.messages.front() = dir_ + ": frame " + std::to_string(k) + ": " + e.messages.front();
    return e;
  }
  return {};
}

}  // namespace reel::app
