#include "sim/rigid/contact.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "core/math.h"
#include "sim/geometry.h"
#include "sim/rigid/contact_detail.h"

namespace reel {

namespace contact_detail {


// The polytope with its edges' faces: itself, or a completed copy in `tmp` (hand-made polytopes).
const ConvexPolytope& withEdgeFaces(const ConvexPolytope& p, ConvexPolytope& tmp) {
  if (p.edge_faces.size() == p.edges.size() && !p.edges.empty()) return p;
  tmp = p;
  finishPolytope(tmp);
  return tmp;
}

// The largest distance of a vertex from the local origin, m: the scale of tolerances.
double polytopeExtent(const ConvexPolytope& p) {
  double r2 = 0;
  for (const Vec3& v : p.vertices) r2 = std::max(r2, v.squaredNorm());
  return std::sqrt(r2);
}

// At most 4 of the candidates (indices, ascending): the deepest; the farthest from it; the one
// spanning the largest triangle with those two; the one adding the most area to that triangle.
// Areas are measured in the plane normal to n.
int reduceToFour(const Candidates& c, const Vec3& n, std::array<int, 4>& pick) {
  const int m = c.size();
  if (m <= 4) {
    for (int i = 0; i < m; ++i) pick[static_cast<Index>(i)] = i;
    return m;
  }
  auto flat = [&](const Vec3& d) -> Vec3 { return d - d.dot(n) * n; };
  // Deepest, then farthest from it
  int i0 = 0;
  for (int i = 1; i < m; ++i)
    if (c[i].depth > c[i0].depth) i0 = i;
  int i1 = -1;
  double best = 0;
  for (int i = 0; i < m; ++i) {
    const double d2 = flat(c[i].x - c[i0].x).squaredNorm();
    if (d2 > best) best = d2, i1 = i;
  }
  int count = 1;
  pick[0] = i0;
  if (i1 >= 0) {
    pick[static_cast<Index>(count++)] = i1;
    // Largest triangle with the first two, on either side
    const Vec3 e = c[i1].x - c[i0].x;
    int i2 = -1;
    double area = 0, sign = 1;
    for (int i = 0; i < m; ++i) {
      const double s = e.cross(c[i].x - c[i0].x).dot(n);
      if (std::abs(s) > area) area = std::abs(s), sign = s > 0 ? 1 : -1, i2 = i;
    }
    if (i2 >= 0) {
      pick[static_cast<Index>(count++)] = i2;
      // The most area added outside the triangle's edges
      const std::array<int, 3> tri{i0, i1, i2};
      int i3 = -1;
      best = 0;
      for (int i = 0; i < m; ++i) {
        double added = 0;
        for (int k = 0; k < 3; ++k) {
          const Vec3& a = c[tri[static_cast<Index>(k)]].x;
          const Vec3& b = c[tri[static_cast<Index>((k + 1) % 3)]].x;
          added = std::max(added, -sign * (b - a).cross(c[i].x - a).dot(n));
        }
        if (added > best) best = added, i3 = i;
      }
      if (i3 >= 0) pick[static_cast<Index>(count++)] = i3;
    }
  }
  std::sort(pick.begin(), pick.begin() + count);
  return count;
}

// The manifold from candidates in a frame (R, p) with normal n in that frame.
bool emit(const Candidates& c, const Mat3& R, const Vec3& p, const Vec3& n, Manifold& out) {
  std::array<int, 4> pick{};
  const int count = reduceToFour(c, n, pick);
  out.normal = R * n;
  out.count = count;
  for (int k = 0; k < count; ++k) {
    const Candidate& q = c[pick[static_cast<Index>(k)]];
    out.points[static_cast<Index>(k)] = {R * q.x + p, q.depth, q.id};
  }
  return count > 0;
}

// ---- Rounded cores: points and segments swept by spheres

// A point or segment core in world space (a == b for a point).
struct Round {
  Vec3 a, b;
  double r;
};

Round roundInWorld(const ConvexShape& s, const Pose& p) {
  const Vec3 a = p.R * s.a + p.p;
  return {a, s.kind == CoreKind::Segment ? Vec3(p.R * s.b + p.p) : a, s.radius};
}

// A direction from A's core toward B's when the cores touch: across both segments, else from
// centre to centre, else across A's segment, else up.
Vec3 touchingNormal(const Round& A, const Round& B) {
  const Vec3 dA = A.b - A.a, dB = B.b - B.a;
  const Vec3 c = 0.5 * (B.a + B.b) - 0.5 * (A.a + A.b);
  const Vec3 x = dA.cross(dB);
  if (x.squaredNorm() > 1e-24 * dA.squaredNorm() * dB.squaredNorm() && x.squaredNorm() > 0)
    return (x.dot(c) < 0 ? -x : x).normalized();
  const double la = dA.squaredNorm();
  const Vec3 across = la > 0 ? Vec3(c - c.dot(dA) / la * dA) : c;
  if (across.squaredNorm() > 1e-24 * (c.squaredNorm() + la)) return across.normalized();
  return la > 0 ? perpendicular(dA.normalized()) : Vec3(0, 1, 0);
}

// Sphere/capsule against sphere/capsule: the closest points of the cores; nearly parallel
// segments rest on the overlap of the two, so they touch at its two ends.
bool roundRound(const Round& A, const Round& B, double margin, Manifold& out) {
  double s, t;
  closestSegmentSegment(A.a, A.b, B.a, B.b, s, t);
  const Vec3 dA = A.b - A.a, dB = B.b - B.a;
  const Vec3 pA = A.a + s * dA, pB = B.a + t * dB;
  const double dist = (pB - pA).norm(), r = A.r + B.r;
  if (dist - r > margin) return false;
  const double tiny = 1e-12 * (r + dA.norm() + dB.norm());
  const Vec3 n = dist > tiny && dist > 0 ? Vec3((pB - pA) / dist) : touchingNormal(A, B);
  out.normal = n;
  out.count = 0;
  auto add = [&](const Vec3& x, const Vec3& y, std::uint32_t id) {
    const double depth = r - (y - x).dot(n);
    if (depth < -margin || out.count == 4) return;
    out.points[static_cast<Index>(out.count++)] = {0.5 * (x + A.r * n + y - B.r * n), depth, id};
  };
  // Nearly parallel segments (within about 1°): the ends of B's shadow on A, and the closest pair
  // between them where it is deeper
  constexpr double kParallel = 0.02;  // sine of the angle
  const double la2 = dA.squaredNorm(), lb2 = dB.squaredNorm();
  if (la2 > 0 && lb2 > 0 && dA.cross(dB).squaredNorm() <= kParallel * kParallel * la2 * lb2) {
    const double u0 = (B.a - A.a).dot(dA) / la2, u1 = (B.b - A.a).dot(dA) / la2;
    const double lo = std::max(0.0, std::min(u0, u1)), hi = std::min(1.0, std::max(u0, u1));
    if (hi - lo > 1e-6) {
      for (const double u : {lo, hi}) {
        const Vec3 x = A.a + u * dA;
        add(x, B.a + closestOnSegment(x, B.a, B.b) * dB, kIdRound | (u == lo ? 1u : 2u));
      }
      double end_depth = -kInf;
      for (int k = 0; k < out.count; ++k) end_depth = std::max(end_depth, out.points[static_cast<Index>(k)].depth);
      if (s > lo && s < hi && r - dist > end_depth + 1e-9 * (r + std::sqrt(la2))) add(pA, pB, kIdRound | 3u);
      if (out.count > 0) return true;
    }
  }
  add(pA, pB, kIdRound);
  return out.count > 0;
}

// The point of polytope P's surface closest to x, x outside P: over the faces facing x, the
// closest point of each face polygon (a fan of triangles; closestOnTriangle).
Vec3 closestOnPolytope(const ConvexPolytope& P, const Vec3& x) {
  Vec3 best = x;
  double best_d2 = kInf;
  for (const auto& f : P.faces) {
    if (f.normal.dot(x) - f.offset < 0) continue;  // (a flat polytope's two faces both see x in their plane)
    const Vec3& v0 = vertexOf(P, f.loop[0]);
    for (Index k = 1; k + 1 < f.loop.size(); ++k) {
      const Vec3& v1 = vertexOf(P, f.loop[k]);
      const Vec3& v2 = vertexOf(P, f.loop[k + 1]);
      const Vec3 w = closestOnTriangle(x, v0, v1, v2);
      const Vec3 y = w[0] * v0 + w[1] * v1 + w[2] * v2;
      const double d2 = (y - x).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = y;
    }
  }
  return best;
}

// The Gauss map of an edge (the normals of the planes touching the polytope along it): the arc
// from face normal n0 to n1; where the two faces are back to back (a flat polytope) half a
// circle, split at the outward normal in their plane. `dir` is the edge as face 0's loop walks it.

EdgeArcs edgeArcs(const Vec3& n0, const Vec3& n1, const Vec3& dir) {
  EdgeArcs g;
  if (n0.dot(n1) < -1 + 1e-9) {
    g.mid = unitOr(dir.cross(n0), perpendicular(n0));
    g.from = {n0, g.mid};
    g.to = {g.mid, n1};
    g.count = 2;
  } else {
    g.mid = n0 + n1;
    g.from[0] = n0;
    g.to[0] = n1;
    g.count = 1;
  }
  for (int k = 0; k < g.count; ++k)
    g.plane[static_cast<Index>(k)] = g.from[static_cast<Index>(k)].cross(g.to[static_cast<Index>(k)]);
  return g;
}

// The arcs through the opposite normals (the Gauss map of −P); their planes are the same.
EdgeArcs negated(EdgeArcs g) {
  for (int k = 0; k < g.count; ++k) {
    g.from[static_cast<Index>(k)] = -g.from[static_cast<Index>(k)];
    g.to[static_cast<Index>(k)] = -g.to[static_cast<Index>(k)];
  }
  g.mid = -g.mid;
  return g;
}

// Whether arcs a→b and c→d (each shorter than half a circle) cross. The great circles meet at ±p;
// c and d must lie on either side of the plane of a, b, and a and b on either side of the plane
// of c, d; p lies on arc ab when a·(c×d) > 0 and on arc cd when c·(a×b) < 0, so both arcs hold
// the same one of ±p when (c·(a×b))·(b·(c×d)) > 0 (Gregorius, "The Separating Axis Test between
// convex polyhedra", GDC 2013: a Minkowski-difference face from an edge pair).
bool arcsCross(const EdgeArcs& g, const EdgeArcs& h) {
  for (Index i = 0; i < static_cast<Index>(g.count); ++i)
    for (Index j = 0; j < static_cast<Index>(h.count); ++j) {
      const double cab = h.from[j].dot(g.plane[i]), dab = h.to[j].dot(g.plane[i]);
      if (!(cab * dab < 0)) continue;
      const double acd = g.from[i].dot(h.plane[j]), bcd = g.to[i].dot(h.plane[j]);
      if (acd * bcd < 0 && cab * bcd > 0) return true;
    }
  return false;
}

// The arcs of edge e of P, given P's face normals and the edge's direction in the working frame.
EdgeArcs edgeArcsOf(const ConvexPolytope& P, int e, const Vec3* normals, const Vec3& dir) {
  const auto [f0, f1] = P.edge_faces[static_cast<Index>(e)];
  return edgeArcs(normals[f0], normals[f1], dir);
}

// Clips segment x0–x1 to the prism over face f of P (the planes through its edges along its
// normal), as parameters [t0, t1]; false when nothing is left.
bool clipToFacePrism(const ConvexPolytope& P, const ConvexPolytope::Face& f, const Vec3& x0,
                     const Vec3& x1, double& t0, double& t1) {
  t0 = 0;
  t1 = 1;
  const Index m = f.loop.size();
  for (Index k = 0; k < m; ++k) {
    const Vec3& v = vertexOf(P, f.loop[k]);
    const Vec3 side = (vertexOf(P, f.loop[(k + 1) % m]) - v).cross(f.normal);
    const double d0 = side.dot(x0 - v), d1 = side.dot(x1 - v);
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0) t0 = std::max(t0, d0 / (d0 - d1));
    else if (d1 > 0) t1 = std::min(t1, d0 / (d0 - d1));
  }
  return t0 <= t1;
}

// Cyrus–Beck: narrows the part [t0, t1] of a segment inside a half-space, given its ends' signed
// distances da, db from the plane (positive outside); an empty part has t0 > t1.
void clipToHalfSpace(double da, double db, double& t0, double& t1) {
  if (da > 0 && db > 0) t0 = kInf;
  else if (da > 0) t0 = std::max(t0, da / (da - db));
  else if (db > 0) t1 = std::min(t1, da / (da - db));
}

// Sphere/capsule S against polytope P (radius rounded): contacts with the normal from S toward P.
// Cores apart: the exact closest points (endpoint to surface, segment to every edge); a capsule
// lying along a face touches it where the segment, clipped to the face's prism, meets it (two
// points). Cores overlapping: separating axes over P's faces and P's edges × the segment.
bool roundPolytope(const Round& S, const ConvexPolytope& Pin, const double rP, const Pose& pp,
                   double margin, Manifold& out) {
  ConvexPolytope tmp;
  const ConvexPolytope& P = withEdgeFaces(Pin, tmp);
  out.count = 0;
  // The core in P's frame
  const Mat3 Rt = pp.R.transpose();
  const Vec3 a = Rt * (S.a - pp.p), b = Rt * (S.b - pp.p), d = b - a;
  const double r = S.r + rP, len = d.norm();
  const bool segment = len > 0;

  // Clip the core to every face's half-space (Cyrus–Beck); the face separating it most
  double t0 = 0, t1 = 1, face_sep = -kInf;
  int face = 0;
  for (Index f = 0; f < P.faces.size(); ++f) {
    const auto& F = P.faces[f];
    const double da = F.normal.dot(a) - F.offset, db = F.normal.dot(b) - F.offset;
    const double sep = std::min(da, db);
    if (sep - r > margin) return false;
    if (sep > face_sep) face_sep = sep, face = static_cast<int>(f);
    clipToHalfSpace(da, db, t0, t1);
  }
  // A flat polytope (faces back to back) is bounded in its plane by its edges' outward normals
  for (Index e = 0; e < P.edges.size(); ++e) {
    const auto [f0, f1] = P.edge_faces[e];
    if (f0 < 0 || f1 < 0) continue;
    const Vec3& n0 = P.faces[static_cast<Index>(f0)].normal;
    if (n0.dot(P.faces[static_cast<Index>(f1)].normal) >= -1 + 1e-9) continue;
    const Vec3& v0 = vertexOf(P, P.edges[e][0]);
    const Vec3 side = unitOr((vertexOf(P, P.edges[e][1]) - v0).cross(n0), perpendicular(n0));
    const double da = side.dot(a - v0), db = side.dot(b - v0);
    if (std::min(da, db) - r > margin) return false;
    clipToHalfSpace(da, db, t0, t1);
  }
  const bool cores_apart = t0 > t1;

  // Candidate contacts in P's frame; the normal n points from P toward S
  Candidates c;
  Vec3 n(0, 1, 0);
  // The contacts of face f where the segment's clipped part lies within the margin
  auto faceContacts = [&](int f, std::uint32_t base) {
    const auto& F = P.faces[static_cast<Index>(f)];
    n = F.normal;
    double u0 = 0, u1 = 0;
    if (!clipToFacePrism(P, F, a, b, u0, u1)) return;
    const int ends = segment && u1 > u0 ? 2 : 1;
    for (int k = 0; k < ends; ++k) {
      const Vec3 x = a + (k == 0 ? u0 : u1) * d;
      const double g = n.dot(x) - F.offset;
      if (r - g < -margin) continue;
      c.push({x + 0.5 * (rP - g - S.r) * n, r - g,
              base | (static_cast<std::uint32_t>(f) & 0xFFu) << 8 | (segment ? k + 1u : 0u)});
    }
  };
  // One contact between core point x and polytope point q along n
  auto pointContact = [&](const Vec3& x, const Vec3& q, double gap) {
    if (r - gap >= -margin) c.push({0.5 * (x - S.r * n + q + rP * n), r - gap, kIdRound});
  };

  if (cores_apart) {
    // The closest points: each endpoint to the surface, the segment to each edge
    Vec3 x = a, q = closestOnPolytope(P, a);
    double best = (x - q).squaredNorm();
    if (segment) {
      const Vec3 qb = closestOnPolytope(P, b);
      if ((b - qb).squaredNorm() < best) x = b, q = qb, best = (b - qb).squaredNorm();
      for (const auto& e : P.edges) {
        const Vec3& v0 = vertexOf(P, e[0]);
        const Vec3& v1 = vertexOf(P, e[1]);
        double s, t;
        closestSegmentSegment(a, b, v0, v1, s, t);
        const Vec3 xs = a + s * d, qs = v0 + t * (v1 - v0);
        if ((xs - qs).squaredNorm() < best) x = xs, q = qs, best = (xs - qs).squaredNorm();
      }
    }
    const double dist = std::sqrt(best);
    if (dist - r > margin) return false;
    // A segment along the face that nearly separates as well: the face's contacts, provided the
    // clipped part holds the closest point (not where the segment dips past the face's edge)
    const double tol = 1e-3 * (len + r);
    if (segment && face_sep >= dist - tol) {
      faceContacts(face, kIdRound);
      double deepest = -kInf;
      for (int k = 0; k < c.size(); ++k) deepest = std::max(deepest, c[k].depth);
      if (deepest < r - dist - tol) c.clear();
    }
    if (c.size() == 0) {
      n = dist > 0 ? Vec3((x - q) / dist) : P.faces[static_cast<Index>(face)].normal;
      pointContact(x, q, dist);
    }
  } else {
    // Separating axes, faces preferred: P's edges × the segment where the edge's Gauss arc
    // crosses the segment's great circle (a face of their Minkowski difference)
    double edge_sep = -kInf;
    int edge = -1;
    Vec3 edge_axis(0, 0, 0);
    if (segment) {
      SmallBuf<Vec3, 64> normals;
      for (const auto& F : P.faces) normals.push(F.normal);
      for (Index e = 0; e < P.edges.size(); ++e) {
        if (P.edge_faces[e][0] < 0 || P.edge_faces[e][1] < 0) continue;
        const Vec3& v0 = vertexOf(P, P.edges[e][0]);
        const Vec3 de = vertexOf(P, P.edges[e][1]) - v0;
        const EdgeArcs g = edgeArcsOf(P, static_cast<int>(e), &normals[0], de);
        bool crosses = false;
        for (int k = 0; k < g.count; ++k)
          crosses = crosses || g.from[static_cast<Index>(k)].dot(d) * g.to[static_cast<Index>(k)].dot(d) < 0;
        if (!crosses) continue;
        Vec3 u = de.cross(d);
        if (!(u.squaredNorm() > 1e-12 * de.squaredNorm() * d.squaredNorm())) continue;
        u.normalize();
        if (u.dot(g.mid) < 0) u = -u;
        const double sep = std::min(u.dot(a), u.dot(b)) - u.dot(v0);
        if (sep - r > margin) return false;
        if (sep > edge_sep) edge_sep = sep, edge = static_cast<int>(e), edge_axis = u;
      }
    }
    const double tol = 0.05 * std::abs(face_sep) + 1e-4 * (len + r);
    if (edge >= 0 && edge_sep > face_sep + tol) {
      // Edge axis: one point at the closest points of the segment and the edge
      const Vec3& v0 = vertexOf(P, P.edges[static_cast<Index>(edge)][0]);
      const Vec3& v1 = vertexOf(P, P.edges[static_cast<Index>(edge)][1]);
      double s, t;
      closestSegmentSegment(a, b, v0, v1, s, t);
      n = edge_axis;
      pointContact(a + s * d, v0 + t * (v1 - v0), edge_sep);
    } else {
      // Face axis: the least-penetrated face; the segment clipped to its prism, else its
      // deepest end
      faceContacts(face, kIdRound);
      if (c.size() == 0) {
        const auto& F = P.faces[static_cast<Index>(face)];
        const Vec3 x = n.dot(a) <= n.dot(b) ? a : b;
        const double g = n.dot(x) - F.offset;
        pointContact(x, x - g * n, g);
      }
    }
  }
  // World: the normal from S toward P
  return emit(c, pp.R, pp.p, -n, out);
}

}  // namespace contact_detail

using namespace contact_detail;


bool collide(const ConvexShape& A, const Pose& pa, const ConvexShape& B, const Pose& pb,
             double margin, Manifold& out) {
  out.count = 0;
  // Order the pair by core kind; the normal turned back afterwards
  if (static_cast<int>(A.kind) > static_cast<int>(B.kind)) {
    const bool hit = collide(B, pb, A, pa, margin, out);
    out.normal = -out.normal;
    return hit;
  }
  if (B.kind != CoreKind::Polytope) return roundRound(roundInWorld(A, pa), roundInWorld(B, pb), margin, out);
  if (!B.poly) return false;
  if (A.kind != CoreKind::Polytope) return roundPolytope(roundInWorld(A, pa), *B.poly, B.radius, pb, margin, out);
  if (!A.poly) return false;
  return polytopePair(*A.poly, A.radius, pa, *B.poly, B.radius, pb, margin, out);
}

bool collideHalfSpace(const ConvexShape& A, const Pose& pa, const Vec3& n, double offset,
                      double margin, Manifold& out) {
  out.count = 0;
  out.normal = -n;
  const double r = A.radius;
  // Rounded cores: each end of the core within the margin
  if (A.kind != CoreKind::Polytope) {
    const Round S = roundInWorld(A, pa);
    const int ends = A.kind == CoreKind::Segment ? 2 : 1;
    for (int k = 0; k < ends; ++k) {
      const Vec3& x = k == 0 ? S.a : S.b;
      const double s = n.dot(x) - offset;
      if (r - s < -margin) continue;
      out.points[static_cast<Index>(out.count++)] = {x - 0.5 * (r + s) * n, r - s,
                                                     kIdRound | (ends == 2 ? k + 1u : 0u)};
    }
    return out.count > 0;
  }
  if (!A.poly) return false;
  // Polytope: its vertices within the margin, the plane in A's frame
  const Vec3 nl = pa.R.transpose() * n;
  const double offl = offset - n.dot(pa.p);
  Candidates c;
  for (Index i = 0; i < A.poly->vertices.size(); ++i) {
    const Vec3& v = A.poly->vertices[i];
    const double s = nl.dot(v) - offl;
    if (r - s < -margin) continue;
    c.push({v - 0.5 * (r + s) * nl, r - s, kIdRound | (static_cast<std::uint32_t>(i) & 0xFFFFu)});
  }
  return emit(c, pa.R, pa.p, -nl, out);
}

void shapeBounds(const ConvexShape& s, const Pose& p, Vec3& lo, Vec3& hi) {
  const Vec3 r = Vec3::Constant(s.radius);
  if (s.kind == CoreKind::Polytope && s.poly && !s.poly->vertices.empty()) {
    lo = hi = p.R * s.poly->vertices[0] + p.p;
    for (const Vec3& v : s.poly->vertices) {
      const Vec3 w = p.R * v + p.p;
      lo = lo.cwiseMin(w);
      hi = hi.cwiseMax(w);
    }
  } else {
    const Round c = roundInWorld(s, p);
    lo = c.a.cwiseMin(c.b);
    hi = c.a.cwiseMax(c.b);
  }
  lo -= r;
  hi += r;
}

}  // namespace reel
