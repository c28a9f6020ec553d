// Direct solves of a sparse symmetric positive definite system over nodes with 3×3 blocks (the
// implicit integrators' A = M − h ∂f/∂v − h² ∂f/∂x), piece by piece. The free nodes split into
// pieces that no block couples (the connected components of the coupling graph once the fixed
// nodes are taken out: each fish of a school, each kelp stalk), and each piece is factorised by
// Cholesky in envelope (skyline) storage: row r of L keeps its entries from the first column any
// coupling of its node reaches, and the factorisation's fill stays inside that envelope (George &
// Liu 1981, "Computer Solution of Large Sparse Positive Definite Systems", ch. 4, the envelope
// method). Nodes numbered along a body (a rope's chain, a fish's rings) keep the envelope a few
// nodes wide, so a piece of n nodes costs O(n·w²) multiply-adds, and no iteration count at all.
// Each piece is solved on one thread in a fixed order: the same bits for any thread count.
// Four pieces of one envelope (the fish of a school, the stalks of a kelp bed) are factorised and
// solved side by side, a Lane4 lane each, by the same operations in the same order: the same bits
// as one by one, four times the work per instruction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace reel {

// Which free nodes form each piece, and each row's envelope (the nodes' own numbering within a
// piece, ascending).
struct SkylinePlan {
  std::vector<int> piece_start;  // (pieces + 1) into `nodes`
  std::vector<int> nodes;        // the free nodes, piece by piece
  std::vector<int> local;        // per node of the system: its index within its piece (−1: fixed)
  std::vector<int> first;        // per entry of `nodes`: the lowest local node it is coupled to (or itself)
  double factor_cost = 0.0;      // multiply-adds of one factorisation and its two substitutions, all pieces
  std::size_t largest = 0;       // the largest piece's factor, doubles
  std::size_t free_ends = 0;     // couplings at free nodes, counted at each end
  std::vector<int> batch_start;  // runs of pieces solved together: 4 of one envelope, or 1

  // From the coupling graph in compressed rows (node i is coupled to other[start[i] .. start[i+1])).
  void build(std::size_t n, const int* start, const int* other, const std::uint8_t* fixed);
  std::size_t pieces() const { return piece_start.empty() ? 0 : piece_start.size() - 1; }
};

// One piece's factor: fill with add(), then factor() and solve().
class SkylineFactor {
 public:
  // Sizes and zeroes the factor for piece p of the plan.
  void begin(const SkylinePlan& plan, std::size_t p);
  // Adds block A_ij (local nodes, j ≤ i; for j = i only its lower triangle is read).
  void add(int i, int j, const Mat3& block);
  // Row r (a dof) of the factor: row(r)[c] is entry (r, c), for c from the row's first column to r.
  double* row(int r) { return value_.data() + offset_[static_cast<std::size_t>(r)]; }
  // L Lᵀ = A in place; false when a pivot is not positive (A not positive definite to rounding).
  bool factor();
  // b := A⁻¹ b, b holding 3 doubles per local node.
  void solve(double* b) const;
  // Gives the storage back when it holds more than `keep` doubles (a thread's scratch after a
  // large piece).
  void release(std::size_t keep);

 private:
  std::vector<std::ptrdiff_t> offset_;  // per row (dof): where its entries start, less its first column
  std::vector<int> first_;           // per row: its first column
  std::vector<double> value_;
  std::vector<double> inv_;  // per row: 1 / L_rr
  int rows_ = 0;
  double& at(int r, int c) { return value_[static_cast<std::size_t>(offset_[static_cast<std::size_t>(r)] + c)]; }
};

// Four doubles, a lane each, aligned as a Lane4 is in every clone (core/lanes.h): the kernels
// read an array of them as Lane4s.
struct alignas(32) LaneSlot {
  double v[4] = {0, 0, 0, 0};
};

// Four pieces of one envelope side by side, a lane each: begin() with the first of them, fill
// each lane with add() or through row(), then factor() and solve().
class SkylineBatch {
 public:
  // Sizes and zeroes the four lanes for the envelope of piece p (and of the three after it).
  void begin(const SkylinePlan& plan, std::size_t p);
  // Adds block A_ij into `lane` (as SkylineFactor::add).
  void add(int lane, int i, int j, const Mat3& block);
  // Row r of `lane`: row(lane, r)[4 c] is entry (r, c), for c from the row's first column to r.
  double* row(int lane, int r) { return value_.data()->v + 4 * offset_[static_cast<std::size_t>(r)] + lane; }
  // L Lᵀ = A lane by lane; the bits of the lanes whose pivots were not all positive (0: none).
  unsigned factor();
  // b := A⁻¹ b lane by lane, b holding per local dof a slot (lane l: piece l).
  void solve(LaneSlot* b) const;
  // Gives the storage back when it holds more than `keep` doubles (as SkylineFactor::release).
  void release(std::size_t keep);

 private:
  std::vector<std::ptrdiff_t> offset_;
  std::vector<int> first_;
  std::vector<LaneSlot> value_;  // per entry
  std::vector<LaneSlot> inv_;    // per row
  int rows_ = 0;
};

}  // namespace reel
