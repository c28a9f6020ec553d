#include "sim/skyline.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/lanes.h"
#include "core/union_find.h"

namespace reel {

void SkylinePlan::build(std::size_t n, const int* start, const int* other, const std::uint8_t* fixed) {
  // Pieces: the free nodes joined by a coupling (a root is its piece's lowest node).
  std::vector<int> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = static_cast<int>(i);
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    for (int e = start[i]; e < start[i + 1]; ++e) {
      const int j = other[e];
      if (!fixed[static_cast<std::size_t>(j)]) unite(parent, static_cast<int>(i), j);
    }
  }
  std::vector<int> piece_of(n, -1);
  std::vector<int> count;
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    const auto r = static_cast<std::size_t>(findRoot(parent, static_cast<int>(i)));
    if (r == i) piece_of[i] = static_cast<int>(count.size()), count.push_back(0);
    else piece_of[i] = piece_of[r];  // (r < i: seen already)
    ++count[static_cast<std::size_t>(piece_of[i])];
  }
  piece_start.assign(count.size() + 1, 0);
  for (std::size_t p = 0; p < count.size(); ++p) piece_start[p + 1] = piece_start[p] + count[p];
  nodes.assign(static_cast<std::size_t>(piece_start.back()), 0);
  local.assign(n, -1);
  std::vector<int> fill(piece_start.begin(), piece_start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    const auto p = static_cast<std::size_t>(piece_of[i]);
    local[i] = fill[p] - piece_start[p];
    nodes[static_cast<std::size_t>(fill[p]++)] = static_cast<int>(i);
  }
  // Each row's envelope, and what the pieces cost: a row of width w (columns from its first to
  // the diagonal) takes about w²/2 multiply-adds to factor and 2w to substitute.
  first.assign(nodes.size(), 0);
  factor_cost = 0.0;
  largest = free_ends = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!fixed[i]) free_ends += static_cast<std::size_t>(start[i + 1] - start[i]);
  for (std::size_t p = 0; p + 1 < piece_start.size(); ++p) {
    std::size_t size = 0;
    for (int k = piece_start[p]; k < piece_start[p + 1]; ++k) {
      const auto i = static_cast<std::size_t>(nodes[static_cast<std::size_t>(k)]);
      int f = local[i];
      for (int e = start[i]; e < start[i + 1]; ++e)
        if (const int j = local[static_cast<std::size_t>(other[e])]; j >= 0) f = std::min(f, j);
      first[static_cast<std::size_t>(k)] = f;
      for (int c = 0; c < 3; ++c) {
        const double w = 3.0 * (local[i] - f) + c + 1;
        factor_cost += 0.5 * w * w + 2.0 * w;
        size += static_cast<std::size_t>(w);
      }
    }
    largest = std::max(largest, size);
  }
}

void SkylineFactor::begin(const SkylinePlan& plan, std::size_t p) {
  const int k0 = plan.piece_start[p], k1 = plan.piece_start[p + 1];
  rows_ = 3 * (k1 - k0);
  offset_.resize(static_cast<std::size_t>(rows_));
  first_.resize(static_cast<std::size_t>(rows_));
  std::ptrdiff_t base = 0;
  for (int r = 0; r < rows_; ++r) {
    const int f = 3 * plan.first[static_cast<std::size_t>(k0 + r / 3)];
    first_[static_cast<std::size_t>(r)] = f;
    offset_[static_cast<std::size_t>(r)] = base - f;
    base += r - f + 1;
  }
  value_.assign(static_cast<std::size_t>(base), 0.0);
}

void SkylineFactor::add(int i, int j, const Mat3& block) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < (i == j ? a + 1 : 3); ++b) at(3 * i + a, 3 * j + b) += block(a, b);
}

namespace {

// Σ a[k]·b[k] over [0, n): four lanes, then the lanes and the rest in a fixed order (the same bits
// with or without AVX2; core/lanes.h).
inline double dotLanes(const double* a, const double* b, int n) {
  Lane4 acc = {0, 0, 0, 0};
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    Lane4 x, y;
    std::memcpy(&x, a + k, sizeof x);
    std::memcpy(&y, b + k, sizeof y);
    acc += x * y;
  }
  double s = hsum(acc);
  for (; k < n; ++k) s += a[k] * b[k];
  return s;
}

// The nine sums S_ab = Σ_k R_a[k]·C_b[k] over [0, n) of three rows R against three rows C, four
// lanes each (nine independent chains: a single dot product's latency bound the row-by-row loop).
inline void dots3x3(const double* const R[3], const double* const C[3], int n, double S[3][3]) {
  double s00 = 0, s01 = 0, s02 = 0, s10 = 0, s11 = 0, s12 = 0, s20 = 0, s21 = 0, s22 = 0;
  const double *r0 = R[0], *r1 = R[1], *r2 = R[2], *c0 = C[0], *c1 = C[1], *c2 = C[2];
  for (int k = 0; k < n; ++k) {
    const double x0 = r0[k], x1 = r1[k], x2 = r2[k], y0 = c0[k], y1 = c1[k], y2 = c2[k];
    s00 += x0 * y0, s01 += x0 * y1, s02 += x0 * y2;
    s10 += x1 * y0, s11 += x1 * y1, s12 += x1 * y2;
    s20 += x2 * y0, s21 += x2 * y1, s22 += x2 * y2;
  }
  S[0][0] = s00, S[0][1] = s01, S[0][2] = s02, S[1][0] = s10, S[1][1] = s11, S[1][2] = s12, S[2][0] = s20, S[2][1] = s21, S[2][2] = s22;
}

// Node by node (the three rows of a node share their envelope's first column): for each block
// column J of node row I, L_IJ = (A_IJ − Σ_K L_IK L_JKᵀ) L_JJ⁻ᵀ, then L_II = chol(A_II − Σ_K L_IK
// L_IKᵀ). (Each pivot's reciprocal is kept in `inv`: a multiplication instead of a division.)
// Within a block the nine entries are worked in registers, the three rows side by side: stored
// and read back one by one, each waited on the last (the factor's time in a school of fish went
// mostly to those stalls). The operations and their order are those of the plain recurrence
// L_{r,c0+b} = (A − S_ab − Σ_{b' < b} L_{r,c0+b'} L_{c0+b,c0+b'}) / L_{c0+b,c0+b}: the same bits.
REEL_CLONED
bool factorEnvelope(double* v, double* inv, const std::ptrdiff_t* offset, const int* first, int rows) {
  for (int I = 0; I < rows / 3; ++I) {
    const int r0 = 3 * I, fr = first[r0];
    double* L[3] = {v + offset[r0], v + offset[r0 + 1], v + offset[r0 + 2]};
    double S[3][3];
    for (int c0 = fr; c0 < r0; c0 += 3) {
      const double* C[3] = {v + offset[c0], v + offset[c0 + 1], v + offset[c0 + 2]};
      const int k0 = std::max(fr, first[c0]);
      const double* Rk[3] = {L[0] + k0, L[1] + k0, L[2] + k0};
      const double* Ck[3] = {C[0] + k0, C[1] + k0, C[2] + k0};
      dots3x3(Rk, Ck, c0 - k0, S);
      const double j10 = C[1][c0], j20 = C[2][c0], j21 = C[2][c0 + 1];
      const double i0 = inv[c0], i1 = inv[c0 + 1], i2 = inv[c0 + 2];
      for (int a = 0; a < 3; ++a) {
        double* l = L[a] + c0;
        const double x0 = (l[0] - S[a][0]) * i0;
        double t1 = l[1] - S[a][1];
        t1 -= x0 * j10;
        const double x1 = t1 * i1;
        double t2 = l[2] - S[a][2];
        t2 -= x0 * j20;
        t2 -= x1 * j21;
        l[0] = x0, l[1] = x1, l[2] = t2 * i2;
      }
    }
    // The diagonal block: chol(A_II − S).
    {
      const int k0 = fr;
      const double* Rk[3] = {L[0] + k0, L[1] + k0, L[2] + k0};
      dots3x3(Rk, Rk, r0 - k0, S);
      double* l0 = L[0] + r0;
      double* l1 = L[1] + r0;
      double* l2 = L[2] + r0;
      const double t00 = l0[0] - S[0][0];
      if (!(t00 > 0.0) || !std::isfinite(t00)) return false;
      const double d0 = std::sqrt(t00), i0 = 1.0 / d0;
      const double x10 = (l1[0] - S[1][0]) * i0;
      double t11 = l1[1] - S[1][1];
      t11 -= x10 * x10;
      if (!(t11 > 0.0) || !std::isfinite(t11)) return false;
      const double d1 = std::sqrt(t11), i1 = 1.0 / d1;
      const double x20 = (l2[0] - S[2][0]) * i0;
      double t21 = l2[1] - S[2][1];
      t21 -= x20 * x10;
      const double x21 = t21 * i1;
      double t22 = l2[2] - S[2][2];
      t22 -= x20 * x20;
      t22 -= x21 * x21;
      if (!(t22 > 0.0) || !std::isfinite(t22)) return false;
      const double d2 = std::sqrt(t22);
      l0[0] = d0, l1[0] = x10, l1[1] = d1, l2[0] = x20, l2[1] = x21, l2[2] = d2;
      inv[r0] = i0, inv[r0 + 1] = i1, inv[r0 + 2] = 1.0 / d2;
    }
  }
  return true;
}

}  // namespace

bool SkylineFactor::factor() {
  inv_.resize(static_cast<std::size_t>(rows_));
  return factorEnvelope(value_.data(), inv_.data(), offset_.data(), first_.data(), rows_);
}

void SkylineFactor::solve(double* b) const {
  const double* v = value_.data();
  for (int r = 0; r < rows_; ++r) {  // L y = b
    const double* Lr = v + offset_[static_cast<std::size_t>(r)];
    const int f = first_[static_cast<std::size_t>(r)];
    b[r] = (b[r] - dotLanes(Lr + f, b + f, r - f)) * inv_[static_cast<std::size_t>(r)];
  }
  for (int r = rows_ - 1; r >= 0; --r) {  // Lᵀ x = y, column by column
    const double* Lr = v + offset_[static_cast<std::size_t>(r)];
    const double x = b[r] * inv_[static_cast<std::size_t>(r)];
    b[r] = x;
    for (int k = first_[static_cast<std::size_t>(r)]; k < r; ++k) b[k] -= Lr[k] * x;
  }
}

void SkylineFactor::release(std::size_t keep) {
  if (value_.capacity() <= keep) return;
  value_ = {};
  offset_ = {};
  first_ = {};
  inv_ = {};
}

}  // namespace reel
