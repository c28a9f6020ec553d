// reel's head's drawn parts that are not tissue: the ears (rim, antihelix, bowl and lobe, as a
// relief over an ear-shaped outline standing off the skull), the teeth, and the shoulders in a
// sweater that the neck enters. They are drawn, not simulated: the ears and upper teeth turn with
// the skull, the lower teeth with the jaw, the shoulders a third as far (face_draw.cpp).
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/mesh.h"
#include "sim/face/head.h"
#include "sim/face/head_shape.h"

namespace reel {
namespace {

using head::sq;

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

}  // namespace

void ringTriangles(TriMesh& m, std::uint32_t first, int rings, int segments, bool flip, bool closed) {
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const int next = closed ? (j + 1) % rings : j + 1;  // the ring after ring j
      const auto a = first + static_cast<std::uint32_t>(j * segments + i), b = first + static_cast<std::uint32_t>(j * segments + (i + 1) % segments);
      const auto c = first + static_cast<std::uint32_t>(next * segments + i), d = first + static_cast<std::uint32_t>(next * segments + (i + 1) % segments);
      if (flip) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
      else m.indices.insert(m.indices.end(), {a, d, b, a, c, d});
    }
}

namespace {

// One ear at height 0.24 m: 62 mm tall, 30 mm wide, leaning back 15°, its root in the skull behind the jaw's
// hinge, its back edge 13 mm off the head. A closed shell, its rings from the middle of the front
// out to the rim, round the rim and back in over the back: the front's relief (the helix's rolled
// rim, the antihelix's ridge above, the bowl of the concha, the lobe flat) rolls over the rim
// into the smooth back of the auricle, 2 mm behind the rim and 4 mm behind the middle, bulging
// toward the head behind the bowl. (A single sheet read as a blade from behind and flat from the
// side.)
void addEar(TriMesh& m, double scale, double side, const Vec3& skin) {
  constexpr int kRings = 40, kRoll = 5, kSegments = 112;  // (16 and 56 cut the antihelix's ridge, across the rings, into steps)
  const auto first = static_cast<std::uint32_t>(m.vertexCount());
  const Vec3 origin(side * 0.0705, -0.012, -0.02), out(side, 0, 0), back(0, 0, -1), up(0, 1, 0);
  const Vec3 rim_tone = skin + 0.18 * (Vec3(0.62, 0.3, 0.26) - skin);  // thin skin, redder (at 0.3, a cut-out pink outline)
  // The ear leans back 15° from upright, as ears do (upright, it read as a leaf stuck on).
  const double lean_c = std::cos(0.26), lean_s = std::sin(0.26);
  auto lean = [&](double u, double v) { return Vec3((u * lean_c + v * lean_s) * back + (v * lean_c - u * lean_s) * up); };
  // Where (u back, v up) a point of the outline at fraction r of the way out lies, its relief
  // off the ear's plane (front or back) and how far the ear stands off the skull there.
  struct At {
    double u, v, front, back, sunk;
  };
  auto at = [&](double r, double a) {
    const double ca = std::cos(a), sa = std::sin(a);
    // The outline: wider at the back, the lobe narrower below.
    double rx = ca > 0 ? 0.0175 : 0.0115, ry = sa > 0 ? 0.031 : 0.03;
    if (sa < 0) rx *= 1.0 - 0.18 * sq(sa);  // (at 0.3 the lobe came to a point)
    At p;
    p.u = r * rx * ca, p.v = r * ry * sa + 0.002;
    const double bowl = 0.009 * std::exp(-sq(p.u / 0.007) - sq((p.v + 0.002) / 0.009));
    // The helix: a rolled rim over the top and down the back to the lobe, none along the front
    // below the top, where the ear joins the head (rolled all round, with the antihelix a ring
    // inside it, the ear read as a dish of concentric rings); its crus, the rim's front end,
    // running down and back into the bowl.
    const double rim = std::max(smoothstep(-0.55, -0.1, ca), smoothstep(0.45, 0.75, sa)) * (sa > -0.6 ? 1.0 : 0.3);
    double h = 0.0045 * std::exp(-sq((r - 0.9) / 0.075)) * rim;
    auto ridge = [&](double height, double width, double au, double av, double bu, double bv) {
      return height * std::exp(-sq(head::segmentDistance(p.u, p.v, au, av, bu, bv) / width));
    };
    h += ridge(0.002, 0.0016, -0.0095, 0.02, -0.002, 0.006);
    // The antihelix: a ridge inside the back rim, up from above the lobe, forking at the top into
    // its upper crus (up and forward) and its lower (forward, over the bowl).
    h += ridge(0.003, 0.0022, 0.0075, -0.016, 0.006, 0.005);
    h += ridge(0.0022, 0.0016, 0.006, 0.005, 0.002, 0.021);
    h += ridge(0.0018, 0.0014, 0.006, 0.005, -0.005, 0.012);
    // The tragus, a flap over the bowl's front; the ear's canal, a pit in the bowl behind it.
    h += 0.0035 * std::exp(-sq((p.u + 0.0085) / 0.0025) - sq((p.v + 0.003) / 0.004));
    const double canal = 0.003 * std::exp(-sq((p.u + 0.0045) / 0.0025) - sq((p.v + 0.003) / 0.0025));
    const double stand = 0.5 * (p.u + 0.0115) - 0.0012;
    // How far the front sinks below its stand (the bowl's floor, darker: the concha is a cavity
    // the light reaches little of); its floor 0.5 mm off the ear's plane (sunk below it, the
    // bowl's floor passed under the head's skin, which showed through it as a pale crescent).
    p.sunk = std::min(h - bowl - canal, 0.0);
    p.front = std::max(stand + h - bowl - canal, 0.0005);
    // (The back goes in with the canal: the shell there, 2.5 mm thick, would pass through itself.)
    p.back = stand - 0.7 * bowl - canal - (0.002 + 0.002 * (1.0 - r * r)) + 0.3 * std::min(h, 0.0015);
    return p;
  };
  auto place = [&](const At& p, double off) { return Vec3(scale * (origin + lean(p.u, p.v) + off * out)); };
  auto color = [&](const Vec3& c) {
    for (int k = 0; k < 3; ++k) m.colors.push_back(static_cast<float>(c[k]));
  };
  // The front, from its middle out to the rim.
  for (int j = 0; j <= kRings; ++j)
    for (int i = 0; i < kSegments; ++i) {
      const double r = static_cast<double>(j) / kRings;
      const At p = at(r, 2 * kPi * i / kSegments);
      m.addVertex(place(p, p.front), out);
      // Darker down in the bowl and the folds, redder toward the rim.
      const double shade = std::clamp(1.0 + 70.0 * p.sunk, 0.3, 1.0);
      color(shade * (skin + smoothstep(0.6, 1.0, r) * (rim_tone - skin) + 0.08 * (Vec3(0.62, 0.3, 0.26) - skin)));
    }
  // Round the rim: a half turn from the front's edge to the back's, out past the outline.
  for (int q = 1; q < kRoll; ++q)
    for (int i = 0; i < kSegments; ++i) {
      const double a = 2 * kPi * i / kSegments, phi = kPi * q / kRoll;
      const At p = at(1.0, a);
      const double mid = 0.5 * (p.front + p.back), half = 0.5 * (p.front - p.back);
      const Vec3 radial = lean(p.u, p.v - 0.002).normalized();
      m.addVertex(place(p, mid + half * std::cos(phi)) + scale * half * std::sin(phi) * radial, out);
      color(rim_tone);
    }
  // The back, from the rim in to its middle.
  for (int j = kRings; j >= 0; --j)
    for (int i = 0; i < kSegments; ++i) {
      const double r = static_cast<double>(j) / kRings;
      const At p = at(r, 2 * kPi * i / kSegments);
      m.addVertex(place(p, p.back), -out);
      color(skin + smoothstep(0.6, 1.0, r) * (rim_tone - skin));
    }
  ringTriangles(m, first, 2 * kRings + kRoll, kSegments, side < 0);
}

}  // namespace

void ribbonTriangles(TriMesh& m, std::uint32_t base, int segments) {
  for (int j = 0; j < segments; ++j) {
    const std::uint32_t a = base + static_cast<std::uint32_t>(2 * j);
    m.indices.insert(m.indices.end(), {a, a + 1, a + 3, a, a + 3, a + 2});
  }
}

void gridTriangles(TriMesh& m, std::uint32_t base, int rows, int cols) {
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const std::uint32_t a = base + static_cast<std::uint32_t>(j * (cols + 1) + i), b = a + 1, c = a + static_cast<std::uint32_t>(cols) + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
}

std::shared_ptr<const TriMesh> makeEars(double scale, const Vec3& skin) {
  auto m = std::make_shared<TriMesh>();
  addEar(*m, scale, 1.0, skin);
  addEar(*m, scale, -1.0, skin);
  smoothNormals(*m);
  return m;
}

// The teeth: each row a band around a dental arch of radius 22 mm, its labial face `front` (z)
// at the midline, from the incisal edge `edge` (y) away from the parting (upper up, lower down).
// Teeth by their crowns' widths from the midline (permanent dentition, Ash & Nelson, "Wheeler's
// dental anatomy", 2003: upper 8.5, 6.5, 7.5, 7, 6.5, 10 mm; lower 5, 5.5, 7, 7, 7, 11 mm) and
// heights (upper incisor 10.5 mm, lower 9 mm, shorter toward the molars); each one's incisal
// corners rounded, its gum line arched over it, its face turned a little to either side (each
// crown shades round), darker at the gaps and toward the back of the mouth, then 2 mm of gum.
std::shared_ptr<const TriMesh> makeTeeth(double scale, double front, double edge, bool upper) {
  static constexpr double kUpper[] = {8.5, 6.5, 7.5, 7.0, 6.5, 10.0, 10.0}, kLower[] = {5.0, 5.5, 7.0, 7.0, 7.0, 11.0, 11.0};
  const double* widths = upper ? kUpper : kLower;
  const double arch = 0.022 * scale, sign = upper ? 1.0 : -1.0, mm = 0.001 * scale;
  const double crown = (upper ? 10.5 : 9.0) * mm;
  constexpr int kColumns = 120;  // across both sides: about 0.5 mm apart
  constexpr double kReach = 1.3;   // rad either side of the midline
  // Rows from the edge: the edge itself, 1 mm in, the middle of the crown, the gum line twice
  // (enamel, then gum: a sharp line), the gum.
  constexpr int kRows = 6;
  auto m = std::make_shared<TriMesh>();
  for (int i = 0; i <= kColumns; ++i) {
    const double a = kReach * (2.0 * i / kColumns - 1.0);
    // Which tooth, and where across it (0..1 from the side nearer the midline).
    double along = std::abs(a) * arch / mm, u = 0.0;
    int tooth = 0;
    while (tooth < 6 && along > widths[tooth]) along -= widths[tooth++];
    u = std::clamp(along / widths[tooth], 0.0, 1.0);
    const double hump = std::sin(kPi * u);  // 0 at a tooth's sides, 1 mid-crown
    const double height = crown * (1.0 - 0.07 * tooth);
    const double round_off = 0.9 * mm * std::pow(1.0 - hump, 3.0);  // the incisal corners
    const double gum = height - 1.6 * mm * (1.0 - hump);              // papillae between the crowns
    // (At the midline, between the two central incisors, neither's turn.)
    const double turn = i * 2 == kColumns ? 0.0 : 0.9 * (u - 0.5) * std::copysign(1.0, a);
    const Vec3 normal(std::sin(a + turn), 0, std::cos(a + turn));
    const double gap = 0.55 + 0.45 * smoothstep(0.0, 0.2, std::min(u, 1.0 - u));
    const double back = 1.0 - 0.6 * std::abs(a) / kReach;
    const double rows[kRows] = {round_off, round_off + 1.0 * mm, 0.5 * (round_off + gum), gum, gum, gum + 2.0 * mm};
    for (int j = 0; j < kRows; ++j) {
      const Vec3 q(arch * std::sin(a), edge + sign * rows[j], front - arch * (1 - std::cos(a)));
      m->addVertex(q, normal);
      // Enamel: greyer and translucent at the edge, ivory over the crown; then 2 mm of gum.
      const Vec3 enamel = j == 0 ? Vec3(0.6, 0.6, 0.6) : j == 1 ? Vec3(0.72, 0.7, 0.65) : Vec3(0.8, 0.75, 0.64);
      const Vec3 c = j >= 4 ? Vec3(back * Vec3(0.5, 0.2, 0.19)) : Vec3(gap * back * enamel);
      for (int k = 0; k < 3; ++k) m->colors.push_back(static_cast<float>(c[k]));
    }
  }
  for (int i = 0; i < kColumns; ++i)
    for (int j = 0; j + 1 < kRows; ++j) {
      const auto v = static_cast<std::uint32_t>(i * kRows + j), r = v + kRows;
      if (upper) m->indices.insert(m->indices.end(), {v, r, r + 1, v, r + 1, v + 1});
      else m->indices.insert(m->indices.end(), {v, r + 1, r, v, v + 1, r + 1});
    }
  return m;
}

std::shared_ptr<const TriMesh> makeBust(double scale, const FaceLook& look) {
  // Sections (height y, half-width, half-depth) from the sweater's collar round the neck down
  // over the shoulders to the chest; wider for a man and a heavier build.
  struct Section {
    double y, w, d;
  };
  const double broad = 1.0 + 0.08 * (look.sex - 0.5) + 0.1 * (look.build - 0.5);
  // The collar's rim turns in to the neck's own ellipse (head::neckRadii), so no gap shows
  // between them (at 6–10 mm wider than the neck, a dark band ran round it; at 1.5 mm the neck
  // poked through as the head turned).
  // Above the rim it rolls in over the neck, 4 mm up and to 3 mm inside it (hidden in the neck):
  // as the head turns, its ellipse and the collar's part at the sides, and the gap showed the
  // collar's dark inside as a wedge; now it shows the roll's top.
  const auto [nx, nz] = head::neckRadii(look);
  const Section sections[] = {{head::kCollarY + 0.004, nx - 0.003, nz - 0.003}, {head::kCollarY, nx + 0.0045, nz + 0.005}, {-0.134, nx + 0.01, nz + 0.012},
                              {-0.16, nx + 0.016, nz + 0.019},
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
      // A superellipse: the neck's ellipse at the collar (a squarer rim stood off the neck at its
      // corners), n = 2.6 from the shoulders down (square shoulders).
      const double sq_n = 2.0 + 0.6 * smoothstep(-0.16, -0.185, y);
      for (int i = 0; i < kSegments; ++i) {
        const double ang = 2 * kPi * i / kSegments, ca = std::cos(ang), sa = std::sin(ang);
        const double x = w * std::copysign(std::pow(std::abs(sa), 2.0 / sq_n), sa);
        const double z = d * std::copysign(std::pow(std::abs(ca), 2.0 / sq_n), ca) + head::kNeckAxisZ;
        m->addVertex(scale * Vec3(x, y, z), Vec3(sa, 0, ca));
      }
      ++rings;
    }
  ringTriangles(*m, 0, rings - 1, kSegments, false);
  smoothNormals(*m);
  return m;
}

}  // namespace reel
