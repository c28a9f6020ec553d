// The rigid narrow phase's polytope pairs: separating axes over both polytopes' faces and the edge
// pairs that form faces of their Minkowski difference, and the incident face clipped against the
// reference face (sim/rigid/contact.h states the conventions).
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "sim/geometry.h"
#include "sim/rigid/contact_detail.h"

namespace reel::contact_detail {
namespace {

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

}  // namespace

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

  // The face of one polytope with all of the other lying farthest beyond it (its separation),
  // and the other's deepest vertex under it; false when some face separates them beyond reach.
  auto deepestFace = [&](int faces, int verts, auto normal, auto offset, auto vertex, double& best, int& face, int& deep) {
    best = -kInf;
    face = -1;
    deep = 0;
    for (int f = 0; f < faces; ++f) {
      double lo = kInf;
      int at = 0;
      for (int j = 0; j < verts; ++j)
        if (const double h = normal(f).dot(vertex(j)); h < lo) lo = h, at = j;
      const double sep = lo - offset(f);
      if (sep - r > margin) return false;
      if (sep > best) best = sep, face = f, deep = at;
    }
    return true;
  };
  double sepA, sepB;
  int faceA, deepB, faceB, deepA;
  if (!deepestFace(nFA, nVB, [&](int f) -> const Vec3& { return an[f]; },
                [&](int f) { return A.faces[static_cast<Index>(f)].offset; }, [&](int j) -> const Vec3& { return bv[j]; },
                sepA, faceA, deepB))
    return false;
  if (!deepestFace(nFB, nVA, [&](int f) -> const Vec3& { return bn[f]; }, [&](int f) { return bo[f]; },
                [&](int i) { return vertexOf(A, i); }, sepB, faceB, deepA))
    return false;
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
}  // namespace reel::contact_detail
