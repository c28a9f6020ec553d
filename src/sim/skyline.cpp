#include "sim/skyline.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

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
  // Runs of four pieces alike: the same size and the same first columns, counted from each one's
  // first node.
  auto alike = [&](std::size_t p, std::size_t q) {
    const int size = piece_start[p + 1] - piece_start[p];
    if (piece_start[q + 1] - piece_start[q] != size) return false;
    for (int k = 0; k < size; ++k)
      if (first[static_cast<std::size_t>(piece_start[p] + k)] != first[static_cast<std::size_t>(piece_start[q] + k)]) return false;
    return true;
  };
  batch_start.assign(1, 0);
  for (std::size_t p = 0; p < pieces();) {
    const bool four = p + 4 <= pieces() && alike(p, p + 1) && alike(p, p + 2) && alike(p, p + 3);
    p += four ? 4 : 1;
    batch_start.push_back(static_cast<int>(p));
  }
}

namespace {

// Piece p's rows: where each starts in the storage (less its first column) and its first column;
// returns the entries in all.
std::size_t envelopeOf(const SkylinePlan& plan, std::size_t p, std::vector<std::ptrdiff_t>& offset, std::vector<int>& first) {
  const int k0 = plan.piece_start[p], k1 = plan.piece_start[p + 1];
  const int rows = 3 * (k1 - k0);
  offset.resize(static_cast<std::size_t>(rows));
  first.resize(static_cast<std::size_t>(rows));
  std::ptrdiff_t base = 0;
  for (int r = 0; r < rows; ++r) {
    const int f = 3 * plan.first[static_cast<std::size_t>(k0 + r / 3)];
    first[static_cast<std::size_t>(r)] = f;
    offset[static_cast<std::size_t>(r)] = base - f;
    base += r - f + 1;
  }
  return static_cast<std::size_t>(base);
}

}  // namespace

void SkylineFactor::begin(const SkylinePlan& plan, std::size_t p) {
  rows_ = 3 * (plan.piece_start[p + 1] - plan.piece_start[p]);
  value_.assign(envelopeOf(plan, p, offset_, first_), 0.0);
}

void SkylineFactor::add(int i, int j, const Mat3& block) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < (i == j ? a + 1 : 3); ++b) at(3 * i + a, 3 * j + b) += block(a, b);
}

namespace {

// Σ a[k]·b[k] over [0, n): four lanes, then the lanes and the rest in a fixed order (the same bits
// with or without AVX2; core/lanes.h).
[[gnu::always_inline]] inline double dotLanes(const double* a, const double* b, int n) {
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

// The same sum of four pieces side by side (a lane each), in the same order for each lane.
[[gnu::always_inline]] inline Lane4 dotLanes(const Lane4* a, const Lane4* b, int n) {
  Lane4 acc[4] = {};
  int k = 0;
  for (; k + 4 <= n; k += 4)
    for (int j = 0; j < 4; ++j) acc[j] += a[k + j] * b[k + j];
  Lane4 s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
  for (; k < n; ++k) s += a[k] * b[k];
  return s;
}

[[gnu::always_inline]] inline double sqrtOf(double a) { return std::sqrt(a); }
[[gnu::always_inline]] inline Lane4 sqrtOf(const Lane4& a) { return sqrt4(a); }

// Whether a pivot's square is not positive or not finite (for four: the lanes' bits).
[[gnu::always_inline]] inline bool badPivot(double t) { return !(t > 0.0) || !std::isfinite(t); }
[[gnu::always_inline]] inline unsigned badPivot(const Lane4& t) { return maskBits(~(t > 0.0) | ~((t - t) == 0.0)); }

// The nine sums S_ab = Σ_k R_a[k]·C_b[k] over [0, n) of three rows R against three rows C (nine
// independent chains: a single dot product's latency bound the row-by-row loop).
template <class T>
[[gnu::always_inline]] inline void dots3x3(const T* const R[3], const T* const C[3], int n, T S[3][3]) {
  T s00{}, s01{}, s02{}, s10{}, s11{}, s12{}, s20{}, s21{}, s22{};
  const T *r0 = R[0], *r1 = R[1], *r2 = R[2], *c0 = C[0], *c1 = C[1], *c2 = C[2];
  for (int k = 0; k < n; ++k) {
    const T x0 = r0[k], x1 = r1[k], x2 = r2[k], y0 = c0[k], y1 = c1[k], y2 = c2[k];
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
// L_{r,c0+b} = (A − S_ab − Σ_{b' < b} L_{r,c0+b'} L_{c0+b,c0+b'}) / L_{c0+b,c0+b}. T is a double,
// or a Lane4 for four pieces of one envelope: the same operations lane by lane. Returns the bits
// of the pieces with a pivot that is not positive (one piece stops at it; four go on, the failed
// lane's numbers thrown away).
// (Always inlined: compiled inside each clone of its callers, AVX2 included.)
template <class T>
[[gnu::always_inline]] inline unsigned factorEnvelope(T* v, T* inv, const std::ptrdiff_t* offset, const int* first, int rows) {
  unsigned failed = 0;
  const T one = T{} + 1.0;
  // A pivot's square taken in: whether to stop (one piece stops at its first bad pivot).
  auto stop = [&](const T& t) {
    failed |= badPivot(t);
    return std::is_same_v<T, double> && failed != 0;
  };
  for (int I = 0; I < rows / 3; ++I) {
    const int r0 = 3 * I, fr = first[r0];
    T* L[3] = {v + offset[r0], v + offset[r0 + 1], v + offset[r0 + 2]};
    T S[3][3];
    for (int c0 = fr; c0 < r0; c0 += 3) {
      const T* C[3] = {v + offset[c0], v + offset[c0 + 1], v + offset[c0 + 2]};
      const int k0 = std::max(fr, first[c0]);
      const T* Rk[3] = {L[0] + k0, L[1] + k0, L[2] + k0};
      const T* Ck[3] = {C[0] + k0, C[1] + k0, C[2] + k0};
      dots3x3(Rk, Ck, c0 - k0, S);
      const T j10 = C[1][c0], j20 = C[2][c0], j21 = C[2][c0 + 1];
      const T i0 = inv[c0], i1 = inv[c0 + 1], i2 = inv[c0 + 2];
      for (int a = 0; a < 3; ++a) {
        T* l = L[a] + c0;
        const T x0 = (l[0] - S[a][0]) * i0;
        T t1 = l[1] - S[a][1];
        t1 -= x0 * j10;
        const T x1 = t1 * i1;
        T t2 = l[2] - S[a][2];
        t2 -= x0 * j20;
        t2 -= x1 * j21;
        l[0] = x0, l[1] = x1, l[2] = t2 * i2;
      }
    }
    // The diagonal block: chol(A_II − S).
    const T* Rk[3] = {L[0] + fr, L[1] + fr, L[2] + fr};
    dots3x3(Rk, Rk, r0 - fr, S);
    T* l0 = L[0] + r0;
    T* l1 = L[1] + r0;
    T* l2 = L[2] + r0;
    const T t00 = l0[0] - S[0][0];
    if (stop(t00)) return failed;
    const T d0 = sqrtOf(t00), i0 = one / d0;
    const T x10 = (l1[0] - S[1][0]) * i0;
    T t11 = l1[1] - S[1][1];
    t11 -= x10 * x10;
    if (stop(t11)) return failed;
    const T d1 = sqrtOf(t11), i1 = one / d1;
    const T x20 = (l2[0] - S[2][0]) * i0;
    T t21 = l2[1] - S[2][1];
    t21 -= x20 * x10;
    const T x21 = t21 * i1;
    T t22 = l2[2] - S[2][2];
    t22 -= x20 * x20;
    t22 -= x21 * x21;
    if (stop(t22)) return failed;
    const T d2 = sqrtOf(t22);
    l0[0] = d0, l1[0] = x10, l1[1] = d1, l2[0] = x20, l2[1] = x21, l2[2] = d2;
    inv[r0] = i0, inv[r0 + 1] = i1, inv[r0 + 2] = one / d2;
  }
  return failed;
}

REEL_CLONED bool factorOne(double* v, double* inv, const std::ptrdiff_t* offset, const int* first, int rows) {
  return factorEnvelope(v, inv, offset, first, rows) == 0;
}
REEL_CLONED unsigned factorFour(Lane4* v, Lane4* inv, const std::ptrdiff_t* offset, const int* first, int rows) {
  return factorEnvelope(v, inv, offset, first, rows);
}

// b := (L Lᵀ)⁻¹ b.
template <class T>
[[gnu::always_inline]] inline void solveEnvelope(const T* v, const T* inv, const std::ptrdiff_t* offset, const int* first, int rows, T* b) {
  for (int r = 0; r < rows; ++r) {  // L y = b
    const T* Lr = v + offset[r];
    const int f = first[r];
    b[r] = (b[r] - dotLanes(Lr + f, b + f, r - f)) * inv[r];
  }
  for (int r = rows - 1; r >= 0; --r) {  // Lᵀ x = y, column by column
    const T* Lr = v + offset[r];
    const T x = b[r] * inv[r];
    b[r] = x;
    for (int k = first[r]; k < r; ++k) b[k] -= Lr[k] * x;
  }
}

REEL_CLONED void solveOne(const double* v, const double* inv, const std::ptrdiff_t* offset, const int* first, int rows, double* b) {
  solveEnvelope(v, inv, offset, first, rows, b);
}
REEL_CLONED void solveFour(const Lane4* v, const Lane4* inv, const std::ptrdiff_t* offset, const int* first, int rows, Lane4* b) {
  solveEnvelope(v, inv, offset, first, rows, b);
}

}  // namespace

bool SkylineFactor::factor() {
  inv_.resize(static_cast<std::size_t>(rows_));
  return factorOne(value_.data(), inv_.data(), offset_.data(), first_.data(), rows_);
}

void SkylineFactor::solve(double* b) const {
  solveOne(value_.data(), inv_.data(), offset_.data(), first_.data(), rows_, b);
}

void SkylineFactor::release(std::size_t keep) {
  if (value_.capacity() <= keep) return;
  value_ = {};
  offset_ = {};
  first_ = {};
  inv_ = {};
}

void SkylineBatch::begin(const SkylinePlan& plan, std::size_t p) {
  rows_ = 3 * (plan.piece_start[p + 1] - plan.piece_start[p]);
  value_.assign(envelopeOf(plan, p, offset_, first_), LaneSlot{});
}

void SkylineBatch::add(int lane, int i, int j, const Mat3& block) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < (i == j ? a + 1 : 3); ++b) row(lane, 3 * i + a)[4 * (3 * j + b)] += block(a, b);
}

namespace {

// An array of slots as Lane4s (the same 32 bytes; a vector type may alias its element type).
Lane4* lanes(LaneSlot* s) { return reinterpret_cast<Lane4*>(s); }
const Lane4* lanes(const LaneSlot* s) { return reinterpret_cast<const Lane4*>(s); }

}  // namespace

unsigned SkylineBatch::factor() {
  inv_.resize(static_cast<std::size_t>(rows_));
  static_assert(sizeof(LaneSlot) == sizeof(Lane4) && alignof(LaneSlot) >= alignof(Lane4));
  return factorFour(lanes(value_.data()), lanes(inv_.data()), offset_.data(), first_.data(), rows_);
}

void SkylineBatch::solve(LaneSlot* b) const {
  solveFour(lanes(value_.data()), lanes(inv_.data()), offset_.data(), first_.data(), rows_, lanes(b));
}

void SkylineBatch::release(std::size_t keep) {
  if (4 * value_.capacity() <= keep) return;
  value_ = {};
  offset_ = {};
  first_ = {};
  inv_ = {};
}

}  // namespace reel
