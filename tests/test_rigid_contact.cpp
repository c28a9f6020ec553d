// The rigid-body narrow phase (sim/rigid/contact.h, sim/rigid/hull.h): contacts that match the
// geometry worked by hand: depths, normals, midpoint positions, point counts, stable feature ids.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/math.h"
#include "core/random.h"
#include "sim/rigid/contact.h"
#include "sim/rigid/hull.h"

using namespace reel;

namespace {

ConvexShape sphereShape(double r) {
  ConvexShape s;
  s.kind = CoreKind::Point;
  s.radius = r;
  return s;
}

ConvexShape capsuleShape(const Vec3& a, const Vec3& b, double r) {
  ConvexShape s;
  s.kind = CoreKind::Segment;
  s.a = a;
  s.b = b;
  s.radius = r;
  return s;
}

ConvexShape polytopeShape(ConvexPolytope p) {
  ConvexShape s;
  s.kind = CoreKind::Polytope;
  s.poly = std::make_shared<const ConvexPolytope>(std::move(p));
  return s;
}

ConvexShape boxShape(const Vec3& half) { return polytopeShape(boxPolytope(half)); }

Pose at(const Vec3& p, const Mat3& R = Mat3::Identity()) { return {R, p}; }

Mat3 aboutX(double deg) { return Eigen::AngleAxisd(deg * kPi / 180, Vec3::UnitX()).toRotationMatrix(); }
Mat3 aboutY(double deg) { return Eigen::AngleAxisd(deg * kPi / 180, Vec3::UnitY()).toRotationMatrix(); }
Mat3 aboutZ(double deg) { return Eigen::AngleAxisd(deg * kPi / 180, Vec3::UnitZ()).toRotationMatrix(); }

std::vector<double> depthsOf(const Manifold& m) {
  std::vector<double> d;
  for (int k = 0; k < m.count; ++k) d.push_back(m.points[static_cast<std::size_t>(k)].depth);
  std::sort(d.begin(), d.end());
  return d;
}

std::vector<std::uint32_t> idsOf(const Manifold& m) {
  std::vector<std::uint32_t> ids;
  for (int k = 0; k < m.count; ++k) ids.push_back(m.points[static_cast<std::size_t>(k)].id);
  return ids;
}

const ContactPoint& pt(const Manifold& m, int k) { return m.points[static_cast<std::size_t>(k)]; }

bool near(const Vec3& a, const Vec3& b, double tol = 1e-9) { return (a - b).norm() <= tol; }

// A well-formed closed polytope: loops counter-clockwise from outside on their face planes, every
// vertex inside every face, each edge on two faces walked both ways, Euler's V − E + F = 2.
void checkPolytope(const ConvexPolytope& p, double tol = 1e-9) {
  const auto V = p.vertices.size(), E = p.edges.size(), F = p.faces.size();
  CHECK(static_cast<long>(V) - static_cast<long>(E) + static_cast<long>(F) == 2);
  REQUIRE(p.edge_faces.size() == E);
  int bad_normal = 0, off_plane = 0, clockwise = 0, outside = 0;
  for (const auto& f : p.faces) {
    bad_normal += std::abs(f.normal.norm() - 1) > 1e-12;
    Vec3 newell(0, 0, 0);
    for (std::size_t k = 0; k < f.loop.size(); ++k) {
      const Vec3& a = p.vertices[static_cast<std::size_t>(f.loop[k])];
      const Vec3& b = p.vertices[static_cast<std::size_t>(f.loop[(k + 1) % f.loop.size()])];
      newell += a.cross(b);
      off_plane += std::abs(f.normal.dot(a) - f.offset) > tol;
    }
    clockwise += newell.normalized().dot(f.normal) < 1 - 1e-9;
    for (const Vec3& v : p.vertices) outside += f.normal.dot(v) > f.offset + tol;
  }
  CHECK(bad_normal == 0);
  CHECK(off_plane == 0);
  CHECK(clockwise == 0);
  CHECK(outside == 0);
  std::set<std::pair<int, int>> seen;
  for (std::size_t e = 0; e < E; ++e) {
    const auto [i, j] = p.edges[e];
    CHECK(seen.insert({std::min(i, j), std::max(i, j)}).second);
    const auto [f0, f1] = p.edge_faces[e];
    REQUIRE(f0 >= 0);
    REQUIRE(f1 >= 0);
    CHECK(f0 != f1);
    // Face f0 walks i → j, face f1 walks j → i
    auto walks = [&](int f, int from, int to) {
      const auto& loop = p.faces[static_cast<std::size_t>(f)].loop;
      for (std::size_t k = 0; k < loop.size(); ++k)
        if (loop[k] == from && loop[(k + 1) % loop.size()] == to) return true;
      return false;
    };
    CHECK(walks(f0, i, j));
    CHECK(walks(f1, j, i));
  }
}

}  // namespace

TEST_CASE("rigid contact: a sphere and a capsule on a half-space") {
  Manifold m;
  const Vec3 up(0, 1, 0);
  // Sphere of radius 0.5 with its centre 0.45 above the ground: 0.05 deep, midway between its
  // lowest point (y = −0.05) and the ground (y = 0)
  REQUIRE(collideHalfSpace(sphereShape(0.5), at({1, 0.45, 2}), up, 0.0, 0.01, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, Vec3(0, -1, 0)));
  CHECK(pt(m, 0).depth == doctest::Approx(0.05));
  CHECK(near(pt(m, 0).position, Vec3(1, -0.025, 2)));
  // 0.1 above: a contact only within a margin of 0.1
  CHECK_FALSE(collideHalfSpace(sphereShape(0.5), at({0, 0.6, 0}), up, 0.0, 0.05, m));
  CHECK(m.count == 0);
  REQUIRE(collideHalfSpace(sphereShape(0.5), at({0, 0.6, 0}), up, 0.0, 0.2, m));
  CHECK(pt(m, 0).depth == doctest::Approx(-0.1));
  // A tilted ground plane: the depth is along its normal
  const Vec3 n = Vec3(1, 1, 0).normalized();
  REQUIRE(collideHalfSpace(sphereShape(0.2), at(n * 0.15 + Vec3(0, 0, 3)), n, 0.0, 0.0, m));
  CHECK(pt(m, 0).depth == doctest::Approx(0.05));
  CHECK(near(m.normal, -n));
  // A capsule lying on the ground touches at both ends
  REQUIRE(collideHalfSpace(capsuleShape({-1, 0, 0}, {1, 0, 0}, 0.1), at({0, 1.09, 0}, aboutY(30)),
                           up, 1.0, 0.0, m));
  REQUIRE(m.count == 2);
  for (int k = 0; k < 2; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    CHECK(pt(m, k).position.y() == doctest::Approx(0.995));
  }
  CHECK(pt(m, 0).id != pt(m, 1).id);
  CHECK(std::abs(pt(m, 0).position.x() - pt(m, 1).position.x()) == doctest::Approx(2 * std::cos(kPi / 6)));
}

TEST_CASE("rigid contact: a box and a prism on a half-space") {
  Manifold m;
  const Vec3 up(0, 1, 0);
  // A unit box turned about y, 0.01 into the ground: its four lower corners
  REQUIRE(collideHalfSpace(boxShape({0.5, 0.5, 0.5}), at({0.3, 0.49, -0.2}, aboutY(30)), up, 0.0, 0.0, m));
  REQUIRE(m.count == 4);
  for (int k = 0; k < 4; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    CHECK(pt(m, k).position.y() == doctest::Approx(-0.005));
    CHECK((pt(m, k).position - Vec3(0.3, 0, -0.2)).norm() == doctest::Approx(std::sqrt(0.5)).epsilon(1e-3));
  }
  const auto ids = idsOf(m);
  CHECK(std::set<std::uint32_t>(ids.begin(), ids.end()).size() == 4);
  // A 12-sided prism standing on its cap: twelve corners within reach, the manifold keeps the four
  // spanning the most area (a square inscribed in the circle: area 2r²)
  const ConvexShape prism = polytopeShape(prismPolytope(0.5, 0.3, 12));
  REQUIRE(collideHalfSpace(prism, at({0, 0.29, 0}), up, 0.0, 0.0, m));
  REQUIRE(m.count == 4);
  for (int k = 0; k < 4; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.01));
  const Vec3 d1 = pt(m, 2).position - pt(m, 0).position, d2 = pt(m, 3).position - pt(m, 1).position;
  CHECK(0.5 * d1.cross(d2).norm() == doctest::Approx(2 * 0.25).epsilon(1e-9));
  // Lying on its side (axis along z): one corner of each cap ring is lowest
  REQUIRE(collideHalfSpace(prism, at({0, 0.49, 0}, aboutX(90)), up, 0.0, 0.0, m));
  REQUIRE(m.count == 2);
  for (int k = 0; k < 2; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.01));
  CHECK(std::abs(pt(m, 0).position.z() - pt(m, 1).position.z()) == doctest::Approx(0.6));
  // Well clear: nothing
  CHECK_FALSE(collideHalfSpace(prism, at({0, 0.4, 0}), up, 0.0, 0.05, m));
}

TEST_CASE("rigid contact: spheres and capsules") {
  Manifold m;
  // Two spheres overlapping by 0.1 along x: the point midway between the two surfaces
  REQUIRE(collide(sphereShape(0.5), at({0, 0, 0}), sphereShape(0.5), at({0.9, 0, 0}), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, Vec3(1, 0, 0)));
  CHECK(pt(m, 0).depth == doctest::Approx(0.1));
  CHECK(near(pt(m, 0).position, Vec3(0.45, 0, 0)));
  // A sphere beside the middle of a capsule, and beyond its end
  const ConvexShape cap = capsuleShape({-1, 0, 0}, {1, 0, 0}, 0.2);
  REQUIRE(collide(sphereShape(0.3), at({0.4, 0.45, 0}), cap, at({0, 0, 0}), 0.0, m));
  CHECK(near(m.normal, Vec3(0, -1, 0)));
  CHECK(pt(m, 0).depth == doctest::Approx(0.05));
  CHECK(near(pt(m, 0).position, Vec3(0.4, 0.175, 0)));
  const Vec3 beyond = Vec3(1, 0, 0) + 0.45 * Vec3(1, 1, 0).normalized();
  REQUIRE(collide(sphereShape(0.3), at(beyond), cap, at({0, 0, 0}), 0.0, m));
  CHECK(near(m.normal, -Vec3(1, 1, 0).normalized()));
  CHECK(pt(m, 0).depth == doctest::Approx(0.05));
  // Two parallel capsules, one on the other, overlapping along x over [−0.5, 1]: two points at the
  // ends of the overlap
  const ConvexShape upper = capsuleShape({-1, 0, 0}, {1, 0, 0}, 0.2);
  REQUIRE(collide(cap, at({0, 0, 0}), upper, at({0.5, 0.35, 0}), 0.0, m));
  REQUIRE(m.count == 2);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  std::vector<double> xs;
  for (int k = 0; k < 2; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.05));
    CHECK(pt(m, k).position.y() == doctest::Approx(0.175));
    xs.push_back(pt(m, k).position.x());
  }
  std::sort(xs.begin(), xs.end());
  CHECK(xs[0] == doctest::Approx(-0.5));
  CHECK(xs[1] == doctest::Approx(1.0));
  CHECK(pt(m, 0).id != pt(m, 1).id);
  // Crossing capsules: one point where they cross
  REQUIRE(collide(cap, at({0, 0, 0}), upper, at({0.2, 0.35, 0.1}, aboutY(90)), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  CHECK(pt(m, 0).depth == doctest::Approx(0.05));
  CHECK(near(pt(m, 0).position, Vec3(0.2, 0.175, 0)));
  // Cores that meet: the normal still points from A toward B, across both segments
  REQUIRE(collide(cap, at({0, 0, 0}), upper, at({0, 0, 0}, aboutY(90)), 0.0, m));
  CHECK(std::abs(m.normal.norm() - 1) < 1e-12);
  CHECK(pt(m, 0).depth == doctest::Approx(0.4));
}

TEST_CASE("rigid contact: a sphere at a box's corner is at the exact distance") {
  Manifold m;
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  const Vec3 diag = Vec3(1, 1, 1).normalized();
  // 0.1 from the corner along the diagonal: a face plane alone would say 0.1/√3
  const Vec3 c = Vec3(0.5, 0.5, 0.5) + 0.1 * diag;
  REQUIRE(collide(sphereShape(0.15), at(c), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, -diag, 1e-12));
  CHECK(std::abs(pt(m, 0).depth - 0.05) < 1e-12);
  CHECK(near(pt(m, 0).position, Vec3(0.5, 0.5, 0.5) - 0.025 * diag, 1e-12));  // sphere 0.05 inside
  // The same with the box turned and moved: distance is frame-free
  const Mat3 R = rotationFromEulerDeg({20, -35, 50});
  const Vec3 p(1, -2, 0.5);
  REQUIRE(collide(sphereShape(0.15), at(R * c + p), box, at(p, R), 0.0, m));
  CHECK(std::abs(pt(m, 0).depth - 0.05) < 1e-12);
  CHECK(near(m.normal, -(R * diag), 1e-12));
  // Beside an edge: the distance to the edge
  const Vec3 e = Vec3(0.5, 0.5, 0.1) + 0.1 * Vec3(1, 1, 0).normalized();
  REQUIRE(collide(sphereShape(0.15), at(e), box, at({0, 0, 0}), 0.0, m));
  CHECK(std::abs(pt(m, 0).depth - 0.05) < 1e-12);
  // Out of reach of the corner (0.2 away) though within reach of each face plane (0.115)
  CHECK_FALSE(collide(sphereShape(0.15), at(Vec3(0.5, 0.5, 0.5) + 0.2 * diag), box, at({0, 0, 0}), 0.0, m));
}

TEST_CASE("rigid contact: a sphere inside a box pushes out through the nearest face") {
  Manifold m;
  const ConvexShape box = boxShape({1, 0.5, 1});
  REQUIRE(collide(sphereShape(0.1), at({0.2, 0.3, 0}), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, Vec3(0, -1, 0)));  // the sphere leaves upward: from it toward the box is down
  CHECK(pt(m, 0).depth == doctest::Approx(0.3));
  CHECK(near(pt(m, 0).position, Vec3(0.2, 0.35, 0)));
}

TEST_CASE("rigid contact: a capsule on a box") {
  Manifold m;
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  // Lying on the top face, 0.01 deep: both ends
  const ConvexShape cap = capsuleShape({-0.3, 0, 0}, {0.3, 0, 0}, 0.1);
  REQUIRE(collide(cap, at({0, 0.59, 0.1}, aboutY(20)), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 2);
  CHECK(near(m.normal, Vec3(0, -1, 0)));
  for (int k = 0; k < 2; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    CHECK(pt(m, k).position.y() == doctest::Approx(0.495));
  }
  CHECK(std::abs(pt(m, 0).position.x() - pt(m, 1).position.x()) == doctest::Approx(0.6 * std::cos(kPi / 9)));
  const auto ids = idsOf(m);
  // Sunk so deep that the core is inside the box: the same two points, deeper
  REQUIRE(collide(cap, at({0, 0.45, 0.1}, aboutY(20)), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 2);
  for (int k = 0; k < 2; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.15));
  CHECK(idsOf(m) == ids);
  // Hanging over the edge: the part over the face, cut at the edge
  REQUIRE(collide(cap, at({0.5, 0.59, 0}), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 2);
  std::vector<double> xs{pt(m, 0).position.x(), pt(m, 1).position.x()};
  std::sort(xs.begin(), xs.end());
  CHECK(xs[0] == doctest::Approx(0.2));
  CHECK(xs[1] == doctest::Approx(0.5));
  // Box first: the normal flips, the points stay
  REQUIRE(collide(box, at({0, 0, 0}), cap, at({0, 0.59, 0.1}, aboutY(20)), 0.0, m));
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  CHECK(m.count == 2);
}

TEST_CASE("rigid contact: a capsule across a box's edge touches at one point") {
  Manifold m;
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  const Vec3 out = Vec3(1, 1, 0).normalized();
  // Across the top edge along z (x = y = 0.5), 0.1·√2 from it
  const ConvexShape cap = capsuleShape({0.3, 0.9, 0}, {0.9, 0.3, 0}, 0.15);
  REQUIRE(collide(cap, at({0, 0, 0}), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, -out, 1e-12));
  CHECK(pt(m, 0).depth == doctest::Approx(0.15 - 0.1 * std::sqrt(2.0)));
  const double mid = 0.5 * (0.1 * std::sqrt(2.0) - 0.15);  // along `out` from the edge
  CHECK(near(pt(m, 0).position, Vec3(0.5, 0.5, 0) + mid * out, 1e-12));
  // The core cutting the corner (an edge × segment axis): 0.05/√2 inside the edge
  const ConvexShape cut = capsuleShape({0.3, 0.65, 0}, {0.65, 0.3, 0}, 0.1);
  REQUIRE(collide(cut, at({0, 0, 0}), box, at({0, 0, 0}), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, -out, 1e-12));
  CHECK(pt(m, 0).depth == doctest::Approx(0.1 + 0.05 / std::sqrt(2.0)));
}

TEST_CASE("rigid contact: a box resting on a box") {
  Manifold m;
  const ConvexShape table = boxShape({2, 0.5, 2});
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  REQUIRE(collide(table, at({0, 0, 0}), box, at({0.1, 0.99, -0.2}, aboutY(10)), 0.0, m));
  REQUIRE(m.count == 4);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  for (int k = 0; k < 4; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    CHECK(pt(m, k).position.y() == doctest::Approx(0.495));
    CHECK((pt(m, k).position - Vec3(0.1, 0.495, -0.2)).norm() == doctest::Approx(std::sqrt(0.5)));
  }
  const auto ids = idsOf(m);
  CHECK(std::set<std::uint32_t>(ids.begin(), ids.end()).size() == 4);
  // A tiny shift and turn: the same features, the same ids in the same order
  REQUIRE(collide(table, at({0, 0, 0}), box, at({0.1013, 0.9893, -0.2021}, aboutY(10.2)), 0.0, m));
  REQUIRE(m.count == 4);
  CHECK(idsOf(m) == ids);
  for (int k = 0; k < 4; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.0107));
  // The whole stack moved and turned: the same contacts, carried along
  const Mat3 R = rotationFromEulerDeg({15, 40, -25});
  const Vec3 p(3, 1, -2);
  REQUIRE(collide(table, at(p, R), box, at(R * Vec3(0.1, 0.99, -0.2) + p, R * aboutY(10)), 0.0, m));
  REQUIRE(m.count == 4);
  CHECK(near(m.normal, R * Vec3(0, 1, 0), 1e-12));
  CHECK(idsOf(m) == ids);
  for (int k = 0; k < 4; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.01));
}

TEST_CASE("rigid contact: a box turned 45° on a box keeps 4 of the 8 clipped points") {
  Manifold m;
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  REQUIRE(collide(box, at({0, 0, 0}), box, at({0, 0.99, 0}, aboutY(45)), 0.0, m));
  REQUIRE(m.count == 4);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  // Every point a corner of the octagon where the square (|x|, |z| ≤ 0.5) and the diamond
  // (|x| + |z| ≤ √½) cross
  for (int k = 0; k < 4; ++k) {
    const Vec3& x = pt(m, k).position;
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    CHECK(std::max(std::abs(x.x()), std::abs(x.z())) == doctest::Approx(0.5));
    CHECK(std::abs(x.x()) + std::abs(x.z()) == doctest::Approx(std::sqrt(0.5)));
  }
  // Spanning most of the octagon: the four points' quadrilateral has at least half its area
  const Vec3 d1 = pt(m, 2).position - pt(m, 0).position, d2 = pt(m, 3).position - pt(m, 1).position;
  const double octagon = 1.0 - 4 * 0.5 * std::pow(1 - std::sqrt(0.5), 2);
  CHECK(0.5 * d1.cross(d2).norm() > 0.5 * octagon);
}

TEST_CASE("rigid contact: a box on its edge and on its corner on a box") {
  Manifold m;
  const ConvexShape table = boxShape({2, 0.5, 2});
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  const double h = std::sqrt(0.5);  // half a face diagonal
  // On its edge (turned 45° about x): the two ends of the lowest edge
  REQUIRE(collide(table, at({0, 0, 0}), box, at({0.2, 0.5 + h - 0.01, 0.3}, aboutX(45)), 0.0, m));
  REQUIRE(m.count == 2);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  std::vector<double> xs;
  for (int k = 0; k < 2; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    CHECK(pt(m, k).position.z() == doctest::Approx(0.3));
    xs.push_back(pt(m, k).position.x());
  }
  std::sort(xs.begin(), xs.end());
  CHECK(xs[0] == doctest::Approx(-0.3));
  CHECK(xs[1] == doctest::Approx(0.7));
  // On its corner (a long diagonal vertical): one point
  const Mat3 R = Eigen::Quaterniond::FromTwoVectors(Vec3(-1, -1, -1).normalized(), Vec3(0, -1, 0))
                     .toRotationMatrix();
  const double c = std::sqrt(0.75);  // half the long diagonal
  REQUIRE(collide(table, at({0, 0, 0}), box, at({-0.4, 0.5 + c - 0.01, 0.1}, R), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  CHECK(pt(m, 0).depth == doctest::Approx(0.01));
  CHECK(near(pt(m, 0).position, Vec3(-0.4, 0.495, 0.1)));
}

TEST_CASE("rigid contact: crossed box edges touch at one point") {
  Manifold m;
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  const double h = std::sqrt(0.5);
  // A's top edge runs along z at height √½, B's bottom edge along x, 0.01 lower
  REQUIRE(collide(box, at({0, 0, 0}, aboutZ(45)), box, at({0.05, 2 * h - 0.01, -0.1}, aboutX(45)), 0.0, m));
  REQUIRE(m.count == 1);
  CHECK(near(m.normal, Vec3(0, 1, 0), 1e-12));
  CHECK(pt(m, 0).depth == doctest::Approx(0.01));
  CHECK(near(pt(m, 0).position, Vec3(0, h - 0.005, -0.1), 1e-12));
  // Swapped: the normal turns, the point stays
  REQUIRE(collide(box, at({0.05, 2 * h - 0.01, -0.1}, aboutX(45)), box, at({0, 0, 0}, aboutZ(45)), 0.0, m));
  CHECK(near(m.normal, Vec3(0, -1, 0), 1e-12));
  CHECK(pt(m, 0).depth == doctest::Approx(0.01));
  CHECK(near(pt(m, 0).position, Vec3(0, h - 0.005, -0.1), 1e-12));
}

TEST_CASE("rigid contact: a triangle under a box") {
  Manifold m;
  // Front face up (counter-clockwise from above)
  const ConvexShape tri = polytopeShape(trianglePolytope({-2, 0, -2}, {0, 0, 2}, {2, 0, -2}));
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  REQUIRE(collide(tri, at({0, 0, 0}), box, at({0, 0.49, -0.8}, aboutY(15)), 0.0, m));
  REQUIRE(m.count == 4);
  CHECK(near(m.normal, Vec3(0, 1, 0)));
  for (int k = 0; k < 4; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.01));
  // Under its back face
  REQUIRE(collide(tri, at({0, 0, 0}), box, at({0, -0.49, -0.8}), 0.0, m));
  REQUIRE(m.count == 4);
  CHECK(near(m.normal, Vec3(0, -1, 0)));
  for (int k = 0; k < 4; ++k) CHECK(pt(m, k).depth == doctest::Approx(0.01));
  // A box edge across the triangle's edge (x = 2 − |…|): a corner of the box over the triangle's
  // border, box turned about y, resting: still face contacts, clipped to the triangle
  REQUIRE(collide(tri, at({0, 0, 0}), box, at({1.2, 0.49, -1.6}, aboutY(30)), 0.0, m));
  CHECK(m.count >= 3);
  for (int k = 0; k < m.count; ++k) {
    CHECK(pt(m, k).depth == doctest::Approx(0.01));
    const Vec3& x = pt(m, k).position;
    CHECK(x.z() >= -2 - 1e-7);
    CHECK(2 * x.x() + x.z() <= 2 + 1e-7);  // right edge: from (2, −2) to (0, 2)
  }
  // A sphere on the triangle's edge
  const Vec3 edgeOut = Vec3(2, 0, 1).normalized();  // outward in-plane normal of the right edge
  const Vec3 onEdge(1, 0, 0);
  REQUIRE(collide(sphereShape(0.2), at(onEdge + 0.15 * edgeOut), tri, at({0, 0, 0}), 0.0, m));
  CHECK(pt(m, 0).depth == doctest::Approx(0.05));
  CHECK(near(m.normal, -edgeOut, 1e-12));
}

TEST_CASE("rigid contact: margin gives speculative contacts with negative depth") {
  Manifold m;
  const ConvexShape table = boxShape({2, 0.5, 2});
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  // 0.01 apart
  REQUIRE(collide(table, at({0, 0, 0}), box, at({0, 1.01, 0}), 0.02, m));
  REQUIRE(m.count == 4);
  for (int k = 0; k < 4; ++k) CHECK(pt(m, k).depth == doctest::Approx(-0.01));
  CHECK_FALSE(collide(table, at({0, 0, 0}), box, at({0, 1.01, 0}), 0.005, m));
  CHECK(m.count == 0);
  // The same for spheres, capsules and the half-space
  REQUIRE(collide(sphereShape(0.5), at({0, 0, 0}), sphereShape(0.5), at({1.01, 0, 0}), 0.02, m));
  CHECK(pt(m, 0).depth == doctest::Approx(-0.01));
  CHECK_FALSE(collide(sphereShape(0.5), at({0, 0, 0}), sphereShape(0.5), at({1.01, 0, 0}), 0.005, m));
  const ConvexShape cap = capsuleShape({-0.3, 0, 0}, {0.3, 0, 0}, 0.1);
  REQUIRE(collide(cap, at({0, 0.61, 0}), box, at({0, 0, 0}), 0.02, m));
  REQUIRE(m.count == 2);
  for (int k = 0; k < 2; ++k) CHECK(pt(m, k).depth == doctest::Approx(-0.01));
  CHECK_FALSE(collide(cap, at({0, 0.61, 0}), box, at({0, 0, 0}), 0.005, m));
  REQUIRE(collide(sphereShape(0.2), at({0, 0.5 + 0.21, 0}), box, at({0, 0, 0}), 0.02, m));
  CHECK(pt(m, 0).depth == doctest::Approx(-0.01));
  CHECK_FALSE(collide(sphereShape(0.2), at({0, 0.5 + 0.21, 0}), box, at({0, 0, 0}), 0.005, m));
  REQUIRE(collideHalfSpace(box, at({0, 0.51, 0}), Vec3(0, 1, 0), 0.0, 0.02, m));
  CHECK(m.count == 4);
  CHECK(pt(m, 0).depth == doctest::Approx(-0.01));
  CHECK_FALSE(collideHalfSpace(box, at({0, 0.51, 0}), Vec3(0, 1, 0), 0.0, 0.005, m));
}

TEST_CASE("rigid contact: swapping A and B flips the normal and keeps the depths") {
  const ConvexShape box = boxShape({0.5, 0.5, 0.5});
  const ConvexShape table = boxShape({2, 0.5, 2});
  const ConvexShape cap = capsuleShape({-0.3, 0, 0}, {0.3, 0, 0}, 0.1);
  const ConvexShape prism = polytopeShape(prismPolytope(0.4, 0.3, 10));
  struct Pair {
    const ConvexShape* a;
    Pose pa;
    const ConvexShape* b;
    Pose pb;
  };
  const Vec3 corner = Vec3(0.5, 0.5, 0.5) + 0.1 * Vec3(1, 1, 1).normalized();
  const ConvexShape sphere = sphereShape(0.15);
  const std::vector<Pair> pairs = {
      {&table, at({0, 0, 0}), &box, at({0.1, 0.99, -0.2}, aboutY(10))},
      {&box, at({0, 0, 0}), &box, at({0, 0.99, 0}, aboutY(45))},
      {&sphere, at(corner), &box, at({0, 0, 0})},
      {&cap, at({0, 0.59, 0}, aboutY(20)), &box, at({0, 0, 0})},
      {&cap, at({0, 0, 0}), &cap, at({0.1, 0.15, 0})},
      {&prism, at({0, 0.78, 0}, aboutX(90)), &box, at({0, 0, 0})},
      {&prism, at({0.2, 0.3, 0.1}, rotationFromEulerDeg({30, 10, 50})), &box, at({0, 0, 0}, aboutY(20))},
  };
  for (const Pair& p : pairs) {
    Manifold ab, ba;
    REQUIRE(collide(*p.a, p.pa, *p.b, p.pb, 0.01, ab));
    REQUIRE(collide(*p.b, p.pb, *p.a, p.pa, 0.01, ba));
    CHECK(near(ab.normal, -ba.normal, 1e-9));
    const auto da = depthsOf(ab), db = depthsOf(ba);
    REQUIRE(da.size() == db.size());
    for (std::size_t k = 0; k < da.size(); ++k) CHECK(da[k] == doctest::Approx(db[k]));
  }
}

TEST_CASE("rigid contact: bounds enclose the shapes") {
  Vec3 lo, hi;
  shapeBounds(boxShape({0.5, 0.5, 0.5}), at({1, 2, 3}, aboutY(45)), lo, hi);
  CHECK(near(lo, Vec3(1 - std::sqrt(0.5), 1.5, 3 - std::sqrt(0.5))));
  CHECK(near(hi, Vec3(1 + std::sqrt(0.5), 2.5, 3 + std::sqrt(0.5))));
  shapeBounds(capsuleShape({-1, 0, 0}, {1, 0, 0}, 0.2), at({0, 1, 0}, aboutZ(90)), lo, hi);
  CHECK(near(lo, Vec3(-0.2, -0.2, -0.2)));
  CHECK(near(hi, Vec3(0.2, 2.2, 0.2)));
  shapeBounds(sphereShape(0.3), at({1, 1, 1}), lo, hi);
  CHECK(near(lo, Vec3(0.7, 0.7, 0.7)));
  CHECK(near(hi, Vec3(1.3, 1.3, 1.3)));
}

TEST_CASE("convex polytopes: box, prism and triangle are well formed") {
  const ConvexPolytope box = boxPolytope({0.5, 1, 1.5});
  CHECK(box.vertices.size() == 8);
  CHECK(box.faces.size() == 6);
  CHECK(box.edges.size() == 12);
  checkPolytope(box);
  const ConvexPolytope prism = prismPolytope(0.5, 0.3, 12);
  CHECK(prism.vertices.size() == 24);
  CHECK(prism.faces.size() == 14);
  CHECK(prism.edges.size() == 36);
  checkPolytope(prism);
  const ConvexPolytope tri = trianglePolytope({0, 0, 0}, {1, 0, 0}, {0, 0, -1});
  CHECK(tri.faces.size() == 2);
  CHECK(tri.edges.size() == 3);
  CHECK(near(tri.faces[0].normal, Vec3(0, 1, 0)));
  CHECK(near(tri.faces[1].normal, Vec3(0, -1, 0)));
}

TEST_CASE("convex hull: cube corners with interior, on-face and on-edge points") {
  std::vector<Vec3> pts = {{0, 0, 0}, {0.1, -0.2, 0.3}, {0.5, 0.1, 0.2}, {-0.2, 0.5, 0}, {0, 0, -0.5},
                           {0.5, 0.5, 0}, {-0.3, -0.5, 0.4}};
  for (int i = 0; i < 8; ++i) pts.emplace_back((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
  const auto hull = convexHull(pts);
  REQUIRE(hull.has_value());
  CHECK(hull->vertices.size() == 8);
  CHECK(hull->faces.size() == 6);
  CHECK(hull->edges.size() == 12);
  checkPolytope(*hull);
  std::set<std::pair<int, int>> axes;  // (axis, sign) of every face normal
  for (const auto& f : hull->faces) {
    CHECK(f.loop.size() == 4);
    CHECK(f.offset == doctest::Approx(0.5));
    for (int ax = 0; ax < 3; ++ax)
      if (std::abs(f.normal[ax]) > 0.999) axes.insert({ax, f.normal[ax] > 0 ? 1 : -1});
  }
  CHECK(axes.size() == 6);
  for (const Vec3& v : hull->vertices) CHECK(v.cwiseAbs().minCoeff() == doctest::Approx(0.5));
  // As a shape it rests on a box like a box
  Manifold m;
  REQUIRE(collide(boxShape({2, 0.5, 2}), at({0, 0, 0}), polytopeShape(*hull), at({0, 0.99, 0}), 0.0, m));
  CHECK(m.count == 4);
  CHECK(pt(m, 0).depth == doctest::Approx(0.01));
}

TEST_CASE("convex hull: a random point cloud") {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    std::vector<Vec3> pts;
    for (std::uint64_t i = 0; i < 300; ++i) {
      const Vec3 d = sphereDirection(uniformAt(seed, 0, i), uniformAt(seed, 1, i));
      const double r = seed % 2 ? std::cbrt(uniformAt(seed, 2, i)) : 1.0;  // in a ball, on a sphere
      pts.push_back(Vec3(2, 1, 0.5).cwiseProduct(r * d) + Vec3(3, -1, 2));
    }
    const auto hull = convexHull(pts);
    REQUIRE(hull.has_value());
    checkPolytope(*hull, 1e-9);
    // Every point inside or on every face plane; every corner an input point
    int outside = 0, foreign = 0;
    for (const auto& f : hull->faces)
      for (const Vec3& p : pts) outside += f.normal.dot(p) > f.offset + 1e-9;
    for (const Vec3& v : hull->vertices)
      foreign += std::none_of(pts.begin(), pts.end(), [&](const Vec3& p) { return p == v; });
    CHECK(outside == 0);
    CHECK(foreign == 0);
    CHECK(hull->vertices.size() >= 20);
    // And the same again: deterministic
    const auto again = convexHull(pts);
    REQUIRE(again.has_value());
    CHECK(again->vertices == hull->vertices);
    CHECK(again->edges == hull->edges);
  }
}

TEST_CASE("convex hull: no volume, no hull") {
  std::vector<Vec3> plane, line;
  for (int i = 0; i < 20; ++i) {
    plane.emplace_back(std::cos(i), 0.5 * std::sin(3 * i), 0.25);
    line.emplace_back(0.1 * i, 0.2 * i, -0.05 * i);
  }
  CHECK_FALSE(convexHull(plane).has_value());
  CHECK_FALSE(convexHull(line).has_value());
  // Nearly flat: thinner than a millionth of the extent
  plane.emplace_back(0, 0, 0.25 + 1e-9);
  CHECK_FALSE(convexHull(plane).has_value());
  CHECK_FALSE(convexHull(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).has_value());
}

namespace {

// Separation of two posed polytopes over every candidate axis (all face normals, every edge pair's
// cross product: no pruning), m; negative: the penetration depth.
double bruteForceSeparation(const ConvexPolytope& A, const Pose& pa, const ConvexPolytope& B, const Pose& pb) {
  std::vector<Vec3> va, vb, axes;
  for (const Vec3& v : A.vertices) va.push_back(pa.R * v + pa.p);
  for (const Vec3& v : B.vertices) vb.push_back(pb.R * v + pb.p);
  for (const auto& f : A.faces) axes.push_back(pa.R * f.normal);
  for (const auto& f : B.faces) axes.push_back(pb.R * f.normal);
  for (const auto& ea : A.edges)
    for (const auto& eb : B.edges) {
      const Vec3 u = (pa.R * (A.vertices[static_cast<std::size_t>(ea[1])] - A.vertices[static_cast<std::size_t>(ea[0])]))
                         .cross(pb.R * (B.vertices[static_cast<std::size_t>(eb[1])] - B.vertices[static_cast<std::size_t>(eb[0])]));
      if (u.norm() > 1e-9) axes.push_back(u.normalized());
    }
  double best = -1e300;
  for (const Vec3& u : axes) {
    double loA = 1e300, hiA = -1e300, loB = 1e300, hiB = -1e300;
    for (const Vec3& v : va) loA = std::min(loA, u.dot(v)), hiA = std::max(hiA, u.dot(v));
    for (const Vec3& v : vb) loB = std::min(loB, u.dot(v)), hiB = std::max(hiB, u.dot(v));
    best = std::max(best, std::max(loB - hiA, loA - hiB));
  }
  return best;
}

// Whether world point x lies inside the posed polytope, within tol.
bool insidePolytope(const ConvexPolytope& P, const Pose& p, const Vec3& x, double tol) {
  const Vec3 l = p.R.transpose() * (x - p.p);
  return std::all_of(P.faces.begin(), P.faces.end(),
                     [&](const ConvexPolytope::Face& f) { return f.normal.dot(l) <= f.offset + tol; });
}

Mat3 randomRotation(std::uint64_t seed, std::uint64_t i) {
  const Vec3 axis = sphereDirection(uniformAt(seed, 10, i), uniformAt(seed, 11, i));
  return Eigen::AngleAxisd(2 * kPi * uniformAt(seed, 12, i), axis).toRotationMatrix();
}

}  // namespace

TEST_CASE("rigid contact: random polytope pairs agree with a brute-force separating-axis test") {
  std::vector<Vec3> cloud;
  for (std::uint64_t i = 0; i < 40; ++i)
    cloud.push_back(0.5 * sphereDirection(uniformAt(7, 0, i), uniformAt(7, 1, i)).cwiseProduct(Vec3(1, 0.6, 0.8)));
  const std::vector<ConvexShape> shapes = {
      boxShape({0.5, 0.5, 0.5}), boxShape({0.8, 0.2, 0.4}), polytopeShape(prismPolytope(0.4, 0.3, 7)),
      polytopeShape(*convexHull(cloud)), polytopeShape(trianglePolytope({-0.6, 0, -0.5}, {0, 0, 0.7}, {0.6, 0, -0.4}))};
  const double margin = 0.02;
  int hits = 0, misses = 0, deep_unseen = 0, not_inside = 0, too_deep = 0, too_shallow = 0, not_freed = 0;
  for (std::uint64_t i = 0; i < 3000; ++i) {
    const ConvexShape& A = shapes[i % shapes.size()];
    const ConvexShape& B = shapes[(i / shapes.size()) % shapes.size()];
    const Pose pa = at(Vec3(0, 0, 0), randomRotation(1, i));
    const Pose pb = at(0.9 * Vec3(uniformAt(2, 0, i) - 0.5, uniformAt(2, 1, i) - 0.5, uniformAt(2, 2, i) - 0.5) * 2,
                       randomRotation(3, i));
    const double sep = bruteForceSeparation(*A.poly, pa, *B.poly, pb);
    if (std::abs(sep - margin) < 1e-9) continue;
    Manifold m;
    const bool hit = collide(A, pa, B, pb, margin, m);
    // Within the margin exactly when the brute-force axes say so (a flat triangle may still miss:
    // a pair within the margin whose clipped points all lie farther)
    if (hit) ++hits; else ++misses;
    if (sep < -1e-6 && !hit) ++deep_unseen;
    if (!hit) {
      CHECK(sep > -1e-6);
      continue;
    }
    CHECK(sep <= margin + 1e-9);
    CHECK(std::abs(m.normal.norm() - 1) < 1e-12);
    // Shallow overlaps of solids (not the flat triangle): every penetrating point is in both
    const bool shallow = sep > -0.05 && A.poly->faces.size() > 2 && B.poly->faces.size() > 2;
    double deepest = -1e300;
    for (int k = 0; k < m.count; ++k) {
      const ContactPoint& c = pt(m, k);
      deepest = std::max(deepest, c.depth);
      // A penetrating point lies in both solids
      // (a point clipped at the side plane of a reference face can stick out past a slanted
      // neighbour face by a fraction of its half depth)
      const double tol = 1e-7 + 0.1 * c.depth;
      if (shallow && c.depth > 1e-9 &&
          !(insidePolytope(*A.poly, pa, c.position, tol) && insidePolytope(*B.poly, pb, c.position, tol)))
        ++not_inside;
    }
    // As deep as the best axis says (up to the face preference), and, when shallow, moving B out
    // by the deepest contact along the normal frees it
    const double slack = 0.05 * std::abs(sep) + 2e-3;
    if (deepest > -sep + slack) ++too_deep;
    if (sep > -0.05 && deepest < -sep - slack) ++too_shallow;
    Pose moved = pb;
    moved.p += (deepest + 1e-7) * m.normal;
    if (sep > -0.05 && bruteForceSeparation(*A.poly, pa, *B.poly, moved) < -1e-6) ++not_freed;
  }
  CHECK(hits > 500);
  CHECK(misses > 500);
  CHECK(deep_unseen == 0);
  CHECK(not_inside == 0);
  CHECK(too_deep == 0);
  CHECK(too_shallow == 0);
  CHECK(not_freed == 0);
}

namespace {

// Signed distance from x to a box of half extents h at the origin (exact inside and out).
double boxDistance(const Vec3& h, const Vec3& x) {
  const Vec3 q = x.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

}  // namespace

TEST_CASE("rigid contact: random spheres and capsules against a box agree with its exact distance") {
  const Vec3 half(0.5, 0.3, 0.4);
  const ConvexShape box = boxShape(half);
  int hits = 0, wrong_depth = 0, wrong_normal = 0, wrong_hit = 0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const Vec3 c = Vec3(uniformAt(4, 0, i) - 0.5, uniformAt(4, 1, i) - 0.5, uniformAt(4, 2, i) - 0.5) * 2.2;
    const double r = 0.05 + 0.3 * uniformAt(4, 3, i), margin = 0.02;
    const double d = boxDistance(half, c);
    Manifold m;
    // Sphere: depth r − distance exactly; the normal the distance's gradient, reversed
    const bool hit = collide(sphereShape(r), at(c), box, at({0, 0, 0}), margin, m);
    if (hit != (d - r <= margin)) ++wrong_hit;
    if (!hit) continue;
    ++hits;
    if (std::abs(m.points[0].depth - (r - d)) > 1e-12) ++wrong_depth;
    if (d > 1e-6) {
      const double e = 1e-6;
      const Vec3 grad((boxDistance(half, c + e * Vec3::UnitX()) - boxDistance(half, c - e * Vec3::UnitX())) / (2 * e),
                      (boxDistance(half, c + e * Vec3::UnitY()) - boxDistance(half, c - e * Vec3::UnitY())) / (2 * e),
                      (boxDistance(half, c + e * Vec3::UnitZ()) - boxDistance(half, c - e * Vec3::UnitZ())) / (2 * e));
      if ((m.normal + grad.normalized()).norm() > 1e-6) ++wrong_normal;
    }
  }
  CHECK(hits > 300);
  CHECK(wrong_hit == 0);
  CHECK(wrong_depth == 0);
  CHECK(wrong_normal == 0);

  // Capsules whose core stays outside the box: the deepest contact is r − the least distance of
  // the segment (a convex function along it: ternary search), up to the face preference; cores
  // inside: r + the penetration of the best separating axis
  int capsule_hits = 0, capsule_inside = 0, capsule_wrong = 0, capsule_missed = 0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const Vec3 c = Vec3(uniformAt(5, 0, i) - 0.5, uniformAt(5, 1, i) - 0.5, uniformAt(5, 2, i) - 0.5) * 2.4;
    const Vec3 dir = sphereDirection(uniformAt(5, 3, i), uniformAt(5, 4, i));
    const double len = 0.8 * uniformAt(5, 5, i), r = 0.05 + 0.2 * uniformAt(5, 6, i), margin = 0.02;
    const Vec3 a = c - 0.5 * len * dir, b = c + 0.5 * len * dir;
    double lo = 0, hi = 1;
    for (int k = 0; k < 200; ++k) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (boxDistance(half, a + m1 * (b - a)) < boxDistance(half, a + m2 * (b - a))) hi = m2;
      else lo = m1;
    }
    const double d = boxDistance(half, a + 0.5 * (lo + hi) * (b - a));
    Manifold m;
    if (d <= 1e-6) {
      // The core reaches into the box: the penetration over the box's faces and its edges × the
      // segment (every face of their Minkowski difference)
      double sep = -1e300;
      std::vector<Vec3> axes = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
      for (int k = 0; k < 3; ++k)
        if (Vec3::Unit(k).cross(dir).norm() > 1e-9) axes.push_back(Vec3::Unit(k).cross(dir).normalized());
      for (const Vec3& u : axes) {
        const double reach = half.cwiseProduct(u).cwiseAbs().sum();
        sep = std::max(sep, std::max(std::min(u.dot(a), u.dot(b)) - reach, -reach - std::max(u.dot(a), u.dot(b))));
      }
      REQUIRE(collide(capsuleShape(a, b, r), at({0, 0, 0}), box, at({0, 0, 0}), margin, m));
      double deepest = -1e300;
      for (int k = 0; k < m.count; ++k) deepest = std::max(deepest, pt(m, k).depth);
      // (faces are preferred unless an edge axis separates clearly more)
      const double bias = 0.05 * std::abs(sep) + 1e-4 * (len + r) + 1e-9;
      if (std::abs(deepest - (r - sep)) > bias) ++capsule_wrong;
      ++capsule_inside;
      continue;
    }
    const bool hit = collide(capsuleShape(a, b, r), at({0, 0, 0}), box, at({0, 0, 0}), margin, m);
    if (hit != (d - r <= margin)) ++capsule_missed;
    if (!hit) continue;
    ++capsule_hits;
    double deepest = -1e300;
    for (int k = 0; k < m.count; ++k) deepest = std::max(deepest, pt(m, k).depth);
    if (deepest > r - d + 1e-9 || deepest < r - d - 1e-3 * (len + r) - 1e-9) {
      ++capsule_wrong;
      MESSAGE("capsule " << i << " deepest " << deepest << " expected " << r - d << " count " << m.count << " len " << len);
    }
  }
  CHECK(capsule_hits > 150);
  CHECK(capsule_inside > 100);
  CHECK(capsule_missed == 0);
  CHECK(capsule_wrong == 0);
}

TEST_CASE("rigid contact: random capsule pairs agree with the segments' least distance") {
  int hits = 0, wrong = 0;
  for (std::uint64_t i = 0; i < 1000; ++i) {
    auto point = [&](std::uint64_t k) {
      return Vec3(uniformAt(6, 3 * k, i), uniformAt(6, 3 * k + 1, i), uniformAt(6, 3 * k + 2, i));
    };
    const Vec3 a0 = point(0), a1 = point(1), b0 = point(2), b1 = point(3);
    const double ra = 0.1, rb = 0.15;
    // The least distance: nested ternary searches (convex in both parameters)
    auto along = [&](double s) {
      const Vec3 x = a0 + s * (a1 - a0);
      double lo = 0, hi = 1;
      for (int k = 0; k < 100; ++k) {
        const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        if ((b0 + m1 * (b1 - b0) - x).norm() < (b0 + m2 * (b1 - b0) - x).norm()) hi = m2;
        else lo = m1;
      }
      return (b0 + 0.5 * (lo + hi) * (b1 - b0) - x).norm();
    };
    double lo = 0, hi = 1;
    for (int k = 0; k < 100; ++k) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (along(m1) < along(m2)) hi = m2;
      else lo = m1;
    }
    const double d = along(0.5 * (lo + hi));
    Manifold m;
    const bool hit = collide(capsuleShape(a0, a1, ra), at({0, 0, 0}), capsuleShape(b0, b1, rb), at({0, 0, 0}), 0.0, m);
    if (hit != (d < ra + rb)) {
      if (std::abs(d - ra - rb) > 1e-9) ++wrong;
      continue;
    }
    if (!hit) continue;
    ++hits;
    double deepest = -1e300;
    for (int k = 0; k < m.count; ++k) deepest = std::max(deepest, pt(m, k).depth);
    if (std::abs(deepest - (ra + rb - d)) > 1e-9) ++wrong;
  }
  CHECK(hits > 100);
  CHECK(wrong == 0);
}
