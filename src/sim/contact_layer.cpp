#include "sim/contact_layer.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "sim/body.h"
#include "sim/collide.h"
#include "sim/geometry.h"
#include "sim/rigid/parts.h"

namespace reel {

bool ContactLayer::skipped(std::size_t a, std::size_t b) const {
  const std::array<std::size_t, 2> k{std::min(a, b), std::max(a, b)};
  return std::binary_search(skip_.begin(), skip_.end(), k);
}

int ContactLayer::hookOf(std::uint32_t point_slot, std::uint32_t surface_slot) const {
  return hook_of_.empty() ? -1 : hook_of_[point_slot * exporters_.size() + surface_slot];
}

void ContactLayer::setup(const std::vector<std::unique_ptr<Body>>& bodies, std::span<const HookedPair> hooks,
                         const std::vector<Collider>& colliders) {
  exporters_.clear();
  convex_exporters_.clear();
  held_.clear();
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    if (bodies[k]->exportsContacts()) exporters_.push_back(k);
    if (bodies[k]->exportsConvex()) convex_exporters_.push_back(k);
    std::vector<std::size_t> holders;
    bodies[k]->heldBy(holders);
    for (std::size_t c : holders) held_.push_back({k, c});
  }
  std::sort(held_.begin(), held_.end());
  const std::size_t n = exporters_.size();
  // The hooked pairs: between them only the hook's law (on the points of one against the
  // triangles of the other, those grown by its margin).
  skip_.clear();
  hooks_.clear();
  hook_of_.clear();
  grow_.assign(n, 0.0);
  auto slotOf = [&](std::size_t k) {
    return static_cast<std::uint32_t>(std::lower_bound(exporters_.begin(), exporters_.end(), k) - exporters_.begin());
  };
  for (const HookedPair& h : hooks) {
    skip_.push_back({std::min(h.points, h.surface), std::max(h.points, h.surface)});
    const std::uint32_t a = slotOf(h.points), b = slotOf(h.surface);
    if (a >= n || exporters_[a] != h.points || b >= n || exporters_[b] != h.surface) continue;
    REEL_CHECK(hooks_.size() < 32767 && a != b, "contact hooks: too many, or a body hooked to itself");
    if (hook_of_.empty()) hook_of_.assign(n * n, -1);
    if (hook_of_[a * n + b] >= 0) continue;  // (one law a pair)
    hook_of_[a * n + b] = static_cast<std::int16_t>(hooks_.size());
    hooks_.push_back({a, b, h.hook});
    grow_[b] = std::max(grow_[b], h.hook->margin());
  }
  std::sort(skip_.begin(), skip_.end());
  // A body is worth a search when another exporter (or its own other pieces) may meet it.
  touches_points_.assign(n, 0);
  self_meet_.assign(n, 0);
  active_ = false;
  for (std::size_t a = 0; a < n; ++a) {
    self_meet_[a] = bodies[exporters_[a]]->meetsItself();
    if (self_meet_[a]) touches_points_[a] = 1;
    for (std::size_t b = 0; b < n; ++b)
      if (a != b && !skipped(exporters_[a], exporters_[b])) touches_points_[a] = 1;
    active_ = active_ || touches_points_[a];
  }
  for (const Hook& h : hooks_) touches_points_[h.points] = touches_points_[h.surface] = 1, active_ = true;
  // Convex parts meet the surfaces of every exporter (their own contacts among themselves are
  // their system's).
  for (std::size_t c : convex_exporters_)
    for (std::size_t k : exporters_)
      if (k != c && !skipped(k, c)) active_ = true;
  // The scene objects meet the triangles of every exporter that has some (a trial export), when
  // one of them is more than a plane and does not hold it (a flag pinned to its pole).
  objects_active_ = false;
  objects_ = nullptr;
  held_at_start_.clear();
  ContactProxies trial;
  trial.clear();
  for (std::size_t k : exporters_) trial.add(*bodies[k], k);
  std::vector<std::size_t> solid;
  for (std::size_t k = 0; k < colliders.size(); ++k)
    if (!colliders[k].shape->free_body && colliders[k].shape->kind != ObjectKind::Plane) solid.push_back(k);
  if (trial.tri.empty() || solid.empty()) return;
  objectHolds(trial, colliders, solid, held_at_start_);
  // An object no thinner than a surface's longest edge (at the start) is left to that surface's
  // nodes: their contacts already hold the surface off it, and a triangle's interior dips into it
  // by no more than the sag of one edge over its curve or edge. What the layer adds is what fits
  // between the nodes: a post, a rail, a paddle, a pole. (A fold jammed between two large objects
  // would otherwise be pushed back and forth by them and by the sheet's own self-collision.)
  auto parts = std::make_shared<ObjectParts>();
  buildParts(colliders, *parts);
  std::vector<double> thinnest(colliders.size(), 0.0);
  {
    std::vector<Vec3> lo(colliders.size(), Vec3::Constant(1e300)), hi(colliders.size(), Vec3::Constant(-1e300));
    for (const ObjectPart& part : parts->parts)
      if (!part.half_space) {
        lo[part.collider] = lo[part.collider].cwiseMin(part.lo);
        hi[part.collider] = hi[part.collider].cwiseMax(part.hi);
      }
    for (std::size_t k : solid)
      if (lo[k].x() <= hi[k].x()) thinnest[k] = (hi[k] - lo[k]).minCoeff() + 2.0 * colliders[k].shape->thickness;
  }
  std::vector<double> longest(exporters_.size(), 0.0);
  std::vector<std::uint8_t> surface(exporters_.size(), 0);
  for (const auto& T : trial.tri) {
    const std::uint32_t e = trial.slot[T[0]];
    surface[e] = 1;
    for (int q = 0; q < 3; ++q) longest[e] = std::max(longest[e], (trial.x[T[q]] - trial.x[T[(q + 1) % 3]]).norm());
  }
  for (std::size_t e = 0; e < exporters_.size(); ++e)
    for (std::size_t k : solid)
      if (surface[e] && !(thinnest[k] < longest[e])) held_at_start_.push_back({e, k});
  std::sort(held_at_start_.begin(), held_at_start_.end());
  held_at_start_.erase(std::unique(held_at_start_.begin(), held_at_start_.end()), held_at_start_.end());
  for (std::size_t e = 0; e < exporters_.size(); ++e)
    for (std::size_t k : solid)
      if (surface[e] && !std::binary_search(held_at_start_.begin(), held_at_start_.end(), std::array<std::size_t, 2>{e, k}))
        objects_active_ = true;
  if (objects_active_) objects_ = std::move(parts);
}

// Whether points i and j (or a point and a triangle's piece) may touch: other pieces, and bodies
// whose contacts are the layer's.
bool ContactLayer::meet(std::uint32_t i, std::uint32_t j) const {
  if (p_.piece[i] == p_.piece[j]) return false;
  const std::uint32_t a = p_.slot[i], b = p_.slot[j];
  return a == b ? self_meet_[a] != 0 : !skipped(p_.body[a], p_.body[b]);
}

// --- narrow phase ----------------------------------------------------------------------------
// One contact: point i against points k (the corners of a triangle, or one other point) at the
// contact's barycentric weights beta, along the unit normal n (from the others towards i), with
// `depth` of overlap. Positions first: the overlap closed with each side moved by its inverse
// mass (no velocity changes, so momentum stays); then velocities: the approach along n taken out
// (a plastic contact) and Coulomb friction on the sliding part, bounded by μ times the normal
// impulse (the positional one counted as λ/h). Each impulse acts on i and, opposite, on the k by
// their weights: Σ beta = 1, so momentum is kept.
void ContactLayer::apply(const std::uint32_t* ka, const double* ba, int na, const std::uint32_t* kb, const double* bb,
                         int nb, const Vec3& n, double depth, double h) {
  double W = 0.0;
  for (int q = 0; q < na; ++q) W += ba[q] * ba[q] * p_.w[ka[q]];
  for (int q = 0; q < nb; ++q) W += bb[q] * bb[q] * p_.w[kb[q]];
  if (!(W > 0.0)) return;
  const double lambda = depth / W;  // kg·m
  for (int q = 0; q < na; ++q) p_.x[ka[q]] += (ba[q] * p_.w[ka[q]] * lambda) * n;
  for (int q = 0; q < nb; ++q) p_.x[kb[q]] -= (bb[q] * p_.w[kb[q]] * lambda) * n;
  Vec3 va = Vec3::Zero(), vb = Vec3::Zero();
  for (int q = 0; q < na; ++q) va += ba[q] * p_.v[ka[q]];
  for (int q = 0; q < nb; ++q) vb += bb[q] * p_.v[kb[q]];
  const Vec3 rel = va - vb;
  const double vn = rel.dot(n);
  const double jn = vn < 0.0 ? -vn / W : 0.0;  // N·s
  Vec3 J = jn * n;
  const Vec3 vt = rel - vn * n;
  const double vt_len = vt.norm();
  if (vt_len > 1e-12) {
    const double jt = std::min(vt_len / W, kContactFriction * (jn + lambda / h));
    J -= (jt / vt_len) * vt;
  }
  for (int q = 0; q < na; ++q) p_.v[ka[q]] += (ba[q] * p_.w[ka[q]]) * J;
  for (int q = 0; q < nb; ++q) p_.v[kb[q]] -= (bb[q] * p_.w[kb[q]]) * J;
  touched_[p_.slot[ka[0]]] = 1;
  touched_[p_.slot[kb[0]]] = 1;
}

// A point against a triangle, both moving over the step (start x0, end x). The point keeps the
// side of the triangle it was on at the start: within the sum of the radii of the triangle's
// face it is pushed out to that distance on that side; one that crossed the plane through the
// triangle this step (the crossing found on the straight paths of point and corners) is brought
// back to its side; near an edge or corner it is pushed off the closest point.
bool ContactLayer::solvePointTriangle(std::uint32_t i, std::uint32_t t, double h) {
  const auto& T = p_.tri[t];
  const Vec3 &p = p_.x[i], &p0 = p_.x0[i];
  const Vec3 &a = p_.x[T[0]], &b = p_.x[T[1]], &c = p_.x[T[2]];
  const Vec3 &a0 = p_.x0[T[0]], &b0 = p_.x0[T[1]], &c0 = p_.x0[T[2]];
  Vec3 n1 = (b - a).cross(c - a);
  const double len1 = n1.norm();
  if (!(len1 > 1e-300)) return false;
  n1 /= len1;
  Vec3 n0 = (b0 - a0).cross(c0 - a0);
  const double len0 = n0.norm();
  const double d0 = len0 > 1e-300 ? (p0 - a0).dot(n0) / len0 : 0.0;
  const double d1 = (p - a).dot(n1);
  const double s = d0 > 0 ? 1.0 : d0 < 0 ? -1.0 : (d1 >= 0 ? 1.0 : -1.0);
  const double r = p_.r[i] + (p_.r[T[0]] + p_.r[T[1]] + p_.r[T[2]]) / 3.0;
  const double sd = s * d1;
  if (sd >= r) return false;
  double beta[3];
  Vec3 n;
  double depth;
  if (sd >= 0.0) {
    // On its side, closer than r to the plane: the closest point of the triangle.
    const Vec3 wts = closestOnTriangle(p, a, b, c);
    const Vec3 q = wts[0] * a + wts[1] * b + wts[2] * c;
    const Vec3 diff = p - q;
    const double dist = diff.norm();
    if (dist >= r) return false;
    beta[0] = wts[0], beta[1] = wts[1], beta[2] = wts[2];
    const bool face = wts.minCoeff() > 1e-9;
    n = face || !(dist > 1e-12) ? Vec3(s * n1) : Vec3(diff / dist);
    depth = r - (face ? sd : dist);
  } else {
    // Crossed the plane this step: where the straight paths meet, is the point inside the triangle?
    const double s0 = s * d0;
    if (!(s0 - sd > 1e-300)) return false;
    const double tau = std::clamp(s0 / (s0 - sd), 0.0, 1.0);
    const Vec3 pc = p0 + tau * (p - p0), ac = a0 + tau * (a - a0), bc = b0 + tau * (b - b0), cc = c0 + tau * (c - c0);
    const Vec3 nc = (bc - ac).cross(cc - ac);
    const double area = nc.squaredNorm();
    if (!(area > 1e-300)) return false;
    const double wb = (pc - ac).cross(cc - ac).dot(nc) / area, wc = (bc - ac).cross(pc - ac).dot(nc) / area;
    const double wa = 1.0 - wb - wc;
    constexpr double kEdge = -1e-3;  // a crossing just beside an edge still counts
    if (wa < kEdge || wb < kEdge || wc < kEdge) return false;
    const double ca = std::max(wa, 0.0), cb = std::max(wb, 0.0), cs = std::max(wc, 0.0), sum = ca + cb + cs;
    beta[0] = ca / sum, beta[1] = cb / sum, beta[2] = cs / sum;
    n = s * n1;
    depth = r - sd;
  }
  const double one = 1.0;
  apply(&i, &one, 1, T.data(), beta, 3, n, depth, h);
  return true;
}

// Two points as spheres: pushed apart to the sum of their radii along the line between them.
bool ContactLayer::solvePointPoint(std::uint32_t i, std::uint32_t j, double h) {
  const Vec3 d = p_.x[i] - p_.x[j];
  const double dist = d.norm(), r = p_.r[i] + p_.r[j];
  if (dist >= r || !(dist > 1e-12)) return false;
  const double one = 1.0;
  apply(&i, &one, 1, &j, &one, 1, d / dist, r - dist, h);
  return true;
}

// Two threads as capsules: apart by the sum of their radii at their closest points. Threads that
// crossed this step (their closest points inside both, on the other side of each other along
// the common normal than at the start) are brought back to the side they came from.
bool ContactLayer::solveEdgeEdge(std::uint32_t e, std::uint32_t f, double h) {
  const auto &E = p_.edge[e], &F = p_.edge[f];
  const Vec3 &a = p_.x[E[0]], &b = p_.x[E[1]], &c = p_.x[F[0]], &d = p_.x[F[1]];
  double s = 0.0, t = 0.0;
  closestSegmentSegment(a, b, c, d, s, t);
  const Vec3 diff = (a + s * (b - a)) - (c + t * (d - c));
  const double dist = diff.norm();
  const double r = 0.5 * (p_.r[E[0]] + p_.r[E[1]] + p_.r[F[0]] + p_.r[F[1]]);
  const Vec3 &a0 = p_.x0[E[0]], &b0 = p_.x0[E[1]], &c0 = p_.x0[F[0]], &d0 = p_.x0[F[1]];
  Vec3 n1 = (b - a).cross(d - c);
  const double len1 = n1.norm();
  Vec3 n;
  double depth;
  bool crossed = false;
  if (len1 > 1e-300 && s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) {
    n1 /= len1;
    const Vec3 n0 = (b0 - a0).cross(d0 - c0);
    const double side0 = ((a0 + s * (b0 - a0)) - (c0 + t * (d0 - c0))).dot(n0);
    const double side1 = diff.dot(n1);
    const double cosine = n0.dot(n1), n0_len = n0.norm();
    // (threads turned across each other, or farther apart than this step's motion, did not cross)
    double moved = 0.0;
    for (std::uint32_t k : {E[0], E[1], F[0], F[1]}) moved = std::max(moved, (p_.x[k] - p_.x0[k]).norm());
    if (std::abs(cosine) > 0.3 * n0_len && std::abs(side1) < 2.0 * moved + r) {
      const double from = cosine > 0.0 ? side0 : -side0;  // the start side, along n1
      if ((from > 0.0 && side1 < 0.0) || (from < 0.0 && side1 > 0.0)) {
        const double sg = from > 0.0 ? 1.0 : -1.0;
        n = sg * n1;
        depth = r - sg * side1;
        crossed = true;
      }
    }
  }
  if (!crossed) {
    if (dist >= r || !(dist > 1e-12)) return false;
    n = diff / dist;
    depth = r - dist;
  }
  const double wa[2] = {1.0 - s, s}, wb[2] = {1.0 - t, t};
  apply(E.data(), wa, 2, F.data(), wb, 2, n, depth, h);
  return true;
}

void ContactLayer::step(const std::vector<std::unique_ptr<Body>>& bodies, double h,
                        const std::vector<Collider>& colliders, Coupling& coupling) {
  counts_ = {};
  touched_bodies_.clear();
  if (!active_ && !objects_active_) return;  // (its time is the World's coupling stage's)
  // Gather: each exporting body's points and triangles, in scene order.
  p_.clear();
  std::uint32_t next_piece = 0;
  for (std::size_t k : exporters_) next_piece += p_.add(*bodies[k], k, next_piece);
  const std::size_t np = p_.x.size();
  const ParallelScope threads(static_cast<std::ptrdiff_t>(np));  // (one decision for the layer's loops)
  p_.gone.assign(np, 0);
  for (std::size_t i = 0; i < np; ++i)
    if (!p_.x0_given[p_.slot[i]]) p_.x0[i] = p_.x[i] - h * p_.v[i];
  touched_.assign(exporters_.size(), 0);
  // Pieces far from every piece they may touch sit out this step.
  const std::uint32_t pieces = next_piece;
  piece_lo_.assign(pieces, Vec3::Constant(1e300));
  piece_hi_.assign(pieces, Vec3::Constant(-1e300));
  piece_slot_.assign(pieces, 0);
  for (std::size_t i = 0; i < np; ++i) {
    const std::uint32_t q = p_.piece[i];
    const Vec3 g = Vec3::Constant(p_.r[i] + grow_[p_.slot[i]]);
    piece_lo_[q] = piece_lo_[q].cwiseMin(p_.x[i] - g).cwiseMin(p_.x0[i] - g);
    piece_hi_[q] = piece_hi_[q].cwiseMax(p_.x[i] + g).cwiseMax(p_.x0[i] + g);
    piece_slot_[q] = p_.slot[i];
  }
  // The convex parts of the bodies moved by systems.
  for (std::size_t k : convex_exporters_) {
    ContactExport out(p_);
    out.body_ = k;
    bodies[k]->exportConvex(out);
  }
  // The scene objects near the bodies' surfaces.
  colliders_ = &colliders;
  if (objects_active_) gatherObjectParts(colliders);
  // Which bodies hold which (a cloth gripped by a figure's link is left apart from the figure).
  held_bodies_.clear();
  for (const auto& [held, collider] : held_)
    for (const ContactProxies::Convex& C : p_.convex)
      if (C.collider == collider) held_bodies_.push_back({held, C.body});
  std::sort(held_bodies_.begin(), held_bodies_.end());
  const bool points_near = active_ && nearPieces(pieces);
  pt_pairs_.clear();
  hk_pairs_.clear();
  pp_pairs_.clear();
  ee_pairs_.clear();
  // Broad phase, then the pairs in id order, twice (Gauss–Seidel: a point pressed between two
  // surfaces settles between them).
  if (points_near) {
    findPointTriangle();
    findPointPoint();
    findEdgeEdge();
  }
  findTriangleConvex(h);
  findPointConvex(h);
  if (!points_near && tc_pairs_.empty() && pc_pairs_.empty()) return;
  convex_J_.assign(p_.convex.size(), Vec3::Zero());
  convex_L_.assign(p_.convex.size(), Vec3::Zero());
  for (int pass = 0; pass < 2; ++pass) {
    std::size_t pt = 0, pp = 0, ee = 0, tc = 0, pc = 0;
    for (const auto& q : pc_pairs_) pc += solvePointConvex(q[0], q[1], h, pass == 0);
    for (const auto& q : pt_pairs_) pt += solvePointTriangle(q[0], q[1], h);
    for (const auto& q : pp_pairs_) pp += solvePointPoint(q[0], q[1], h);
    for (const auto& q : ee_pairs_) ee += solveEdgeEdge(q[0], q[1], h);
    for (const auto& q : tc_pairs_) tc += solveTriangleConvex(q[0], q[1], h);
    if (pass == 0) counts_ = {pt, pp, ee, tc, pc, 0};
  }
  // The hooks' laws, after the layer's own, a point's candidate triangles at a time, in id order.
  std::vector<std::uint8_t> started(hooks_.size(), 0);  // begun this step
  for (std::size_t a = 0; a < hk_pairs_.size();) {
    const std::uint32_t i = hk_pairs_[a][0], k = hk_pairs_[a][2];
    std::size_t b = a;
    hk_tris_.clear();
    for (; b < hk_pairs_.size() && hk_pairs_[b][0] == i && hk_pairs_[b][2] == k; ++b) hk_tris_.push_back(hk_pairs_[b][1]);
    const Hook& hk = hooks_[k];
    if (!started[k]) hk.hook->begin(p_, hk.points, hk.surface, h), started[k] = 1;
    if (!p_.gone[i] && hk.hook->point(p_, i, hk_tris_, h)) {
      touched_[hk.points] = touched_[hk.surface] = 1;
      ++counts_.hooked;
    }
    a = b;
  }
  total_.point_triangle += counts_.point_triangle;
  total_.point_point += counts_.point_point;
  total_.edge_edge += counts_.edge_edge;
  total_.triangle_convex += counts_.triangle_convex;
  total_.point_convex += counts_.point_convex;
  total_.hooked += counts_.hooked;
  // What the bodies' convex parts took, to their colliders' Coupling entries (angular about the
  // collider's pose.pos). The objects' is taken by what holds them.
  for (std::size_t c = 0; c < p_.convex.size(); ++c) {
    const std::size_t k = p_.convex[c].collider;
    if (p_.convex[c].body == ContactProxies::kObject) continue;
    if (convex_J_[c].isZero(0.0) && convex_L_[c].isZero(0.0)) continue;
    coupling.impulse[k] += convex_J_[c];
    coupling.angular[k] += convex_L_[c] + (p_.convex[c].centre - colliders[k].pose.pos).cross(convex_J_[c]);
  }
  // Hand back each touched body its points.
  for (std::size_t e = 0; e < exporters_.size(); ++e) {
    if (!touched_[e]) continue;
    touched_bodies_.push_back(exporters_[e]);
    const std::size_t f = p_.first[e], n = p_.first[e + 1] - f;
    bodies[exporters_[e]]->importContacts(std::span<const Vec3>(p_.x).subspan(f, n),
                                          std::span<const Vec3>(p_.v).subspan(f, n));
    const std::span<const std::uint8_t> gone = std::span<const std::uint8_t>(p_.gone).subspan(f, n);
    if (std::find(gone.begin(), gone.end(), std::uint8_t{1}) != gone.end()) bodies[exporters_[e]]->dropPoints(gone);
  }
}

}  // namespace reel
