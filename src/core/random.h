// reel's own random numbers (DESIGN 6): the standard distributions are implementation-defined,
// so every random value comes from the scene seed through these explicit mappings.
#pragma once

#include <cstdint>

namespace reel {

// SplitMix64 (Steele, Lea & Flood 2014): a 64-bit counter hashed to a well-mixed output.
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// A uniform double in [0, 1) from the top 53 bits of a 64-bit value.
inline double unitFromBits(std::uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

// The value number `index` of stream `stream` under `seed`, uniform in [0, 1): random access, so
// a parallel loop may draw value i for element i and get the same bits in any order.
inline double uniformAt(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  return unitFromBits(splitmix64(splitmix64(splitmix64(seed) ^ stream) + index));
}

}  // namespace reel
