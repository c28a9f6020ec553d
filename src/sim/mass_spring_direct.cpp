// MassSpringSystem's direct solve (sim/mass_spring.h, docs/engine.md): the plan of pieces, each
// piece's matrix assembled spring by spring, factorised by envelope Cholesky (sim/skyline.h), four
// pieces of one envelope side by side.
#include <algorithm>

#include "core/parallel.h"
#include "sim/mass_spring.h"

namespace reel {

using Index = std::ptrdiff_t;

// Whether this step's solve will be direct: no force term, the plan of pieces up to date, the
// largest piece's factor within bounds, and (auto) its cost under kDirectIterations of CG's.
bool MassSpringSystem::planDirect() {
  if (term_) return false;
  const auto& inc = m_.incidence;
  if (plan_generation_ != inc.generation || plan_fixed_ != m_.fixed) {
    plan_.build(m_.nodes(), inc.start.data(), inc.other.data(), m_.fixed.data());
    plan_generation_ = inc.generation;
    plan_fixed_ = m_.fixed;
    // Each piece's springs (a spring's free ends lie in one piece), in index order.
    std::vector<int> piece_of(m_.nodes(), -1);
    for (std::size_t p = 0; p < plan_.pieces(); ++p)
      for (int k = plan_.piece_start[p]; k < plan_.piece_start[p + 1]; ++k) piece_of[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(k)])] = static_cast<int>(p);
    const Springs& sp = m_.springs;
    auto pieceOf = [&](std::size_t s) {
      const int pa = piece_of[static_cast<std::size_t>(sp.a[s])];
      return pa >= 0 ? pa : piece_of[static_cast<std::size_t>(sp.b[s])];
    };
    piece_spring_start_.assign(plan_.pieces() + 1, 0);
    for (std::size_t s = 0; s < sp.size(); ++s)
      if (const int p = pieceOf(s); p >= 0) ++piece_spring_start_[static_cast<std::size_t>(p) + 1];
    for (std::size_t p = 0; p < plan_.pieces(); ++p) piece_spring_start_[p + 1] += piece_spring_start_[p];
    piece_springs_.resize(static_cast<std::size_t>(piece_spring_start_.back()));
    std::vector<int> fill(piece_spring_start_.begin(), piece_spring_start_.end() - 1);
    for (std::size_t s = 0; s < sp.size(); ++s)
      if (const int p = pieceOf(s); p >= 0) piece_springs_[static_cast<std::size_t>(fill[static_cast<std::size_t>(p)]++)] = static_cast<int>(s);
  }
  if (plan_.largest > kDirectMaxDoubles) return false;
  if (solver_ == LinearSolver::Direct) return true;
  // One CG iteration: a product (9 multiply-adds a spring block at each free end) and its passes
  // over the free nodes (about 30).
  const double cg_iteration = 9.0 * static_cast<double>(plan_.free_ends) + 30.0 * static_cast<double>(plan_.nodes.size());
  return plan_.factor_cost <= kDirectIterations * cg_iteration;
}

bool MassSpringSystem::solveDirect(const Vec3* rhs, Vec3* dv) {
  if (!direct_) return false;
  const std::size_t nodes = m_.nodes();
  const Index pieces = static_cast<Index>(plan_.pieces());
  failed_.assign(static_cast<std::size_t>(pieces), 0);
  auto& failed = failed_;
  // The spring blocks of piece p asked for ahead of their use: linearize() wrote them all, far
  // out of cache by the time they are read here. (Each block: 48 bytes, one or two lines.)
  auto prefetch = [&](Index p) {
    if (p >= pieces) return;
    for (int k = piece_spring_start_[static_cast<std::size_t>(p)]; k < piece_spring_start_[static_cast<std::size_t>(p) + 1]; ++k) {
      const double* B = B_[static_cast<std::size_t>(piece_springs_[static_cast<std::size_t>(k)])].m;
      __builtin_prefetch(B);
      __builtin_prefetch(B + 5);
    }
  };
  // Piece p's A, (m + hγ) I + h D_i + Σ B on the diagonal blocks and −B to the other end of each
  // spring, into a zeroed envelope whose row r is row(r), entry c at row(r)[S c] (S = 4: a lane
  // of a batch). Spring by spring in index order, the blocks read in the order they lie: each
  // entry takes its terms in the order a node's springs are listed (by index), so the same sums
  // as node by node through the incidence, whose scattered reads waited on memory.
  const Springs& sp = m_.springs;
  auto assemble = [&](Index p, auto&& row, int S) {
    const int k0 = plan_.piece_start[static_cast<std::size_t>(p)], k1 = plan_.piece_start[static_cast<std::size_t>(p) + 1];
    for (int k = k0; k < k1; ++k) {
      const int li = k - k0;
      const double own = own_[static_cast<std::size_t>(plan_.nodes[static_cast<std::size_t>(k)])];
      for (int a = 0; a < 3; ++a) row(3 * li + a)[S * (3 * li + a)] = own;
    }
    // The lower triangle of a diagonal block: xx, yx, yy, zx, zy, zz.
    auto addDiagonal = [&](int li, const double* B) {
      double* x = row(3 * li) + S * 3 * li;
      double* y = row(3 * li + 1) + S * 3 * li;
      double* z = row(3 * li + 2) + S * 3 * li;
      x[0] += B[0];
      y[0] += B[3], y[S] += B[1];
      z[0] += B[4], z[S] += B[5], z[2 * S] += B[2];
    };
    for (int e = piece_spring_start_[static_cast<std::size_t>(p)]; e < piece_spring_start_[static_cast<std::size_t>(p) + 1]; ++e) {
      const auto s = static_cast<std::size_t>(piece_springs_[static_cast<std::size_t>(e)]);
      const double* B = B_[s].m;
      const int la = plan_.local[static_cast<std::size_t>(sp.a[s])], lb = plan_.local[static_cast<std::size_t>(sp.b[s])];
      if (la >= 0) addDiagonal(la, B);
      if (lb >= 0) addDiagonal(lb, B);
      if (la < 0 || lb < 0) continue;
      const int li = std::max(la, lb), lj = std::min(la, lb);
      double* x = row(3 * li) + S * 3 * lj;
      double* y = row(3 * li + 1) + S * 3 * lj;
      double* z = row(3 * li + 2) + S * 3 * lj;
      x[0] -= B[0], x[S] -= B[3], x[2 * S] -= B[4];
      y[0] -= B[3], y[S] -= B[1], y[2 * S] -= B[5];
      z[0] -= B[4], z[S] -= B[5], z[2 * S] -= B[2];
    }
    if (node_drag_)
      for (int k = k0; k < k1; ++k) {
        const int li = k - k0;
        const Mat3 hD = h_ * node_drag_[plan_.nodes[static_cast<std::size_t>(k)]];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c <= r; ++c) row(3 * li + r)[S * (3 * li + c)] += hD(r, c);
      }
  };
  const Index batches = static_cast<Index>(plan_.batch_start.size()) - 1;
  parallelBlocks(batches, 1, [&](Index q0, Index q1) {
    thread_local SkylineFactor F;
    thread_local SkylineBatch F4;
    thread_local std::vector<double> b;
    thread_local std::vector<LaneSlot> b4;
    for (Index q = q0; q < q1; ++q) {
      const Index p0 = plan_.batch_start[static_cast<std::size_t>(q)], p1 = plan_.batch_start[static_cast<std::size_t>(q) + 1];
      const int n = 3 * (plan_.piece_start[static_cast<std::size_t>(p0) + 1] - plan_.piece_start[static_cast<std::size_t>(p0)]);
      auto rhsOf = [&](Index p, int r) {
        return rhs[plan_.nodes[static_cast<std::size_t>(plan_.piece_start[static_cast<std::size_t>(p)] + r / 3)]][r % 3];
      };
      auto result = [&](Index p, int li) -> Vec3& { return dv[plan_.nodes[static_cast<std::size_t>(plan_.piece_start[static_cast<std::size_t>(p)] + li)]]; };
      // (A thread's batches are consecutive: its next piece is most likely the one after.)
      if (p1 - p0 == 4) {  // four pieces of one envelope side by side
        F4.begin(plan_, static_cast<std::size_t>(p0));
        b4.resize(static_cast<std::size_t>(n));
        for (int l = 0; l < 4; ++l) {
          prefetch(p0 + l + 1);
          assemble(p0 + l, [&](int r) { return F4.row(l, r); }, 4);
          for (int r = 0; r < n; ++r) b4[static_cast<std::size_t>(r)].v[l] = rhsOf(p0 + l, r);
        }
        if (const unsigned bad = F4.factor()) {
          for (int l = 0; l < 4; ++l)
            if (bad >> l & 1) failed[static_cast<std::size_t>(p0 + l)] = 1;
          F4.release(kDirectKeepDoubles);
          continue;
        }
        F4.solve(b4.data());
        F4.release(kDirectKeepDoubles);  // (as a large single piece's factor)
        for (int l = 0; l < 4; ++l)
          for (int li = 0; li < n / 3; ++li)
            result(p0 + l, li) = Vec3(b4[static_cast<std::size_t>(3 * li)].v[l], b4[static_cast<std::size_t>(3 * li + 1)].v[l],
                                      b4[static_cast<std::size_t>(3 * li + 2)].v[l]);
        continue;
      }
      prefetch(p1);
      F.begin(plan_, static_cast<std::size_t>(p0));
      assemble(p0, [&](int r) { return F.row(r); }, 1);
      b.resize(static_cast<std::size_t>(n));
      for (int r = 0; r < n; ++r) b[static_cast<std::size_t>(r)] = rhsOf(p0, r);
      const bool ok = F.factor();
      if (ok) F.solve(b.data());
      F.release(kDirectKeepDoubles);  // (a large piece's factor is not kept by the thread)
      if (!ok) {
        failed[static_cast<std::size_t>(p0)] = 1;
        continue;
      }
      for (int li = 0; li < n / 3; ++li)
        result(p0, li) = Vec3(b[static_cast<std::size_t>(3 * li)], b[static_cast<std::size_t>(3 * li + 1)], b[static_cast<std::size_t>(3 * li + 2)]);
    }
  }, static_cast<Index>(plan_.factor_cost / 64.0));
  // A piece that is not positive definite to rounding (never expected) sends the whole solve to CG.
  if (std::find(failed.begin(), failed.end(), 1) != failed.end()) {
    ensureCg();
    return false;
  }
  for (std::size_t i = 0; i < nodes; ++i)
    if (m_.fixed[i]) dv[i].setZero();
  return true;
}

}  // namespace reel
