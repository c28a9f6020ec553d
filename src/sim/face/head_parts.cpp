// reel's head's drawn parts that are not tissue: the ears (rim, antihelix, bowl and lobe, as a
// relief over an ear-shaped outline standing off the skull) and the shoulders in a sweater that
// the neck enters. They are drawn, not simulated: the ears turn with the skull, the shoulders a
// third as far (face_draw.cpp).
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/mesh.h"
#include "sim/face/head.h"

namespace reel {
namespace {

double sq(double x) { return x * x; }

// Smooth normals of a mesh from its triangles' areas.
void smoothNormals(TriMesh& m) {
  std::vector<Vec3> p(m.vertexCount());
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = Vec3(m.positions[3 * k], m.positions[3 * k + 1], m.positions[3 * k + 2]);
  const std::vector<Vec3> n = areaNormals(p, m.indices);
  for (std::size_t k = 0; k < n.size(); ++k) {
    const Vec3 u = unitOr(n[k], Vec3::UnitY());
    for (int c = 0; c < 3; ++c) m.normals[3 * k + static_cast<std::size_t>(c)] = static_cast<float>(u[c]);
  }
}

// A grid of (rings + 1) × segments vertices joined into triangles, the segments closing around.
void ringTriangles(TriMesh& m, std::uint32_t first, int rings, int segments, bool flip) {
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const auto a = first + static_cast<std::uint32_t>(j * segments + i), b = first + static_cast<std::uint32_t>(j * segments + (i + 1) % segments);
      const auto c = a + static_cast<std::uint32_t>(segments), d = b + static_cast<std::uint32_t>(segments);
      if (flip) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
      else m.indices.insert(m.indices.end(), {a, d, b, a, c, d});
    }
}

// One ear at height 0.24 m: 62 mm tall, 30 mm wide, its root in the skull behind the jaw's
// hinge, its back edge 13 mm off the head.
void addEar(TriMesh& m, double scale, double side, const Vec3& skin) {
  constexpr int kRings = 14, kSegments = 48;
  const auto first = static_cast<std::uint32_t>(m.vertexCount());
  const Vec3 origin(side * 0.0705, -0.012, -0.02), out(side, 0, 0), back(0, 0, -1), up(0, 1, 0);
  for (int j = 0; j <= kRings; ++j) {
    const double r = static_cast<double>(j) / kRings;
    for (int i = 0; i < kSegments; ++i) {
      const double a = 2 * kPi * i / kSegments, ca = std::cos(a), sa = std::sin(a);
      // The outline: wider at the back, the lobe narrower below.
      double rx = ca > 0 ? 0.0175 : 0.0115, ry = sa > 0 ? 0.031 : 0.03;
      if (sa < 0) rx *= 1.0 - 0.3 * sq(sa);
      const double u = r * rx * ca, v = r * ry * sa + 0.002;
      // Relief: the helix's rolled rim, the antihelix's ridge above, the bowl (concha) at the
      // middle, the lobe flat; the whole standing off the skull toward the back.
      const double upper = std::clamp(0.5 + sa, 0.0, 1.0);
      double h = 0.0045 * std::exp(-sq((r - 0.9) / 0.075)) * (sa > -0.6 ? 1.0 : 0.3);
      h += 0.0028 * std::exp(-sq((r - 0.58) / 0.09)) * upper;
      h -= 0.006 * std::exp(-sq(u / 0.007) - sq((v + 0.002) / 0.009));
      const double stand = 0.55 * (u + 0.0115) - 0.0035;
      const Vec3 p = origin + u * back + v * up + (h + stand) * out;
      m.addVertex(scale * p, out);
      const double shade = std::clamp(1.0 + 40.0 * std::min(h, 0.0), 0.55, 1.0);
      const Vec3 c = shade * (skin + 0.15 * (Vec3(0.62, 0.3, 0.26) - skin));
      for (int k = 0; k < 3; ++k) m.colors.push_back(static_cast<float>(c[k]));
    }
  }
  ringTriangles(m, first, kRings, kSegments, side < 0);
  // The centre: its first ring collapses to a point; nothing else to close.
}

}  // namespace

std::shared_ptr<const TriMesh> makeEars(double scale, const Vec3& skin) {
  auto m = std::make_shared<TriMesh>();
  addEar(*m, scale, 1.0, skin);
  addEar(*m, scale, -1.0, skin);
  smoothNormals(*m);
  return m;
}

std::shared_ptr<const TriMesh> makeBust(double scale, const FaceLook& look) {
  // Sections (height y, half-width, half-depth) from the sweater's collar round the neck down
  // over the shoulders to the chest; wider for a man and a heavier build.
  struct Section {
    double y, w, d;
  };
  const double broad = 1.0 + 0.08 * (look.sex - 0.5) + 0.1 * (look.build - 0.5);
  const double neck = 0.052 + 0.008 * look.build;
  // The collar's rim turns in to the neck, so no gap shows between them.
  const Section sections[] = {{-0.142, neck + 0.002, neck + 0.004}, {-0.134, neck + 0.009, neck + 0.012},
                              {-0.16, neck + 0.015, neck + 0.018},
                              {-0.185, 0.1 * broad, 0.08},         {-0.215, 0.16 * broad, 0.1},
                              {-0.25, 0.195 * broad, 0.11},        {-0.285, 0.21 * broad, 0.118},
                              {-0.34, 0.205 * broad, 0.122},       {-0.5, 0.19 * broad, 0.12}};
  constexpr int kSegments = 64, kSub = 4;
  auto m = std::make_shared<TriMesh>();
  const int n = static_cast<int>(std::size(sections));
  int rings = 0;
  for (int s = 0; s + 1 < n; ++s)
    for (int k = 0; k < kSub || (s + 2 == n && k == kSub); ++k) {
      const double t = static_cast<double>(k) / kSub, e = t * t * (3 - 2 * t);
      const Section& a = sections[s];
      const Section& b = sections[s + 1];
      const double y = a.y + t * (b.y - a.y), w = a.w + e * (b.w - a.w), d = a.d + e * (b.d - a.d);
      for (int i = 0; i < kSegments; ++i) {
        const double ang = 2 * kPi * i / kSegments, ca = std::cos(ang), sa = std::sin(ang);
        // A superellipse (n = 2.6): square shoulders.
        const double x = w * std::copysign(std::pow(std::abs(sa), 2.0 / 2.6), sa);
        const double z = d * std::copysign(std::pow(std::abs(ca), 2.0 / 2.6), ca) - 0.018;
        m->addVertex(scale * Vec3(x, y, z), Vec3(sa, 0, ca));
      }
      ++rings;
    }
  ringTriangles(*m, 0, rings - 1, kSegments, false);
  smoothNormals(*m);
  return m;
}

}  // namespace reel
