#include "io/files.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <fstream>
#include <sstream>

namespace reel::io {

namespace fs = std::filesystem;

Result<std::string> readFile(const std::string& path, std::size_t max_bytes) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    return Error(ErrorKind::BadInput, path + ": " + (fs::exists(path, ec) ? "not a regular file" : "no such file"));
  const auto size = fs::file_size(path, ec);
  if (ec) return Error(ErrorKind::BadInput, path + ": cannot read: " + ec.message());
  if (size > max_bytes)
    return Error(ErrorKind::BadInput, path + ": file is " + std::to_string(size) +
                                          " bytes, more than the limit of " + std::to_string(max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error(ErrorKind::BadInput, path + ": cannot open: " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (!in && !in.eof()) return Error(ErrorKind::BadInput, path + ": read error");
  return ss.str();
}

namespace {

bool within(const fs::path& p, const fs::path& root) {
  auto rel = p.lexically_relative(root);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

std::vector<std::string> assetRoots(const std::string& scene_file) {
  std::error_code ec;
  std::vector<std::string> roots;
  roots.push_back(fs::weakly_canonical(fs::absolute(scene_file, ec).parent_path(), ec).string());
  roots.push_back(fs::weakly_canonical(fs::current_path(ec) / "assets", ec).string());
#ifdef REEL_ASSET_DIR
  roots.push_back(fs::weakly_canonical(fs::path(REEL_ASSET_DIR), ec).string());
#endif
  return roots;
}

bool insideRoots(const std::string& path, const std::vector<std::string>& roots) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return false;
  for (const auto& r : roots)
    if (within(p, fs::weakly_canonical(fs::path(r), ec))) return true;
  return false;
}

namespace {
std::mutex g_assets_mutex;
std::vector<std::string> g_assets;
}  // namespace

std::vector<std::string> resolvedAssets() {
  std::lock_guard<std::mutex> lock(g_assets_mutex);
  return g_assets;
}

void clearResolvedAssets() {
  std::lock_guard<std::mutex> lock(g_assets_mutex);
  g_assets.clear();
}

Result<std::string> resolveAsset(const std::string& scene_file, const std::string& path,
                                 const std::vector<std::string>& extensions, std::size_t max_bytes) {
  std::error_code ec;
  std::vector<fs::path> roots;
  for (const auto& r : assetRoots(scene_file)) roots.emplace_back(r);
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  bool ext_ok = false;
  std::string ext_list;
  for (const auto& e : extensions) {
    ext_ok = ext_ok || e == ext;
    ext_list += (ext_list.empty() ? "" : ", ") + e;
  }
  if (!ext_ok) return Error(ErrorKind::BadInput, "\"" + path + "\": unsupported file type (supported: " + ext_list + ")");
  for (const auto& root : roots) {
    const fs::path candidate = fs::weakly_canonical(root / path, ec);
    if (ec || !fs::exists(candidate, ec)) continue;
    if (!within(candidate, root))
      return Error(ErrorKind::BadInput, "\"" + path + "\": path escapes the allowed folders (the scene's folder and assets/)");
    if (!fs::is_regular_file(candidate, ec))
      return Error(ErrorKind::BadInput, "\"" + path + "\": not a regular file");
    const auto size = fs::file_size(candidate, ec);
    if (ec || size > max_bytes)
      return Error(ErrorKind::BadInput, "\"" + path + "\": file is larger than the limit of " +
                                            std::to_string(max_bytes) + " bytes");
    std::lock_guard<std::mutex> lock(g_assets_mutex);
    g_assets.push_back(candidate.string());
    return candidate.string();
  }
  return Error(ErrorKind::BadInput, "\"" + path + "\": no such file in the scene's folder or assets/");
}

Status createParentFolders(const std::string& path) {
  const fs::path dir = fs::path(path).parent_path();
  std::error_code ec;
  if (dir.empty() || fs::is_directory(dir, ec)) return {};
  fs::create_directories(dir, ec);
  // A file where a folder should be is not always an error of create_directories: look again.
  if (!ec && fs::is_directory(dir, ec)) return {};
  return Error(ErrorKind::Output, path + ": cannot create the folder " + dir.string() + ": " +
                                      (ec ? ec.message() : std::string("a file of that name is in the way")));
}

std::string kindInWords(const fs::file_status& st) {
  return fs::is_directory(st)                                 ? "a folder"
         : fs::is_character_file(st) || fs::is_block_file(st) ? "a device"
         : fs::is_fifo(st)                                    ? "a FIFO"
         : fs::is_socket(st)                                  ? "a socket"
                                                              : "not a regular file";
}

Status checkOutputTarget(const std::string& path) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(path + ".part", ec)))  // reel's own part file is never a link
    return Error(ErrorKind::Output, path + ".part: is a symbolic link, not a regular file: remove it");
  for (const std::string& p : {path, path + ".part"}) {
    const fs::file_status st = fs::status(p, ec);
    if (ec || !fs::exists(st) || fs::is_regular_file(st)) continue;
    return Error(ErrorKind::Output, p + ": is " + kindInWords(st) + ", not a regular file: reel writes its outputs only to regular files");
  }
  return {};
}

std::string writeThrough(const std::string& path) {
  std::error_code ec;
  if (!fs::is_symlink(fs::symlink_status(path, ec))) return path;
  fs::path p = path;
  // Link after link (a dangling one too: the file it names is made), as the kernel's 40 at most.
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    const fs::path t = fs::read_symlink(p, ec);
    if (ec) return path;  // (a link it cannot read: the rename fails, exit 4)
    p = t.is_absolute() ? t : p.parent_path() / t;
  }
  return p.lexically_normal().string();
}

std::string safeFileName(const std::string& name) {
  std::string out;
  const std::string in = name.substr(0, 100);
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
  for (std::size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    // A '.' stays only between letters or digits ("v1.2"), so no "..", no hidden file.
    const bool keep = word(c) || c == '-' || c == '_' ||
                      (c == '.' && !out.empty() && word(out.back()) && i + 1 < in.size() && word(in[i + 1]));
    if (keep) out += c;
    else if (out.empty() || out.back() != '_') out += '_';  // one '_' for a run of others
  }
  return out.empty() || out == "_" ? std::string("scene") : out;
}

AtomicFile::~AtomicFile() { abandon(); }

Status AtomicFile::open(const std::string& path, bool shared) {
  abandon();
  if (Status st = checkOutputTarget(path); !st) return st;
  path_ = writeThrough(path);
  if (path_ != path)
    if (Status st = checkOutputTarget(path_); !st) return st;
  if (Status st = createParentFolders(path_); !st) return st;
  if (shared) {
    static std::atomic<unsigned long long> writers{0};
    part_ = path_ + "." + std::to_string(::getpid()) + "-" + std::to_string(writers++) + ".part";
  } else {
    part_ = path_ + ".part";
  }
  f_ = std::fopen(part_.c_str(), "wb");
  if (!f_) return Error(ErrorKind::Output, part_ + ": cannot write: " + std::strerror(errno));
  return {};
}

Status AtomicFile::write(const std::string& bytes) {
  if (!f_) return Error(ErrorKind::Output, path_ + ": not open");
  if (std::fwrite(bytes.data(), 1, bytes.size(), f_) == bytes.size()) return {};
  const int e = errno;
  abandon();
  return Error(ErrorKind::Output, path_ + ": write failed: " + std::strerror(e ? e : EIO));
}

Status AtomicFile::commit() {
  if (!f_) return Error(ErrorKind::Output, path_ + ": not open");
  const bool bad = std::ferror(f_) != 0;
  const int err_flush = std::fflush(f_);
  const int saved = errno;
  const int err_close = std::fclose(f_);
  f_ = nullptr;
  if (bad || err_flush != 0 || err_close != 0) {
    std::remove(part_.c_str());
    return Error(ErrorKind::Output, path_ + ": write failed: " + std::strerror(saved ? saved : EIO));
  }
  if (std::rename(part_.c_str(), path_.c_str()) != 0) {
    const int e = errno;
    std::remove(part_.c_str());
    return Error(ErrorKind::Output, path_ + ": cannot rename from .part: " + std::strerror(e));
  }
  return {};
}

void AtomicFile::abandon() {
  if (f_) {
    std::fclose(f_);
    f_ = nullptr;
    std::remove(part_.c_str());
  }
}

}  // namespace reel::io
