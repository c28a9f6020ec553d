// The contact layer's broad phase (sim/contact_layer.h): which pieces are near one they may touch,
// and the candidate pairs of points and triangles, points and points, threads and threads, found
// in parallel in fixed blocks and joined in order (the same pairs for any thread count).
#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "sim/collide.h"
#include "sim/contact_layer.h"

namespace reel {

// Which pieces are near a piece they may touch: the pieces' boxes in a grid of cells as large as
// twice their mean size (each small piece looks in the 27 cells around its centre, which hold
// every box it overlaps); the few larger pieces (a pool, a big sheet) are tried against every
// piece. False when none is near.
bool ContactLayer::nearPieces(std::uint32_t pieces) {
  near_.assign(pieces, 0);
  double mean = 0.0;
  std::uint32_t counted = 0;
  for (std::uint32_t q = 0; q < pieces; ++q)
    if (piece_lo_[q].x() <= piece_hi_[q].x()) {
      mean += (piece_hi_[q] - piece_lo_[q]).maxCoeff();
      ++counted;
    }
  if (counted < 2 || !(mean > 0.0 && mean < 1e300)) return false;
  const double cell = 2.0 * mean / counted;
  // 0: they do not meet; kPlain: by the layer's own law; kHooked: by a hook's.
  // (Symmetric in a and b. The boxes first: most candidates of the grid fail there.)
  auto may = [&](std::uint32_t a, std::uint32_t b) -> std::uint8_t {
    const bool overlap =
        (piece_lo_[a].array() <= piece_hi_[b].array()).all() && (piece_lo_[b].array() <= piece_hi_[a].array()).all();
    if (!overlap) return 0;
    const std::uint32_t sa = piece_slot_[a], sb = piece_slot_[b];
    if (!touches_points_[sa] || !touches_points_[sb]) return 0;
    if (sa == sb ? !self_meet_[sa] : skipped(p_.body[sa], p_.body[sb])) {
      if (sa == sb || (hookOf(sa, sb) < 0 && hookOf(sb, sa) < 0)) return 0;
      return kHooked;
    }
    return kPlain;
  };
  // Small pieces in the grid; large ones (and empty ones) not listed.
  big_.clear();
  lo_.resize(pieces);
  hi_.resize(pieces);
  for (std::uint32_t q = 0; q < pieces; ++q) {
    const bool empty = !(piece_lo_[q].x() <= piece_hi_[q].x());
    const bool small = !empty && (piece_hi_[q] - piece_lo_[q]).maxCoeff() <= cell;
    if (!empty && !small) big_.push_back(q);
    lo_[q] = piece_lo_[q], hi_[q] = piece_hi_[q];
    if (!small) BoxGrid::unlist(lo_[q], hi_[q]);
  }
  point_grid_.build(lo_, hi_, cell);
  // Each small piece from its own search, in parallel: two small pieces whose boxes overlap find
  // each other (each box lies within half a cell of its centre, so the other box reaches a cell
  // next to that centre's), and `may` is symmetric, so a piece's own search sets all its flags.
  parallelFor(static_cast<std::ptrdiff_t>(pieces), [&](std::ptrdiff_t qi) {
    const auto q = static_cast<std::uint32_t>(qi);
    if (!BoxGrid::listed(lo_[q], hi_[q])) return;
    std::uint8_t flags = 0;
    point_grid_.forEachNear(0.5 * (piece_lo_[q] + piece_hi_[q]), [&](int o) {
      const auto ou = static_cast<std::uint32_t>(o);
      if (ou != q) flags |= may(q, ou);
    });
    near_[q] = flags;
  });
  bool any = std::find_if(near_.begin(), near_.end(), [](std::uint8_t f) { return f != 0; }) != near_.end();
  for (std::uint32_t b : big_)
    for (std::uint32_t q = 0; q < pieces; ++q) {
      if (q == b) continue;
      if (const std::uint8_t how = may(b, q)) near_[b] |= how, near_[q] |= how, any = true;
    }
  return any;
}

// --- broad phase -----------------------------------------------------------------------------
// Pairs (a, b) for every item a in [0, n): candidates(a, cand) appends a's partners to cand, which
// are then sorted and made unique. Items in fixed blocks (in parallel), blocks joined in order:
// the same pairs in the same order for any thread count.
template <class F>
void ContactLayer::gatherPairs(std::size_t n, std::vector<std::array<std::uint32_t, 2>>& pairs, F&& candidates) {
  pairs.clear();
  constexpr std::ptrdiff_t kBlock = 256;
  const auto count = static_cast<std::ptrdiff_t>(n);
  chunk_pairs_.resize(static_cast<std::size_t>((count + kBlock - 1) / kBlock));
  parallelBlocks(count, kBlock, [&](std::ptrdiff_t a0, std::ptrdiff_t a1) {
    auto& out = chunk_pairs_[static_cast<std::size_t>(a0 / kBlock)];
    out.clear();
    std::vector<std::uint32_t> cand;
    for (std::ptrdiff_t aa = a0; aa < a1; ++aa) {
      const auto a = static_cast<std::uint32_t>(aa);
      cand.clear();
      candidates(a, cand);
      std::sort(cand.begin(), cand.end());
      cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
      for (std::uint32_t b : cand) out.push_back({a, b});
    }
  });
  for (const auto& c : chunk_pairs_) pairs.insert(pairs.end(), c.begin(), c.end());
}

// Point–triangle: the triangles' boxes over the step (start and end, grown by their radius and
// the largest point radius) in a grid; each point looks along its own path, a cell at a time, so
// a fast point finds a sheet it would pass through. Candidates of each point sorted and unique;
// points in fixed blocks, blocks joined in order.
void ContactLayer::findPointTriangle() {
  pt_pairs_.clear();
  const std::size_t nt = p_.tri.size(), np = p_.x.size();
  if (nt == 0) return;
  double rmax = 0.0;
  for (double r : p_.r) rmax = std::max(rmax, r);
  lo_.resize(nt);
  hi_.resize(nt);
  double mean = 0.0;
  std::size_t counted = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    if (!near(p_.tri[t][0])) {
      BoxGrid::unlist(lo_[t], hi_[t]);
      continue;
    }
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    double rt = 0.0;
    for (std::uint32_t k : p_.tri[t]) {
      lo = lo.cwiseMin(p_.x[k]).cwiseMin(p_.x0[k]);
      hi = hi.cwiseMax(p_.x[k]).cwiseMax(p_.x0[k]);
      rt = std::max(rt, p_.r[k]);
    }
    rt += grow_[p_.slot[p_.tri[t][0]]];
    lo_[t] = lo - Vec3::Constant(rt + rmax);
    hi_[t] = hi + Vec3::Constant(rt + rmax);
    mean += (hi_[t] - lo_[t]).maxCoeff();
    ++counted;
  }
  if (counted == 0) return;
  mean /= static_cast<double>(counted);
  if (!(mean > 0.0 && mean < 1e6)) return;  // a non-finite state: the state check reports it
  const double cell = mean;
  // A triangle spread over very many cells (a corner flung far in one step) is left out.
  for (std::size_t t = 0; t < nt; ++t)
    if (BoxGrid::listed(lo_[t], hi_[t]) && !((hi_[t] - lo_[t]).maxCoeff() <= 16 * cell)) BoxGrid::unlist(lo_[t], hi_[t]);
  tri_grid_.build(lo_, hi_, cell);
  // Each surface's triangles' boxes together: a point outside those of the surfaces it may meet
  // meets none.
  const std::size_t slots = p_.body.size();
  slot_lo_.assign(slots, Vec3::Constant(1e300));
  slot_hi_.assign(slots, Vec3::Constant(-1e300));
  for (std::size_t t = 0; t < nt; ++t)
    if (BoxGrid::listed(lo_[t], hi_[t])) {
      const std::uint32_t e = p_.slot[p_.tri[t][0]];
      slot_lo_[e] = slot_lo_[e].cwiseMin(lo_[t]);
      slot_hi_[e] = slot_hi_[e].cwiseMax(hi_[t]);
    }
  std::vector<std::uint32_t> surfaces;
  for (std::uint32_t e = 0; e < slots; ++e)
    if (slot_lo_[e].x() <= slot_hi_[e].x()) surfaces.push_back(e);
  auto mayMeet = [&](std::uint32_t a, std::uint32_t b) {
    return a == b ? self_meet_[a] != 0 : !skipped(p_.body[a], p_.body[b]) || hookOf(a, b) >= 0;
  };
  gatherPairs(np, pt_pairs_, [&](std::uint32_t i, std::vector<std::uint32_t>& cand) {
    if (!near(i)) return;
    const Vec3 &p1 = p_.x[i], &p0 = p_.x0[i];
    const Vec3 plo = p0.cwiseMin(p1) - Vec3::Constant(p_.r[i]), phi = p0.cwiseMax(p1) + Vec3::Constant(p_.r[i]);
    bool any = false;
    for (std::uint32_t e : surfaces)
      if (!((plo.array() > slot_hi_[e].array()).any() || (phi.array() < slot_lo_[e].array()).any()) && mayMeet(p_.slot[i], e)) {
        any = true;
        break;
      }
    if (!any) return;
    const int samples = std::min(64, 1 + static_cast<int>((p1 - p0).norm() / (0.5 * cell)));
    std::array<std::int64_t, 3> last{};
    for (int s = 0; s <= samples; ++s) {
      const Vec3 at = p0 + (p1 - p0) * (static_cast<double>(s) / samples);
      const std::array<std::int64_t, 3> c = tri_grid_.cellOf(at);
      if (s > 0 && c == last) continue;  // (the cell just visited)
      last = c;
      tri_grid_.forEachAt(at, [&](int t) {
        const auto tu = static_cast<std::size_t>(t);
        if ((plo.array() > hi_[tu].array()).any() || (phi.array() < lo_[tu].array()).any()) return;
        const std::uint32_t k = p_.tri[tu][0];
        if (meet(i, k) || (!hooks_.empty() && hookOf(p_.slot[i], p_.slot[k]) >= 0)) cand.push_back(static_cast<std::uint32_t>(t));
      });
    }
  });
  // The hooked pairs apart, in the same order.
  hk_pairs_.clear();
  if (hooks_.empty()) return;
  std::size_t kept = 0;
  for (const auto& q : pt_pairs_) {
    const int h = hookOf(p_.slot[q[0]], p_.slot[p_.tri[q[1]][0]]);
    if (h >= 0)
      hk_pairs_.push_back({q[0], q[1], static_cast<std::uint32_t>(h)});
    else
      pt_pairs_[kept++] = q;
  }
  pt_pairs_.resize(kept);
}

// Point–point: the points' end positions in a grid of cells twice the largest radius; each pair
// of points closer than their radii, i < j, in order of i then j.
void ContactLayer::findPointPoint() {
  const std::size_t np = p_.x.size();
  double rmax = 0.0;
  for (std::size_t i = 0; i < np; ++i)
    if (nearPlain(i)) rmax = std::max(rmax, p_.r[i]);
  pp_pairs_.clear();
  if (!(rmax > 0.0 && rmax < 1e6)) return;
  const double cell = 2.0 * rmax;
  lo_.resize(np);
  hi_.resize(np);
  for (std::size_t i = 0; i < np; ++i) {
    // (Points of bodies that meet no one by the layer's own law are not listed.)
    lo_[i] = hi_[i] = p_.x[i];
    if (!nearPlain(i)) BoxGrid::unlist(lo_[i], hi_[i]);
  }
  point_grid_.build(lo_, hi_, cell);
  gatherPairs(np, pp_pairs_, [&](std::uint32_t i, std::vector<std::uint32_t>& cand) {
    if (!nearPlain(i)) return;
    point_grid_.forEachNear(p_.x[i], [&](int j) {
      const auto ju = static_cast<std::uint32_t>(j);
      if (ju <= i || !meet(i, ju)) return;
      const double rr = p_.r[i] + p_.r[ju];
      if ((p_.x[ju] - p_.x[i]).squaredNorm() < rr * rr) cand.push_back(ju);
    });
  });
}

// Edge–edge: the threads' boxes over the step (grown by their radii) in a grid of cells as large
// as the largest box, so the 27 cells around a box's centre hold every box it overlaps; pairs
// e < f of other pieces that share no point, in order of e then f.
void ContactLayer::findEdgeEdge() {
  ee_pairs_.clear();
  const std::size_t ne = p_.edge.size();
  if (ne < 2) return;
  lo_.resize(ne);
  hi_.resize(ne);
  double cell = 0.0;
  for (std::size_t e = 0; e < ne; ++e) {
    const auto& E = p_.edge[e];
    if (!nearPlain(E[0]) && !nearPlain(E[1])) {
      BoxGrid::unlist(lo_[e], hi_[e]);
      continue;
    }
    const Vec3 g = Vec3::Constant(std::max(p_.r[E[0]], p_.r[E[1]]));
    lo_[e] = p_.x[E[0]].cwiseMin(p_.x[E[1]]).cwiseMin(p_.x0[E[0]]).cwiseMin(p_.x0[E[1]]) - g;
    hi_[e] = p_.x[E[0]].cwiseMax(p_.x[E[1]]).cwiseMax(p_.x0[E[0]]).cwiseMax(p_.x0[E[1]]) + g;
    cell = std::max(cell, (hi_[e] - lo_[e]).maxCoeff());
  }
  if (!(cell > 0.0 && cell < 1e3)) return;  // none near, or a runaway the state check reports
  point_grid_.build(lo_, hi_, cell);
  gatherPairs(ne, ee_pairs_, [&](std::uint32_t e, std::vector<std::uint32_t>& cand) {
    if (!BoxGrid::listed(lo_[e], hi_[e])) return;
    const auto& E = p_.edge[e];
    point_grid_.forEachNear(0.5 * (lo_[e] + hi_[e]), [&](int f) {
      const auto fu = static_cast<std::uint32_t>(f);
      if (fu <= e) return;
      const auto& F = p_.edge[fu];
      if ((lo_[e].array() > hi_[fu].array()).any() || (hi_[e].array() < lo_[fu].array()).any()) return;
      if (E[0] == F[0] || E[0] == F[1] || E[1] == F[0] || E[1] == F[1] || !meet(E[0], F[0])) return;
      cand.push_back(fu);
    });
  });
}

// Point–convex: the parts moved by a system (rigid bodies, figures' links; not a fixed or keyed
// rigid entry, whose collider every body meets in its own step as an object), each by its box over
// the step (its shape at its pose, grown by its motion, its collider's thickness, the largest
// point radius and adhesion range). A body's points are looked at only when its box meets some
// part's it may touch (not its own, not a hooked body's); each of those points tries those parts'
// boxes against its path. Held points (inverse mass 0) and points taken this step meet none.
// Pairs in order of point, then part.
void ContactLayer::findPointConvex(double h) {
  pc_pairs_.clear();
  pc_parts_.clear();
  for (std::size_t c = 0; c < p_.convex.size(); ++c)
    if (p_.convex[c].body != ContactProxies::kObject && (*colliders_)[p_.convex[c].collider].shape->free_body)
      pc_parts_.push_back(static_cast<std::uint32_t>(c));
  const std::size_t np = p_.x.size(), nc = pc_parts_.size(), slots = p_.body.size();
  if (nc == 0 || np == 0) return;
  double grow = 0.0;
  for (double r : p_.r) grow = std::max(grow, r);
  for (const ContactProxies::Surfaces& s : p_.surfaces)
    for (double r : s.range) grow = std::max(grow, r);
  pc_lo_.resize(nc);
  pc_hi_.resize(nc);
  for (std::size_t k = 0; k < nc; ++k) {
    const ContactProxies::Convex& C = p_.convex[pc_parts_[k]];
    shapeBounds(*C.shape, C.pose, pc_lo_[k], pc_hi_[k]);
    const double extent = 0.5 * (pc_hi_[k] - pc_lo_[k]).norm();
    const Vec3 g = Vec3::Constant(grow + (*colliders_)[C.collider].shape->thickness + h * (C.v.norm() + C.w.norm() * extent));
    pc_lo_[k] -= g;
    pc_hi_[k] += g;
    if (!pc_lo_[k].allFinite() || !pc_hi_[k].allFinite()) pc_lo_[k] = Vec3::Constant(1e300), pc_hi_[k] = Vec3::Constant(-1e300);
  }
  // Per body: its points' box over the step, and the parts that box meets.
  slot_lo_.assign(slots, Vec3::Constant(1e300));
  slot_hi_.assign(slots, Vec3::Constant(-1e300));
  for (std::size_t i = 0; i < np; ++i) {
    const std::uint32_t e = p_.slot[i];
    slot_lo_[e] = slot_lo_[e].cwiseMin(p_.x[i]).cwiseMin(p_.x0[i]);
    slot_hi_[e] = slot_hi_[e].cwiseMax(p_.x[i]).cwiseMax(p_.x0[i]);
  }
  auto overlap = [](const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
    return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
  };
  std::vector<std::vector<std::uint32_t>>& slot_parts = pc_slot_parts_;
  slot_parts.resize(slots);
  for (auto& parts : slot_parts) parts.clear();
  bool any = false;
  for (std::size_t e = 0; e < slots; ++e)
    for (std::size_t k = 0; k < nc; ++k) {
      const std::size_t body = p_.convex[pc_parts_[k]].body;
      if (body == p_.body[e] || skipped(p_.body[e], body)) continue;
      if (overlap(pc_lo_[k], pc_hi_[k], slot_lo_[e] - Vec3::Constant(grow), slot_hi_[e] + Vec3::Constant(grow)))
        slot_parts[e].push_back(static_cast<std::uint32_t>(k)), any = true;
    }
  if (!any) return;
  gatherPairs(np, pc_pairs_, [&](std::uint32_t i, std::vector<std::uint32_t>& cand) {
    const std::vector<std::uint32_t>& parts = slot_parts[p_.slot[i]];
    if (parts.empty() || !(p_.w[i] > 0.0) || p_.gone[i]) return;
    const Vec3 g = Vec3::Constant(p_.r[i]);
    const Vec3 lo = p_.x[i].cwiseMin(p_.x0[i]) - g, hi = p_.x[i].cwiseMax(p_.x0[i]) + g;
    for (std::uint32_t k : parts)
      if (overlap(pc_lo_[k], pc_hi_[k], lo, hi)) cand.push_back(pc_parts_[k]);
  });
}

}  // namespace reel
