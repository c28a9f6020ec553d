#include "core/isosurface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

#include "core/math.h"
#include "core/parallel.h"

namespace reel {

double GridField::sample(const Vec3& p) const {
  const Vec3 q = (p - origin) / cell;
  const double fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
  if (!(fx >= 0 && fy >= 0 && fz >= 0 && fx < dims[0] - 1 && fy < dims[1] - 1 && fz < dims[2] - 1)) return 0.0;
  const int i = static_cast<int>(fx), j = static_cast<int>(fy), k = static_cast<int>(fz);
  const double tx = q.x() - fx, ty = q.y() - fy, tz = q.z() - fz;
  double s = 0.0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
    s += w * value[index(i + dx, j + dy, k + dz)];
  }
  return s;
}

namespace {

using EdgeVertices = std::unordered_map<std::uint64_t, std::uint32_t>;

// The marching loop over the cube layers [k0, k1), in one piece: its cell, tetrahedron and
// edge-cache steps share their indices, which separate functions would have to pass around. One
// vertex per crossed grid edge, keyed by its two node ids in `edge_vertex`.
void marchSlab(const GridField& f, double iso, int k0, int k1, TriMesh& out, EdgeVertices& edge_vertex) {
  const int nx = f.dims[0], ny = f.dims[1], nz = f.dims[2];
  const bool coloured = f.color.size() == 3 * f.value.size();
  // Gradient at a node by central differences (one-sided at the border).
  auto gradient = [&](int i, int j, int k) {
    auto at = [&](int a, int b, int c) {
      return static_cast<double>(f.value[f.index(std::clamp(a, 0, nx - 1), std::clamp(b, 0, ny - 1), std::clamp(c, 0, nz - 1))]);
    };
    return Vec3(at(i + 1, j, k) - at(i - 1, j, k), at(i, j + 1, k) - at(i, j - 1, k), at(i, j, k + 1) - at(i, j, k - 1));
  };
  auto nodeOf = [&](std::size_t id, int& i, int& j, int& k) {
    i = static_cast<int>(id % static_cast<std::size_t>(nx));
    j = static_cast<int>((id / static_cast<std::size_t>(nx)) % static_cast<std::size_t>(ny));
    k = static_cast<int>(id / (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)));
  };
  auto vertexOn = [&](std::size_t a, std::size_t b) -> std::uint32_t {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint64_t>(b);  // ids < 2³²
    auto [it, fresh] = edge_vertex.try_emplace(key, static_cast<std::uint32_t>(out.vertexCount()));
    if (!fresh) return it->second;
    int ia, ja, ka, ib, jb, kb;
    nodeOf(a, ia, ja, ka);
    nodeOf(b, ib, jb, kb);
    const double va = f.value[a], vb = f.value[b];
    const double t = va != vb ? std::clamp((iso - va) / (vb - va), 0.0, 1.0) : 0.5;
    const Vec3 pa = f.origin + f.cell * Vec3(ia, ja, ka), pb = f.origin + f.cell * Vec3(ib, jb, kb);
    const Vec3 g = (1 - t) * gradient(ia, ja, ka) + t * gradient(ib, jb, kb);
    const double gl = g.norm();
    out.addVertex((1 - t) * pa + t * pb, gl > 0 ? Vec3(-g / gl) : Vec3::UnitY());
    if (coloured)
      for (int c = 0; c < 3; ++c)
        out.colors.push_back(static_cast<float>((1 - t) * f.color[3 * a + c] + t * f.color[3 * b + c]));
    return it->second;
  };
  // Kuhn's six tetrahedra of a cube, corners numbered dx + 2dy + 4dz.
  static constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  auto position = [&](std::size_t id) {
    int i, j, k;
    nodeOf(id, i, j, k);
    return Vec3(f.origin + f.cell * Vec3(i, j, k));
  };
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, const Vec3& outward) {
    auto P = [&](std::uint32_t v) { return Vec3(out.positions[3 * v], out.positions[3 * v + 1], out.positions[3 * v + 2]); };
    const Vec3 n = (P(b) - P(a)).cross(P(c) - P(a));
    if (n.dot(outward) < 0) std::swap(b, c);
    out.indices.insert(out.indices.end(), {a, b, c});
  };
  for (int k = k0; k < k1; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        std::size_t id[8];
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
          id[c] = f.index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          inside += f.value[id[c]] > iso;
        }
        if (inside == 0 || inside == 8) continue;
        for (const auto& tet : kTets) {
          std::size_t in[4], outv[4];
          int ni = 0, no = 0;
          for (int c : tet) (f.value[id[c]] > iso ? in[ni++] : outv[no++]) = id[c];
          if (ni == 0 || no == 0) continue;
          Vec3 ci = Vec3::Zero(), co = Vec3::Zero();
          for (int q = 0; q < ni; ++q) ci += position(in[q]) / ni;
          for (int q = 0; q < no; ++q) co += position(outv[q]) / no;
          const Vec3 outward = co - ci;
          if (ni == 1) {
            emit(vertexOn(in[0], outv[0]), vertexOn(in[0], outv[1]), vertexOn(in[0], outv[2]), outward);
          } else if (ni == 3) {
            emit(vertexOn(outv[0], in[0]), vertexOn(outv[0], in[1]), vertexOn(outv[0], in[2]), outward);
          } else {
            const std::uint32_t a = vertexOn(in[0], outv[0]), b = vertexOn(in[0], outv[1]);
            const std::uint32_t c = vertexOn(in[1], outv[1]), d = vertexOn(in[1], outv[0]);
            emit(a, b, c, outward);
            emit(a, c, d, outward);
          }
        }
      }
}

}  // namespace

// In slabs of cube layers, marched in parallel, each with its own vertices; then joined in slab
// order, a vertex on the node layer two slabs share (its edge's both nodes on that layer) taken
// from the lower slab, which met it first. Vertices and triangles come out in the order one pass
// over the cubes would make them: the same bits on any number of threads.
TriMesh isosurface(const GridField& f, double iso) {
  const int nx = f.dims[0], ny = f.dims[1], nz = f.dims[2];
  if (nx < 2 || ny < 2 || nz < 2) return {};
  const int layers = nz - 1, thick = std::max(2, (layers + 15) / 16), slabs = (layers + thick - 1) / thick;
  std::vector<TriMesh> part(static_cast<std::size_t>(slabs));
  std::vector<EdgeVertices> edges(static_cast<std::size_t>(slabs));
  parallelBlocks(
      slabs, 1,
      [&](std::ptrdiff_t s0, std::ptrdiff_t) {
        const auto s = static_cast<std::size_t>(s0);
        const int k0 = static_cast<int>(s0) * thick;
        marchSlab(f, iso, k0, std::min(layers, k0 + thick), part[s], edges[s]);
      },
      static_cast<std::ptrdiff_t>(f.value.size() / 64));
  const std::size_t per_layer = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  TriMesh out;
  const bool coloured = f.color.size() == 3 * f.value.size();
  std::vector<std::uint32_t> remap, below_remap;  // a slab's vertices in `out`, and the slab below's
  for (std::size_t s = 0; s < part.size(); ++s) {
    const TriMesh& m = part[s];
    remap.assign(m.vertexCount(), 0);
    std::vector<char> shared(m.vertexCount(), 0);
    if (s > 0) {
      // The edges on this slab's bottom node layer: the slab below made their vertices.
      const std::size_t layer = s * static_cast<std::size_t>(thick);
      for (const auto& [key, v] : edges[s]) {
        const std::uint64_t a = key >> 32, b = key & 0xFFFFFFFFu;
        if (a / per_layer != layer || b / per_layer != layer) continue;
        const auto below = edges[s - 1].find(key);
        if (below == edges[s - 1].end()) continue;  // (both slabs cross every edge they share)
        remap[v] = below_remap[below->second];
        shared[v] = 1;
      }
    }
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
      if (shared[v]) continue;
      remap[v] = static_cast<std::uint32_t>(out.vertexCount());
      out.positions.insert(out.positions.end(), m.positions.begin() + 3 * static_cast<std::ptrdiff_t>(v),
                           m.positions.begin() + 3 * static_cast<std::ptrdiff_t>(v) + 3);
      out.normals.insert(out.normals.end(), m.normals.begin() + 3 * static_cast<std::ptrdiff_t>(v),
                         m.normals.begin() + 3 * static_cast<std::ptrdiff_t>(v) + 3);
      if (coloured)
        out.colors.insert(out.colors.end(), m.colors.begin() + 3 * static_cast<std::ptrdiff_t>(v),
                          m.colors.begin() + 3 * static_cast<std::ptrdiff_t>(v) + 3);
    }
    for (std::uint32_t i : m.indices) out.indices.push_back(remap[i]);
    below_remap.swap(remap);
  }
  return out;
}

void smoothSurface(TriMesh& m, int passes) {
  const std::size_t n = m.vertexCount();
  if (passes <= 0 || n == 0) return;
  // Each vertex's edge neighbours, once each and in increasing order (a CSR table): dealt by a
  // counting sort on the vertex, then each short list sorted and its repeats (an edge's two
  // triangles) dropped, in parallel.
  std::vector<std::uint32_t> start(n + 1, 0), nb;
  const std::size_t tris = m.indices.size() / 3;
  auto edge = [&](std::size_t t, int e) {
    return std::array<std::uint32_t, 2>{m.indices[3 * t + static_cast<std::size_t>(e)], m.indices[3 * t + static_cast<std::size_t>((e + 1) % 3)]};
  };
  for (std::size_t t = 0; t < tris; ++t)
    for (int e = 0; e < 3; ++e) {
      const auto [a, b] = edge(t, e);
      ++start[a + 1], ++start[b + 1];
    }
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  nb.resize(start[n]);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < tris; ++t)
      for (int e = 0; e < 3; ++e) {
        const auto [a, b] = edge(t, e);
        nb[fill[a]++] = b, nb[fill[b]++] = a;
      }
  }
  std::vector<std::uint32_t> count(n);
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t vi) {
    const auto v = static_cast<std::size_t>(vi);
    std::uint32_t* first = nb.data() + start[v];
    std::uint32_t* last = nb.data() + start[v + 1];
    std::sort(first, last);
    count[v] = static_cast<std::uint32_t>(std::unique(first, last) - first);
  });
  for (std::size_t v = 0, out = 0; v < n; ++v) {  // (compacted in place: out never passes start[v])
    const std::uint32_t from = start[v];
    start[v] = static_cast<std::uint32_t>(out);
    for (std::uint32_t k = 0; k < count[v]; ++k) nb[out++] = nb[from + k];
    if (v + 1 == n) start[n] = static_cast<std::uint32_t>(out);
  }
  std::vector<float> next(m.positions.size());
  auto relax = [&](double factor) {
    parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t vi) {
      const auto v = static_cast<std::size_t>(vi);
      for (int a = 0; a < 3; ++a) next[3 * v + static_cast<std::size_t>(a)] = m.positions[3 * v + static_cast<std::size_t>(a)];
      if (start[v + 1] == start[v]) return;
      double mean[3] = {0, 0, 0};
      for (std::uint32_t e = start[v]; e < start[v + 1]; ++e) {
        const auto u = static_cast<std::size_t>(nb[e]);
        for (int a = 0; a < 3; ++a) mean[a] += m.positions[3 * u + static_cast<std::size_t>(a)];
      }
      const double k = 1.0 / static_cast<double>(start[v + 1] - start[v]);
      for (int a = 0; a < 3; ++a) {
        const double x = m.positions[3 * v + static_cast<std::size_t>(a)];
        next[3 * v + static_cast<std::size_t>(a)] = static_cast<float>(x + factor * (k * mean[a] - x));
      }
    });
    m.positions.swap(next);
  };
  for (int p = 0; p < passes; ++p) {
    relax(0.5);
    relax(-0.53);
  }
}

}  // namespace reel
