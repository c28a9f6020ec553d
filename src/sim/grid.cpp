#include "sim/grid.h"

#include <algorithm>

#include "core/error.h"

namespace reel {

void BoxGrid::build(std::span<const Vec3> lo, std::span<const Vec3> hi, double cell) {
  REEL_CHECK(cell > 0 && std::isfinite(cell), "grid cell must be positive");
  REEL_CHECK(lo.size() == hi.size(), "grid boxes: lo and hi differ in size");
  cell_ = cell;
  inv_cell_ = 1.0 / cell;
  // Cells per item, then a table of at least twice as many buckets (a power of two).
  std::size_t total = 0;
  for (std::size_t k = 0; k < lo.size(); ++k) {
    if (!listed(lo[k], hi[k])) continue;
    const double nx = std::floor(hi[k].x() * inv_cell_) - std::floor(lo[k].x() * inv_cell_) + 1;
    const double ny = std::floor(hi[k].y() * inv_cell_) - std::floor(lo[k].y() * inv_cell_) + 1;
    const double nz = std::floor(hi[k].z() * inv_cell_) - std::floor(lo[k].z() * inv_cell_) + 1;
    REEL_CHECK(nx * ny * nz <= 4096, "grid: a box spans too many cells (cell size too small)");
    total += static_cast<std::size_t>(nx * ny * nz);
  }
  std::size_t buckets = 64;
  while (buckets < 2 * total) buckets *= 2;
  mask_ = buckets - 1;
  start_.assign(buckets + 1, 0);
  auto visit = [&](std::size_t k, auto&& f) {
    const std::int64_t i0 = coord(lo[k].x()), i1 = coord(hi[k].x());
    const std::int64_t j0 = coord(lo[k].y()), j1 = coord(hi[k].y());
    const std::int64_t k0 = coord(lo[k].z()), k1 = coord(hi[k].z());
    for (std::int64_t c = k0; c <= k1; ++c)
      for (std::int64_t b = j0; b <= j1; ++b)
        for (std::int64_t a = i0; a <= i1; ++a) f(bucket(a, b, c));
  };
  // Counting sort: count per bucket, prefix sums, then fill in item order.
  for (std::size_t k = 0; k < lo.size(); ++k)
    if (listed(lo[k], hi[k])) visit(k, [&](std::uint32_t b) { ++start_[b + 1]; });
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  items_.assign(total, 0);
  fill_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t k = 0; k < lo.size(); ++k)
    if (listed(lo[k], hi[k])) visit(k, [&](std::uint32_t b) {
      // A box over several cells that share a bucket is listed there once.
      const std::uint32_t at = fill_[b];
      if (at > start_[b] && items_[at - 1] == static_cast<std::int32_t>(k)) return;
      items_[fill_[b]++] = static_cast<std::int32_t>(k);
    });
  // Close the gaps left by skipped duplicates so each bucket is contiguous.
  std::uint32_t w = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::uint32_t s = start_[b], e = fill_[b];
    start_[b] = w;
    for (std::uint32_t r = s; r < e; ++r) items_[w++] = items_[r];
  }
  start_[buckets] = w;
  items_.resize(w);
}

}  // namespace reel
