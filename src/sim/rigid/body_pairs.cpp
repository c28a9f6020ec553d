// The rigid solver's pairs (sim/rigid/solver_detail.h): the broad phase, sweep and prune in
// strips on fattened boxes, and the narrow phase with the manifolds a pair of bodies keeps.
#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "sim/rigid/parts.h"
#include "sim/rigid/solver_detail.h"

namespace reel::rigid_detail {
namespace {

constexpr double kReuse = 1e-3;  // m: how far a pair may move against itself and keep its manifold
constexpr double kKeptMargin = 2e-3;  // m: added to the margin of a manifold that is kept

// B's pose in A's frame.
Eigen::Quaterniond relativeTurn(const SolverBody& A, const SolverBody& B) { return A.state->q.conjugate() * B.state->q; }
Vec3 relativeShift(const SolverBody& A, const SolverBody& B) { return A.pose.R.transpose() * (B.pose.p - A.pose.p); }

// A fresh manifold of A and B, kept with their relative pose.
CachedManifold keepManifold(std::uint32_t ga, std::uint32_t gb, const SolverBody& A, const SolverBody& B,
                            const Manifold& m, double margin) {
  CachedManifold c;
  c.a = ga, c.b = gb;
  c.count = m.count;
  c.margin = margin;
  const Eigen::Quaterniond q = relativeTurn(A, B);
  c.q = {q.w(), q.x(), q.y(), q.z()};
  const Vec3 t = relativeShift(A, B), n = A.pose.R.transpose() * m.normal;
  c.t = {t.x(), t.y(), t.z()};
  c.normal = {n.x(), n.y(), n.z()};
  for (int i = 0; i < m.count; ++i) {
    const ContactPoint& p = m.points[static_cast<std::size_t>(i)];
    // The surface points the midpoint joins: A's lies depth/2 along the normal, B's as far back.
    const Vec3 on_a = A.pose.R.transpose() * (p.position + 0.5 * p.depth * m.normal - A.pose.p);
    const Vec3 on_b = B.pose.R.transpose() * (p.position - 0.5 * p.depth * m.normal - B.pose.p);
    c.on_a[static_cast<std::size_t>(i)] = {on_a.x(), on_a.y(), on_a.z()};
    c.on_b[static_cast<std::size_t>(i)] = {on_b.x(), on_b.y(), on_b.z()};
    c.id[static_cast<std::size_t>(i)] = p.id;
  }
  return c;
}

// The kept manifold carried by the bodies as they are now, when B has moved less than kReuse in
// A's frame since it was computed (its turn measured at B's extent) and their margin now, plus
// kReuse, is within the one it was computed with.
bool reuseManifold(const CachedManifold& c, const SolverBody& A, const SolverBody& B, Manifold& m) {
  const Vec3 shift = relativeShift(A, B) - Vec3(c.t[0], c.t[1], c.t[2]);
  const Eigen::Quaterniond turn = Eigen::Quaterniond(c.q[0], c.q[1], c.q[2], c.q[3]).conjugate() * relativeTurn(A, B);
  const double angle = 2.0 * std::asin(std::min(1.0, turn.vec().norm()));
  if (!(shift.norm() + angle * B.model->extent <= kReuse) || !(A.margin + B.margin + kReuse <= c.margin)) return false;
  m.normal = A.pose.R * Vec3(c.normal[0], c.normal[1], c.normal[2]);
  m.count = c.count;
  for (int i = 0; i < c.count; ++i) {
    const auto& a = c.on_a[static_cast<std::size_t>(i)];
    const auto& b = c.on_b[static_cast<std::size_t>(i)];
    const Vec3 pa = A.pose.R * Vec3(a[0], a[1], a[2]) + A.pose.p, pb = B.pose.R * Vec3(b[0], b[1], b[2]) + B.pose.p;
    m.points[static_cast<std::size_t>(i)] = {0.5 * (pa + pb), (pa - pb).dot(m.normal), c.id[static_cast<std::size_t>(i)]};
  }
  return true;
}

// Sorts `order` by `less` (a strict total order), starting from the order it has (last step's,
// nearly sorted): insertion, or a full sort once it has moved too much. The result does not
// depend on where it started.
template <class Less>
void sortNearlySorted(std::vector<int>& order, Less less) {
  std::size_t moves = 0;
  const std::size_t budget = 8 * order.size() + 64;
  for (std::size_t i = 1; i < order.size(); ++i) {
    const int v = order[i];
    std::size_t j = i;
    for (; j > 0 && less(v, order[j - 1]); --j) order[j] = order[j - 1];
    order[j] = v;
    moves += i - j;
    if (moves > budget) {
      std::sort(order.begin(), order.end(), less);
      return;
    }
  }
}

}  // namespace

// Broad phase. Candidates: the pairs whose fattened boxes overlap, kept while every body's box
// stays inside its fattened one (a resting pile keeps them for ever). The idea is Box2D's fat
// boxes (a fixed 0.1 m there); reel's margin is 5% of the body's size, at least 1 cm, and two
// steps of its motion. The pairs of a step are the candidates whose boxes overlap now (and not
// both asleep), so they are the same whatever candidates were kept. Candidates are found by sweep
// and prune (Baraff 1992; Cohen et al. 1995, I-COLLIDE) in strips: the fattened boxes are cut
// into strips across the axis they spread second most, each strip as wide as the widest box, and
// swept along the axis they spread most (a tall stack is swept along y). A box meets the boxes
// after it in its own strip and those of the next strip whose interval reaches it, each pair
// found once (a strip two away lies beyond the widest box): a pile of columns is swept column by
// column, not a row of columns at once. Sorted by strip, then the box's low end, then the body,
// starting from the last order.
void broadPhase(Step& t) {
  Scratch& S = t.S;
  RigidSolverCache& cache = t.cache;
  std::vector<Collider>& colliders = t.colliders;
  const double h = t.h;
  const int nb = t.nb;
  std::vector<SolverBody>& bodies = t.S.bodies;
  auto& pairs = S.pairs;
  pairs.clear();
  auto& fat_lo = cache.fat_lo;
  auto& fat_hi = cache.fat_hi;
  auto& candidates = cache.candidates;
  bool inside = fat_lo.size() == static_cast<std::size_t>(nb);
  for (int i = 0; i < nb && inside; ++i) {
    const SolverBody& b = bodies[static_cast<std::size_t>(i)];
    const Vec3& lo = fat_lo[static_cast<std::size_t>(i)];
    const Vec3& hi = fat_hi[static_cast<std::size_t>(i)];
    inside = lo.allFinite() && hi.allFinite() && (b.lo.array() >= lo.array()).all() && (b.hi.array() <= hi.array()).all();
  }
  if (!inside) {
    fat_lo.resize(static_cast<std::size_t>(nb));
    fat_hi.resize(static_cast<std::size_t>(nb));
    candidates.clear();
    Vec3 spread_lo = Vec3::Constant(1e300), spread_hi = Vec3::Constant(-1e300), widest = Vec3::Zero();
    double largest = 0.0;  // the largest coordinate, for the rounding slack below
    for (int i = 0; i < nb; ++i) {
      const SolverBody& b = bodies[static_cast<std::size_t>(i)];
      const RigidState& st = *b.state;
      const double fat = std::max(0.01, 0.05 * b.model->extent) + 2.0 * h * (st.v.norm() + st.w.norm() * b.model->extent);
      fat_lo[static_cast<std::size_t>(i)] = b.lo - Vec3::Constant(fat);
      fat_hi[static_cast<std::size_t>(i)] = b.hi + Vec3::Constant(fat);
      const Vec3& lo = fat_lo[static_cast<std::size_t>(i)];
      const Vec3& hi = fat_hi[static_cast<std::size_t>(i)];
      if (lo.allFinite() && hi.allFinite()) {
        spread_lo = spread_lo.cwiseMin(lo);
        spread_hi = spread_hi.cwiseMax(lo);
        widest = widest.cwiseMax(hi - lo);
        largest = std::max({largest, lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()});
      }
    }
    const Vec3 spread = (spread_hi - spread_lo).cwiseMax(0.0);
    int axis = 0;
    spread.maxCoeff(&axis);
    const int across = spread[(axis + 1) % 3] >= spread[(axis + 2) % 3] ? (axis + 1) % 3 : (axis + 2) % 3;
    // (Strips and the window along the axis take a slack far beyond the rounding of coordinates
    // this large, so no overlapping pair falls between them.)
    const double slack = 1e-9 * (1.0 + largest);
    const double strip_width = widest[across] + slack;
    auto& sweep = S.sweep;
    sweep.resize(static_cast<std::size_t>(nb));
    for (int i = 0; i < nb; ++i) {
      Scratch::Sweep& w = sweep[static_cast<std::size_t>(i)];
      w = {fat_lo[static_cast<std::size_t>(i)], fat_hi[static_cast<std::size_t>(i)], i, 0.0};
      // (A box with a non-finite bound goes last and meets nothing.)
      const double k = (w.lo[across] - spread_lo[across]) / strip_width;
      w.strip = w.lo.allFinite() && w.hi.allFinite() ? std::floor(std::clamp(k, 0.0, 1e15)) : 2e15;
      if (!std::isfinite(w.lo[axis])) w.lo[axis] = 1e300;
    }
    std::vector<int>& order = cache.sweep_order;
    if (order.size() != static_cast<std::size_t>(nb)) {
      order.resize(static_cast<std::size_t>(nb));
      for (int i = 0; i < nb; ++i) order[static_cast<std::size_t>(i)] = i;
    }
    sortNearlySorted(order, [&](int i, int j) {
      const Scratch::Sweep& p = sweep[static_cast<std::size_t>(i)];
      const Scratch::Sweep& q = sweep[static_cast<std::size_t>(j)];
      return p.strip != q.strip ? p.strip < q.strip : p.lo[axis] != q.lo[axis] ? p.lo[axis] < q.lo[axis] : i < j;
    });
    auto& sorted = S.sorted;
    sorted.resize(static_cast<std::size_t>(nb));
    for (int i = 0; i < nb; ++i) sorted[static_cast<std::size_t>(i)] = sweep[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])];
    auto test = [&](const Scratch::Sweep& A, const Scratch::Sweep& B) {
      if (A.strip < 1e15 && B.strip < 1e15 && overlaps(A.lo, A.hi, B.lo, B.hi))
        candidates.push_back({std::min(A.body, B.body), std::max(A.body, B.body)});
    };
    const std::size_t ns = sorted.size();
    for (std::size_t s0 = 0; s0 < ns;) {
      std::size_t s1 = s0;  // the strip [s0, s1), the next one [s1, s2)
      while (s1 < ns && sorted[s1].strip == sorted[s0].strip) ++s1;
      std::size_t s2 = s1;
      if (s1 < ns && sorted[s1].strip == sorted[s0].strip + 1 && sorted[s0].strip < 1e15)
        while (s2 < ns && sorted[s2].strip == sorted[s1].strip) ++s2;
      std::size_t from = s1;  // the next strip's first box that may reach the current one
      for (std::size_t i = s0; i < s1; ++i) {
        const Scratch::Sweep& A = sorted[i];
        const double end = A.hi[axis];
        for (std::size_t j = i + 1; j < s1 && sorted[j].lo[axis] <= end; ++j) test(A, sorted[j]);
        while (from < s2 && sorted[from].lo[axis] < A.lo[axis] - widest[axis] - slack) ++from;
        for (std::size_t j = from; j < s2 && sorted[j].lo[axis] <= end; ++j) test(A, sorted[j]);
      }
      s0 = s1;
    }
    std::sort(candidates.begin(), candidates.end());
  }
  // The pairs in the order of the cache's keys: by A, then B's bodies, then the object parts (a
  // sleeping body meets only moving objects, which may wake it).
  std::vector<std::uint32_t>& near = S.near;
  std::size_t cursor = 0;
  for (int i = 0; i < nb; ++i) {
    const SolverBody& A = bodies[static_cast<std::size_t>(i)];
    for (; cursor < candidates.size() && candidates[cursor][0] == i; ++cursor) {
      const SolverBody& B = bodies[static_cast<std::size_t>(candidates[cursor][1])];
      if (A.state->asleep && B.state->asleep) continue;
      if (overlaps(A.lo, A.hi, B.lo, B.hi)) pairs.push_back({i, candidates[cursor][1]});
    }
    partsNear(cache, colliders, A.lo, A.hi, near);
    for (std::uint32_t p : near)
      if (!A.state->asleep || colliders[cache.parts[p].collider].moving()) pairs.push_back({i, -1, p});
  }
}

// Narrow phase, in parallel: each pair writes its own manifold.
void narrowPhase(Step& t) {
  Scratch& S = t.S;
  RigidSolverCache& cache = t.cache;
  std::vector<Collider>& colliders = t.colliders;
  std::vector<SolverBody>& bodies = t.S.bodies;
  const std::vector<std::uint32_t>& global = t.S.global;
  auto& pairs = t.S.pairs;
  std::vector<Manifold>& manifolds = S.manifolds;
  manifolds.resize(pairs.size());
  // Body pairs take last step's manifold where they have barely moved against each other (see
  // CachedManifold), else compute it and keep it. (A pair costs about a microsecond, a few hundred
  // times an element of a plain loop: the threshold is taken on 16 times the pairs.)
  auto& reused = S.reused;  // per pair: the cached manifold it took, or −1
  reused.assign(pairs.size(), -1);
  const std::vector<CachedManifold>& kept = cache.manifolds;
  parallelBlocks(static_cast<std::ptrdiff_t>(pairs.size()), 8, [&](std::ptrdiff_t k0, std::ptrdiff_t k1) {
    for (std::ptrdiff_t k = k0; k < k1; ++k) {
      const Scratch::Pair& p = pairs[static_cast<std::size_t>(k)];
      const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
      Manifold& m = manifolds[static_cast<std::size_t>(k)];
      if (p.b < 0) {
        const ObjectPart& part = cache.parts[p.part];
        collidePart(A.model->shape, A.pose, part, colliders[part.collider], A.margin, m);
        continue;
      }
      const SolverBody& B = bodies[static_cast<std::size_t>(p.b)];
      CachedManifold key;
      key.a = global[static_cast<std::size_t>(p.a)], key.b = global[static_cast<std::size_t>(p.b)];
      const auto it = std::lower_bound(kept.begin(), kept.end(), key);
      if (it != kept.end() && it->a == key.a && it->b == key.b && reuseManifold(*it, A, B, m)) {
        reused[static_cast<std::size_t>(k)] = static_cast<int>(it - kept.begin());
        continue;
      }
      collide(A.model->shape, A.pose, B.model->shape, B.pose, A.margin + B.margin + kKeptMargin, m);
    }
  }, static_cast<std::ptrdiff_t>(pairs.size()) * 16);
  {
    auto& next = S.next_manifolds;
    next.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const Scratch::Pair& p = pairs[k];
      if (p.b < 0 || manifolds[k].count == 0) continue;
      if (reused[k] >= 0) next.push_back(kept[static_cast<std::size_t>(reused[k])]);
      else {
        const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
        const SolverBody& B = bodies[static_cast<std::size_t>(p.b)];
        next.push_back(keepManifold(global[static_cast<std::size_t>(p.a)], global[static_cast<std::size_t>(p.b)], A, B,
                                    manifolds[k], A.margin + B.margin + kKeptMargin));
      }
    }
    std::swap(cache.manifolds, next);
  }
}

}  // namespace reel::rigid_detail
