// The contact layer's convex parts (sim/contact_layer.h): the triangle–convex search and handler.
// Rigid bodies and figures' links meet the triangles of every body's surface here.
#include <algorithm>
#include <cmath>
#include <memory>

#include <Eigen/Geometry>

#include "sim/collide.h"
#include "sim/contact_layer.h"
#include "sim/geometry.h"
#include "sim/rigid/hull.h"
#include "sim/rigid/parts.h"

namespace reel {

// The scene objects as convex parts: the parts (sim/rigid/parts.h; not the planes, whose
// half-spaces every node already meets) whose box meets the box of the points of the bodies
// with triangles over the step, each with inverse mass 0 and its surface's motion. A body with a
// held point (inverse mass 0) on an object or within 1 cm of it, when the World was made or now,
// is held there by it (a flag pinned to its pole): the layer leaves the two apart, as the pin
// says where the body is.
void ContactLayer::gatherObjectParts(const std::vector<Collider>& colliders) {
  auto surface = [&](std::uint32_t slot) { return p_.tri_first[slot + 1] > p_.tri_first[slot]; };
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t i = 0; i < p_.x.size(); ++i)
    if (surface(p_.slot[i])) {
      const Vec3 g = Vec3::Constant(p_.r[i]);
      lo = lo.cwiseMin(p_.x[i] - g).cwiseMin(p_.x0[i] - g);
      hi = hi.cwiseMax(p_.x[i] + g).cwiseMax(p_.x0[i] + g);
    }
  if (!(lo.array() <= hi.array()).all() || !lo.allFinite() || !hi.allFinite()) return;
  partsNear(*objects_, colliders, lo, hi, object_near_);
  std::vector<std::size_t> near_colliders;
  for (std::uint32_t id : object_near_) {
    const ObjectPart& part = objects_->parts[id];
    if (part.half_space) continue;
    const Collider& c = colliders[part.collider];
    ContactProxies::Convex C;
    C.shape = &part.shape;
    C.pose = colliderPose(c);
    C.centre = C.pose.R * (0.5 * (part.lo + part.hi)) + C.pose.p;
    C.v = c.velocityAt(C.centre);
    C.w = c.angularVelocity();
    C.collider = part.collider;
    C.body = ContactProxies::kObject;
    p_.convex.push_back(C);
    if (near_colliders.empty() || near_colliders.back() != part.collider) near_colliders.push_back(part.collider);
  }
  object_held_ = held_at_start_;
  objectHolds(p_, colliders, near_colliders, object_held_);
}

void ContactLayer::objectHolds(const ContactProxies& p, const std::vector<Collider>& colliders,
                               const std::vector<std::size_t>& which, std::vector<std::array<std::size_t, 2>>& out) {
  for (std::size_t i = 0; i < p.x.size() && !which.empty(); ++i) {
    const std::uint32_t s = p.slot[i];
    if (p.w[i] != 0.0 || !(p.tri_first[s + 1] > p.tri_first[s])) continue;  // held points of bodies with a surface
    for (std::size_t k : which) {
      const Collider& c = colliders[k];
      const double reach = c.shape->thickness + p.r[i] + 0.01;
      double d = 0.0;
      Vec3 n;
      if (c.near(p.x[i], reach) && c.distance(p.x[i], d, n) && d < reach) out.push_back({p.slot[i], k});
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// Triangle–convex: each convex part's box (its shape at its pose, grown by the largest radius and
// its motion over the step) against the boxes of the triangles over the step. Triangles are taken
// in blocks of 32 in id order (a body's surface is handed over row by row, so a block is a patch
// of it): a part tries the triangles of the blocks whose box meets its own. Only bodies whose
// points' box meets some part's box are looked at. Pairs in order of part, then triangle.
// (Runs after the other searches: it reuses their scratch.)
void ContactLayer::findTriangleConvex(double h) {
  tc_pairs_.clear();
  const std::size_t nc = p_.convex.size(), nt = p_.tri.size(), slots = p_.body.size();
  if (nc == 0 || nt == 0) return;
  double rmax = 0.0;
  for (double r : p_.r) rmax = std::max(rmax, r);
  // The parts' boxes.
  std::vector<Vec3>& clo = tc_.clo;
  std::vector<Vec3>& chi = tc_.chi;
  clo.resize(nc);
  chi.resize(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    const ContactProxies::Convex& C = p_.convex[c];
    shapeBounds(*C.shape, C.pose, clo[c], chi[c]);
    const double extent = 0.5 * (chi[c] - clo[c]).norm();
    const Vec3 g = Vec3::Constant(rmax + h * (C.v.norm() + C.w.norm() * extent));
    clo[c] -= g;
    chi[c] += g;
    if (!clo[c].allFinite() || !chi[c].allFinite()) clo[c] = Vec3::Constant(1e300), chi[c] = Vec3::Constant(-1e300);
  }
  // Per exporting body: its points' box over the step; whether a part it may meet is near it.
  std::vector<Vec3>& slot_lo = tc_.slot_lo;
  std::vector<Vec3>& slot_hi = tc_.slot_hi;
  slot_lo.assign(slots, Vec3::Constant(1e300));
  slot_hi.assign(slots, Vec3::Constant(-1e300));
  for (std::size_t i = 0; i < p_.x.size(); ++i) {
    const std::uint32_t e = p_.slot[i];
    slot_lo[e] = slot_lo[e].cwiseMin(p_.x[i]).cwiseMin(p_.x0[i]);
    slot_hi[e] = slot_hi[e].cwiseMax(p_.x[i]).cwiseMax(p_.x0[i]);
  }
  auto may = [&](std::size_t e, std::size_t c) {
    const ContactProxies::Convex& C = p_.convex[c];
    if (C.body == ContactProxies::kObject)
      return !std::binary_search(object_held_.begin(), object_held_.end(), std::array<std::size_t, 2>{e, C.collider});
    if (p_.body[e] == C.body || skipped(p_.body[e], C.body)) return false;
    return !std::binary_search(held_bodies_.begin(), held_bodies_.end(), std::array<std::size_t, 2>{p_.body[e], C.body});
  };
  auto overlap = [](const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
    return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
  };
  std::vector<std::uint8_t>& slot_near = tc_.slot_near;
  slot_near.assign(slots, 0);
  bool any = false;
  for (std::size_t e = 0; e < slots; ++e)
    for (std::size_t c = 0; c < nc && !slot_near[e]; ++c)
      if (may(e, c) && overlap(clo[c], chi[c], slot_lo[e] - Vec3::Constant(rmax), slot_hi[e] + Vec3::Constant(rmax)))
        slot_near[e] = 1, any = true;
  if (!any) return;
  // The triangles of those bodies by their boxes over the step, and the blocks' boxes.
  constexpr std::size_t kBlock = 32;
  const std::size_t nb = (nt + kBlock - 1) / kBlock;
  lo_.assign(nt, Vec3::Constant(1e300));
  hi_.assign(nt, Vec3::Constant(-1e300));
  std::vector<Vec3>& blo = tc_.blo;
  std::vector<Vec3>& bhi = tc_.bhi;
  blo.assign(nb, Vec3::Constant(1e300));
  bhi.assign(nb, Vec3::Constant(-1e300));
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& T = p_.tri[t];
    if (!slot_near[p_.slot[T[0]]]) continue;
    Vec3 lo = p_.x[T[0]].cwiseMin(p_.x0[T[0]]), hi = p_.x[T[0]].cwiseMax(p_.x0[T[0]]);
    for (int q = 1; q < 3; ++q) {
      lo = lo.cwiseMin(p_.x[T[q]]).cwiseMin(p_.x0[T[q]]);
      hi = hi.cwiseMax(p_.x[T[q]]).cwiseMax(p_.x0[T[q]]);
    }
    lo_[t] = lo;
    hi_[t] = hi;
    blo[t / kBlock] = blo[t / kBlock].cwiseMin(lo);
    bhi[t / kBlock] = bhi[t / kBlock].cwiseMax(hi);
  }
  // The blocks in a grid of cells about as large as the typical block (at most 16 cells a side
  // for the largest), so that a part (a mesh's triangle among hundreds) looks only at the blocks
  // in the cells its box covers; a part over more than 512 cells tries every block.
  std::vector<std::uint32_t>& live = tc_.live;
  std::vector<double>& extent = tc_.extent;
  live.clear();
  extent.clear();
  for (std::size_t b = 0; b < nb; ++b)
    if (blo[b].x() <= bhi[b].x()) {
      live.push_back(static_cast<std::uint32_t>(b));
      extent.push_back((bhi[b] - blo[b]).maxCoeff());
    }
  if (live.empty()) return;
  std::vector<Vec3>& llo = tc_.llo;
  std::vector<Vec3>& lhi = tc_.lhi;
  llo.resize(live.size());
  lhi.resize(live.size());
  for (std::size_t k = 0; k < live.size(); ++k) llo[k] = blo[live[k]], lhi[k] = bhi[live[k]];
  const double largest = *std::max_element(extent.begin(), extent.end());
  std::nth_element(extent.begin(), extent.begin() + static_cast<std::ptrdiff_t>(extent.size() / 2), extent.end());
  const double cell = std::max({extent[extent.size() / 2], largest / 15.0, 1e-6});
  const bool gridded = std::isfinite(cell) && cell < 1e200;
  if (gridded) tri_grid_.build(llo, lhi, cell);
  std::vector<std::uint32_t>& blocks = tc_.blocks;
  for (std::size_t c = 0; c < nc; ++c) {
    blocks.clear();
    double cells = 0.0;
    std::array<std::int64_t, 3> c0{}, c1{};
    if (gridded && clo[c].x() <= chi[c].x()) {
      c0 = tri_grid_.cellOf(clo[c]);
      c1 = tri_grid_.cellOf(chi[c]);
      cells = 1.0;
      for (std::size_t k = 0; k < 3; ++k) cells *= static_cast<double>(c1[k] - c0[k] + 1);
    }
    if (gridded && cells > 0.0 && cells <= 512.0) {
      for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
        for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
          for (std::int64_t i = c0[0]; i <= c1[0]; ++i)
            tri_grid_.forEachAt(Vec3((static_cast<double>(i) + 0.5) * cell, (static_cast<double>(j) + 0.5) * cell,
                                       (static_cast<double>(k) + 0.5) * cell),
                                  [&](std::int32_t q) { blocks.push_back(live[static_cast<std::size_t>(q)]); });
      std::sort(blocks.begin(), blocks.end());
      blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    } else if (clo[c].x() <= chi[c].x()) {
      blocks = live;
    }
    for (std::uint32_t b : blocks) {
      if (!overlap(clo[c], chi[c], blo[b], bhi[b])) continue;
      for (std::size_t t = b * kBlock; t < std::min(nt, (b + 1) * kBlock); ++t)
        if (overlap(clo[c], chi[c], lo_[t], hi_[t]) && may(p_.slot[p_.tri[t][0]], c))
          tc_pairs_.push_back({static_cast<std::uint32_t>(t), static_cast<std::uint32_t>(c)});
    }
  }
}

// A triangle (a plate of its corners' mean radius) against a convex part: the rigid bodies'
// narrow phase (sim/rigid/contact.h) gives up to four points along one normal. The part keeps the
// side of the triangle its centre of mass was on at the start of the step (a normal that would
// push it through is left alone). At each point, sequential impulses: the approach along the
// normal taken out, with the part's overlap share as a separating speed (20% of it a step, at
// most 0.5 m/s), and Coulomb friction bounded by μ times the normal impulse; the effective mass
// counts the part's rotation (1/m + (r×n)·I⁻¹(r×n)) and the triangle's corners by their weights
// (against an object, which nothing moves, its largest corner's share).
// The triangle's share of the deepest point's overlap is closed at once, by moving its corners
// (positions only). The triangle's corners take the opposite of the part's impulse: momentum and
// angular momentum are kept.
bool ContactLayer::solveTriangleConvex(std::uint32_t t, std::uint32_t ci, double h) {
  const auto& T = p_.tri[t];
  ContactProxies::Convex& C = p_.convex[ci];
  const Vec3 a = p_.x[T[0]], b = p_.x[T[1]], c = p_.x[T[2]];
  Vec3 nt = (b - a).cross(c - a);
  const double len = nt.norm();
  if (!(len > 1e-300)) return false;
  nt /= len;
  const Vec3 &a0 = p_.x0[T[0]], &b0 = p_.x0[T[1]], &c0 = p_.x0[T[2]];
  double side = ((C.centre - h * C.v) - a0).dot((b0 - a0).cross(c0 - a0));
  if (side == 0.0 || !std::isfinite(side)) side = (C.centre - a).dot(nt);
  const Vec3 up = side >= 0.0 ? nt : Vec3(-nt);  // from the triangle toward the part
  const double radius = (p_.r[T[0]] + p_.r[T[1]] + p_.r[T[2]]) / 3.0;
  // An object's part meets the triangles none of whose corners touches the object: a corner that
  // does is held off it by its own contact (sim/collide.h, with the object's surface), and the
  // triangle's plate would answer the same contact a second time. What the layer adds is what
  // pokes between the corners (a post, a rail, a box's edge under a coarse mesh).
  const bool object = C.body == ContactProxies::kObject;
  if (object) {
    const Collider& obj = (*colliders_)[C.collider];
    for (int k = 0; k < 3; ++k) {
      const Vec3& x = p_.x[T[k]];
      const double reach = obj.shape->thickness + 1.5 * p_.r[T[k]];
      double d = 0.0;
      Vec3 dn;
      if (obj.near(x, reach) && obj.distance(x, d, dn) && d < reach) return false;
    }
  }
  // An object's polytope part with the whole plate outside one of its faces (a sheet lying on a
  // thin box, its nodes held off it by their own contacts) is apart: the narrow phase is not asked.
  if (object && C.shape->kind == CoreKind::Polytope && C.shape->poly) {
    const double reach = radius + C.shape->radius - 1e-9;
    for (const ConvexPolytope::Face& f : C.shape->poly->faces) {
      const Vec3 nw = C.pose.R * f.normal;
      const double off = f.offset + nw.dot(C.pose.p);
      if (std::min({nw.dot(a), nw.dot(b), nw.dot(c)}) - off >= reach) return false;
    }
  }
  // The plate: a flat triangle's polytope (sim/rigid/hull.h), made once and moved to this
  // triangle (its faces' planes; the loops and edges stay).
  static thread_local const std::shared_ptr<ConvexPolytope> poly =
      std::make_shared<ConvexPolytope>(trianglePolytope(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)));
  poly->vertices = {a, b, c};
  const double off = nt.dot(a + b + c) / 3.0;
  poly->faces[0].normal = nt;
  poly->faces[0].offset = off;
  poly->faces[1].normal = -nt;
  poly->faces[1].offset = -off;
  ConvexShape plate;
  plate.kind = CoreKind::Polytope;
  plate.radius = radius;
  plate.poly = poly;
  Manifold m;
  if (!collide(plate, Pose{}, *C.shape, C.pose, 0.0, m) || m.count == 0) return false;
  const Vec3 n = m.normal;  // from the triangle toward the part
  if (!(n.dot(up) >= 0.0)) return false;
  int deepest = -1;
  for (int k = 0; k < m.count; ++k)
    if (m.points[k].depth > 0.0 && (deepest < 0 || m.points[k].depth > m.points[deepest].depth)) deepest = k;
  if (deepest < 0) return false;
  // The triangle's inverse mass at a point of weights β: Σβ²w (the point's velocity change per
  // unit impulse shared by the weights). Against an object (nothing moves it, so the triangle
  // takes the whole overlap) its largest corner's share max βw instead (never less, as Σβ = 1): no
  // corner moves more than the point must, where Σβ²w would throw a free corner by 1/β of the
  // overlap when the point lies by a held one (a flag's cloth beside its pins). Against a body's
  // part the part's own inverse mass bounds the throw.
  auto triangleMass = [&](const Vec3& beta) {
    double W = 0.0;
    for (int q = 0; q < 3; ++q) W = object ? std::max(W, beta[q] * p_.w[T[q]]) : W + beta[q] * beta[q] * p_.w[T[q]];
    return W;
  };
  auto partMass = [&](const Vec3& r, const Vec3& dir) {
    const Vec3 rd = r.cross(dir);
    return C.inv_mass + rd.dot(C.inv_inertia * rd);
  };
  // Positions: the triangle's share of the deepest overlap.
  double lambda_pos = 0.0;  // kg·m
  {
    const ContactPoint& q = m.points[deepest];
    const Vec3 beta = closestOnTriangle(q.position, a, b, c);
    const double Wt = triangleMass(beta), Wc = partMass(q.position - C.centre, n);
    if (Wt > 0.0 && Wt + Wc > 0.0) {
      lambda_pos = q.depth / (Wt + Wc);
      for (int k = 0; k < 3; ++k) p_.x[T[k]] -= (beta[k] * p_.w[T[k]] * lambda_pos) * n;
    }
  }
  // Velocities, point by point.
  bool any = false;
  for (int k = 0; k < m.count; ++k) {
    const ContactPoint& q = m.points[k];
    if (!(q.depth > 0.0)) continue;
    const Vec3 beta = closestOnTriangle(q.position, a, b, c);
    const Vec3 r = q.position - C.centre;
    const double Wt = triangleMass(beta), Wc = partMass(r, n);
    if (!(Wt + Wc > 0.0)) continue;
    const Vec3 vt_tri = beta[0] * p_.v[T[0]] + beta[1] * p_.v[T[1]] + beta[2] * p_.v[T[2]];
    const Vec3 rel = C.v + C.w.cross(r) - vt_tri;
    const double vn = rel.dot(n);
    const double push = std::min(0.2 * q.depth * Wc / (Wt + Wc) / h, 0.5);  // m/s
    const double jn = std::max(0.0, push - vn) / (Wt + Wc);
    Vec3 J = jn * n;
    const Vec3 slide = rel - vn * n;
    const double slide_len = slide.norm();
    if (slide_len > 1e-12) {
      const Vec3 dir = slide / slide_len;
      const double jt = std::min(slide_len / (Wt + partMass(r, dir)), kContactFriction * (jn + lambda_pos / h));
      J -= jt * dir;
    }
    C.v += C.inv_mass * J;
    C.w += C.inv_inertia * r.cross(J);
    convex_J_[ci] += J;
    convex_L_[ci] += r.cross(J);
    for (int c3 = 0; c3 < 3; ++c3) p_.v[T[c3]] -= (beta[c3] * p_.w[T[c3]]) * J;
    any = true;
  }
  if (any || lambda_pos > 0.0) touched_[p_.slot[T[0]]] = 1;
  return any || lambda_pos > 0.0;
}

// Point–convex: a point (a sphere of its radius) against a part moved by a system, by the signed
// distance of the part's collider at its pose now (sim/collide.h, the primitive every object
// contact uses). The law is the one points meet the scene's objects by (contactNode): the part's
// surface (or the one the scene gives the point's liquid species) with restitution e, Coulomb
// friction μ bounded by μ times the normal impulse, friction taking back the step's tangential
// drift at the old velocity (so static friction holds), and a liquid's adhesion as a pull towards
// the surface within its range (the first pass only). Here it is solved with both sides' masses:
// the point's inverse mass w and the part's 1/m + (r×n)·I⁻¹(r×n) at the contact. The point's
// share of the overlap is closed at once, the part's becomes a separating speed (20% a step, at
// most 0.5 m/s), as in triangle–convex. A point whose end lies clear of the part, beyond the
// surface its path over the step (sampled at its reach) first came within reach of, crossed it:
// it is caught at that place. The part takes the opposite of every impulse (its collider's Coupling entry).
bool ContactLayer::solvePointConvex(std::uint32_t i, std::uint32_t ci, double h, bool adhere) {
  ContactProxies::Convex& C = p_.convex[ci];
  const Collider& col = (*colliders_)[C.collider];
  double range = 0.0;
  const Surface& sf = p_.surfaceOf(i, C.collider, col.shape->surface, range);
  if (!adhere) range = 0.0;
  const double reach = col.shape->thickness + p_.r[i];
  Vec3& x = p_.x[i];
  Vec3& v = p_.v[i];
  auto within = [&](const Vec3& q, double far, double& d, Vec3& n) {
    return col.near(q, far) && col.distance(q, d, n) && d < far;
  };
  double d = 0.0;
  Vec3 n;
  const bool at_end = within(x, reach + range, d, n);
  // Through the part this step? The first place on its path (at steps no longer than the reach,
  // at most 32 of them)
  // within reach of the part with the end beyond that place's surface: a point that ends clear of
  // the part, or within reach of its far side, crossed it and is caught there; one that slid off an
  // edge or bounced away ends on the near side.
  const Vec3 path = x - p_.x0[i];
  const double len = path.norm();
  bool crossed = false;
  if (len > reach) {
    const int samples = static_cast<int>(std::min(32.0, std::ceil(len / reach)));
    for (int k = 0; k < samples; ++k) {
      const Vec3 q = p_.x0[i] + (static_cast<double>(k) / samples) * path;
      double dq = 0.0;
      Vec3 nq;
      if (!within(q, reach, dq, nq) || !((x - (q - dq * nq)).dot(nq) < 0.0)) continue;
      if (!at_end || !(n.dot(nq) > 0.0)) x = q, d = dq, n = nq, crossed = true;
      break;
    }
  }
  if (!at_end && !crossed) return false;
  const double w = p_.w[i];
  // The impulses act along lines through the point (where it is once its share of the overlap is
  // closed): the part takes them there, so angular momentum is kept too.
  Vec3 r = x - C.centre;
  auto partMass = [&](const Vec3& dir) {
    const Vec3 rd = r.cross(dir);
    return C.inv_mass + rd.dot(C.inv_inertia * rd);
  };
  Vec3 J = Vec3::Zero();  // on the point, N·s
  if (range > 0.0) J -= (h * sf.adhesion * std::clamp(1.0 - (d - reach) / range, 0.0, 1.0) / w) * n;
  if (d < reach) {
    const double depth = reach - d;
    x += (w * depth / (w + partMass(n))) * n;
    r = x - C.centre;
    const double Wn = partMass(n);
    const Vec3 rel = v + w * J - (C.v + C.w.cross(r));
    const double vn = rel.dot(n);
    const double push = std::min(0.2 * depth * Wn / (w + Wn) / h, 0.5);  // m/s
    const double target = std::max(push, vn < 0.0 ? -sf.restitution * vn : 0.0);
    const double jn = vn < target ? (target - vn) / (w + Wn) : 0.0;
    J += jn * n;
    const Vec3 slide = rel - vn * n;
    const double slide_len = slide.norm();
    if (slide_len > 1e-12 && jn > 0.0) {
      const Vec3 dir = slide / slide_len;
      const double jt = std::min(slide_len / (w + partMass(dir)), sf.friction * jn);
      J -= jt * dir;
      x -= (h * w * jt) * dir;  // the step's tangential drift, redone at the new velocity
    }
  }
  if (J.isZero(0.0) && !(d < reach)) return false;
  v += w * J;
  C.v -= C.inv_mass * J;
  C.w -= C.inv_inertia * r.cross(J);
  convex_J_[ci] -= J;
  convex_L_[ci] -= r.cross(J);
  touched_[p_.slot[i]] = 1;
  return true;
}

}  // namespace reel
