#include "app/sim_cache.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "core/hash.h"
#include "core/state_blob.h"
#include "io/files.h"

namespace reel::app {
namespace {

namespace fs = std::filesystem;
constexpr char kMagic[9] = "REELSIM5";
constexpr std::size_t kMaxSceneBytes = 64u << 20;

// A vector's length; on reading, the vector sized to it (false: unreadable or above `limit`).
template <class Archive, class Vector>
bool sized(Archive& a, Vector& v, std::size_t limit) {
  std::size_t n = v.size();
  a(n);
  if constexpr (std::is_same_v<Archive, StateReader>) {
    if (!a.ok() || n > limit) return false;
    v.resize(n);
  }
  return true;
}

// The snapshot's fields in one order for writing and reading.
template <class Snap, class Archive>
void fields(Snap& s, Archive& a) {
  a(s.frame)(s.step);
  if (!sized(a, s.colliders, 1u << 20)) return;
  for (auto& p : s.colliders) a(p.rot)(p.rot_prev)(p.pos)(p.pos_prev)(p.dt)(p.inv_mass)(p.inv_inertia)(p.centre);
  if (!sized(a, s.bodies, 1u << 20)) return;
  for (auto& blob : s.bodies) a(blob.bytes);
  if (!sized(a, s.systems, 1u << 10)) return;
  for (auto& blob : s.systems) a(blob.bytes);
  a(s.solver.last.cg_iterations)(s.solver.last.cg_relative_residual)(s.solver.unconverged)(s.solver.worst_residual);
  auto& c = s.camera;
  a(c.active)(c.centre0)(c.centre)(c.velocity)(c.radius)(c.radius_rate);
}

std::uint64_t checksum(const std::byte* p, std::size_t n) { return hashBytes(p, n).h; }

// The reel binary's size and modification time: a rebuilt reel keys its own cache.
void hashBinary(Hasher& h) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return;
  const auto size = fs::file_size(exe, ec);
  const auto time = fs::last_write_time(exe, ec).time_since_epoch().count();
  h.add(&size, sizeof size);
  h.add(&time, sizeof time);
}

}  // namespace

std::vector<std::byte> encodeSnapshot(const WorldSnapshot& snap) {
  StateBlob blob;
  StateWriter w(blob);
  fields(snap, w);
  return std::move(blob.bytes);
}

bool decodeSnapshot(const std::byte* bytes, std::size_t n, WorldSnapshot& snap) {
  StateBlob blob;
  blob.bytes.assign(bytes, bytes + n);
  StateReader r(blob);
  fields(snap, r);
  return r.done();
}

SimCache::SimCache(const std::string& root, const std::string& scene_file, std::optional<std::uint64_t> seed, int frames)
    : frames_(frames) {
  auto text = io::readFile(scene_file, kMaxSceneBytes);
  if (!text.ok()) return;
  Hasher h;
  h.add(text.value().data(), text.value().size());
  const std::string version = REEL_VERSION;
  h.add(version.data(), version.size());
  const std::uint64_t s = seed.value_or(~std::uint64_t{0});
  const char given = seed ? 1 : 0;
  h.add(&s, sizeof s);
  h.add(&given, 1);
  hashBinary(h);
  // The meshes and textures the scene loaded: their paths, sizes and modification times.
  for (const std::string& a : io::resolvedAssets()) {
    std::error_code ec;
    const auto size = fs::file_size(a, ec);
    const auto time = fs::last_write_time(a, ec).time_since_epoch().count();
    h.add(a.data(), a.size());
    h.add(&size, sizeof size);
    h.add(&time, sizeof time);
  }
  key_ = h.h;
  dir_ = (fs::path(root) / h.hex()).string();
  // Least recently used scenes beyond kScenes go; this one is touched.
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) {
    dir_.clear();
    return;
  }
  fs::last_write_time(dir_, fs::file_time_type::clock::now(), ec);
  std::vector<std::pair<fs::file_time_type, fs::path>> scenes;
  for (const auto& e : fs::directory_iterator(root, ec))
    if (e.is_directory(ec) && e.path().filename().string().size() == 16) scenes.push_back({e.last_write_time(ec), e.path()});
  std::sort(scenes.begin(), scenes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = kScenes; i < scenes.size(); ++i)
    if (scenes[i].second != fs::path(dir_)) fs::remove_all(scenes[i].second, ec);
}

std::string SimCache::path(int frame) const {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d.sim", frame);
  return (fs::path(dir_) / name).string();
}

int SimCache::restoreNearest(World& world, int k) const {
  if (!on()) return world.frame();
  // Checkpoints present, latest first.
  std::vector<int> have;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    int f = -1;
    const std::string n = e.path().filename().string();
    if (std::sscanf(n.c_str(), "frame_%d.sim", &f) == 1 && f > world.frame() && f <= k && n == fs::path(path(f)).filename())
      have.push_back(f);
  }
  std::sort(have.rbegin(), have.rend());
  for (int f : have) {
    auto bytes = io::readFile(path(f), static_cast<std::size_t>(4 * kBudgetBytes));
    if (!bytes.ok()) continue;
    const std::string& b = bytes.value();
    const std::size_t head = 8 + sizeof(std::uint64_t), tail = sizeof(std::uint64_t);
    if (b.size() < head + tail || std::memcmp(b.data(), kMagic, 8) != 0) continue;
    std::uint64_t key = 0, sum = 0;
    std::memcpy(&key, b.data() + 8, sizeof key);
    std::memcpy(&sum, b.data() + b.size() - tail, sizeof sum);
    const auto* payload = reinterpret_cast<const std::byte*>(b.data() + head);
    const std::size_t n = b.size() - head - tail;
    if (key != key_ || checksum(payload, n) != sum) continue;
    WorldSnapshot snap;
    if (!decodeSnapshot(payload, n, snap) || snap.frame != f) continue;
    if (world.restore(snap)) return f;
  }
  return world.frame();
}

void SimCache::offer(const World& world, bool always) {
  if (!on()) return;
  const int f = world.frame();
  if (interval_ > 0 && !always && f % interval_ != 0) return;
  std::error_code ec;
  if (fs::exists(path(f), ec)) return;
  StateBlob blob;
  blob.bytes = encodeSnapshot(world.snapshot());
  if (interval_ == 0) {
    // Every frame when the whole film's checkpoints fit the budget, else evenly spaced.
    const double per = static_cast<double>(blob.bytes.size()) + 64;
    interval_ = std::max(1, static_cast<int>(std::ceil(per * std::max(frames_, 1) / kBudgetBytes)));
    if (!always && f % interval_ != 0) return;
  }
  std::string out(kMagic, 8);
  out.append(reinterpret_cast<const char*>(&key_), sizeof key_);
  out.append(reinterpret_cast<const char*>(blob.bytes.data()), blob.bytes.size());
  const std::uint64_t sum = checksum(blob.bytes.data(), blob.bytes.size());
  out.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  io::AtomicFile file;
  Status st = file.open(path(f), /*shared=*/true);
  if (st) st = file.write(out);
  if (st) st = file.commit();
  if (!st) {
    std::fprintf(stderr, "reel: warning: the simulation cache is off for this run: %s\n", st.error().messages.front().c_str());
    dir_.clear();
  }
}

}  // namespace reel::app
