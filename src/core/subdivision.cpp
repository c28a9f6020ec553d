#include "core/subdivision.h"

#include <algorithm>
#include <map>

#include "core/error.h"

namespace reel {
namespace {

// A point as weights of the control points, sorted by control index.
using Stencil = std::vector<std::pair<std::uint32_t, double>>;

Stencil combine(std::initializer_list<std::pair<const Stencil*, double>> terms) {
  Stencil out;
  for (const auto& [s, w] : terms)
    for (const auto& [i, v] : *s) out.emplace_back(i, v * w);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Stencil merged;
  for (const auto& e : out) {
    if (!merged.empty() && merged.back().first == e.first) merged.back().second += e.second;
    else merged.push_back(e);
  }
  return merged;
}

// Σ w_k·s_k over a list (for the means over a vertex's faces and edges).
Stencil sum(const std::vector<std::pair<const Stencil*, double>>& terms) {
  Stencil acc;
  for (const auto& t : terms) acc = combine({{&acc, 1.0}, {t.first, t.second}});
  return acc;
}

struct Edge {
  std::uint32_t a, b;
  std::vector<std::uint32_t> faces;
};

// One level of the paper's rules; `v` and `quads` are replaced by the refined ones.
void refine(std::vector<Stencil>& v, std::vector<std::array<std::uint32_t, 4>>& quads) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_of;
  std::vector<Edge> edges;
  auto edgeIndex = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, fresh] = edge_of.emplace(key, static_cast<std::uint32_t>(edges.size()));
    if (fresh) edges.push_back({key.first, key.second, {}});
    return it->second;
  };
  std::vector<std::array<std::uint32_t, 4>> quad_edges(quads.size());
  for (std::size_t f = 0; f < quads.size(); ++f)
    for (int i = 0; i < 4; ++i) {
      const std::uint32_t e = edgeIndex(quads[f][i], quads[f][(i + 1) % 4]);
      edges[e].faces.push_back(static_cast<std::uint32_t>(f));
      quad_edges[f][i] = e;
    }
  const std::size_t nv = v.size(), ne = edges.size();
  std::vector<Stencil> face_pt(quads.size()), edge_pt(ne), vertex_pt(nv);
  for (std::size_t f = 0; f < quads.size(); ++f) {
    const auto& q = quads[f];
    face_pt[f] = combine({{&v[q[0]], 0.25}, {&v[q[1]], 0.25}, {&v[q[2]], 0.25}, {&v[q[3]], 0.25}});
  }
  std::vector<std::vector<std::uint32_t>> vertex_edges(nv), vertex_faces(nv);
  for (std::size_t e = 0; e < ne; ++e) {
    const Edge& E = edges[e];
    if (E.faces.size() == 2)
      edge_pt[e] = combine({{&v[E.a], 0.25}, {&v[E.b], 0.25}, {&face_pt[E.faces[0]], 0.25}, {&face_pt[E.faces[1]], 0.25}});
    else
      edge_pt[e] = combine({{&v[E.a], 0.5}, {&v[E.b], 0.5}});
    vertex_edges[E.a].push_back(static_cast<std::uint32_t>(e));
    vertex_edges[E.b].push_back(static_cast<std::uint32_t>(e));
  }
  for (std::size_t f = 0; f < quads.size(); ++f)
    for (std::uint32_t c : quads[f]) vertex_faces[c].push_back(static_cast<std::uint32_t>(f));
  for (std::size_t p = 0; p < nv; ++p) {
    const auto& es = vertex_edges[p];
    std::vector<std::uint32_t> border;
    for (std::uint32_t e : es)
      if (edges[e].faces.size() < 2) border.push_back(edges[e].a == p ? edges[e].b : edges[e].a);
    if (es.empty() || (!border.empty() && border.size() != 2)) {
      vertex_pt[p] = v[p];  // unused, or a corner of an open mesh: kept
    } else if (border.size() == 2) {
      vertex_pt[p] = combine({{&v[p], 0.75}, {&v[border[0]], 0.125}, {&v[border[1]], 0.125}});
    } else {
      const double n = static_cast<double>(es.size());
      std::vector<std::pair<const Stencil*, double>> terms;
      for (std::uint32_t f : vertex_faces[p]) terms.emplace_back(&face_pt[f], 1.0 / (n * static_cast<double>(vertex_faces[p].size())));
      // 2R/n with R the mean of the edges' midpoints: each edge gives (P + Q)/2 · 2/n².
      for (std::uint32_t e : es) {
        const std::uint32_t o = edges[e].a == p ? edges[e].b : edges[e].a;
        terms.emplace_back(&v[o], 1.0 / (n * n));
      }
      terms.emplace_back(&v[p], n / (n * n) + (n - 3.0) / n);
      vertex_pt[p] = sum(terms);
    }
  }
  std::vector<Stencil> next = std::move(vertex_pt);
  next.insert(next.end(), edge_pt.begin(), edge_pt.end());
  next.insert(next.end(), face_pt.begin(), face_pt.end());
  std::vector<std::array<std::uint32_t, 4>> refined;
  refined.reserve(4 * quads.size());
  const auto E = [&](std::uint32_t e) { return static_cast<std::uint32_t>(nv + e); };
  for (std::size_t f = 0; f < quads.size(); ++f) {
    const std::uint32_t fc = static_cast<std::uint32_t>(nv + ne + f);
    for (int i = 0; i < 4; ++i)
      refined.push_back({quads[f][i], E(quad_edges[f][i]), fc, E(quad_edges[f][(i + 3) % 4])});
  }
  v = std::move(next);
  quads = std::move(refined);
}

}  // namespace

SubdivisionSurface::SubdivisionSurface(int control_points, std::span<const std::array<int, 4>> quads, int levels)
    : control_(control_points) {
  REEL_CHECK(control_points >= 0 && levels >= 0, "subdivision of a negative count");
  std::vector<Stencil> v(static_cast<std::size_t>(control_points));
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = {{static_cast<std::uint32_t>(i), 1.0}};
  std::vector<std::array<std::uint32_t, 4>> q;
  for (const auto& quad : quads) {
    std::array<std::uint32_t, 4> u{};
    for (int i = 0; i < 4; ++i) {
      REEL_CHECK(quad[i] >= 0 && quad[i] < control_points, "a quad names a missing control point");
      u[i] = static_cast<std::uint32_t>(quad[i]);
    }
    q.push_back(u);
  }
  for (int l = 0; l < levels; ++l) refine(v, q);
  // Only the points a quad uses (a lattice's inner nodes are control points of nothing).
  std::vector<std::uint32_t> index(v.size(), UINT32_MAX);
  offsets_ = {0};
  for (const auto& quad : q)
    for (std::uint32_t c : quad) {
      if (index[c] != UINT32_MAX) continue;
      index[c] = static_cast<std::uint32_t>(offsets_.size() - 1);
      for (const auto& [src, w] : v[c]) {
        if (w == 0.0) continue;
        sources_.push_back(src);
        weights_.push_back(w);
      }
      offsets_.push_back(static_cast<std::uint32_t>(sources_.size()));
    }
  for (const auto& quad : q)
    for (int t : {0, 1, 2, 0, 2, 3}) triangles_.push_back(index[quad[static_cast<std::size_t>(t)]]);
}

std::vector<Vec3> SubdivisionSurface::points(std::span<const Vec3> control) const {
  REEL_CHECK(control.size() == static_cast<std::size_t>(control_), "subdivision of another mesh's points");
  std::vector<Vec3> out(pointCount());
  for (std::size_t k = 0; k < out.size(); ++k) {
    Vec3 p = Vec3::Zero();
    for (std::uint32_t j = offsets_[k]; j < offsets_[k + 1]; ++j) p += weights_[j] * control[sources_[j]];
    out[k] = p;
  }
  return out;
}

std::shared_ptr<TriMesh> SubdivisionSurface::mesh(std::span<const Vec3> control, double offset) const {
  const std::vector<Vec3> p = points(control);
  auto m = smoothMesh(p, 0, p.size(), triangles_);
  if (offset != 0.0)
    for (std::size_t i = 0; i < m->positions.size(); ++i) m->positions[i] += static_cast<float>(offset) * m->normals[i];
  return m;
}

}  // namespace reel
