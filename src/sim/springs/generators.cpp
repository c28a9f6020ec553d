#include "sim/springs/generators.h"

#include "core/math.h"

namespace reel {
namespace {

// Equal node masses from the total, the generator keys common to all bodies applied.
void finishNodes(MassSpringDesc& out, double total_mass, double node_damping,
                 const Vec3& velocity, const std::vector<int>& pinned) {
  const double m = total_mass / static_cast<double>(out.nodes.size());
  for (NodeDesc& n : out.nodes) {
    n.mass = m;
    n.damping = node_damping;
    n.velocity = velocity;
  }
  for (int p : pinned) out.nodes[static_cast<std::size_t>(p)].fixed = true;
}

void addSpring(MassSpringDesc& out, int a, int b, const SpringParams& p) {
  out.springs.push_back({a, b, p.stiffness, p.damping, -1.0});
}

}  // namespace

MassSpringDesc buildRope(const RopeDesc& d) {
  MassSpringDesc out;
  const int n = d.segments + 1;
  const double straight = (d.end - d.start).norm();
  const double rest = (d.length > 0.0 ? d.length : straight) / d.segments;
  for (int i = 0; i < n; ++i)
    out.nodes.push_back({d.start + (d.end - d.start) * (static_cast<double>(i) / d.segments)});
  for (int i = 0; i + 1 < n; ++i) out.springs.push_back({i, i + 1, d.spring.stiffness, d.spring.damping, rest});
  finishNodes(out, d.mass, d.node_damping, d.velocity, d.pinned);
  return out;
}

MassSpringDesc buildNet(const NetDesc& d) {
  MassSpringDesc out;
  const int nx = d.resolution[0], ny = d.resolution[1];
  const Mat3 R = rotationFromEulerDeg(d.rotation_deg);
  auto id = [nx](int i, int j) { return j * nx + i; };
  // Nodes on the local x–z plane, centred on `position`.
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Vec3 local(d.size[0] * (static_cast<double>(i) / (nx - 1) - 0.5), 0.0,
                       d.size[1] * (static_cast<double>(j) / (ny - 1) - 0.5));
      out.nodes.push_back({d.position + R * local});
    }
  // Structural springs along the grid lines, then shear springs across each cell.
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) addSpring(out, id(i, j), id(i + 1, j), d.structural);
      if (j + 1 < ny) addSpring(out, id(i, j), id(i, j + 1), d.structural);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      addSpring(out, id(i, j), id(i + 1, j + 1), d.shear);
      addSpring(out, id(i + 1, j), id(i, j + 1), d.shear);
    }
  finishNodes(out, d.mass, d.node_damping, d.velocity, d.pinned);
  return out;
}

std::vector<std::array<int, 4>> latticeSkin(const LatticeDesc& d) {
  const std::array<int, 3> n = d.resolution;
  std::vector<std::array<int, 4>> quads;
  auto id = [&](const std::array<int, 3>& c) { return (c[2] * n[1] + c[1]) * n[0] + c[0]; };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b × e_c = e_a: counter-clockwise about +e_a
    for (int side : {0, n[a] - 1})
      for (int u = 0; u + 1 < n[b]; ++u)
        for (int v = 0; v + 1 < n[c]; ++v) {
          std::array<int, 4> q{};
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> p{};
            p[a] = side;
            p[b] = u + du[k];
            p[c] = v + dv[k];
            q[k] = id(p);
          }
          if (side == 0) std::swap(q[1], q[3]);  // the −e_a face: turned to face out
          quads.push_back(q);
        }
  }
  return quads;
}

MassSpringDesc buildLattice(const LatticeDesc& d) {
  MassSpringDesc out;
  const int nx = d.resolution[0], ny = d.resolution[1], nz = d.resolution[2];
  const Mat3 R = rotationFromEulerDeg(d.rotation_deg);
  auto id = [nx, ny](int i, int j, int k) { return (k * ny + j) * nx + i; };
  auto frac = [](int i, int n) { return static_cast<double>(i) / (n - 1) - 0.5; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 local(d.size.x() * frac(i, nx), d.size.y() * frac(j, ny), d.size.z() * frac(k, nz));
        out.nodes.push_back({d.position + R * local});
      }
  auto inside = [&](int i, int j, int k) { return i < nx && j < ny && k < nz; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int p = id(i, j, k);
        // Edges along x, y, z.
        if (inside(i + 1, j, k)) addSpring(out, p, id(i + 1, j, k), d.edge);
        if (inside(i, j + 1, k)) addSpring(out, p, id(i, j + 1, k), d.edge);
        if (inside(i, j, k + 1)) addSpring(out, p, id(i, j, k + 1), d.edge);
        // Face diagonals: both diagonals of the cell faces in the xy, xz and yz planes.
        if (inside(i + 1, j + 1, k)) {
          addSpring(out, p, id(i + 1, j + 1, k), d.face);
          addSpring(out, id(i + 1, j, k), id(i, j + 1, k), d.face);
        }
        if (inside(i + 1, j, k + 1)) {
          addSpring(out, p, id(i + 1, j, k + 1), d.face);
          addSpring(out, id(i + 1, j, k), id(i, j, k + 1), d.face);
        }
        if (inside(i, j + 1, k + 1)) {
          addSpring(out, p, id(i, j + 1, k + 1), d.face);
          addSpring(out, id(i, j + 1, k), id(i, j, k + 1), d.face);
        }
        // Body diagonals: the four of each cell.
        if (inside(i + 1, j + 1, k + 1)) {
          addSpring(out, p, id(i + 1, j + 1, k + 1), d.body);
          addSpring(out, id(i + 1, j, k), id(i, j + 1, k + 1), d.body);
          addSpring(out, id(i, j + 1, k), id(i + 1, j, k + 1), d.body);
          addSpring(out, id(i, j, k + 1), id(i + 1, j + 1, k), d.body);
        }
      }
  finishNodes(out, d.mass, d.node_damping, d.velocity, d.pinned);
  return out;
}

}  // namespace reel
