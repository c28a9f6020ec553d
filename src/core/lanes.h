// Four doubles processed together (GCC's vector extension), for the hot loops that gather from
// neighbour lists: the fluid's pair forces and list builds, a school's zones, the springs'
// products and linearisation in implicit Euler, four pieces' envelope factors side by side and
// the rigid solver's wide contacts.
//
// Every operation on a Lane4 is lane-wise IEEE arithmetic (no fused multiply-add: the build
// has -ffp-contract=off), so a loop written with them gives the same bits whether the compiler
// maps a Lane4 to one AVX register or to two SSE2 ones. REEL_CLONED compiles a function for
// both and lets the loader pick by CPU: faster where AVX2 exists, and the same results on
// every x86-64 (DESIGN 6). REEL_CLONED_WIDE adds AVX-512 (x86-64-v4: its mask registers take
// the lane selections), for the loops it was measured to help: a school's zone sums (0.92x the
// time at 100k agents; the fluid's forces, the springs' products and the envelope factor ran the
// same, with the same bits). A loop keeps one accumulator per lane and adds the lanes in a fixed
// order at the end (hsum). A Lane4 is aligned to 16 bytes where AVX is off and to 32 where it is
// on: a structure that keeps lanes in memory is declared alignas(32) (its lane members too), so
// that both clones lay it out alike (the rigid solver's wide contacts).
#pragma once

namespace reel {

using Lane4 = double __attribute__((vector_size(32)));
using Mask4 = long long __attribute__((vector_size(32)));  // lane-wise comparison results
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int __attribute__((vector_size(16)));

// (l0 + l1) + (l2 + l3).
inline double hsum(const Lane4& a) { return (a[0] + a[1]) + (a[2] + a[3]); }

// A mask's lanes as four bits, lane 0 the lowest.
[[gnu::always_inline]] inline unsigned maskBits(const Mask4& m) {
  return static_cast<unsigned>((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8));
}

// How many lanes four mask bits keep (a table: plain x86-64 has no popcount instruction).
[[gnu::always_inline]] inline unsigned keptCount(unsigned bits) {
  static constexpr unsigned char kCount[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
  return kCount[bits & 15];
}

// The lanes of v that `bits` keeps, first and in order (a left-pack; the other lanes follow):
// a loop that keeps the entries a mask selects writes the four together and advances by
// keptCount(bits), where one store and one dependent add a lane would chain (a liquid's list
// build and its force loop's first pass: docs/fluids.md, Speed).
[[gnu::always_inline]] inline Int4 leftPack(const Int4& v, unsigned bits) {
  static constexpr Int4 kOrder[16] = {{0, 1, 2, 3}, {0, 1, 2, 3}, {1, 0, 2, 3}, {0, 1, 2, 3}, {2, 0, 1, 3}, {0, 2, 1, 3},
                                      {1, 2, 0, 3}, {0, 1, 2, 3}, {3, 0, 1, 2}, {0, 3, 1, 2}, {1, 3, 0, 2}, {0, 1, 3, 2},
                                      {2, 3, 0, 1}, {0, 2, 3, 1}, {1, 2, 3, 0}, {0, 1, 2, 3}};
#if defined(__clang__)  // (no variable shuffle: the sanitizer builds take the lanes one by one)
  const Int4& k = kOrder[bits & 15];
  return Int4{v[k[0]], v[k[1]], v[k[2]], v[k[3]]};
#else
  return __builtin_shuffle(v, kOrder[bits & 15]);
#endif
}

// Three coordinates of four points or vectors, a Lane4 each (the rigid solver's wide contacts, the
// springs' linearisation). Helpers that take and return lanes are always inlined into the clones
// that call them: no call passes a vector across the ABI, whatever the -Wpsabi note says. Four
// lanes are 32-byte aligned where AVX is on and 16 where it is not: every structure that holds
// them in memory is aligned to 32, so that both clones agree on where they lie.
#pragma GCC diagnostic ignored "-Wpsabi"  // (for the including file: GCC reports it at its end)
struct alignas(32) L3 {
  alignas(32) Lane4 x{}, y{}, z{};
};
// (a.x b.x + a.y b.y) + a.z b.z: the order of a Vec3's dot product.
[[gnu::always_inline]] inline Lane4 dot(const L3& a, const L3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
[[gnu::always_inline]] inline L3 operator+(const L3& a, const L3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[gnu::always_inline]] inline L3 operator-(const L3& a, const L3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[gnu::always_inline]] inline L3 operator*(const Lane4& k, const L3& a) { return {k * a.x, k * a.y, k * a.z}; }
[[gnu::always_inline]] inline Lane4 splat(double v) { return Lane4{v, v, v, v}; }
// Lane by lane: a where m is set, b elsewhere.
[[gnu::always_inline]] inline Lane4 select(const Mask4& m, const Lane4& a, const Lane4& b) { return m ? a : b; }
[[gnu::always_inline]] inline L3 select(const Mask4& m, const L3& a, const L3& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
// Lane-wise square roots (IEEE, correctly rounded: the bits of std::sqrt; -fno-math-errno lets
// the compiler take them together).
[[gnu::always_inline]] inline Lane4 sqrt4(const Lane4& a) {
  return Lane4{__builtin_sqrt(a[0]), __builtin_sqrt(a[1]), __builtin_sqrt(a[2]), __builtin_sqrt(a[3])};
}

}  // namespace reel

// Building with -DREEL_TARGET_CLONES=OFF (REEL_NO_CLONES) leaves only the plain version: a dump
// from that build must equal one from the default build byte for byte (docs/engine.md).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(REEL_NO_CLONES)
#define REEL_CLONED __attribute__((target_clones("avx2", "default")))
#define REEL_CLONED_WIDE __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define REEL_CLONED
#define REEL_CLONED_WIDE
#endif
