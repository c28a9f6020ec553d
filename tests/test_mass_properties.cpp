// Polyhedral mass properties (Mirtich 1996) against closed forms; the solid-mesh checks' refusals.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/mass_properties.h"
#include "core/math.h"
#include "core/mesh.h"

using namespace reel;

namespace {

// A polyhedron as double-precision vertices and counter-clockwise triangles.
struct Poly {
  std::vector<Vec3> v;                // m
  std::vector<std::array<int, 3>> t;  // corner indices
  MassProperties mass(double density) const { return polyhedronMass(v, t, density); }
};

Poly fromMesh(const TriMesh& m) {
  Poly p;
  for (std::size_t i = 0; i < m.vertexCount(); ++i)
    p.v.emplace_back(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
  for (std::size_t i = 0; i < m.triangleCount(); ++i)
    p.t.push_back({static_cast<int>(m.indices[3 * i]), static_cast<int>(m.indices[3 * i + 1]),
                   static_cast<int>(m.indices[3 * i + 2])});
  return p;
}

// Positions rounded to float (exact for the small dyadic numbers the refusal tests use).
TriMesh toMesh(const Poly& p) {
  TriMesh m;
  for (const Vec3& x : p.v)
    for (int k = 0; k < 3; ++k) m.positions.push_back(static_cast<float>(x[k]));
  for (const auto& t : p.t)
    for (int k : t) m.indices.push_back(static_cast<std::uint32_t>(k));
  return m;
}

// Appends q's vertices and triangles to p.
void append(Poly& p, const Poly& q) {
  const int base = static_cast<int>(p.v.size());
  p.v.insert(p.v.end(), q.v.begin(), q.v.end());
  for (const auto& t : q.t) p.t.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// A welded box [lo, hi]: 8 corners, 12 triangles, outward.
Poly boxPoly(const Vec3& lo, const Vec3& hi) {
  Poly p;
  for (int k = 0; k < 8; ++k)  // corner k: bit 0 → x, bit 1 → y, bit 2 → z at hi
    p.v.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  // Each face as a quad a, b, c, d counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    p.t.push_back({q[0], q[1], q[2]});
    p.t.push_back({q[0], q[2], q[3]});
  }
  return p;
}

// Each triangle with its own three vertices (as some importers give them).
Poly unwelded(const Poly& p) {
  Poly q;
  for (const auto& t : p.t) {
    const int base = static_cast<int>(q.v.size());
    for (int k : t) q.v.push_back(p.v[static_cast<std::size_t>(k)]);
    q.t.push_back({base, base + 1, base + 2});
  }
  return q;
}

Poly flipped(Poly p) {
  for (auto& t : p.t) std::swap(t[1], t[2]);
  return p;
}

// A right prism over the L-shaped polygon (0,0) (2,0) (2,1) (1,1) (1,3) (0,3), z from 0 to depth.
Poly lPrism(double depth) {
  const double xy[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  Poly p;
  for (int z = 0; z < 2; ++z)
    for (const auto& c : xy) p.v.emplace_back(c[0], c[1], z * depth);
  // Sides: edge i → i+1 (counter-clockwise seen from +z) faces outward as (i, i+1, top i+1, top i).
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    p.t.push_back({i, j, j + 6});
    p.t.push_back({i, j + 6, i + 6});
  }
  // Caps: a fan from the reflex corner 3 (every fan triangle lies inside the L).
  const int fan[4][2] = {{4, 5}, {5, 0}, {0, 1}, {1, 2}};
  for (const auto& f : fan) {
    p.t.push_back({3 + 6, f[0] + 6, f[1] + 6});  // top, seen from +z
    p.t.push_back({3, f[1], f[0]});              // bottom, seen from −z
  }
  return p;
}

// A right prism of n sides inscribed in the cylinder of radius r, height h along y, centred.
Poly prism(double r, double h, int n) {
  Poly p;
  for (int i = 0; i < n; ++i) {
    const double phi = 2 * kPi * i / n;
    for (int k = 0; k < 2; ++k) p.v.emplace_back(r * std::cos(phi), (k - 0.5) * h, -r * std::sin(phi));
  }
  const int bottom = 2 * n, top = 2 * n + 1;
  p.v.emplace_back(0, -h / 2, 0);
  p.v.emplace_back(0, h / 2, 0);
  // φ runs counter-clockwise seen from +y (x toward −z).
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const int a = 2 * i, b = 2 * j;
    p.t.push_back({a, b, b + 1});
    p.t.push_back({a, b + 1, a + 1});
    p.t.push_back({top, a + 1, b + 1});
    p.t.push_back({bottom, b, a});
  }
  return p;
}

// A unit icosahedron subdivided `levels` times onto the sphere of radius r: 20·4^levels triangles.
Poly icosphere(double r, int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  Poly p;
  p.v = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
         {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  p.t = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
         {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
         {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;  // edge → its midpoint's index
    const auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.v.push_back((p.v[static_cast<std::size_t>(a)] + p.v[static_cast<std::size_t>(b)]) / 2);
      return mid[key] = static_cast<int>(p.v.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : p.t) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    p.t = std::move(next);
  }
  for (Vec3& x : p.v) x = r * x.normalized();
  return p;
}

// |a − b| ≤ rel·|b| (or ≤ rel when b = 0).
void checkRel(double a, double b, double rel) { CHECK(std::abs(a - b) <= rel * std::max(std::abs(b), 1e-300)); }
void checkRel(const Vec3& a, const Vec3& b, double rel, double scale) { CHECK((a - b).norm() <= rel * scale); }
void checkRel(const Mat3& a, const Mat3& b, double rel) {
  CAPTURE(a);
  CAPTURE(b);
  CHECK((a - b).norm() <= rel * b.norm());
}

void checkSame(const MassProperties& a, const MassProperties& b, double rel, double length) {
  checkRel(a.volume, b.volume, rel);
  checkRel(a.mass, b.mass, rel);
  checkRel(a.center_of_mass, b.center_of_mass, rel, length);
  checkRel(a.inertia, b.inertia, rel);
}

// Two boxes added by the parallel axis theorem: each box's inertia about the joint centre.
MassProperties addShifted(const MassProperties& a, const Vec3& ca, const MassProperties& b, const Vec3& cb) {
  MassProperties s;
  s.volume = a.volume + b.volume;
  s.mass = a.mass + b.mass;
  s.center_of_mass = (a.mass * ca + b.mass * cb) / s.mass;
  const auto shift = [&](const MassProperties& m, const Vec3& c) {
    const Vec3 d = c - s.center_of_mass;
    return Mat3(m.inertia + m.mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
  };
  s.inertia = shift(a, ca) + shift(b, cb);
  return s;
}

// The headline of a refusal, after checking it is BadInput.
std::string refusal(const Result<MassProperties>& r) {
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().kind == ErrorKind::BadInput);
  return r.error().headline();
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("mass properties: boxes, axis-aligned and rotated off-centre") {
  // Unit cube: V = 1, I = 1/6 about each axis.
  const MassProperties unit = boxPoly(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)).mass(1.0);
  checkRel(unit.volume, 1.0, 1e-12);
  CHECK(unit.center_of_mass.norm() <= 1e-12);
  checkRel(unit.inertia, Mat3::Identity() / 6, 1e-9);
  // A box of makeBox (its own per-face vertices) agrees with boxMass.
  const Vec3 size(0.5, 2.0, 3.0);
  checkSame(fromMesh(makeBox(size)).mass(700.0), boxMass(size, 700.0), 1e-9, 1.0);

  // Moved off the origin and rotated: centre t, inertia R·I·Rᵀ with products of inertia.
  const Vec3 s(0.3, 0.5, 1.1), t(3.0, -2.0, 5.0);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Poly box = boxPoly(-s / 2, s / 2);
  for (Vec3& x : box.v) x = R * x + t;
  const MassProperties rotated = box.mass(450.0);
  const MassProperties closed = boxMass(s, 450.0);
  const Mat3 expected = R * closed.inertia * R.transpose();
  CHECK(std::abs(expected(0, 1)) > 1e-3 * expected.norm());
  CHECK(std::abs(expected(1, 2)) > 1e-3 * expected.norm());
  CHECK(std::abs(expected(0, 2)) > 1e-3 * expected.norm());
  checkRel(rotated.volume, closed.volume, 1e-9);
  checkRel(rotated.mass, closed.mass, 1e-9);
  checkRel(rotated.center_of_mass, t, 1e-9, t.norm());
  checkRel(rotated.inertia, expected, 1e-9);
  CHECK((rotated.inertia - rotated.inertia.transpose()).norm() <= 1e-12 * expected.norm());
}

TEST_CASE("mass properties: tetrahedra") {
  // In barycentric coordinates λ over a tetrahedron of volume V, ∫λ_k² dV = V/10 and
  // ∫λ_k λ_l dV = V/20 (k ≠ l), so with x = Σ λ_k v_k, ∫x xᵀ dV = V/20 (Σ v_k v_kᵀ + s sᵀ),
  // s = Σ v_k; the centroid is s/4, V = (v1 − v0)·((v2 − v0) × (v3 − v0))/6, and the inertia
  // about the centroid ρ(tr C · 1 − C) with C = ∫x xᵀ dV − V c cᵀ. For the canonical
  // tetrahedron (0,0,0), (a,0,0), (0,b,0), (0,0,c): V = abc/6, c = (a,b,c)/4, ∫x² = V a²/10,
  // ∫xy = V ab/20.
  const auto closedForm = [](const std::array<Vec3, 4>& v, double density) {
    MassProperties m;
    m.volume = (v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0])) / 6;
    m.mass = density * m.volume;
    const Vec3 s = v[0] + v[1] + v[2] + v[3];
    m.center_of_mass = s / 4;
    Mat3 S = s * s.transpose();
    for (const Vec3& x : v) S += x * x.transpose();
    const Mat3 C = m.volume / 20 * S - m.volume * m.center_of_mass * m.center_of_mass.transpose();
    m.inertia = density * (C.trace() * Mat3::Identity() - C);
    return m;
  };
  const auto tetra = [](const std::array<Vec3, 4>& v) {
    Poly p;
    p.v.assign(v.begin(), v.end());
    p.t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};  // outward when (v1 − v0)·((v2 − v0) × (v3 − v0)) > 0
    return p;
  };

  SUBCASE("canonical") {
    const double a = 1.5, b = 0.7, c = 2.3, rho = 3.0;
    const std::array<Vec3, 4> v = {Vec3(0, 0, 0), Vec3(a, 0, 0), Vec3(0, b, 0), Vec3(0, 0, c)};
    const MassProperties m = tetra(v).mass(rho);
    const double V = a * b * c / 6;
    checkRel(m.volume, V, 1e-12);
    checkRel(m.center_of_mass, Vec3(a, b, c) / 4, 1e-12, Vec3(a, b, c).norm());
    // About the centroid: ∫x'² = V a²/10 − V a²/16 = 3 V a²/80, ∫x'y' = V ab/20 − V ab/16 = −V ab/80.
    const Vec3 d2 = 3 * V / 80 * Vec3(a * a, b * b, c * c);
    Mat3 I;
    I << d2.y() + d2.z(), V * a * b / 80, V * a * c / 80,  //
        V * a * b / 80, d2.z() + d2.x(), V * b * c / 80,   //
        V * a * c / 80, V * b * c / 80, d2.x() + d2.y();
    I *= rho;
    checkRel(m.inertia, I, 1e-9);
    checkSame(m, closedForm(v, rho), 1e-9, 1.0);
  }
  SUBCASE("general, far from the origin") {
    const Vec3 o(40.0, -25.0, 13.0);
    const std::array<Vec3, 4> v = {o + Vec3(0.1, 0.2, -0.3), o + Vec3(1.4, -0.2, 0.5), o + Vec3(0.3, 1.7, 0.2),
                                   o + Vec3(-0.2, 0.4, 1.9)};
    REQUIRE((v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0])) > 0);
    checkSame(tetra(v).mass(1000.0), closedForm(v, 1000.0), 1e-9, 1.0);
  }
}

TEST_CASE("mass properties: a non-convex L-shaped prism is the sum of its two boxes") {
  const double depth = 0.75, rho = 1200.0;
  // The L is [0,2]×[0,1] and [0,1]×[1,3], both through z ∈ [0, depth].
  const MassProperties expected = addShifted(boxMass(Vec3(2, 1, depth), rho), Vec3(1, 0.5, depth / 2),
                                             boxMass(Vec3(1, 2, depth), rho), Vec3(0.5, 2, depth / 2));
  CHECK(std::abs(expected.inertia(0, 1)) > 0);  // products of inertia present
  checkSame(lPrism(depth).mass(rho), expected, 1e-9, 3.0);
  // Through the solid checks too (the coordinates are exact in float).
  const auto checked = solidMassProperties(toMesh(lPrism(depth)), rho);
  REQUIRE(checked.ok());
  checkSame(checked.value(), expected, 1e-9, 3.0);
}

TEST_CASE("mass properties: unwelded input gives what welded does") {
  const Poly welded = lPrism(0.75);
  const Poly loose = unwelded(welded);
  REQUIRE(loose.v.size() == 3 * welded.t.size());
  const auto a = solidMassProperties(toMesh(welded), 900.0), b = solidMassProperties(toMesh(loose), 900.0);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a.value().volume == b.value().volume);
  CHECK(a.value().center_of_mass == b.value().center_of_mass);
  CHECK(a.value().inertia == b.value().inertia);
  // makeBox repeats each corner once per face.
  const auto box = solidMassProperties(makeBox(Vec3(1, 2, 4)), 10.0);
  REQUIRE(box.ok());
  checkSame(box.value(), boxMass(Vec3(1, 2, 4), 10.0), 1e-9, 1.0);
}

TEST_CASE("mass properties: a UV sphere converges to 4/3 π r³ and 2/5 m r²") {
  const double r = 1.3, rho = 500.0;
  const MassProperties exact = sphereMass(r, rho);
  double lastVolumeError = 0, lastInertiaError = 0;
  for (int slices = 16; slices <= 256; slices *= 2) {
    const MassProperties m = fromMesh(makeUvSphere(r, slices, slices / 2)).mass(rho);
    const double volumeError = std::abs(m.volume - exact.volume) / exact.volume;
    const double inertiaError = (m.inertia - exact.inertia).norm() / exact.inertia.norm();
    CAPTURE(slices);
    CAPTURE(volumeError);
    CAPTURE(inertiaError);
    CHECK(m.volume < exact.volume);  // inscribed
    CHECK(m.center_of_mass.norm() <= 1e-6 * r);
    CHECK(std::abs(m.inertia(0, 1)) + std::abs(m.inertia(1, 2)) + std::abs(m.inertia(0, 2)) <=
          1e-6 * exact.inertia(0, 0));
    // Second order: the error falls about fourfold per doubling.
    if (slices > 16) {
      CHECK(lastVolumeError / volumeError > 3.5);
      CHECK(lastVolumeError / volumeError < 4.5);
      CHECK(lastInertiaError / inertiaError > 3.5);
      CHECK(lastInertiaError / inertiaError < 4.5);
    }
    if (slices == 256) CHECK(volumeError < 3e-4);
    lastVolumeError = volumeError;
    lastInertiaError = inertiaError;
  }
}

TEST_CASE("mass properties: closed forms of the capsule and cylinder") {
  const double r = 0.4, rho = 800.0;
  // A capsule of no length is a sphere.
  checkSame(capsuleMass(0.0, r, rho), sphereMass(r, rho), 1e-12, r);
  // Its volume is the cylinder's plus a sphere's.
  const MassProperties cap = capsuleMass(1.2, r, rho);
  checkRel(cap.volume, kPi * r * r * 1.2 + 4.0 / 3.0 * kPi * r * r * r, 1e-12);
  // Along y the cylinder's and sphere's moments add; across, the hemispheres sit out at ± (L/2 + 3r/8).
  checkRel(cap.inertia(1, 1), cylinderMass(r, 1.2, rho).inertia(1, 1) + sphereMass(r, rho).inertia(1, 1), 1e-12);
  // The cylinder against a prism of many sides (inscribed: second-order close).
  const MassProperties cyl = cylinderMass(r, 1.5, rho);
  checkSame(prism(r, 1.5, 1024).mass(rho), cyl, 1e-4, 1.5);
  CHECK(std::abs(prism(r, 1.5, 64).mass(rho).volume - cyl.volume) > 1e-4 * cyl.volume);
  // The capsule against makeCapsule's mesh along y.
  const MassProperties mesh = fromMesh(makeCapsule(Vec3(0, -0.6, 0), Vec3(0, 0.6, 0), r, 512, 256)).mass(rho);
  checkSame(mesh, cap, 1e-3, 1.2);
  const auto checked = solidMassProperties(toMesh(prism(r, 1.5, 256)), rho);
  REQUIRE(checked.ok());
  checkSame(checked.value(), cyl, 1e-3, 1.5);
}

TEST_CASE("mass properties: meshes that are not solids are refused with the reason") {
  const Poly box = boxPoly(Vec3(0, 0, 0), Vec3(1, 1, 1));
  SUBCASE("open: a box less one triangle") {
    Poly open = box;
    open.t.pop_back();
    const std::string msg = refusal(solidMassProperties(toMesh(open), 1.0));
    CHECK_MESSAGE(has(msg, "not closed"), msg);
    CHECK_MESSAGE(has(msg, "3 edges belong to one triangle only"), msg);
  }
  SUBCASE("inside out: every winding flipped") {
    const std::string msg = refusal(solidMassProperties(toMesh(flipped(box)), 1.0));
    CHECK_MESSAGE(has(msg, "inside out"), msg);
    CHECK_MESSAGE(has(msg, "clockwise"), msg);
  }
  SUBCASE("inconsistent: one triangle flipped") {
    Poly bad = box;
    std::swap(bad.t[3][1], bad.t[3][2]);
    const std::string msg = refusal(solidMassProperties(toMesh(bad), 1.0));
    CHECK_MESSAGE(has(msg, "wind inconsistently"), msg);
  }
  SUBCASE("self-intersecting: two interpenetrating boxes in one mesh") {
    Poly two = box;
    append(two, boxPoly(Vec3(0.5, 0.25, 0.5), Vec3(1.5, 0.75, 1.5)));
    const std::string msg = refusal(solidMassProperties(toMesh(two), 1.0));
    CHECK_MESSAGE(has(msg, "intersects itself"), msg);
    CHECK_MESSAGE(has(msg, "cross"), msg);
  }
  SUBCASE("degenerate: a zero-area triangle") {
    Poly bad = box;
    bad.v.emplace_back(0.5, 0, 0);  // the midpoint of the edge from corner 0 to corner 1
    bad.t.push_back({0, 8, 1});
    const std::string msg = refusal(solidMassProperties(toMesh(bad), 1.0));
    CHECK_MESSAGE(has(msg, "degenerate (zero-area)"), msg);
    CHECK_MESSAGE(has(msg, "first triangle 12"), msg);
  }
  SUBCASE("a box nested in another, both outward, would count twice") {
    Poly two = box;
    append(two, boxPoly(Vec3(0.25, 0.25, 0.25), Vec3(0.75, 0.75, 0.75)));
    const std::string msg = refusal(solidMassProperties(toMesh(two), 1.0));
    CHECK_MESSAGE(has(msg, "nest wrongly"), msg);
  }
  SUBCASE("one of two separate boxes inside out") {
    Poly two = box;
    append(two, flipped(boxPoly(Vec3(2, 0, 0), Vec3(2.5, 0.5, 0.5))));
    const std::string msg = refusal(solidMassProperties(toMesh(two), 1.0));
    CHECK_MESSAGE(has(msg, "inside out in part"), msg);
  }
  SUBCASE("bad numbers") {
    CHECK(has(refusal(solidMassProperties(toMesh(box), 0.0)), "density"));
    TriMesh m = toMesh(box);
    m.positions[4] = NAN;
    CHECK(has(refusal(solidMassProperties(m, 1.0)), "non-finite"));
    m = toMesh(box);
    m.indices[5] = 99;
    CHECK(has(refusal(solidMassProperties(m, 1.0)), "indexes vertex 99"));
    CHECK(has(refusal(solidMassProperties(TriMesh{}, 1.0)), "no triangles"));
  }
}

TEST_CASE("mass properties: solids with several shells") {
  const Poly box = boxPoly(Vec3(0, 0, 0), Vec3(1, 1, 1));
  SUBCASE("a cavity wound inward is subtracted") {
    Poly hollow = box;
    append(hollow, flipped(boxPoly(Vec3(0.25, 0.25, 0.25), Vec3(0.75, 0.75, 0.75))));
    const auto r = solidMassProperties(toMesh(hollow), 2.0);
    REQUIRE(r.ok());
    checkRel(r.value().volume, 1.0 - 0.125, 1e-12);
    const Mat3 I = boxMass(Vec3(1, 1, 1), 2.0).inertia - boxMass(Vec3(0.5, 0.5, 0.5), 2.0).inertia;
    checkRel(r.value().inertia, I, 1e-9);
  }
  SUBCASE("two boxes stacked, touching face to face without shared corners") {
    Poly two = box;
    append(two, boxPoly(Vec3(0.5, 1, 0), Vec3(1.5, 2, 1)));
    const auto r = solidMassProperties(toMesh(two), 1.0);
    REQUIRE(r.ok());
    checkRel(r.value().volume, 2.0, 1e-12);
    checkRel(r.value().center_of_mass, Vec3(0.75, 1, 0.5), 1e-12, 1.0);
  }
}

TEST_CASE("mass properties: the solid checks stay fast for tens of thousands of triangles") {
  const double r = 0.8;
  const Poly sphere = icosphere(r, 6);  // 81920 triangles
  REQUIRE(sphere.t.size() == 81920);
  const auto start = std::chrono::steady_clock::now();
  const auto m = solidMassProperties(toMesh(sphere), 1.0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  MESSAGE("solidMassProperties on 81920 triangles: " << seconds << " s");
  REQUIRE(m.ok());
  checkRel(m.value().volume, sphereMass(r, 1.0).volume, 1e-3);
  CHECK(seconds < 5.0);  // sweep and prune; all pairs would take minutes
  // The same surface with every vertex repeated per triangle.
  const auto w = solidMassProperties(toMesh(unwelded(sphere)), 1.0);
  REQUIRE(w.ok());
  CHECK(w.value().volume == m.value().volume);
  // One vertex pulled through to the far side: its fan of triangles spikes through the sphere.
  Poly spiked = sphere;
  spiked.v[100] *= -1.2;
  const auto s0 = std::chrono::steady_clock::now();
  const std::string msg = refusal(solidMassProperties(toMesh(spiked), 1.0));
  MESSAGE("refusing the spiked sphere: " << std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count()
                                         << " s");
  CHECK_MESSAGE(has(msg, "intersects itself"), msg);
}
