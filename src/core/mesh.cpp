#include "core/mesh.h"

#include <algorithm>
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

TriMesh makeQuad(double width, double depth) {
  TriMesh m;
  const double w = width / 2, d = depth / 2;
  m.addVertex(Vec3(-w, 0, -d), Vec3::UnitY(), 0, 0);
  m.addVertex(Vec3(-w, 0, d), Vec3::UnitY(), 0, 1);
  m.addVertex(Vec3(w, 0, d), Vec3::UnitY(), 1, 1);
  m.addVertex(Vec3(w, 0, -d), Vec3::UnitY(), 1, 0);
  m.indices = {0, 1, 2, 0, 2, 3};
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

}  // namespace reel
