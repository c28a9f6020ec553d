// What the fuzz targets share: a private folder per process, files written into it, and the seed
// mode. Run with REEL_FUZZ_SEEDS=DIR, a target writes its seeds (small valid inputs, made with
// reel's own writers) into DIR and exits, so the seeds always match today's formats
// (docs/fuzzing.md).
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/files.h"

namespace reel::fuzz {

// A folder of this process's own, made once: the only folder an input may make reel read.
inline const std::string& privateDir() {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/reel-fuzz-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (!d) std::abort();
    return std::string(d);
  }();
  return dir;
}

// Writes `bytes` to `path` (whole or abort: a fuzzer that cannot write has nothing to test).
inline void writeBytes(const std::string& path, const void* bytes, std::size_t n) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (n > 0 && std::fwrite(bytes, 1, n, f) != n) std::abort();
  std::fclose(f);
}

// privateDir()/name holding `bytes`; returns its path.
inline std::string put(const std::string& name, std::string_view bytes) {
  const std::string path = privateDir() + "/" + name;
  writeBytes(path, bytes.data(), bytes.size());
  return path;
}

// Reads a whole file of ours (io::readFile; "" when it cannot be read).
inline std::string slurp(const std::string& path) {
  auto text = io::readFile(path, std::size_t{1} << 30);
  return text.ok() ? text.value() : std::string();
}

// The seed folder (REEL_FUZZ_SEEDS), or nullptr when fuzzing.
inline const char* seedDir() { return std::getenv("REEL_FUZZ_SEEDS"); }

// Writes one seed: the byte that picks the input's kind, then its bytes.
inline void seed(const std::string& name, std::uint8_t kind, std::string_view bytes) {
  std::string s(1, static_cast<char>(kind));
  s.append(bytes);
  writeBytes(std::string(seedDir()) + "/" + name, s.data(), s.size());
}

}  // namespace reel::fuzz
