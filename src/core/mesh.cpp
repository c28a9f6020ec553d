#include "core/mesh.h"

#include <algorithm>
#include <array>
#include <map>
#include <vector>
#include <cmath>

#include "core/math.h"

namespace reel {

void TriMesh::addVertex(const Vec3& p, const Vec3& n, double u, double v) {
  for (int i = 0; i < 3; ++i) {
    positions.push_back(static_cast<float>(p[i]));
    normals.push_back(static_cast<float>(n[i]));
  }
  uvs.push_back(static_cast<float>(u));
  uvs.push_back(static_cast<float>(v));
}

TriMesh placeMesh(const TriMesh& src, const Vec3& scale, const Mat3& R, const Vec3& position) {
  TriMesh m = src;
  for (std::size_t i = 0; i < m.vertexCount(); ++i) {
    const Vec3 p(src.positions[3 * i], src.positions[3 * i + 1], src.positions[3 * i + 2]);
    Vec3 n(src.normals[3 * i] / scale[0], src.normals[3 * i + 1] / scale[1], src.normals[3 * i + 2] / scale[2]);
    n = R * n;
    n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::UnitY();
    const Vec3 q = R * p.cwiseProduct(scale) + position;
    for (int k = 0; k < 3; ++k) {
      m.positions[3 * i + k] = static_cast<float>(q[k]);
      m.normals[3 * i + k] = static_cast<float>(n[k]);
    }
  }
  return m;
}

void TriMesh::transform(const Mat3& R, const Vec3& t) {
  for (std::size_t i = 0; i < vertexCount(); ++i) {
    Vec3 p(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    Vec3 n(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
    p = R * p + t;
    n = R * n;
    for (int k = 0; k < 3; ++k) {
      positions[3 * i + k] = static_cast<float>(p[k]);
      normals[3 * i + k] = static_cast<float>(n[k]);
    }
  }
}

namespace {

// A grid of (slices + 1) x (stacks + 1) vertices from f(u, v) → (position, normal).
template <class F>
void addGrid(TriMesh& m, int slices, int stacks, F&& f) {
  const auto base = static_cast<std::uint32_t>(m.vertexCount());
  for (int j = 0; j <= stacks; ++j)
    for (int i = 0; i <= slices; ++i) {
      const double u = static_cast<double>(i) / slices, v = static_cast<double>(j) / stacks;
      Vec3 p, n;
      f(u, v, p, n);
      m.addVertex(p, n, u, v);
    }
  const auto row = static_cast<std::uint32_t>(slices + 1);
  for (int j = 0; j < stacks; ++j)
    for (int i = 0; i < slices; ++i) {
      const std::uint32_t a = base + static_cast<std::uint32_t>(j) * row + static_cast<std::uint32_t>(i);
      const std::uint32_t b = a + 1, c = a + row, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, c, b, d, c});  // counter-clockwise from outside
    }
}

}  // namespace

TriMesh makeUvSphere(double radius, int slices, int stacks) {
  TriMesh m;
  addGrid(m, slices, stacks, [&](double u, double v, Vec3& p, Vec3& n) {
    const double phi = 2 * kPi * u, th = kPi * (1 - v);  // v = 0 at the south pole
    n = Vec3(std::sin(th) * std::cos(phi), std::cos(th), -std::sin(th) * std::sin(phi));
    p = radius * n;
  });
  return m;
}

TriMesh makeIcosphere(double radius, int subdivisions) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> f = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
      {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (Vec3& p : v) p.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;  // edge → its midpoint
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto [it, added] = mid.try_emplace({key.first, key.second}, static_cast<std::uint32_t>(v.size()));
      if (added) v.push_back((v[a] + v[b]).normalized());
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : f) {
      const std::uint32_t ab = middle(t[0], t[1]), bc = middle(t[1], t[2]), ca = middle(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  TriMesh m;
  for (const Vec3& n : v) m.addVertex(radius * n, n);
  for (const auto& t : f) m.indices.insert(m.indices.end(), {t[0], t[1], t[2]});
  return m;
}

TriMesh makeBox(const Vec3& size) {
  TriMesh m;
  const Vec3 h = size / 2;
  // Each face: normal n and two in-face axes a, b with a × b = n.
  const Vec3 axes[6][3] = {{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()},  {-Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY()},
                           {Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX()},  {-Vec3::UnitY(), Vec3::UnitX(), Vec3::UnitZ()},
                           {Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY()},  {-Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX()}};
  for (const auto& f : axes) {
    const Vec3 n = f[0], a = f[1], b = f[2];
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    for (int k = 0; k < 4; ++k) {
      const double sa = (k == 1 || k == 2) ? 1 : -1, sb = (k >= 2) ? 1 : -1;
      const Vec3 p = (n + sa * a + sb * b).cwiseProduct(h);
      m.addVertex(p, n, (sa + 1) / 2, (sb + 1) / 2);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return m;
}

TriMesh makeCapsule(const Vec3& a, const Vec3& b, double radius, int slices, int stacks) {
  // A sphere split at its equator, the halves moved to the two ends, joined by a cylinder.
  const Vec3 axis = b - a;
  const double len = axis.norm();
  const Mat3 R = rotationFromUp(len > 0 ? Vec3(axis / len) : Vec3::UnitY());
  TriMesh m;
  const int half = stacks / 2;
  addGrid(m, slices, 2 * half + 1, [&](double u, double v, Vec3& p, Vec3& n) {
    const int j = static_cast<int>(std::lround(v * (2 * half + 1)));
    const double phi = 2 * kPi * u;
    const bool top = j > half;
    const double th = kPi * (1.0 - static_cast<double>(top ? j - 1 : j) / (2 * half));
    n = Vec3(std::sin(th) * std::cos(phi), std::cos(th), -std::sin(th) * std::sin(phi));
    p = radius * n + Vec3(0, top ? len : 0.0, 0);
  });
  m.transform(R, a);
  return m;
}

TriMesh makeQuad(double width, double depth, double tile) {
  TriMesh m;
  const double w = width / 2, d = depth / 2;
  const double U = tile > 0 ? width / tile : 1, V = tile > 0 ? depth / tile : 1;
  m.addVertex(Vec3(-w, 0, -d), Vec3::UnitY(), 0, 0);
  m.addVertex(Vec3(-w, 0, d), Vec3::UnitY(), 0, V);
  m.addVertex(Vec3(w, 0, d), Vec3::UnitY(), U, V);
  m.addVertex(Vec3(w, 0, -d), Vec3::UnitY(), U, 0);
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

TriMesh makeCylinder(double radius, double height, int slices) {
  TriMesh m;
  const double h2 = 0.5 * height;
  addGrid(m, slices, 1, [&](double u, double v, Vec3& p, Vec3& n) {
    const double phi = 2 * kPi * u;
    n = Vec3(std::cos(phi), 0, -std::sin(phi));
    p = radius * n + Vec3(0, (2 * v - 1) * h2, 0);
  });
  // The caps: a fan around each centre, counter-clockwise seen from outside.
  for (const double side : {1.0, -1.0}) {
    const auto c = static_cast<std::uint32_t>(m.vertexCount());
    m.addVertex(Vec3(0, side * h2, 0), Vec3(0, side, 0), 0.5, 0.5);
    for (int i = 0; i <= slices; ++i) {
      const double phi = 2 * kPi * i / slices;
      m.addVertex(Vec3(radius * std::cos(phi), side * h2, -radius * std::sin(phi)), Vec3(0, side, 0),
                  0.5 + 0.5 * std::cos(phi), 0.5 + 0.5 * std::sin(phi));
    }
    for (std::uint32_t i = 1; i <= static_cast<std::uint32_t>(slices); ++i) {
      if (side > 0) m.indices.insert(m.indices.end(), {c, c + i, c + i + 1});
      else m.indices.insert(m.indices.end(), {c, c + i + 1, c + i});
    }
  }
  return m;
}

TriMesh makeTube(int slices) {
  TriMesh m;
  addGrid(m, slices, 1, [&](double u, double v, Vec3& p, Vec3& n) {
    const double phi = 2 * kPi * u;
    n = Vec3(std::cos(phi), std::sin(phi), 0);
    p = n + Vec3(0, 0, v);
  });
  return m;
}

std::vector<std::array<double, 2>> hexDisc(double radius, double spacing) {
  std::vector<std::array<double, 2>> pts;
  const double row = spacing * std::sqrt(3.0) / 2.0;
  const int rows = static_cast<int>(std::floor(radius / row));
  for (int j = -rows; j <= rows; ++j) {
    const double v = j * row, shift = (j & 1) ? spacing / 2 : 0.0;
    const int cols = static_cast<int>(std::floor(radius / spacing)) + 1;
    for (int i = -cols; i <= cols; ++i) {
      const double u = i * spacing + shift;
      if (u * u + v * v <= radius * radius * (1 + 1e-12)) pts.push_back({u, v});
    }
  }
  if (pts.empty()) pts.push_back({0.0, 0.0});
  return pts;
}

std::array<std::pair<Vec3, Vec3>, 5> containerBoxes(const Vec3& size, double wall) {
  const Vec3 h = size / 2;
  const double w = std::min(wall, h.minCoeff());
  return {{{Vec3(0, -h.y() + w / 2, 0), Vec3(size.x(), w, size.z())},
           {Vec3(h.x() - w / 2, 0, 0), Vec3(w, size.y(), size.z())},
           {Vec3(-h.x() + w / 2, 0, 0), Vec3(w, size.y(), size.z())},
           {Vec3(0, 0, h.z() - w / 2), Vec3(size.x(), size.y(), w)},
           {Vec3(0, 0, -h.z() + w / 2), Vec3(size.x(), size.y(), w)}}};
}

namespace {

// The fish's body: an ellipse of half-width 0.05·g(u) and half-height 0.115·g(u) at z = −kBody·u,
// g(u) = 2.6·√u·(1 − u) + 0.1·u (a blunt head, deepest a third of the way back, a narrow
// peduncle at u = 1 where the tail fin starts).
constexpr double kBody = 0.84, kHalfWidth = 0.05, kHalfHeight = 0.115;
double fishG(double u) { return 2.6 * std::sqrt(u) * (1 - u) + 0.1 * u; }
double fishDg(double u) { return 2.6 * (0.5 * (1 - u) / std::sqrt(u) - std::sqrt(u)) + 0.1; }

// Darker on the back than the belly (countershading), by the height y of a vertex.
Vec3 fishShade(double y) {
  const double t = std::clamp(0.5 + y / (2 * kHalfHeight), 0.0, 1.0);
  return Vec3(1.0, 1.0, 1.0) * (1.0 - 0.45 * t);
}

void addColoredVertex(TriMesh& m, const Vec3& p, const Vec3& n, double u, double v) {
  m.addVertex(p, n, u, v);
  const Vec3 c = fishShade(p.y());
  for (int k = 0; k < 3; ++k) m.colors.push_back(static_cast<float>(c[k]));
}

// The body: a nose vertex, `rings` rings of `slices` + 1 vertices (the last repeats the first for
// the UV seam), a tail vertex; counter-clockwise from outside.
void addFishBody(TriMesh& m, int slices, int rings) {
  const auto ring0 = static_cast<std::uint32_t>(m.vertexCount()) + 1;
  addColoredVertex(m, Vec3(0, 0, 0), Vec3::UnitZ(), 0, 0.5);
  for (int j = 1; j <= rings; ++j) {
    const double u = static_cast<double>(j) / rings, g = fishG(u), dg = fishDg(u);
    for (int i = 0; i <= slices; ++i) {
      const double phi = 2 * kPi * i / slices, c = std::cos(phi), s = std::sin(phi);
      // Outward normal ∂S/∂u × ∂S/∂φ of S(u, φ) = (w·cos φ, h·sin φ, −kBody·u).
      const Vec3 su(kHalfWidth * dg * c, kHalfHeight * dg * s, -kBody), sp(-kHalfWidth * g * s, kHalfHeight * g * c, 0);
      addColoredVertex(m, Vec3(kHalfWidth * g * c, kHalfHeight * g * s, -kBody * u), su.cross(sp).normalized(), u,
                       static_cast<double>(i) / slices);
    }
  }
  const auto tail = static_cast<std::uint32_t>(m.vertexCount());
  addColoredVertex(m, Vec3(0, 0, -kBody - 0.01), -Vec3::UnitZ(), 1, 0.5);
  const auto row = static_cast<std::uint32_t>(slices + 1);
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(slices); ++i) {
    m.indices.insert(m.indices.end(), {ring0 - 1, ring0 + i, ring0 + i + 1});  // the nose
    for (std::uint32_t j = 0; j + 1 < static_cast<std::uint32_t>(rings); ++j) {
      const std::uint32_t a = ring0 + j * row + i, b = a + row;
      m.indices.insert(m.indices.end(), {a, b, a + 1, b, b + 1, a + 1});
    }
    const std::uint32_t last = ring0 + (static_cast<std::uint32_t>(rings) - 1) * row + i;
    m.indices.insert(m.indices.end(), {last, tail, last + 1});  // the peduncle's end
  }
}

// A fin: the flat polygon `border` fanned from `centre`, as a closed lens whose two faces meet at
// the border and stand `thickness` apart at the centre.
void addFin(TriMesh& m, const std::vector<Vec3>& border, const Vec3& centre, double thickness) {
  // Each face's triangles turn counter-clockwise about its own side of the plane, whichever way
  // the border runs.
  const Vec3 n = (border[1] - centre).cross(border[0] - centre).normalized();
  for (const double side : {1.0, -1.0}) {
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    const Vec3 ns = side * n;
    addColoredVertex(m, centre + ns * (thickness / 2), ns, 0.5, 0.5);
    for (const Vec3& b : border) addColoredVertex(m, b, ns, 0.5 + b.z(), 0.5 + b.y());
    const auto k = static_cast<std::uint32_t>(border.size());
    for (std::uint32_t i = 0; i < k; ++i) {
      const std::uint32_t a = base + 1 + i, b = base + 1 + (i + 1) % k;
      if (side > 0)
        m.indices.insert(m.indices.end(), {base, b, a});
      else
        m.indices.insert(m.indices.end(), {base, a, b});
    }
  }
}

}  // namespace

TriMesh makeFishMesh(int detail) {
  const int d = std::max(detail, 0);
  TriMesh m;
  addFishBody(m, 6 * (d + 1), 4 + 6 * d);
  // Forked tail fin: from the peduncle back to two tips at z = −1, notched in the middle.
  addFin(m, {{0, 0.03, -0.78}, {0, 0.14, -1.0}, {0, 0, -0.9}, {0, -0.14, -1.0}, {0, -0.03, -0.78}}, Vec3(0, 0, -0.84),
         0.008);
  // Dorsal fin on the back, its tip swept back.
  const double ua = 0.3, ub = 0.62;
  const double ya = kHalfHeight * fishG(ua) - 0.01, yb = kHalfHeight * fishG(ub) - 0.01;
  addFin(m, {{0, ya, -kBody * ua}, {0, ya + 0.085, -0.46}, {0, yb, -kBody * ub}}, Vec3(0, ya + 0.02, -0.4), 0.008);
  // Pectoral fins behind the gills, angled out, back and down: too small to see on a distant copy.
  if (d >= 1)
    for (const double sx : {1.0, -1.0}) {
      const double w = kHalfWidth * fishG(0.25) * 0.7;
      const std::vector<Vec3> border{{sx * w, -0.02, -0.20}, {sx * (w + 0.1), -0.075, -0.33}, {sx * w, -0.04, -0.27}};
      addFin(m, border, (border[0] + border[1] + border[2]) / 3, 0.006);
    }
  return m;
}

std::vector<Vec3> areaNormals(std::span<const Vec3> points, const std::vector<std::uint32_t>& tris) {
  std::vector<Vec3> normal(points.size(), Vec3::Zero());
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Vec3 an = (points[tris[t + 1]] - points[tris[t]]).cross(points[tris[t + 2]] - points[tris[t]]);
    for (int c = 0; c < 3; ++c) normal[tris[t + static_cast<std::size_t>(c)]] += an;
  }
  return normal;
}

std::vector<Vec3> angleNormals(std::span<const Vec3> points, const std::vector<std::uint32_t>& tris) {
  std::vector<Vec3> normal(points.size(), Vec3::Zero());
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const std::uint32_t v[3] = {tris[t], tris[t + 1], tris[t + 2]};
    const Vec3 an = (points[v[1]] - points[v[0]]).cross(points[v[2]] - points[v[0]]);
    const double len = an.norm();
    if (!(len > 0)) continue;
    for (int c = 0; c < 3; ++c) {
      const Vec3 a = points[v[(c + 1) % 3]] - points[v[c]], b = points[v[(c + 2) % 3]] - points[v[c]];
      normal[v[c]] += std::atan2(a.cross(b).norm(), a.dot(b)) / len * an;
    }
  }
  for (Vec3& n : normal) n = unitOr(n, Vec3::UnitY());
  return normal;
}

std::shared_ptr<TriMesh> smoothMesh(std::span<const Vec3> points, std::size_t first, std::size_t n,
                                    const std::vector<std::uint32_t>& tris) {
  const std::vector<Vec3> normal = angleNormals(points.subspan(first, n), tris);
  auto mesh = std::make_shared<TriMesh>();
  for (std::size_t k = 0; k < n; ++k) mesh->addVertex(points[first + k], normal[k]);
  mesh->indices = tris;
  return mesh;
}

}  // namespace reel
