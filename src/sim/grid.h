// A uniform spatial grid, hashed, written once for every neighbour search of the simulation
// (cloth self-collision, triangle-mesh colliders, fluid particles' neighbour lists).
//
// Items are axis-aligned boxes; each is listed in every cell its box overlaps. The cells live in
// a hash table (cell coordinates → bucket), built by a counting sort: items appear in a bucket
// in increasing index order, so a query visits candidates in the same order on every run and
// for any thread count. Distinct cells may share a bucket: callers test the geometry anyway.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/types.h"

namespace reel {

class BoxGrid {
 public:
  // Lists item k in the cells overlapped by [lo[k], hi[k]]. `cell` is the cell edge, m. An empty
  // box (lo > hi on any axis, as unlist() makes it, or NaN) is listed nowhere: the items a search leaves
  // out (a contact piece far from any other) cost the build nothing.
  void build(std::span<const Vec3> lo, std::span<const Vec3> hi, double cell);
  static bool listed(const Vec3& lo, const Vec3& hi) { return (lo.array() <= hi.array()).all(); }
  // Makes [lo, hi] the empty box that build() lists nowhere.
  static void unlist(Vec3& lo, Vec3& hi) { lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300); }

  // Calls f(item) for the items listed in the cell that contains p.
  template <class F>
  void forEachAt(const Vec3& p, F&& f) const {
    if (start_.empty()) return;
    const std::uint32_t b = bucket(coord(p.x()), coord(p.y()), coord(p.z()));
    for (std::uint32_t e = start_[b]; e < start_[b + 1]; ++e) f(items_[e]);
  }
  // Calls f(item) for the items listed in the 27 cells around the one that contains p, each
  // bucket once (neighbouring cells that share a bucket do not repeat its items).
  template <class F>
  void forEachNear(const Vec3& p, F&& f) const {
    std::uint32_t near[27];
    const int n = nearBuckets(p, near);
    for (int q = 0; q < n; ++q)
      for (std::uint32_t e = start_[near[q]]; e < start_[near[q] + 1]; ++e) f(items_[e]);
  }
  // The distinct buckets of the 27 cells around the one that contains p, in the order
  // forEachNear visits them; returns how many (0 for an empty grid). Items of bucket b are
  // items()[bucketBegin(b) .. bucketEnd(b)).
  int nearBuckets(const Vec3& p, std::uint32_t (&out)[27]) const {
    if (start_.empty()) return 0;
    const std::int64_t ci = coord(p.x()), cj = coord(p.y()), ck = coord(p.z());
    int n = 0;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const std::uint32_t b = bucket(ci + di, cj + dj, ck + dk);
          bool dup = false;
          for (int q = 0; q < n; ++q) dup = dup || out[q] == b;
          if (!dup) out[n++] = b;
        }
    return n;
  }
  // The cell that contains p, as three integers.
  std::array<std::int64_t, 3> cellOf(const Vec3& p) const { return {coord(p.x()), coord(p.y()), coord(p.z())}; }
  // How many buckets there are (0 for an empty grid).
  std::uint32_t buckets() const { return start_.empty() ? 0 : static_cast<std::uint32_t>(start_.size() - 1); }
  std::uint32_t bucketBegin(std::uint32_t b) const { return start_[b]; }
  std::uint32_t bucketEnd(std::uint32_t b) const { return start_[b + 1]; }
  std::span<const std::int32_t> items() const { return items_; }
  double cell() const { return cell_; }
  std::size_t entries() const { return items_.size(); }

 private:
  // Clamped so that far-away (or non-finite) points still map to a cell without overflow.
  std::int64_t coord(double v) const {
    const double c = std::floor(v * inv_cell_);
    return c >= -1e15 && c <= 1e15 ? static_cast<std::int64_t>(c) : (c > 0 ? 1000000000000000ll : -1000000000000000ll);
  }
  std::uint32_t bucket(std::int64_t i, std::int64_t j, std::int64_t k) const {
    // The three coordinates packed (21 bits each, wrapping) and mixed by SplitMix64's finaliser,
    // so that neighbouring cells land in unrelated buckets under the power-of-two mask.
    std::uint64_t h = (static_cast<std::uint64_t>(i) & 0x1FFFFF) | (static_cast<std::uint64_t>(j) & 0x1FFFFF) << 21 |
                      (static_cast<std::uint64_t>(k) & 0x1FFFFF) << 42;
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    return static_cast<std::uint32_t>((h ^ (h >> 31)) & mask_);
  }
  double cell_ = 1.0, inv_cell_ = 1.0;
  std::uint64_t mask_ = 0;
  std::vector<std::uint32_t> start_;  // (buckets + 1) offsets into items_
  std::vector<std::int32_t> items_;   // item indices, bucket by bucket, increasing within one
  std::vector<std::uint32_t> fill_;   // scratch
};

}  // namespace reel
