#include "core/mass_properties.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "core/format.h"
#include "core/math.h"
#include "core/union_find.h"

namespace reel {

namespace {

// The integrals of 1, α, β, α², αβ, β², α³, α²β, αβ², β³ over a face's projection onto the α–β
// plane (signed: negative where the projection winds clockwise), m^(2..5).
struct ProjectionIntegrals {
  double P1 = 0, Pa = 0, Pb = 0, Paa = 0, Pab = 0, Pbb = 0, Paaa = 0, Paab = 0, Pabb = 0, Pbbb = 0;
};

// Mirtich 1996, projection integrals: Green's theorem turns each projection integral into a sum over the
// projected edges (a0, b0) → (a1, b1), each a polynomial in the end coordinates.
ProjectionIntegrals projectionIntegrals(const std::array<Vec3, 3>& corners, int A, int B) {
  ProjectionIntegrals p;
  for (int e = 0; e < 3; ++e) {
    const Vec3& from = corners[static_cast<std::size_t>(e)];
    const Vec3& to = corners[static_cast<std::size_t>((e + 1) % 3)];
    const double a0 = from[A], b0 = from[B], a1 = to[A], b1 = to[B];
    const double da = a1 - a0, db = b1 - b0;
    const double a0_2 = a0 * a0, a0_3 = a0_2 * a0, a0_4 = a0_3 * a0;
    const double b0_2 = b0 * b0, b0_3 = b0_2 * b0, b0_4 = b0_3 * b0;
    const double a1_2 = a1 * a1, a1_3 = a1_2 * a1;
    const double b1_2 = b1 * b1, b1_3 = b1_2 * b1;
    // The edge's polynomial factors (Mirtich's C and K terms).
    const double C1 = a1 + a0;
    const double Ca = a1 * C1 + a0_2, Caa = a1 * Ca + a0_3, Caaa = a1 * Caa + a0_4;
    const double Cb = b1 * (b1 + b0) + b0_2, Cbb = b1 * Cb + b0_3, Cbbb = b1 * Cbb + b0_4;
    const double Cab = 3 * a1_2 + 2 * a1 * a0 + a0_2, Kab = a1_2 + 2 * a1 * a0 + 3 * a0_2;
    const double Caab = a0 * Cab + 4 * a1_3, Kaab = a1 * Kab + 4 * a0_3;
    const double Cabb = 4 * b1_3 + 3 * b1_2 * b0 + 2 * b1 * b0_2 + b0_3;
    const double Kabb = b1_3 + 2 * b1_2 * b0 + 3 * b1 * b0_2 + 4 * b0_3;
    p.P1 += db * C1;
    p.Pa += db * Ca;
    p.Paa += db * Caa;
    p.Paaa += db * Caaa;
    p.Pb += da * Cb;
    p.Pbb += da * Cbb;
    p.Pbbb += da * Cbbb;
    p.Pab += db * (b1 * Cab + b0 * Kab);
    p.Paab += db * (b1 * Caab + b0 * Kaab);
    p.Pabb += da * (a1 * Cabb + a0 * Kabb);
  }
  p.P1 /= 2.0;
  p.Pa /= 6.0;
  p.Paa /= 12.0;
  p.Paaa /= 20.0;
  p.Pb /= -6.0;
  p.Pbb /= -12.0;
  p.Pbbb /= -20.0;
  p.Pab /= 24.0;
  p.Paab /= 60.0;
  p.Pabb /= -60.0;
  return p;
}

// The integrals of α, β, γ, α², β², γ², α³, β³, γ³, α²β, β²γ, γ²α over the face itself, m^(3..5).
struct FaceIntegrals {
  double Fa = 0, Fb = 0, Fc = 0, Faa = 0, Fbb = 0, Fcc = 0, Faaa = 0, Fbbb = 0, Fccc = 0, Faab = 0, Fbbc = 0, Fcca = 0;
};

// Mirtich 1996, face integrals: on the face's plane n·x + w = 0, γ = −(n_α α + n_β β + w) / n_γ, and
// dA = dα dβ / |n_γ|; the projection's sign (its winding) and 1 / n_γ together give the face's.
FaceIntegrals faceIntegrals(const std::array<Vec3, 3>& corners, const Vec3& n, double w, int A, int B, int C) {
  const ProjectionIntegrals p = projectionIntegrals(corners, A, B);
  const double k1 = 1 / n[C], k2 = k1 * k1, k3 = k2 * k1, k4 = k3 * k1;
  const double na = n[A], nb = n[B];
  FaceIntegrals f;
  f.Fa = k1 * p.Pa;
  f.Fb = k1 * p.Pb;
  f.Fc = -k2 * (na * p.Pa + nb * p.Pb + w * p.P1);
  f.Faa = k1 * p.Paa;
  f.Fbb = k1 * p.Pbb;
  f.Fcc = k3 * (na * na * p.Paa + 2 * na * nb * p.Pab + nb * nb * p.Pbb + w * (2 * (na * p.Pa + nb * p.Pb) + w * p.P1));
  f.Faaa = k1 * p.Paaa;
  f.Fbbb = k1 * p.Pbbb;
  f.Fccc = -k4 * (na * na * na * p.Paaa + 3 * na * na * nb * p.Paab + 3 * na * nb * nb * p.Pabb +
                  nb * nb * nb * p.Pbbb + 3 * w * (na * na * p.Paa + 2 * na * nb * p.Pab + nb * nb * p.Pbb) +
                  w * w * (3 * (na * p.Pa + nb * p.Pb) + w * p.P1));
  f.Faab = k1 * p.Paab;
  f.Fbbc = -k2 * (na * p.Pabb + nb * p.Pbbb + w * p.Pbb);
  f.Fcca = k3 * (na * na * p.Paaa + 2 * na * nb * p.Paab + nb * nb * p.Pabb +
                 w * (2 * (na * p.Paa + nb * p.Pab) + w * p.Pa));
  return f;
}

// (b − a) × (c − a) · (d − a): positive when d lies on the side a, b, c wind counter-clockwise
// about (six times the signed volume of the tetrahedron), m³.
double orient3(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return (b - a).cross(c - a).dot(d - a); }

// The same in the plane of coordinates (A, B), m².
double orient2(const Vec3& a, const Vec3& b, const Vec3& c, int A, int B) {
  return (b[A] - a[A]) * (c[B] - a[B]) - (b[B] - a[B]) * (c[A] - a[A]);
}

// The index of v's largest coefficient, the first of equals.
int largestAxis(const Vec3& v) { return v[1] > v[0] ? (v[2] > v[1] ? 2 : 1) : (v[2] > v[0] ? 2 : 0); }

bool allPositive(double x, double y, double z) { return x > 0 && y > 0 && z > 0; }
bool allNegative(double x, double y, double z) { return x < 0 && y < 0 && z < 0; }

// Whether segment p–q passes through the interior of triangle t: p and q strictly on opposite
// sides of its plane, and the line p–q strictly inside its three edges (the signs of the volumes
// p, q with each edge agree).
bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const std::array<Vec3, 3>& t) {
  const double sp = orient3(t[0], t[1], t[2], p), sq = orient3(t[0], t[1], t[2], q);
  if (!((sp > 0 && sq < 0) || (sp < 0 && sq > 0))) return false;
  const double e0 = orient3(p, q, t[0], t[1]), e1 = orient3(p, q, t[1], t[2]), e2 = orient3(p, q, t[2], t[0]);
  return allPositive(e0, e1, e2) || allNegative(e0, e1, e2);
}

// Whether point p lies strictly inside triangle t in the plane (A, B).
bool strictlyInside2(const Vec3& p, const std::array<Vec3, 3>& t, int A, int B) {
  const double s0 = orient2(t[0], t[1], p, A, B), s1 = orient2(t[1], t[2], p, A, B), s2 = orient2(t[2], t[0], p, A, B);
  return allPositive(s0, s1, s2) || allNegative(s0, s1, s2);
}

// Whether segments p–q and r–s cross at a point inside both, in the plane (A, B).
bool segmentsCross2(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s, int A, int B) {
  const double a = orient2(p, q, r, A, B), b = orient2(p, q, s, A, B);
  const double c = orient2(r, s, p, A, B), d = orient2(r, s, q, A, B);
  return ((a > 0 && b < 0) || (a < 0 && b > 0)) && ((c > 0 && d < 0) || (c < 0 && d > 0));
}

// Whether two triangles with no corner in common cross: interiors pierce each other, or (in one
// plane, facing the same way) overlap. Contact counts as no crossing: a corner or edge on the
// other triangle, or coplanar faces facing apart (two solids touching). Signs in double precision.
bool trianglesCross(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
  // Separated by either triangle's plane.
  const double d0 = orient3(t[0], t[1], t[2], u[0]), d1 = orient3(t[0], t[1], t[2], u[1]),
               d2 = orient3(t[0], t[1], t[2], u[2]);
  if (allPositive(d0, d1, d2) || allNegative(d0, d1, d2)) return false;
  const double e0 = orient3(u[0], u[1], u[2], t[0]), e1 = orient3(u[0], u[1], u[2], t[1]),
               e2 = orient3(u[0], u[1], u[2], t[2]);
  if (allPositive(e0, e1, e2) || allNegative(e0, e1, e2)) return false;
  // In one plane: only faces facing the same way overlap volumes; test in the plane the normal
  // is most nearly perpendicular to.
  if (d0 == 0 && d1 == 0 && d2 == 0) {
    const Vec3 nt = (t[1] - t[0]).cross(t[2] - t[0]), nu = (u[1] - u[0]).cross(u[2] - u[0]);
    if (nt.dot(nu) <= 0) return false;
    const int C = largestAxis(nt.cwiseAbs());
    const int A = (C + 1) % 3, B = (C + 2) % 3;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (segmentsCross2(t[i], t[(i + 1) % 3], u[j], u[(j + 1) % 3], A, B)) return true;
    const Vec3 ct = (t[0] + t[1] + t[2]) / 3, cu = (u[0] + u[1] + u[2]) / 3;
    for (int i = 0; i < 3; ++i)
      if (strictlyInside2(u[i], t, A, B) || strictlyInside2(t[i], u, A, B)) return true;
    return strictlyInside2(cu, t, A, B) || strictlyInside2(ct, u, A, B);
  }
  // Otherwise their common segment, if any, ends where an edge of one pierces the other.
  for (int i = 0; i < 3; ++i)
    if (segmentCrossesTriangle(t[i], t[(i + 1) % 3], u) || segmentCrossesTriangle(u[i], u[(i + 1) % 3], t)) return true;
  return false;
}

// Van Oosterom & Strackee 1983: the solid angle triangle (a, b, c) subtends at the origin, signed
// positive when it winds counter-clockwise seen from the origin's far side, sr.
double solidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2 * std::atan2(num, den);
}

std::string formatPoint(const Vec3& p) {
  return "(" + formatNumber(p.x(), 6) + ", " + formatNumber(p.y(), 6) + ", " + formatNumber(p.z(), 6) + ")";
}

Error badInput(std::string message) { return Error(ErrorKind::BadInput, std::move(message)); }

// A triangle's box in the sweep: its extent along the sweep axis and the two others, m.
struct SweepBox {
  double lo, hi, lo1, hi1, lo2, hi2;
  std::uint32_t tri;
};

// A directed edge u → v of triangle `tri`, keyed by its undirected end points lo < hi.
struct DirectedEdge {
  int lo, hi, tri;
  bool forward;  // u = lo
};

}  // namespace

MassProperties polyhedronMass(std::span<const Vec3> vertices, std::span<const std::array<int, 3>> triangles,
                              double density) {
  if (triangles.empty()) return {};
  // The integrals are exact about any origin; taking them about the centre of the bounds keeps the
  // third powers from cancelling far from the mesh's origin. Moved back at the end.
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const auto& tri : triangles)
    for (int k : tri) {
      lo = lo.cwiseMin(vertices[static_cast<std::size_t>(k)]);
      hi = hi.cwiseMax(vertices[static_cast<std::size_t>(k)]);
    }
  const Vec3 ref = (lo + hi) / 2;

  // Mirtich 1996, volume integrals: ∫1, ∫x, ∫x², ∫xy as sums of face integrals
  // (divergence theorem), face by face in its own (α, β, γ) frame.
  double T0 = 0;           // ∫ dV, m³
  Vec3 T1 = Vec3::Zero();  // ∫ x, ∫ y, ∫ z dV, m⁴
  Vec3 T2 = Vec3::Zero();  // ∫ x², ∫ y², ∫ z² dV, m⁵
  Vec3 TP = Vec3::Zero();  // ∫ xy, ∫ yz, ∫ zx dV, m⁵
  for (const auto& tri : triangles) {
    const std::array<Vec3, 3> corners = {vertices[static_cast<std::size_t>(tri[0])] - ref,
                                         vertices[static_cast<std::size_t>(tri[1])] - ref,
                                         vertices[static_cast<std::size_t>(tri[2])] - ref};
    const Vec3 cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    const double len = cross.norm();
    if (len == 0) continue;  // zero area: nothing to add
    const Vec3 n = cross / len;
    const double w = -n.dot(corners[0]);
    // γ the axis the normal leans most along, so that 1 / n_γ stays ≤ √3; (α, β, γ) right-handed.
    const int C = largestAxis(n.cwiseAbs());
    const int A = (C + 1) % 3, B = (A + 1) % 3;
    const FaceIntegrals f = faceIntegrals(corners, n, w, A, B, C);
    T0 += n[0] * (A == 0 ? f.Fa : B == 0 ? f.Fb : f.Fc);
    T1[A] += n[A] * f.Faa;
    T1[B] += n[B] * f.Fbb;
    T1[C] += n[C] * f.Fcc;
    T2[A] += n[A] * f.Faaa;
    T2[B] += n[B] * f.Fbbb;
    T2[C] += n[C] * f.Fccc;
    TP[A] += n[A] * f.Faab;
    TP[B] += n[B] * f.Fbbc;
    TP[C] += n[C] * f.Fcca;
  }
  T1 /= 2;
  T2 /= 3;
  TP /= 2;

  // Mirtich 1996, mass parameters: mass, centre and inertia about the (shifted) origin from the volume
  // integrals, then moved to the centre of mass (parallel axis theorem).
  MassProperties mp;
  mp.volume = T0;
  mp.mass = density * T0;
  const Vec3 r = T0 != 0 ? Vec3(T1 / T0) : Vec3::Zero();  // centre of mass about ref, m
  mp.center_of_mass = ref + r;
  Mat3 I;  // kg·m², about ref
  I(0, 0) = density * (T2.y() + T2.z());
  I(1, 1) = density * (T2.z() + T2.x());
  I(2, 2) = density * (T2.x() + T2.y());
  I(0, 1) = I(1, 0) = -density * TP.x();
  I(1, 2) = I(2, 1) = -density * TP.y();
  I(2, 0) = I(0, 2) = -density * TP.z();
  mp.inertia = I - mp.mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  return mp;
}

Result<MassProperties> solidMassProperties(const TriMesh& mesh, double density) {
  if (!(density > 0) || !std::isfinite(density))
    return badInput("the density must be positive and finite, not " + formatNumber(density, 6));
  const std::size_t nv = mesh.vertexCount(), nt = mesh.triangleCount();
  if (mesh.positions.size() != 3 * nv || mesh.indices.size() != 3 * nt)
    return badInput("the mesh's positions or indices are not whole triples");
  if (nt == 0) return badInput("the mesh has no triangles");
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (!std::isfinite(mesh.positions[i]))
      return badInput("the mesh has a non-finite position (vertex " + std::to_string(i / 3) + ")");
  for (std::size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= nv)
      return badInput("the mesh's triangle " + std::to_string(i / 3) + " indexes vertex " +
                      std::to_string(mesh.indices[i]) + " of " + std::to_string(nv));

  // Weld: vertices at exactly the same position become one, numbered in order of first appearance.
  std::vector<std::uint32_t> byPos(nv);  // vertex indices sorted by position (x, then y, then z)
  std::iota(byPos.begin(), byPos.end(), 0u);
  const auto pos = [&](std::uint32_t i) {
    return std::array<float, 3>{mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]};
  };
  std::sort(byPos.begin(), byPos.end(), [&](std::uint32_t a, std::uint32_t b) {
    const auto pa = pos(a), pb = pos(b);
    return pa != pb ? pa < pb : a < b;
  });
  std::vector<std::uint32_t> first(nv);  // per vertex, the lowest index at its position
  for (std::size_t i = 0; i < nv;) {
    std::size_t j = i;
    while (j < nv && pos(byPos[j]) == pos(byPos[i])) ++j;
    for (std::size_t k = i; k < j; ++k) first[byPos[k]] = byPos[i];
    i = j;
  }
  std::vector<int> welded(nv, -1);  // per original vertex, its welded index
  std::vector<Vec3> verts;          // welded positions, m
  for (std::size_t i = 0; i < nv; ++i) {
    if (first[i] == i) {
      welded[i] = static_cast<int>(verts.size());
      const auto p = pos(static_cast<std::uint32_t>(i));
      verts.emplace_back(p[0], p[1], p[2]);
    } else {
      welded[i] = welded[first[i]];
    }
  }
  std::vector<std::array<int, 3>> tris(nt);  // welded corner indices per triangle, counter-clockwise
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      tris[t][static_cast<std::size_t>(k)] = welded[mesh.indices[3 * t + static_cast<std::size_t>(k)]];
  const auto corners = [&](std::size_t t) {
    return std::array<Vec3, 3>{verts[static_cast<std::size_t>(tris[t][0])], verts[static_cast<std::size_t>(tris[t][1])],
                               verts[static_cast<std::size_t>(tris[t][2])]};
  };

  // Zero area: two corners at one position, or all three on a line (to rounding).
  std::size_t degenerate = 0, firstDegenerate = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto c = corners(t);
    const double longest =
        std::max({(c[1] - c[0]).squaredNorm(), (c[2] - c[1]).squaredNorm(), (c[0] - c[2]).squaredNorm()});
    const bool zero = tris[t][0] == tris[t][1] || tris[t][1] == tris[t][2] || tris[t][2] == tris[t][0] ||
                      (c[1] - c[0]).cross(c[2] - c[0]).norm() <= 1e-12 * longest;
    if (zero && degenerate++ == 0) firstDegenerate = t;
  }
  if (degenerate > 0) {
    const auto c = corners(firstDegenerate);
    return badInput("the mesh has " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
                    (degenerate == 1 ? "" : "s") + " (first triangle " + std::to_string(firstDegenerate) +
                    ", corners " + formatPoint(c[0]) + ", " + formatPoint(c[1]) + ", " + formatPoint(c[2]) + ")");
  }

  // Closed and consistently wound: each undirected edge used exactly twice, once each way.
  std::vector<DirectedEdge> edges;  // three per triangle, sorted by (lo, hi)
  edges.reserve(3 * nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = tris[t][static_cast<std::size_t>(k)], v = tris[t][static_cast<std::size_t>((k + 1) % 3)];
      edges.push_back({std::min(u, v), std::max(u, v), static_cast<int>(t), u < v});
    }
  std::sort(edges.begin(), edges.end(), [](const DirectedEdge& a, const DirectedEdge& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.tri < b.tri;
  });
  std::size_t open = 0, shared = 0, sameWay = 0;  // edges with one triangle, more than two, two wound alike
  std::pair<int, int> openAt{}, sharedAt{}, sameWayAt{};
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i, forward = 0;
    for (; j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi; ++j)
      forward += edges[j].forward;
    const std::size_t count = j - i;
    const std::pair<int, int> at{edges[i].lo, edges[i].hi};
    if (count == 1 && open++ == 0) openAt = at;
    if (count > 2 && shared++ == 0) sharedAt = at;
    if (count == 2 && forward != 1 && sameWay++ == 0) sameWayAt = at;
    i = j;
  }
  const auto between = [&](std::pair<int, int> e) {
    return "between vertices " + formatPoint(verts[static_cast<std::size_t>(e.first)]) + " and " +
           formatPoint(verts[static_cast<std::size_t>(e.second)]);
  };
  std::vector<std::string> edgeProblems;  // one line per kind of bad edge
  if (open > 0)
    edgeProblems.push_back("the mesh is not closed: " + std::to_string(open) +
                           (open == 1 ? " edge belongs" : " edges belong") + " to one triangle only (first " +
                           between(openAt) + ")");
  if (shared > 0)
    edgeProblems.push_back("the mesh is not a closed surface: " + std::to_string(shared) +
                           (shared == 1 ? " edge is" : " edges are") + " shared by more than two triangles (first " +
                           between(sharedAt) + ")");
  if (sameWay > 0)
    edgeProblems.push_back("the mesh's triangles wind inconsistently: " + std::to_string(sameWay) +
                           (sameWay == 1 ? " edge joins" : " edges each join") +
                           " two triangles that run along it the same way (first " + between(sameWayAt) + ")");
  if (!edgeProblems.empty()) return Error(ErrorKind::BadInput, std::move(edgeProblems));

  // Shells: triangles connected through shared vertices, each with its signed volume (the signed
  // tetrahedra from the centre of the bounds to its triangles, summed), m³.
  std::vector<int> parent(verts.size());  // union–find over welded vertices
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& t : tris)
    for (int k = 1; k < 3; ++k) {
      unite(parent, t[0], t[static_cast<std::size_t>(k)]);
    }
  Vec3 lo = verts[0], hi = verts[0];
  for (const Vec3& v : verts) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Vec3 mid = (lo + hi) / 2;
  std::vector<int> shellOf(nt);                   // per triangle, its shell's index
  std::vector<int> shellIndex(verts.size(), -1);  // per root vertex, its shell's index
  std::vector<double> shellVolume;                // per shell, signed volume, m³
  std::vector<std::size_t> shellFirst;            // per shell, its first triangle
  double total = 0;                               // m³
  for (std::size_t t = 0; t < nt; ++t) {
    const auto root = static_cast<std::size_t>(findRoot(parent, tris[t][0]));
    if (shellIndex[root] < 0) {
      shellIndex[root] = static_cast<int>(shellVolume.size());
      shellVolume.push_back(0);
      shellFirst.push_back(t);
    }
    shellOf[t] = shellIndex[root];
    const auto c = corners(t);
    const double v = (c[0] - mid).dot((c[1] - mid).cross(c[2] - mid)) / 6;
    shellVolume[static_cast<std::size_t>(shellOf[t])] += v;
    total += v;
  }
  const std::string insideOut =
      "the mesh is inside out (its signed volume is negative): its triangles wind clockwise seen from outside";
  if (total < 0) return badInput(insideOut);
  if (total == 0) return badInput("the mesh encloses no volume");

  // Self-intersection: sweep and prune along the bounds' longest axis (triangle boxes sorted by
  // their low end; each box meets the following ones until their low end passes its high end),
  // then the two other axes, then the exact-sign test for pairs that share no vertex.
  const int axis = largestAxis(hi - lo), o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
  std::vector<SweepBox> boxes(nt);  // per triangle, its bounds; then sorted by lo
  for (std::size_t t = 0; t < nt; ++t) {
    const auto c = corners(t);
    const Vec3 bl = c[0].cwiseMin(c[1]).cwiseMin(c[2]), bh = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
    boxes[t] = {bl[axis], bh[axis], bl[o1], bh[o1], bl[o2], bh[o2], static_cast<std::uint32_t>(t)};
  }
  std::sort(boxes.begin(), boxes.end(),
            [](const SweepBox& a, const SweepBox& b) { return a.lo != b.lo ? a.lo < b.lo : a.tri < b.tri; });
  std::size_t crossings = 0;
  std::pair<std::uint32_t, std::uint32_t> firstCrossing{0, 0};
  for (std::size_t i = 0; i < nt; ++i) {
    const SweepBox& a = boxes[i];
    for (std::size_t j = i + 1; j < nt && boxes[j].lo <= a.hi; ++j) {
      const SweepBox& b = boxes[j];
      if (a.hi1 < b.lo1 || b.hi1 < a.lo1 || a.hi2 < b.lo2 || b.hi2 < a.lo2) continue;
      bool adjacent = false;
      for (int u : tris[a.tri])
        for (int v : tris[b.tri]) adjacent = adjacent || u == v;
      if (adjacent || !trianglesCross(corners(a.tri), corners(b.tri))) continue;
      const std::pair<std::uint32_t, std::uint32_t> pair{std::min(a.tri, b.tri), std::max(a.tri, b.tri)};
      if (crossings++ == 0 || pair < firstCrossing) firstCrossing = pair;
    }
  }
  if (crossings > 0)
    return badInput("the mesh intersects itself: triangles " + std::to_string(firstCrossing.first) + " and " +
                    std::to_string(firstCrossing.second) + " cross" +
                    (crossings == 1 ? std::string() : " (" + std::to_string(crossings) + " crossing pairs in all)"));

  // With several shells, each must wind by what surrounds it: a shell in empty space (the winding
  // number of the other shells there 0) outward, a cavity inside material (1) inward. The winding
  // number at a point of the shell's largest triangles, from the other shells whose bounds hold it.
  if (shellVolume.size() > 1) {
    const std::size_t shells = shellVolume.size();
    std::vector<Vec3> shellLo(shells, Vec3::Constant(INFINITY)), shellHi(shells, Vec3::Constant(-INFINITY));  // m
    std::vector<std::vector<std::uint32_t>> members(shells);  // per shell, its triangles
    for (std::size_t t = 0; t < nt; ++t) {
      const auto s = static_cast<std::size_t>(shellOf[t]);
      for (const Vec3& c : corners(t)) {
        shellLo[s] = shellLo[s].cwiseMin(c);
        shellHi[s] = shellHi[s].cwiseMax(c);
      }
      members[s].push_back(static_cast<std::uint32_t>(t));
    }
    for (std::size_t s = 0; s < shells; ++s) {
      // Try the shell's largest triangles' centroids until one is clear of the others' surfaces.
      std::vector<std::uint32_t> byArea = members[s];
      const auto area2 = [&](std::uint32_t t) {
        const auto c = corners(t);
        return (c[1] - c[0]).cross(c[2] - c[0]).squaredNorm();
      };
      std::stable_sort(byArea.begin(), byArea.end(),
                       [&](std::uint32_t a, std::uint32_t b) { return area2(a) > area2(b); });
      int winding = 0;
      bool clear = false;
      for (std::size_t k = 0; k < std::min<std::size_t>(byArea.size(), 8) && !clear; ++k) {
        const auto c = corners(byArea[k]);
        const Vec3 p = (c[0] + c[1] + c[2]) / 3;
        double angle = 0;  // sr
        for (std::size_t o = 0; o < shells; ++o) {
          if (o == s || (p.array() < shellLo[o].array()).any() || (p.array() > shellHi[o].array()).any()) continue;
          for (const std::uint32_t t : members[o]) {
            const auto q = corners(t);
            angle += solidAngle(q[0] - p, q[1] - p, q[2] - p);
          }
        }
        const double w = angle / (4 * kPi);
        winding = static_cast<int>(std::lround(w));
        clear = std::abs(w - winding) < 0.1;
      }
      const std::string which = "the shell of triangle " + std::to_string(shellFirst[s]) + " (" +
                                std::to_string(members[s].size()) + " triangles)";
      if (shellVolume[s] == 0) return badInput("the mesh has a shell that encloses no volume: " + which);
      if (!clear) continue;  // touches the others wherever tried: no verdict
      const bool outward = shellVolume[s] > 0;
      if (outward && winding == 0) continue;
      if (!outward && winding == 1) continue;
      if (!outward && winding == 0)
        return badInput("the mesh is inside out in part: " + which +
                        " has a negative signed volume in empty space: it winds clockwise seen from outside");
      if (outward && winding == 1)
        return badInput("the mesh's shells nest wrongly: " + which +
                        " lies inside the solid and winds outward, so its volume would count twice (a cavity winds "
                        "clockwise seen from outside it)");
      return badInput("the mesh's shells nest wrongly: " + which + " lies where the other shells wind " +
                      std::to_string(winding) + " times");
    }
  }

  return polyhedronMass(verts, tris, density);
}

// Closed forms (standard results): a solid sphere I = 2/5 m r²; a box I_xx = m (y² + z²) / 12.
MassProperties sphereMass(double r, double density) {
  MassProperties mp;
  mp.volume = 4.0 / 3.0 * kPi * r * r * r;
  mp.mass = density * mp.volume;
  mp.inertia = Mat3::Identity() * (0.4 * mp.mass * r * r);
  return mp;
}

MassProperties boxMass(const Vec3& size, double density) {
  MassProperties mp;
  mp.volume = size.x() * size.y() * size.z();
  mp.mass = density * mp.volume;
  const Vec3 s2 = size.cwiseProduct(size);  // m²
  mp.inertia.diagonal() = mp.mass / 12 * Vec3(s2.y() + s2.z(), s2.z() + s2.x(), s2.x() + s2.y());
  return mp;
}

// A solid cylinder along y: I_yy = m r² / 2, I_xx = I_zz = m (3 r² + H²) / 12.
MassProperties cylinderMass(double r, double height, double density) {
  MassProperties mp;
  mp.volume = kPi * r * r * height;
  mp.mass = density * mp.volume;
  const double across = mp.mass * (3 * r * r + height * height) / 12;
  mp.inertia.diagonal() = Vec3(across, 0.5 * mp.mass * r * r, across);
  return mp;
}

// The cylinder plus two hemispheres. A hemisphere of mass m_h has I = 2/5 m_h r² about any axis
// through its flat face's centre; its centre of mass lies 3r/8 from that face, so about its own
// centre the cross-axis moment is (2/5 − 9/64) m_h r² = 83/320 m_h r², then moved out by
// L/2 + 3r/8 to the capsule's centre (parallel axis theorem). Along y, 2/5 m_h r² each.
MassProperties capsuleMass(double length, double r, double density) {
  const MassProperties cyl = cylinderMass(r, length, density);
  const double hemiVolume = 2.0 / 3.0 * kPi * r * r * r;  // m³
  const double mh = density * hemiVolume;                 // kg
  const double d = length / 2 + 3 * r / 8;                // m, capsule centre to hemisphere centre of mass
  const double hemiAcross = 83.0 / 320.0 * mh * r * r + mh * d * d;
  const double hemiAlong = 0.4 * mh * r * r;
  MassProperties mp;
  mp.volume = cyl.volume + 2 * hemiVolume;
  mp.mass = density * mp.volume;
  mp.inertia = cyl.inertia;
  mp.inertia.diagonal() += 2 * Vec3(hemiAcross, hemiAlong, hemiAcross);
  return mp;
}

MassProperties placed(MassProperties m, const Mat3& R, const Vec3& t) {
  m.center_of_mass = R * m.center_of_mass + t;
  m.inertia = R * m.inertia * R.transpose();
  return m;
}

MassProperties combined(std::span<const MassProperties> parts) {
  MassProperties s;
  for (const MassProperties& p : parts) {
    s.volume += p.volume;
    s.mass += p.mass;
    s.center_of_mass += p.mass * p.center_of_mass;
  }
  s.center_of_mass /= s.mass;
  for (const MassProperties& p : parts) {
    const Vec3 d = p.center_of_mass - s.center_of_mass;
    s.inertia += p.inertia + p.mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
  }
  return s;
}

MassProperties withMass(MassProperties m, double mass) {
  m.inertia *= mass / m.mass;
  m.mass = mass;
  return m;
}

}  // namespace reel
