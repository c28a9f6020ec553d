#include "sim/row_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"

namespace reel {

void RowGrid::build(std::span<const Vec3> p, double r) {
  const std::size_t n = p.size();
  if (!(r > 0) || !std::isfinite(r)) r = 1.0;  // (callers pass a positive radius)
  r_ = r;
  // The rows' extent: the finite coordinates' box.
  double ylo = INFINITY, yhi = -INFINITY, zlo = INFINITY, zhi = -INFINITY;
  for (const Vec3& q : p) {
    if (std::isfinite(q.y())) ylo = std::min(ylo, q.y()), yhi = std::max(yhi, q.y());
    if (std::isfinite(q.z())) zlo = std::min(zlo, q.z()), zhi = std::max(zhi, q.z());
  }
  if (!(ylo <= yhi)) ylo = yhi = 0;
  if (!(zlo <= zhi)) zlo = zhi = 0;
  yhi = std::min(yhi, ylo + 1e300), zhi = std::min(zhi, zlo + 1e300);  // (an extent that stays finite)
  const double cap = 4.0 * static_cast<double>(n) + 4096.0;
  cell_ = r;
  while ((yhi - ylo) / cell_ + 1 > cap / ((zhi - zlo) / cell_ + 1)) cell_ *= 1.5;
  y0_ = ylo, z0_ = zlo;
  ny_ = static_cast<std::int64_t>((yhi - ylo) / cell_) + 1;
  nz_ = static_cast<std::int64_t>((zhi - zlo) / cell_) + 1;
  const double inv = 1.0 / cell_;
  auto index = [inv](double v, double v0, std::int64_t m) {
    const double c = std::floor((v - v0) * inv);
    return c >= 0 ? std::min(static_cast<std::int64_t>(std::min(c, 1e15)), m - 1) : std::int64_t{0};
  };
  // Counting sort by row; a point with a non-finite coordinate goes to the extra last row.
  const auto rows = static_cast<std::size_t>(ny_ * nz_) + 1;
  start_.assign(rows + 1, 0);
  row_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<std::uint32_t>(p[i].allFinite() ? index(p[i].z(), z0_, nz_) * ny_ + index(p[i].y(), y0_, ny_)
                                                                  : ny_ * nz_);
    row_[i] = row;
    ++start_[row + 1];
  }
  for (std::size_t k = 0; k < rows; ++k) start_[k + 1] += start_[k];
  // The points are dealt in the last build's order when it covered the same points: each row then
  // arrives almost sorted by x, and an insertion sort finishes it in about one pass.
  key_.resize(n);
  const bool again = order_.size() == n;
  {
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = again ? static_cast<std::size_t>(order_[k]) : k;
      const double xi = p[i].x();
      key_[fill[row_[i]]++] = {std::isnan(xi) ? std::numeric_limits<double>::infinity() : xi, static_cast<std::int32_t>(i)};  // (a total order)
    }
  }
  // Each row by x (ties by index: one order whatever the dealing), rows in parallel; then the
  // coordinates in that order.
  parallelBlocks(static_cast<std::ptrdiff_t>(rows), 64, [&](std::ptrdiff_t r0, std::ptrdiff_t r1) {
    for (std::ptrdiff_t row = r0; row < r1; ++row) {
      auto* a = key_.data() + start_[static_cast<std::size_t>(row)];
      const std::size_t m = start_[static_cast<std::size_t>(row) + 1] - start_[static_cast<std::size_t>(row)];
      // Insertion while the row is nearly sorted; past 8 moves a point (a row dealt in no earlier
      // order, or shuffled), a sort: no quadratic worst case.
      std::size_t moves = 0, j = again ? 1 : m;
      for (; j < m && moves <= 8 * m; ++j) {
        const auto v = a[j];
        std::size_t k = j;
        for (; k > 0 && v < a[k - 1]; --k) a[k] = a[k - 1];
        a[k] = v;
        moves += j - k;
      }
      if (j < m || !again) std::sort(a, a + m);
    }
  }, static_cast<std::ptrdiff_t>(n));
  order_.resize(n);
  for (auto* a : {&x_, &y_, &z_}) a->resize(n + 4);
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t k) {
    const auto i = key_[static_cast<std::size_t>(k)].second;
    order_[k] = i;
    const Vec3& q = p[static_cast<std::size_t>(i)];
    x_[k] = q.x(), y_[k] = q.y(), z_[k] = q.z();
  });
  for (std::size_t k = n; k < n + 4; ++k) x_[k] = y_[k] = z_[k] = 0.0;
}

}  // namespace reel
