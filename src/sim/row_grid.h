// A neighbour grid for a dense set of points that each look around themselves at one radius r
// (a school's perception): the points sorted into rows, square cells of side r in the y–z plane,
// and within a row by x, their coordinates copied in that order. The points within r of a point
// then lie in at most 9 runs of consecutive entries, one per row around it, each cut to x ± r
// (a row farther than r is left out). The runs hold about 4 times the points of the sphere, as
// BoxGrid's 27 cells of side r would 6.4 times (sim/grid.h), in 9 runs instead of 27 scattered
// buckets; and a pass over a row's points in x order finds every run by pointers that only move
// forward. (Rows of side r/2 cut the candidates to 2.5 times the sphere but need 25 runs, whose
// walk cost more than the candidates saved: 100,000 agents of a school, 1.4x slower.)
//
// The order depends on the positions only (ties by index), so a pass over the runs visits the
// same candidates in the same order on every run and for any thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/types.h"

namespace reel {

class RowGrid {
 public:
  using Run = std::array<std::uint32_t, 2>;  // sorted entries [begin, end)
  static constexpr int kMaxRuns = 9;

  // Sorts the points into rows of side r (wider where the points spread so thin that there would
  // be more than 4n + 4,096 rows). r > 0. A point with a non-finite coordinate goes to a row of
  // its own, last: it is visited with no runs, and no other point finds it.
  void build(std::span<const Vec3> p, double r);

  std::size_t size() const { return order_.size(); }
  // Rows to visit: the grid's, and the last one of non-finite points.
  std::int64_t rows() const { return start_.empty() ? 0 : ny_ * nz_ + 1; }
  // Sorted entry → point.
  std::span<const std::int32_t> order() const { return order_; }
  // The points' coordinates in sorted order, padded with four zeros past the end (so that a loop
  // may read a group of four past a run's end).
  const double* x() const { return x_.data(); }
  const double* y() const { return y_.data(); }
  const double* z() const { return z_.data(); }

  // Calls f(entry, runs) for every entry of rows [r0, r1) in order, runs (a std::span<const Run>)
  // holding every point within r of it (the entry itself included, and some farther ones).
  // Always inlined, so that a caller compiled in several clones (core/lanes.h) takes the walk
  // into each: a call out of an AVX2 clone would run it, and f, in plain x86-64 (1.7x slower for
  // a school).
  template <class F>
  [[gnu::always_inline]] void visitRows(std::int64_t r0, std::int64_t r1, F&& f) const {
    std::uint32_t lo[kMaxRuns], hi[kMaxRuns], end[kMaxRuns];
    double slab[kMaxRuns][4];  // the row's y and z intervals
    Run runs[kMaxRuns];
    const double r2 = r_ * r_;
    for (std::int64_t row = r0; row < r1; ++row) {
      const std::uint32_t b = start_[static_cast<std::size_t>(row)], e = start_[static_cast<std::size_t>(row) + 1];
      if (b == e) continue;
      if (row == ny_ * nz_) {  // the non-finite points: nothing near them
        for (std::uint32_t k = b; k < e; ++k) f(k, std::span<const Run>());
        continue;
      }
      const std::int64_t iy = row % ny_, iz = row / ny_;
      int nq = 0;
      for (std::int64_t jz = iz - 1; jz <= iz + 1; ++jz)
        for (std::int64_t jy = iy - 1; jy <= iy + 1; ++jy) {
          if (jy < 0 || jz < 0 || jy >= ny_ || jz >= nz_) continue;
          const auto j = static_cast<std::size_t>(jz * ny_ + jy);
          if (start_[j] == start_[j + 1]) continue;
          lo[nq] = hi[nq] = start_[j], end[nq] = start_[j + 1];
          slab[nq][0] = y0_ + static_cast<double>(jy) * cell_, slab[nq][1] = slab[nq][0] + cell_;
          slab[nq][2] = z0_ + static_cast<double>(jz) * cell_, slab[nq][3] = slab[nq][2] + cell_;
          ++nq;
        }
      for (std::uint32_t k = b; k < e; ++k) {
        const double xk = x_[k], yk = y_[k], zk = z_[k], xlo = xk - r_, xhi = xk + r_;
        // Branch-free where the data decides: a window moves about one entry a point, so two
        // conditional steps nearly always suffice (the loops after them rarely run), and a row
        // farther than r is kept out of the list rather than skipped.
        int nr = 0;
        for (int q = 0; q < nq; ++q) {
          const std::uint32_t stop = end[q];
          std::uint32_t l = lo[q], h = hi[q];
          l += static_cast<std::uint32_t>((l < stop) & (x_[l] < xlo));
          l += static_cast<std::uint32_t>((l < stop) & (x_[l] < xlo));
          while (l < stop && x_[l] < xlo) ++l;
          h = h > l ? h : l;
          h += static_cast<std::uint32_t>((h < stop) & (x_[h] <= xhi));
          h += static_cast<std::uint32_t>((h < stop) & (x_[h] <= xhi));
          while (h < stop && x_[h] <= xhi) ++h;
          lo[q] = l, hi[q] = h;
          const double gy = std::max(std::max(slab[q][0] - yk, yk - slab[q][1]), 0.0);
          const double gz = std::max(std::max(slab[q][2] - zk, zk - slab[q][3]), 0.0);
          runs[nr] = {l, h};
          nr += static_cast<int>((l < h) & (gy * gy + gz * gz <= r2));
        }
        f(k, std::span<const Run>(runs, static_cast<std::size_t>(nr)));
      }
    }
  }

 private:
  double r_ = 1, cell_ = 1, y0_ = 0, z0_ = 0;
  std::int64_t ny_ = 0, nz_ = 0;              // rows along y and z
  std::vector<std::uint32_t> start_;          // row → its first entry (rows() + 1)
  std::vector<std::int32_t> order_;
  std::vector<double> x_, y_, z_;
  std::vector<std::uint32_t> row_;                   // scratch: each point's row
  std::vector<std::pair<double, std::int32_t>> key_;  // scratch: (x, point) in row order
};

}  // namespace reel
