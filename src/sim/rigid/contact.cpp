#include "sim/rigid/contact.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "core/math.h"
#include "sim/geometry.h"

namespace reel {

namespace {

using Index = std::size_t;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Feature ids: the top two bits say which kind of contact, the rest name its features.
//   face contacts: reference face (8 bits), incident face (8 bits), clipped point (14 bits:
//                  the labels of the polygon edges before and after it, 7 bits each);
//   edge pairs:    A's edge (15 bits), B's edge (15 bits);
//   rounded cores: the face (8 bits) and which end of a segment (1, 2; 0 for a single point).
constexpr std::uint32_t kIdFaceA = 0u << 30, kIdFaceB = 1u << 30, kIdEdges = 2u << 30,
                        kIdRound = 3u << 30;

std::uint32_t faceId(std::uint32_t kind, int ref, int inc, std::uint32_t feature) {
  return kind | (static_cast<std::uint32_t>(ref) & 0xFFu) << 22 |
         (static_cast<std::uint32_t>(inc) & 0xFFu) << 14 | (feature & 0x3FFFu);
}

// A list with room for N elements in place and on the heap beyond: the usual polytope (a box's
// 8 vertices, a clipped quad's 8 points) costs no allocation.
template <class T, int N>
class SmallBuf {
 public:
  SmallBuf() = default;
  SmallBuf(const SmallBuf&) = delete;
  SmallBuf& operator=(const SmallBuf&) = delete;
  int size() const { return n_; }
  void clear() { n_ = 0; }
  void push(const T& x) {
    if (n_ == cap_) grow(2 * cap_);
    data_[n_++] = x;
  }
  T& operator[](int i) { return data_[i]; }
  const T& operator[](int i) const { return data_[i]; }

 private:
  void grow(int cap) {
    std::vector<T> bigger(static_cast<Index>(cap));
    std::copy(data_, data_ + n_, bigger.begin());
    heap_.swap(bigger);
    data_ = heap_.data();
    cap_ = cap;
  }
  std::array<T, N> inline_;
  std::vector<T> heap_;
  T* data_ = inline_.data();
  int n_ = 0, cap_ = N;
};

// A contact point before the manifold is reduced: position and depth in a working frame.
struct Candidate {
  Vec3 x;
  double depth;
  std::uint32_t id;
};
using Candidates = SmallBuf<Candidate, 64>;

const Vec3& vertexOf(const ConvexPolytope& p, int i) { return p.vertices[static_cast<Index>(i)]; }

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
struct EdgeArcs {
  std::array<Vec3, 2> from, to;
  std::array<Vec3, 2> plane;  // from × to: the normal of each arc's great circle
  int count;
  Vec3 mid;  // a direction inside the arcs
};

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

// ---- Polytope against polytope

// A vertex of a clipped polygon and the label of the polygon edge leaving it: incident edges
// 0..63 by loop position, reference side planes 64 + side.
struct ClipVertex {
  Vec3 x;
  std::uint32_t out;
};
using ClipPoly = SmallBuf<ClipVertex, 64>;

// Sutherland–Hodgman: the part of polygon `in` on the inner side of plane side·x ≤ off; a cut
// edge's new vertex is labelled by the edges meeting there.
void clipPolygon(const ClipPoly& in, const Vec3& side, double off, std::uint32_t label, ClipPoly& out) {
  out.clear();
  const int m = in.size();
  for (int k = 0; k < m; ++k) {
    const ClipVertex& p = in[k];
    const ClipVertex& q = in[(k + 1) % m];
    const double dp = side.dot(p.x) - off, dq = side.dot(q.x) - off;
    if (dp <= 0) out.push(p);
    if ((dp <= 0) != (dq <= 0)) {
      const double t = dp / (dp - dq);
      // Leaving: the new edge runs along the plane; entering: along p's edge
      out.push({p.x + t * (q.x - p.x), dp <= 0 ? label : p.out});
    }
  }
}

// Separating-axis test with reference/incident face clipping (Gottschalk 1996; Gregorius, GDC
// 2013/2015): A's faces, B's faces and the edge pairs that form faces of the Minkowski
// difference; faces preferred unless an edge pair separates clearly more. Worked in A's frame.
bool polytopePair(const ConvexPolytope& Ain, double rA, const Pose& pa, const ConvexPolytope& Bin,
                  double rB, const Pose& pb, double margin, Manifold& out) {
  ConvexPolytope tmpA, tmpB;
  const ConvexPolytope& A = withEdgeFaces(Ain, tmpA);
  const ConvexPolytope& B = withEdgeFaces(Bin, tmpB);
  out.count = 0;
  const double r = rA + rB;
  const double scale = polytopeExtent(A) + polytopeExtent(B);

  // B in A's frame: vertices (B's vertices), face normals and offsets (B's faces)
  const Mat3 R = pa.R.transpose() * pb.R;
  const Vec3 t = pa.R.transpose() * (pb.p - pa.p);
  const int nVA = static_cast<int>(A.vertices.size()), nVB = static_cast<int>(B.vertices.size());
  const int nFA = static_cast<int>(A.faces.size()), nFB = static_cast<int>(B.faces.size());
  SmallBuf<Vec3, 64> bv, bn, an;
  SmallBuf<double, 64> bo;
  for (const Vec3& v : B.vertices) bv.push(R * v + t);
  for (const auto& F : B.faces) {
    const Vec3 n = R * F.normal;
    bn.push(n);
    bo.push(F.offset + n.dot(t));
  }
  for (const auto& F : A.faces) an.push(F.normal);

  // A's faces: how far all of B lies beyond each
  // (and the deepest vertex of B under the best one)
  double sepA = -kInf;
  int faceA = -1, deepB = 0;
  for (int f = 0; f < nFA; ++f) {
    double lo = kInf;
    int at = 0;
    for (int j = 0; j < nVB; ++j)
      if (const double h = an[f].dot(bv[j]); h < lo) lo = h, at = j;
    const double sep = lo - A.faces[static_cast<Index>(f)].offset;
    if (sep - r > margin) return false;
    if (sep > sepA) sepA = sep, faceA = f, deepB = at;
  }
  // B's faces: how far all of A lies beyond each
  double sepB = -kInf;
  int faceB = -1, deepA = 0;
  for (int f = 0; f < nFB; ++f) {
    double lo = kInf;
    int at = 0;
    for (int i = 0; i < nVA; ++i)
      if (const double h = bn[f].dot(vertexOf(A, i)); h < lo) lo = h, at = i;
    const double sep = lo - bo[f];
    if (sep - r > margin) return false;
    if (sep > sepB) sepB = sep, faceB = f, deepA = at;
  }
  // Edge pairs whose Gauss arcs cross (A's arc against B's negated arc); the axis across both
  // edges, turned out of A
  double sepE = -kInf;
  int edgeA = -1, edgeB = -1;
  Vec3 axisE(0, 0, 0);
  {
    SmallBuf<EdgeArcs, 64> arcsB;
    SmallBuf<Vec3, 64> dirB;
    for (Index e = 0; e < B.edges.size(); ++e) {
      const Vec3 de = bv[B.edges[e][1]] - bv[B.edges[e][0]];
      dirB.push(de);
      const auto [f0, f1] = B.edge_faces[e];
      arcsB.push(f0 < 0 || f1 < 0 ? EdgeArcs{{}, {}, {}, 0, Vec3(0, 0, 0)}
                                  : negated(edgeArcs(bn[f0], bn[f1], de)));
    }
    for (Index ea = 0; ea < A.edges.size(); ++ea) {
      if (A.edge_faces[ea][0] < 0 || A.edge_faces[ea][1] < 0) continue;
      const Vec3& va = vertexOf(A, A.edges[ea][0]);
      const Vec3 da = vertexOf(A, A.edges[ea][1]) - va;
      const EdgeArcs g = edgeArcsOf(A, static_cast<int>(ea), &an[0], da);
      for (int eb = 0; eb < static_cast<int>(B.edges.size()); ++eb) {
        if (!arcsCross(g, arcsB[eb])) continue;
        Vec3 u = da.cross(dirB[eb]);
        const double u2 = u.squaredNorm();
        if (!(u2 > 1e-12 * da.squaredNorm() * dirB[eb].squaredNorm())) continue;  // parallel
        u /= std::sqrt(u2);
        if (u.dot(g.mid) < 0) u = -u;
        const double sep = u.dot(bv[B.edges[static_cast<Index>(eb)][0]] - va);
        if (sep - r > margin) return false;
        if (sep > sepE) sepE = sep, edgeA = static_cast<int>(ea), edgeB = eb, axisE = u;
      }
    }
  }

  // Edge contact: one point at the closest points of the two edges
  auto edgeContact = [&]() {
    const Vec3& a0 = vertexOf(A, A.edges[static_cast<Index>(edgeA)][0]);
    const Vec3& a1 = vertexOf(A, A.edges[static_cast<Index>(edgeA)][1]);
    const Vec3& b0 = bv[B.edges[static_cast<Index>(edgeB)][0]];
    const Vec3& b1 = bv[B.edges[static_cast<Index>(edgeB)][1]];
    double s, w;
    closestSegmentSegment(a0, a1, b0, b1, s, w);
    const Vec3 xa = a0 + s * (a1 - a0), xb = b0 + w * (b1 - b0);
    const double depth = r - sepE;
    if (depth < -margin) return false;
    out.normal = pa.R * axisE;
    out.count = 1;
    out.points[0] = {pa.R * (0.5 * (xa + rA * axisE + xb - rB * axisE)) + pa.p, depth,
                     kIdEdges | (static_cast<std::uint32_t>(edgeA) & 0x7FFFu) << 15 |
                         (static_cast<std::uint32_t>(edgeB) & 0x7FFFu)};
    return true;
  };

  const double bestFace = std::max(sepA, sepB);
  const double tolEdge = 0.05 * std::abs(bestFace) + 5e-4 * scale;
  if (edgeA >= 0 && sepE > bestFace + tolEdge) return edgeContact();

  // Face contact: the reference face (A's unless B's separates clearly more), the incident face
  // of the other (of the faces at its deepest vertex, the one whose normal is the most opposed),
  // clipped to the reference face's side planes
  const bool refIsA = !(sepB > sepA + 0.02 * std::abs(sepA) + 1e-4 * scale);
  const ConvexPolytope& ref = refIsA ? A : B;
  const ConvexPolytope& inc = refIsA ? B : A;
  const int refFace = refIsA ? faceA : faceB;
  const Vec3 n = refIsA ? an[refFace] : bn[refFace];  // out of the reference polytope
  const double off = refIsA ? A.faces[static_cast<Index>(refFace)].offset : bo[refFace];
  const double rRef = refIsA ? rA : rB, rInc = refIsA ? rB : rA;
  auto refVertex = [&](int i) -> Vec3 { return refIsA ? vertexOf(A, i) : bv[i]; };
  auto incVertex = [&](int i) -> Vec3 { return refIsA ? bv[i] : vertexOf(A, i); };
  int incFace = 0;
  {
    const int deep = refIsA ? deepB : deepA;
    double lowest = kInf;
    for (int f = 0; f < static_cast<int>(inc.faces.size()); ++f) {
      const auto& loop = inc.faces[static_cast<Index>(f)].loop;
      if (std::find(loop.begin(), loop.end(), deep) == loop.end()) continue;
      const double c = n.dot(refIsA ? bn[f] : an[f]);
      if (c < lowest) lowest = c, incFace = f;
    }
  }
  // The incident polygon, its edges labelled by loop position
  ClipPoly poly, spare;
  const auto& incLoop = inc.faces[static_cast<Index>(incFace)].loop;
  for (Index k = 0; k < incLoop.size(); ++k)
    poly.push({incVertex(incLoop[k]), static_cast<std::uint32_t>(k) & 63u});
  // Clipped by each side plane of the reference face (through its edge, along its normal),
  // pushed out by a rounding tolerance so a vertex on a side plane stays itself
  const auto& refLoop = ref.faces[static_cast<Index>(refFace)].loop;
  ClipPoly* cur = &poly;
  ClipPoly* nxt = &spare;
  for (Index k = 0; k < refLoop.size() && cur->size() > 0; ++k) {
    const Vec3 v = refVertex(refLoop[k]);
    const Vec3 side = (refVertex(refLoop[(k + 1) % refLoop.size()]) - v).cross(n);
    clipPolygon(*cur, side, side.dot(v) + 1e-9 * scale * side.norm(),
                64u + (static_cast<std::uint32_t>(k) & 63u), *nxt);
    std::swap(cur, nxt);
  }
  // The clipped points below the reference face plus the margin; each at the midpoint of the
  // surfaces and named by its two edges
  Candidates c;
  const std::uint32_t kind = refIsA ? kIdFaceA : kIdFaceB;
  const int m = cur->size();
  for (int k = 0; k < m; ++k) {
    const ClipVertex& p = (*cur)[k];
    const double g = n.dot(p.x) - off, depth = r - g;
    if (depth < -margin) continue;
    const std::uint32_t feature = ((*cur)[(k + m - 1) % m].out << 7) | p.out;
    c.push({p.x + 0.5 * (rRef - g - rInc) * n, depth, faceId(kind, refFace, incFace, feature)});
  }
  if (c.size() == 0) return edgeA >= 0 ? edgeContact() : false;
  // World: the normal from A toward B
  return emit(c, pa.R, pa.p, refIsA ? n : Vec3(-n), out);
}

}  // namespace

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
