#include "sim/rigid/hull.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <utility>

#include "core/math.h"
#include "core/union_find.h"

namespace reel {

namespace {

using Index = std::size_t;

// Unit normal and offset of the plane through a face's loop: Newell's method (a sum over the
// loop's edges, exact for a planar polygon and a best fit for a nearly planar one); the offset
// puts every loop vertex on or below the plane.
void fitFacePlane(const std::vector<Vec3>& v, ConvexPolytope::Face& f) {
  Vec3 n(0, 0, 0);
  const Index m = f.loop.size();
  for (Index k = 0; k < m; ++k) {
    const Vec3& p = v[static_cast<Index>(f.loop[k])];
    const Vec3& q = v[static_cast<Index>(f.loop[(k + 1) % m])];
    n += Vec3((p.y() - q.y()) * (p.z() + q.z()), (p.z() - q.z()) * (p.x() + q.x()),
              (p.x() - q.x()) * (p.y() + q.y()));
  }
  f.normal = unitOr(n, Vec3(0, 1, 0));
  f.offset = -std::numeric_limits<double>::infinity();
  for (const int i : f.loop) f.offset = std::max(f.offset, f.normal.dot(v[static_cast<Index>(i)]));
}

}  // namespace

void finishPolytope(ConvexPolytope& poly) {
  // Every directed loop edge and its face; a closed polytope has each edge once in each direction
  std::map<std::pair<int, int>, int> directed;
  for (Index f = 0; f < poly.faces.size(); ++f) {
    const auto& loop = poly.faces[f].loop;
    for (Index k = 0; k < loop.size(); ++k)
      directed[{loop[k], loop[(k + 1) % loop.size()]}] = static_cast<int>(f);
  }
  // The edges in the order of their smaller vertex, when not given
  if (poly.edges.empty())
    for (const auto& [e, f] : directed)
      if (e.first < e.second) poly.edges.push_back({e.first, e.second});
  // The faces on either side of each edge (−1 where a hand-made polytope is open)
  poly.edge_faces.assign(poly.edges.size(), {-1, -1});
  for (Index e = 0; e < poly.edges.size(); ++e) {
    const auto [i, j] = poly.edges[e];
    if (auto it = directed.find({i, j}); it != directed.end()) poly.edge_faces[e][0] = it->second;
    if (auto it = directed.find({j, i}); it != directed.end()) poly.edge_faces[e][1] = it->second;
  }
}

ConvexPolytope boxPolytope(const Vec3& half) {
  ConvexPolytope p;
  // Vertex i has bit 0, 1, 2 set for the +x, +y, +z side
  for (int i = 0; i < 8; ++i)
    p.vertices.emplace_back((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                            (i & 4) ? half.z() : -half.z());
  // Faces +x, −x, +y, −y, +z, −z, loops counter-clockwise seen from outside
  const int loops[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3},
                           {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const double sign = (f % 2 == 0) ? 1.0 : -1.0;
    Vec3 n(0, 0, 0);
    n[axis] = sign;
    p.faces.push_back({n, half[axis], {loops[f][0], loops[f][1], loops[f][2], loops[f][3]}});
  }
  finishPolytope(p);
  return p;
}

ConvexPolytope prismPolytope(double radius, double half_height, int sides) {
  ConvexPolytope p;
  const int n = std::max(sides, 3);
  // Bottom ring 0..n−1, top ring n..2n−1, at angles 2πi/n from +x toward +z
  for (int ring = 0; ring < 2; ++ring)
    for (int i = 0; i < n; ++i) {
      const double th = 2 * kPi * i / n;
      p.vertices.emplace_back(radius * std::cos(th), ring ? half_height : -half_height,
                              radius * std::sin(th));
    }
  // Caps: increasing angle turns about −y, so the bottom walks up the angles and the top down
  ConvexPolytope::Face bottom{Vec3(0, -1, 0), half_height, {}}, top{Vec3(0, 1, 0), half_height, {}};
  for (int i = 0; i < n; ++i) {
    bottom.loop.push_back(i);
    top.loop.push_back(n + (n - i) % n);
  }
  p.faces.push_back(std::move(top));
  p.faces.push_back(std::move(bottom));
  // Side i between angles i and i + 1: bottom i, top i, top i + 1, bottom i + 1
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const double mid = 2 * kPi * (i + 0.5) / n;
    p.faces.push_back({Vec3(std::cos(mid), 0, std::sin(mid)), radius * std::cos(kPi / n),
                       {i, n + i, n + j, j}});
  }
  finishPolytope(p);
  return p;
}

ConvexPolytope trianglePolytope(const Vec3& a, const Vec3& b, const Vec3& c) {
  ConvexPolytope p;
  p.vertices = {a, b, c};
  const Vec3 n = unitOr((b - a).cross(c - a), Vec3(0, 1, 0));
  const double off = n.dot(a + b + c) / 3;
  p.faces.push_back({n, off, {0, 1, 2}});
  p.faces.push_back({-n, -off, {0, 2, 1}});
  p.edges = {{0, 1}, {1, 2}, {0, 2}};
  finishPolytope(p);
  return p;
}

namespace {

// A hull triangle during quickhull: counter-clockwise from outside, its plane, and the points
// above it that are not yet on the hull.
struct HullTri {
  std::array<int, 3> v;
  Vec3 n;
  double off;
  bool alive = true;
  std::vector<int> outside;  // point indices
};

}  // namespace

std::optional<ConvexPolytope> convexHull(std::span<const Vec3> points) {
  const int count = static_cast<int>(points.size());
  if (count < 4) return std::nullopt;
  auto P = [&](int i) -> const Vec3& { return points[static_cast<Index>(i)]; };

  // Extent and tolerances: a point less than `eps` above a face is on it; a hull thinner than
  // `flat` has no volume; triangles whose far vertices lie within `coplanar` of each other's
  // planes are one face
  Vec3 lo = P(0), hi = P(0);
  for (int i = 1; i < count; ++i) {
    lo = lo.cwiseMin(P(i));
    hi = hi.cwiseMax(P(i));
  }
  const double extent = (hi - lo).norm();
  if (!(extent > 0) || !std::isfinite(extent)) return std::nullopt;
  const double eps = 1e-10 * extent, flat = 1e-6 * extent, coplanar = 1e-6 * extent;

  // Initial tetrahedron: the two extreme points along the axes farthest apart, the point farthest
  // from their line, the point farthest from the plane of the three
  std::array<int, 6> ext{0, 0, 0, 0, 0, 0};
  for (int i = 1; i < count; ++i)
    for (int ax = 0; ax < 3; ++ax) {
      if (P(i)[ax] < P(ext[2 * ax])[ax]) ext[2 * ax] = i;
      if (P(i)[ax] > P(ext[2 * ax + 1])[ax]) ext[2 * ax + 1] = i;
    }
  int i0 = ext[0], i1 = ext[1];
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b)
      if ((P(ext[a]) - P(ext[b])).squaredNorm() > (P(i0) - P(i1)).squaredNorm()) {
        i0 = ext[a];
        i1 = ext[b];
      }
  const Vec3 axis = (P(i1) - P(i0)).normalized();
  int i2 = -1;
  double best = -1;
  for (int i = 0; i < count; ++i) {
    const Vec3 d = P(i) - P(i0);
    const double off_line = (d - d.dot(axis) * axis).norm();
    if (off_line > best) best = off_line, i2 = i;
  }
  if (best < flat) return std::nullopt;  // collinear
  const Vec3 base_n = (P(i1) - P(i0)).cross(P(i2) - P(i0)).normalized();
  int i3 = -1;
  best = -1;
  for (int i = 0; i < count; ++i) {
    const double h = std::abs(base_n.dot(P(i) - P(i0)));
    if (h > best) best = h, i3 = i;
  }
  if (best < flat) return std::nullopt;  // coplanar

  // Triangles, and every directed edge's triangle (each edge of the closed hull once each way)
  std::vector<HullTri> tris;
  std::map<std::pair<int, int>, int> edge_tri;
  auto addTri = [&](int a, int b, int c) {
    HullTri t;
    t.v = {a, b, c};
    t.n = unitOr((P(b) - P(a)).cross(P(c) - P(a)), Vec3(0, 1, 0));
    t.off = t.n.dot(P(a));
    const int id = static_cast<int>(tris.size());
    for (int k = 0; k < 3; ++k) edge_tri[{t.v[static_cast<Index>(k)], t.v[static_cast<Index>((k + 1) % 3)]}] = id;
    tris.push_back(std::move(t));
    return id;
  };
  auto above = [&](const HullTri& t, int i) { return t.n.dot(P(i)) - t.off; };
  // The triangle across directed edge a→b (−1: the hull broke down, which rounding can do to
  // nearly degenerate input)
  auto across = [&](int a, int b) {
    const auto it = edge_tri.find({b, a});
    return it == edge_tri.end() ? -1 : it->second;
  };

  // The tetrahedron's faces, each turned away from the vertex opposite it
  const std::array<int, 4> tet{i0, i1, i2, i3};
  for (int skip = 3; skip >= 0; --skip) {
    std::array<int, 3> f{};
    int k = 0;
    for (int j = 0; j < 4; ++j)
      if (j != skip) f[static_cast<Index>(k++)] = tet[static_cast<Index>(j)];
    const Vec3 n = (P(f[1]) - P(f[0])).cross(P(f[2]) - P(f[0]));
    if (n.dot(P(tet[static_cast<Index>(skip)]) - P(f[0])) > 0) std::swap(f[1], f[2]);
    addTri(f[0], f[1], f[2]);
  }
  // Every other point to the first face it lies above (none: inside)
  for (int i = 0; i < count; ++i) {
    if (i == i0 || i == i1 || i == i2 || i == i3) continue;
    for (auto& t : tris)
      if (above(t, i) > eps) {
        t.outside.push_back(i);
        break;
      }
  }

  // Quickhull: the farthest point above a face joins the hull; the faces it sees go, and new
  // faces join it to the horizon (the edges between seen and unseen faces)
  std::vector<char> state;           // per triangle: 0 untested, 1 seen, 2 not seen
  std::vector<int> seen, stack;      // triangle indices
  std::vector<std::pair<int, int>> horizon;  // directed edges of seen triangles
  for (Index f = 0; f < tris.size(); ++f) {
    while (tris[f].alive && !tris[f].outside.empty()) {
      // The farthest point above this face
      int eye = tris[f].outside[0];
      for (const int i : tris[f].outside)
        if (above(tris[f], i) > above(tris[f], eye)) eye = i;
      // Faces seen from it: a flood fill from this face over edges
      state.assign(tris.size(), 0);
      seen.clear();
      horizon.clear();
      stack.assign(1, static_cast<int>(f));
      state[f] = 1;
      while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        seen.push_back(t);
        for (int k = 0; k < 3; ++k) {
          const int a = tris[static_cast<Index>(t)].v[static_cast<Index>(k)];
          const int b = tris[static_cast<Index>(t)].v[static_cast<Index>((k + 1) % 3)];
          const int u = across(a, b);
          if (u < 0) return std::nullopt;
          char& s = state[static_cast<Index>(u)];
          if (s == 0) {
            s = above(tris[static_cast<Index>(u)], eye) > eps ? 1 : 2;
            if (s == 1) stack.push_back(u);
          }
          if (s == 2) horizon.emplace_back(a, b);
        }
      }
      // Remove the seen faces, keeping their points
      std::vector<int> orphans;
      for (const int t : seen) {
        HullTri& tri = tris[static_cast<Index>(t)];
        tri.alive = false;
        for (int k = 0; k < 3; ++k) {
          const auto key = std::make_pair(tri.v[static_cast<Index>(k)], tri.v[static_cast<Index>((k + 1) % 3)]);
          if (auto it = edge_tri.find(key); it != edge_tri.end() && it->second == t) edge_tri.erase(it);
        }
        for (const int i : tri.outside)
          if (i != eye) orphans.push_back(i);
        tri.outside.clear();
        tri.outside.shrink_to_fit();
      }
      // A face from each horizon edge to the eye; the orphaned points to the first new face they
      // lie above
      const int first_new = static_cast<int>(tris.size());
      for (const auto& [a, b] : horizon) addTri(a, b, eye);
      std::sort(orphans.begin(), orphans.end());
      for (const int i : orphans)
        for (Index t = static_cast<Index>(first_new); t < tris.size(); ++t)
          if (above(tris[t], i) > eps) {
            tris[t].outside.push_back(i);
            break;
          }
    }
  }

  // Coplanar neighbours merge into one face (union–find over the live triangles)
  std::vector<int> parent(tris.size());
  for (Index t = 0; t < tris.size(); ++t) parent[t] = static_cast<int>(t);
  for (Index t = 0; t < tris.size(); ++t) {
    if (!tris[t].alive) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = tris[t].v[static_cast<Index>(k)], b = tris[t].v[static_cast<Index>((k + 1) % 3)];
      const int u = across(a, b);
      if (u < 0) return std::nullopt;
      if (u < static_cast<int>(t)) continue;
      const HullTri& o = tris[static_cast<Index>(u)];
      const int far_t = tris[t].v[static_cast<Index>((k + 2) % 3)];
      int far_o = o.v[0];
      for (const int w : o.v)
        if (w != a && w != b) far_o = w;
      if (std::abs(above(tris[t], far_o)) <= coplanar && std::abs(above(o, far_t)) <= coplanar)
        unite(parent, static_cast<int>(t), u);
    }
  }

  // Each group's boundary (directed edges whose twin is in another group) walked into one loop
  std::vector<char> walked(tris.size(), 0);  // per root triangle
  std::vector<std::vector<int>> loops;
  for (Index t = 0; t < tris.size(); ++t) {
    if (!tris[t].alive) continue;
    const int root = findRoot(parent, static_cast<int>(t));
    if (walked[static_cast<Index>(root)]) continue;
    walked[static_cast<Index>(root)] = 1;
    std::map<int, int> next;  // boundary: start vertex → end vertex
    for (Index s = t; s < tris.size(); ++s) {
      if (!tris[s].alive || findRoot(parent, static_cast<int>(s)) != root) continue;
      for (int k = 0; k < 3; ++k) {
        const int a = tris[s].v[static_cast<Index>(k)], b = tris[s].v[static_cast<Index>((k + 1) % 3)];
        if (findRoot(parent, across(a, b)) != root) next[a] = b;
      }
    }
    if (next.empty()) return std::nullopt;  // every triangle in one group: no solid
    std::vector<int> loop;
    const int start = tris[t].v[0];
    int at = next.count(start) ? start : next.begin()->first;
    const int first = at;
    do {
      loop.push_back(at);
      at = next.at(at);
    } while (at != first && loop.size() <= next.size());
    loops.push_back(std::move(loop));
  }

  // Corners: vertices on at least three faces (one on a face or along an edge is not a corner)
  std::vector<int> faces_at(static_cast<Index>(count), 0);
  for (const auto& loop : loops)
    for (const int i : loop) ++faces_at[static_cast<Index>(i)];
  std::vector<int> new_index(static_cast<Index>(count), -1);
  ConvexPolytope poly;
  for (int i = 0; i < count; ++i)
    if (faces_at[static_cast<Index>(i)] >= 3) {
      new_index[static_cast<Index>(i)] = static_cast<int>(poly.vertices.size());
      poly.vertices.push_back(P(i));
    }
  for (const auto& loop : loops) {
    ConvexPolytope::Face face{Vec3(0, 1, 0), 0.0, {}};
    for (const int i : loop)
      if (new_index[static_cast<Index>(i)] >= 0) face.loop.push_back(new_index[static_cast<Index>(i)]);
    if (face.loop.size() < 3) continue;
    fitFacePlane(poly.vertices, face);
    poly.faces.push_back(std::move(face));
  }
  finishPolytope(poly);
  return poly;
}

}  // namespace reel
