// FNV-1a 64-bit hashing of raw bytes, used for determinism checks of simulation state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

namespace reel {

struct Hasher {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
      h ^= p[i];
      h *= 1099511628211ull;
    }
  }
  template <class T>
  void add(std::span<const T> s) { add(s.data(), s.size_bytes()); }
  // The hash as 16 hexadecimal digits (cache folders, film ids, manifests).
  std::string hex() const {
    char s[17];
    std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
    return s;
  }
};

// The hash of one run of bytes (checksums).
inline Hasher hashBytes(const void* data, std::size_t bytes) {
  Hasher h;
  h.add(data, bytes);
  return h;
}

}  // namespace reel
