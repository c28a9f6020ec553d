#include "sim/mass_spring.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#include <Eigen/Cholesky>

#include "core/error.h"
#include "core/lanes.h"
#include "core/parallel.h"
#include "sim/forces.h"

namespace reel {

using Index = std::ptrdiff_t;

void Incidence::build(std::size_t nodes, const Springs& s) {
  static std::atomic<std::uint64_t> builds{0};
  generation = ++builds;
  start.assign(nodes + 1, 0);
  for (std::size_t k = 0; k < s.size(); ++k) {
    ++start[static_cast<std::size_t>(s.a[k]) + 1];
    ++start[static_cast<std::size_t>(s.b[k]) + 1];
  }
  for (std::size_t i = 0; i < nodes; ++i) start[i + 1] += start[i];
  entries.assign(2 * s.size(), 0);
  other.assign(2 * s.size(), 0);
  std::vector<int> fill(start.begin(), start.end() - 1);
  // Springs in index order: each node's list is sorted by spring index.
  for (std::size_t k = 0; k < s.size(); ++k) {
    const auto ea = static_cast<std::size_t>(fill[static_cast<std::size_t>(s.a[k])]++);
    entries[ea] = static_cast<int>(2 * k);
    other[ea] = s.b[k];
    const auto eb = static_cast<std::size_t>(fill[static_cast<std::size_t>(s.b[k])]++);
    entries[eb] = static_cast<int>(2 * k + 1);
    other[eb] = s.a[k];
  }
}

void buildMassSpring(const MassSpringDesc& desc, const Vec3& gravity, MassSpringModel& model,
                     MassSpringState& state) {
  const std::size_t n = desc.nodes.size();
  model = MassSpringModel{};
  model.gravity = gravity;
  model.mass.resize(n);
  model.inv_mass.resize(n);
  model.drag.resize(n);
  model.fixed.resize(n);
  state.x.resize(n);
  state.v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const NodeDesc& nd = desc.nodes[i];
    REEL_CHECK(nd.mass > 0.0, "node mass must be positive");
    model.mass[i] = nd.mass;
    model.fixed[i] = nd.fixed ? 1 : 0;
    model.inv_mass[i] = nd.fixed ? 0.0 : 1.0 / nd.mass;
    model.drag[i] = nd.damping;
    state.x[i] = nd.position;
    state.v[i] = nd.fixed ? Vec3::Zero() : nd.velocity;  // fixed nodes stay where they are
  }
  for (const SpringDesc& sd : desc.springs) {
    REEL_CHECK(sd.a >= 0 && sd.b >= 0 && static_cast<std::size_t>(sd.a) < n &&
                   static_cast<std::size_t>(sd.b) < n && sd.a != sd.b,
               "spring end out of range");
    const double rest = sd.rest_length >= 0.0
                            ? sd.rest_length
                            : (desc.nodes[static_cast<std::size_t>(sd.b)].position -
                               desc.nodes[static_cast<std::size_t>(sd.a)].position)
                                  .norm();
    model.springs.add(sd.a, sd.b, sd.stiffness, sd.damping, rest);
  }
  model.incidence.build(n, model.springs);
}

void MassSpringSystem::gather(const std::vector<Vec3>& per_spring, std::size_t i,
                                Vec3& out) const {
  const auto& inc = m_.incidence;
  for (int e = inc.start[i]; e < inc.start[i + 1]; ++e) {
    const int code = inc.entries[static_cast<std::size_t>(e)];
    // ±1 times f is exact, so this equals out ± f bit for bit, without a branch to mispredict.
    const double sign = 1.0 - 2.0 * static_cast<double>(code & 1);
    out += sign * per_spring[static_cast<std::size_t>(code >> 1)];
  }
}

void MassSpringSystem::acceleration(const Vec3* x, const Vec3* v, Vec3* a) {
  const Springs& sp = m_.springs;
  const Index ns = static_cast<Index>(sp.size());
  if (fs_.size() != sp.size()) fs_.resize(sp.size());
  // Per-spring Voigt forces on end a.
  parallelFor(ns, [&](Index s) {
    const int ia = sp.a[s], ib = sp.b[s];
    fs_[s] = springForce(x[ia], x[ib], v[ia], v[ib], sp.stiffness[s], sp.damping[s], sp.rest[s]);
  });
  spring_evals_ += sp.size();
  if (term_) {
    term_f_.assign(m_.nodes(), Vec3::Zero());
    term_->addForces(x, term_f_.data());
  }
  // Per node: gravity as an acceleration (exactly g, never m·g/m), drag and the springs' forces.
  const Vec3 g = m_.gravity;
  parallelFor(static_cast<Index>(m_.nodes()), [&](Index i) {
    if (m_.fixed[i]) {
      a[i].setZero();
      return;
    }
    Vec3 f = -m_.drag[i] * v[i];
    gather(fs_, static_cast<std::size_t>(i), f);
    if (external_) f += external_[i];
    if (term_) f += term_f_[i];
    if (node_drag_) f += node_flow_[i] - node_drag_[i] * v[i];
    a[i] = g + m_.inv_mass[i] * f;
  });
}

namespace {

// x[at[0..3]] as lanes.
[[gnu::always_inline]] inline L3 gather4(const Vec3* p, const int* at) {
  const Vec3 &a = p[at[0]], &b = p[at[1]], &c = p[at[2]], &d = p[at[3]];
  return {Lane4{a.x(), b.x(), c.x(), d.x()}, Lane4{a.y(), b.y(), c.y(), d.y()}, Lane4{a.z(), b.z(), c.z(), d.z()}};
}

// linearize()'s springs [s0, s1), four side by side (s0 a multiple of four; the last group may
// be short: its missing lanes repeat its last spring and are not stored): per spring end a's share
// of the force at the step's end as linearised, f₀ + h K w (Baraff & Witkin), or with `predict`
// for a compressed spring the force at the predicted positions x + h w (setPredictor); and B =
// h²K + hD (6 doubles: xx, yy, zz, xy, xz, yz). Lane by lane the operations of springJacobians(),
// springForce() and SpringJacobians::K() (sim/forces.h), so the same bits as one spring at a time;
// the square roots and divisions of four springs go together (they bound the loop one at a time).
REEL_CLONED
void linearizeFour(const Springs& sp, const Vec3* x, const Vec3* v, const Vec3* w, double h, bool predict, std::ptrdiff_t s0,
                   std::ptrdiff_t s1, Vec3* fs, double* B) {
  const Lane4 one = splat(1.0), hk = splat(h);
  for (std::ptrdiff_t s = s0; s < s1; s += 4) {
    const int n = static_cast<int>(std::min<std::ptrdiff_t>(4, s1 - s));
    int ia[4], ib[4];
    Lane4 k, d, rest;
    for (int l = 0; l < 4; ++l) {
      const auto q = static_cast<std::size_t>(s + std::min(l, n - 1));
      ia[l] = sp.a[q], ib[l] = sp.b[q], k[l] = sp.stiffness[q], d[l] = sp.damping[q], rest[l] = sp.rest[q];
    }
    const L3 xa = gather4(x, ia), xb = gather4(x, ib), va = gather4(v, ia), vb = gather4(v, ib);
    const L3 wa = gather4(w, ia), wb = gather4(w, ib);
    const SpringJacobians4 J = springJacobians4(xa, xb, rest);
    const L3 dw = wb - wa;
    const Lane4 a = (one - J.t) * dot(J.u, dw);
    L3 f = springForce4(xa, xb, va, vb, k, d, rest) + hk * (k * (a * J.u + J.t * dw));
    const Mask4 predicted = predict ? Mask4(J.t == 0.0) : Mask4{0, 0, 0, 0};
    if (maskBits(predicted)) f = select(predicted, springForce4(xa + hk * wa, xb + hk * wb, va, vb, k, d, rest), f);
    // B = h²K + hD = c1·I + c2·û ûᵀ.
    const Lane4 hhk = (h * h) * k;
    const Lane4 c1 = hhk * J.t, c2 = hhk * (one - J.t) + h * d;
    const L3& u = J.u;
    const Lane4 bxx = c1 + (c2 * u.x) * u.x, byy = c1 + (c2 * u.y) * u.y, bzz = c1 + (c2 * u.z) * u.z;
    const Lane4 bxy = (c2 * u.x) * u.y, bxz = (c2 * u.x) * u.z, byz = (c2 * u.y) * u.z;
    for (int l = 0; l < n; ++l) {
      fs[s + l] = Vec3(f.x[l], f.y[l], f.z[l]);
      double* b = B + 6 * (s + l);
      b[0] = bxx[l], b[1] = byy[l], b[2] = bzz[l], b[3] = bxy[l], b[4] = bxz[l], b[5] = byz[l];
    }
  }
}

}  // namespace

void MassSpringSystem::linearize(const Vec3* x, const Vec3* v, const Vec3* w, double h, Vec3* rhs,
                                   Mat3* block_inverse) {
  const Springs& sp = m_.springs;
  const Index ns = static_cast<Index>(sp.size());
  fs_.resize(sp.size());
  B_.resize(sp.size());
  // Per spring, four at a time (linearizeFour).
  static_assert(sizeof(Sym3) == 6 * sizeof(double));
  parallelBlocks(ns, 256, [&](Index s0, Index s1) { linearizeFour(sp, x, v, w, h, predict_, s0, s1, fs_.data(), B_.data()->m); });
  spring_evals_ += sp.size();
  // Per node: rhs = h (m g − γ v + Σ w + the force term's f − h H w), and for CG (cgNode) the
  // springs' blocks copied in the node's entry order and the preconditioner's blocks; a direct
  // solve (solveDirect) reads B_ itself and needs neither.
  const Vec3 g = m_.gravity;
  const std::size_t nodes = m_.nodes();
  h_ = h;
  block_inverse_ = block_inverse;
  direct_ = solver_ != LinearSolver::Cg && planDirect();
  if (!direct_) sizeCg();
  own_.resize(nodes);
  // The force term: its force at the step's end as linearised, f₀ − h H w, and h² H's blocks.
  if (term_) {
    term_f_.assign(nodes, Vec3::Zero());
    term_d_.assign(nodes, Mat3::Zero());
    term_->linearize(x, term_f_.data(), term_d_.data());
    term_->addProduct(w, -h, term_f_.data());
  }
  parallelFor(static_cast<Index>(nodes), [&](Index i) {
    Vec3 f = m_.mass[i] * g - m_.drag[i] * v[i];
    gather(fs_, static_cast<std::size_t>(i), f);
    if (external_) f += external_[i];
    if (node_drag_) f += node_flow_[i] - node_drag_[i] * v[i];
    if (term_) f += term_f_[i];
    rhs[i] = h * f;
    own_[i] = m_.mass[i] + h * m_.drag[i];
    if (!direct_) cgNode(i);
  });
  if (!direct_) cgPairs();
}

// CG's arrays sized for the nodes: the groups of four springs, runs of free nodes, the products'
// pieces, the pairs' diagonal blocks.
void MassSpringSystem::sizeCg() {
  const auto& inc = m_.incidence;
  const std::size_t nodes = m_.nodes();
  group_start_.resize(nodes + 1);
  group_start_[0] = 0;
  // A fixed node's row is never used (its Δv is 0): it gets no groups, and the products skip it.
  for (std::size_t i = 0; i < nodes; ++i)
    group_start_[i + 1] = group_start_[i] + (m_.fixed[i] ? 0 : (inc.start[i + 1] - inc.start[i] + 3) / 4);
  free_end_.resize(nodes);
  for (std::size_t i = nodes; i-- > 0;)
    free_end_[i] = m_.fixed[i] ? static_cast<Index>(i) : (i + 1 < nodes && !m_.fixed[i + 1] ? free_end_[i + 1] : static_cast<Index>(i + 1));
  // The products' pieces: runs of nodes of about equal work (a node and its groups), so that the
  // threads' shares stay even where the fixed nodes gather (the face's skull is its last third).
  {
    const double total = static_cast<double>(group_start_[nodes] + static_cast<int>(nodes));
    const auto pieces = static_cast<std::size_t>(std::clamp<double>(total / 512.0, 1.0, 256.0));
    piece_start_.assign(1, 0);
    std::size_t i = 0;
    for (std::size_t k = 1; k < pieces; ++k) {
      const double cut = total * static_cast<double>(k) / static_cast<double>(pieces);
      while (i < nodes && static_cast<double>(group_start_[i] + static_cast<int>(i)) < cut) ++i;
      if (static_cast<Index>(i) > piece_start_.back()) piece_start_.push_back(static_cast<Index>(i));
    }
    if (piece_start_.back() < static_cast<Index>(nodes)) piece_start_.push_back(static_cast<Index>(nodes));
  }
  groups_.resize(static_cast<std::size_t>(group_start_[nodes]));
  // Products with a spring's block per product with A: one per end at a free node, halved (a
  // spring between two free nodes counts once, as it did when every row was taken).
  products_per_apply_ = 0;
  for (std::size_t i = 0; i < nodes; ++i)
    if (!m_.fixed[i]) products_per_apply_ += static_cast<std::uint64_t>(inc.start[i + 1] - inc.start[i]);
  products_per_apply_ /= 2;
  if (!pairs_.empty()) diag_.resize(nodes);
}

// Node i's springs' blocks in its groups (rounded to single precision) and its preconditioner
// block: the diagonal block (m + hγ) I + h D + h² H_ii + Σ B, inverted (a fixed node: 1/(m + hγ)).
void MassSpringSystem::cgNode(Index i) {
  const auto& inc = m_.incidence;
  const double h = h_;
  Mat3* block_inverse = block_inverse_;
  if (m_.fixed[i]) {
    block_inverse[i] = Mat3::Identity() / own_[i];
    return;
  }
  Mat3 d = Mat3::Identity() * own_[i];
  if (node_drag_) d += h * node_drag_[i];
  if (term_) d += (h * h) * term_d_[i];
  for (int gi = group_start_[i]; gi < group_start_[i + 1]; ++gi) {
    Group4& G = groups_[static_cast<std::size_t>(gi)];
    for (int k = 0; k < 4; ++k) {
      const int e = inc.start[i] + 4 * (gi - group_start_[i]) + k;
      if (e >= inc.start[i + 1]) {
        for (int c = 0; c < 6; ++c) G.b[c][k] = 0.0f;
        G.other[k] = static_cast<int>(i);
        continue;
      }
      const Sym3& B = B_[static_cast<std::size_t>(inc.entries[static_cast<std::size_t>(e)] >> 1)];
      for (int c = 0; c < 6; ++c) G.b[c][k] = static_cast<float>(B.m[c]);
      G.other[k] = inc.other[static_cast<std::size_t>(e)];
      d(0, 0) += B.m[0], d(1, 1) += B.m[1], d(2, 2) += B.m[2];
      d(0, 1) += B.m[3], d(0, 2) += B.m[4], d(1, 2) += B.m[5];
    }
  }
  d(1, 0) = d(0, 1), d(2, 0) = d(0, 2), d(2, 1) = d(1, 2);
  if (!pairs_.empty()) diag_[i] = d;
  // Its inverse by cofactors. A block of a positive definite A is positive definite; a
  // degenerate one (never expected) falls back to its diagonal.
  Mat3 inv;
  inv(0, 0) = d(1, 1) * d(2, 2) - d(1, 2) * d(1, 2);
  inv(0, 1) = d(0, 2) * d(1, 2) - d(0, 1) * d(2, 2);
  inv(0, 2) = d(0, 1) * d(1, 2) - d(0, 2) * d(1, 1);
  inv(1, 1) = d(0, 0) * d(2, 2) - d(0, 2) * d(0, 2);
  inv(1, 2) = d(0, 1) * d(0, 2) - d(0, 0) * d(1, 2);
  inv(2, 2) = d(0, 0) * d(1, 1) - d(0, 1) * d(0, 1);
  const double det = d(0, 0) * inv(0, 0) + d(0, 1) * inv(0, 1) + d(0, 2) * inv(0, 2);
  // (Extreme stiffness over mass can leave the cofactors too inexact for a positive inverse:
  // then too the diagonal.)
  if (det > 0.0 && std::isfinite(det) && inv(0, 0) > 0.0 && inv(1, 1) > 0.0 && inv(2, 2) > 0.0) {
    inv(1, 0) = inv(0, 1), inv(2, 0) = inv(0, 2), inv(2, 1) = inv(1, 2);
    block_inverse[i] = inv / det;
  } else {
    block_inverse[i] = Mat3(d.diagonal().cwiseInverse().asDiagonal());
  }
}

// CG's arrays after a linearize() that prepared a direct solve, built when first needed: the
// direct solve failed (a piece not positive definite), or a product with A is asked for.
void MassSpringSystem::ensureCg() {
  if (!direct_) return;
  direct_ = false;
  sizeCg();
  parallelFor(static_cast<Index>(m_.nodes()), [&](Index i) { cgNode(i); });
  cgPairs();
}

void MassSpringSystem::cgPairs() {
  const auto& inc = m_.incidence;
  const std::size_t nodes = m_.nodes();
  const double h = h_;
  // The pairs' 6×6 blocks, [A_aa A_ab; A_ba A_bb] with A_ab = −Σ B over the springs between a and
  // b plus h² H_ab of the force term, inverted by Cholesky (a block of a positive definite A is
  // positive definite; should rounding say otherwise, the two keep their own blocks).
  if (pairs_.empty()) return;
  partner_.assign(nodes, -1);
  pair_rows_.resize(nodes);
  parallelFor(static_cast<Index>(pairs_.size()), [&](Index k) {
    const auto [a, b] = pairs_[static_cast<std::size_t>(k)];
    if (m_.fixed[static_cast<std::size_t>(a)] || m_.fixed[static_cast<std::size_t>(b)]) return;  // (fixed since the pairs were set)
    Mat3 c = Mat3::Zero();
    for (int e = inc.start[static_cast<std::size_t>(a)]; e < inc.start[static_cast<std::size_t>(a) + 1]; ++e) {
      if (inc.other[static_cast<std::size_t>(e)] != b) continue;
      const Sym3& B = B_[static_cast<std::size_t>(inc.entries[static_cast<std::size_t>(e)] >> 1)];
      c -= Mat3{{B.m[0], B.m[3], B.m[4]}, {B.m[3], B.m[1], B.m[5]}, {B.m[4], B.m[5], B.m[2]}};
    }
    if (term_) term_->addPairBlock(a, b, h * h, c);
    Eigen::Matrix<double, 6, 6> P;
    P << diag_[static_cast<std::size_t>(a)], c, c.transpose(), diag_[static_cast<std::size_t>(b)];
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(P);
    if (llt.info() != Eigen::Success) return;
    const Eigen::Matrix<double, 6, 6> inv = llt.solve(Eigen::Matrix<double, 6, 6>::Identity());
    if (!inv.allFinite()) return;
    pair_rows_[static_cast<std::size_t>(a)] = inv.topRows<3>();
    pair_rows_[static_cast<std::size_t>(b)] << inv.block<3, 3>(3, 3), inv.block<3, 3>(3, 0);  // (r_b, r_a)
    partner_[static_cast<std::size_t>(a)] = b;
    partner_[static_cast<std::size_t>(b)] = a;
  });
}


void MassSpringSystem::setPreconditionerPairs(std::vector<std::array<int, 2>> pairs) {
  std::vector<std::uint8_t> seen(m_.nodes(), 0);
  for (const auto& [a, b] : pairs) {
    REEL_CHECK(a >= 0 && b >= 0 && static_cast<std::size_t>(a) < m_.nodes() && static_cast<std::size_t>(b) < m_.nodes() && a != b,
               "preconditioner pair out of range");
    REEL_CHECK(!m_.fixed[static_cast<std::size_t>(a)] && !m_.fixed[static_cast<std::size_t>(b)], "a preconditioner pair of a fixed node");
    REEL_CHECK(!seen[static_cast<std::size_t>(a)]++ && !seen[static_cast<std::size_t>(b)]++, "a node in two preconditioner pairs");
  }
  pairs_ = std::move(pairs);
  partner_.clear();
}

OdeSystem::PreconditionerPairs MassSpringSystem::preconditionerPairs() const {
  if (direct_ || pairs_.empty() || partner_.size() != m_.nodes()) return {};  // (direct: the pairs are not made)
  return {partner_.data(), pair_rows_.data()};
}

namespace {

// out_i = (m + hγ) p_i + Σ over the springs at i of B (p_i − p_other), for nodes [i0, i1): each
// node reads its springs' groups in order, four springs a lane each, and adds the lanes last.
REEL_CLONED
void applyGroups(const MassSpringSystem::Group4* groups, const int* group_start, const double* own, const Vec3* p,
                 Vec3* out, Index i0, Index i1) {
  const Lane4 zero = {0, 0, 0, 0};
  for (Index i = i0; i < i1; ++i) {
    const Vec3 pi = p[i];
    const Lane4 pi0 = zero + pi.x(), pi1 = zero + pi.y(), pi2 = zero + pi.z();
    Lane4 a0 = zero, a1 = zero, a2 = zero;
    for (int g = group_start[i]; g < group_start[i + 1]; ++g) {
      const MassSpringSystem::Group4& G = groups[g];
      const Vec3 &q0 = p[G.other[0]], &q1 = p[G.other[1]], &q2 = p[G.other[2]], &q3 = p[G.other[3]];
      const Lane4 d0 = pi0 - Lane4{q0.x(), q1.x(), q2.x(), q3.x()};
      const Lane4 d1 = pi1 - Lane4{q0.y(), q1.y(), q2.y(), q3.y()};
      const Lane4 d2 = pi2 - Lane4{q0.z(), q1.z(), q2.z(), q3.z()};
      Float4 f[6];
      std::memcpy(f, G.b, sizeof f);
      // Widened to doubles exactly.
      const Lane4 bxx = __builtin_convertvector(f[0], Lane4), byy = __builtin_convertvector(f[1], Lane4);
      const Lane4 bzz = __builtin_convertvector(f[2], Lane4), bxy = __builtin_convertvector(f[3], Lane4);
      const Lane4 bxz = __builtin_convertvector(f[4], Lane4), byz = __builtin_convertvector(f[5], Lane4);
      a0 += bxx * d0 + bxy * d1 + bxz * d2;
      a1 += bxy * d0 + byy * d1 + byz * d2;
      a2 += bxz * d0 + byz * d1 + bzz * d2;
    }
    out[i] = Vec3(own[i] * pi.x() + hsum(a0), own[i] * pi.y() + hsum(a1), own[i] * pi.z() + hsum(a2));
  }
}

}  // namespace

void MassSpringSystem::applySystem(const Vec3* p, Vec3* out) {
  ensureCg();
  // The force term's share, h² H p, gathered in the same pass over the nodes as the springs'.
  if (term_) term_->prepareProduct(p, h_ * h_);
  const Index pieces = static_cast<Index>(piece_start_.size()) - 1;
  parallelBlocks(pieces, 1, [&](Index c0, Index c1) {
    const Index b0 = piece_start_[c0], b1 = piece_start_[c1];
    // Runs of free nodes; a fixed node's row is 0.
    for (Index i0 = b0; i0 < b1;) {
      if (m_.fixed[i0]) {
        out[i0++].setZero();
        continue;
      }
      const Index i1 = std::min(free_end_[i0], b1);
      applyGroups(groups_.data(), group_start_.data(), own_.data(), p, out, i0, i1);
      if (node_drag_)
        for (Index i = i0; i < i1; ++i) out[i] += h_ * (node_drag_[i] * p[i]);
      if (term_) term_->addProductTo(i0, i1, out);
      i0 = i1;
    }
  }, static_cast<Index>(m_.nodes()));
  spring_products_ += products_per_apply_;
}

double kineticEnergy(const MassSpringModel& m, const MassSpringState& s) {
  return deterministicSum(static_cast<Index>(m.nodes()),
                          [&](Index i) { return 0.5 * m.mass[i] * s.v[i].squaredNorm(); });
}

double totalEnergy(const MassSpringModel& m, const MassSpringState& s) {
  const Springs& sp = m.springs;
  const double spring = deterministicSum(static_cast<Index>(sp.size()), [&](Index k) {
    const double e = (s.x[sp.b[k]] - s.x[sp.a[k]]).norm() - sp.rest[k];
    return 0.5 * sp.stiffness[k] * e * e;
  });
  const double grav = deterministicSum(static_cast<Index>(m.nodes()), [&](Index i) {
    return m.fixed[i] ? 0.0 : -m.mass[i] * m.gravity.dot(s.x[i]);
  });
  return kineticEnergy(m, s) + spring + grav;
}

}  // namespace reel
