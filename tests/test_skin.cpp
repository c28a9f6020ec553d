// Catmull–Clark subdivision (core/subdivision.*) against the paper's rules worked by hand, and a
// lattice's skin: closed, facing out, lying over its nodes.
#include <doctest/doctest.h>

#include <map>

#include "core/subdivision.h"
#include "helpers.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// The cube [−1, 1]³: corners i = x + 2y + 4z (bit set: +1), faces counter-clockwise from outside.
std::vector<Vec3> cubePoints() {
  std::vector<Vec3> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  return p;
}
const std::vector<std::array<int, 4>> kCube = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                               {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

// Each edge of a closed, consistently wound triangle mesh is used once in each direction.
bool closedAndConsistent(const std::vector<std::uint32_t>& tris) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < tris.size(); t += 3)
    for (int k = 0; k < 3; ++k) ++directed[{tris[t + k], tris[t + (k + 1) % 3]}];
  for (const auto& [e, n] : directed)
    if (n != 1 || directed.count({e.second, e.first}) == 0) return false;
  return true;
}

// The volume inside a closed mesh (divergence theorem): positive when its faces turn outwards.
double volume(const TriMesh& m) {
  double v = 0;
  auto P = [&](std::uint32_t i) { return Vec3(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]); };
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    v += P(m.indices[t]).dot(P(m.indices[t + 1]).cross(P(m.indices[t + 2]))) / 6.0;
  return v;
}

}  // namespace

TEST_CASE("Catmull–Clark: a cube's first level by the paper's rules, closed at every level") {
  const std::vector<Vec3> cube = cubePoints();
  const SubdivisionSurface one(8, kCube, 1);
  CHECK(one.pointCount() == 8 + 12 + 6);
  CHECK(one.triangles().size() == 3 * 2 * 24);
  const std::vector<Vec3> p = one.points(cube);
  // A corner of valence 3: F = (1,1,1)/3, R = (2,2,2)/3, (F + 2R)/3 = (5,5,5)/9.
  // An edge point: the mean of its ends (1,1,0)·… and its two face points: (3/4, 3/4, 0) for the edge
  // from (1,1,−1) to (1,1,1). A face point: the face's centre.
  int corners = 0, edges = 0, faces = 0;
  for (const Vec3& q : p) {
    const Vec3 a = q.cwiseAbs();
    if ((a - Vec3::Constant(5.0 / 9)).norm() < 1e-12) ++corners;
    const double big = a.maxCoeff();
    if (std::abs(big - 1.0) < 1e-12 && std::abs(a.sum() - 1.0) < 1e-12) ++faces;
    if (std::abs(big - 0.75) < 1e-12 && std::abs(a.sum() - 1.5) < 1e-12) ++edges;
  }
  CHECK(corners == 8);
  CHECK(edges == 12);
  CHECK(faces == 6);
  // Each level shrinks toward the limit surface (a rounded blob for so coarse a cage), inside the
  // cube and outside the sphere of radius 0.8, its faces turned out.
  double before = 8;
  for (int levels : {1, 2, 3}) {
    const SubdivisionSurface s(8, kCube, levels);
    CAPTURE(levels);
    CHECK(closedAndConsistent(s.triangles()));
    const auto m = s.mesh(cube);
    CHECK(volume(*m) < before);
    CHECK(volume(*m) > 4.0 / 3.0 * kPi * 0.8 * 0.8 * 0.8);
    before = volume(*m);
    for (const Vec3& q : s.points(cube)) {
      CHECK(q.cwiseAbs().maxCoeff() <= 1.0);
      CHECK(q.norm() > 0.8);
    }
  }
}

TEST_CASE("Catmull–Clark: weights sum to one, a flat grid stays flat and evenly spaced inside") {
  // A 5x5-point grid in the plane z = 0, spacing 1, open at its border.
  std::vector<Vec3> grid;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) grid.emplace_back(i, j, 0);
  std::vector<std::array<int, 4>> quads;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) quads.push_back({j * 5 + i, j * 5 + i + 1, (j + 1) * 5 + i + 1, (j + 1) * 5 + i});
  const SubdivisionSurface s(25, quads, 2);
  // Translating every control point translates the surface: the weights of each point sum to 1.
  std::vector<Vec3> moved = grid;
  for (Vec3& g : moved) g += Vec3(3, -2, 7);
  const auto a = s.points(grid), b = s.points(moved);
  for (std::size_t k = 0; k < a.size(); ++k) CHECK((b[k] - a[k] - Vec3(3, -2, 7)).norm() < 1e-12);
  // Uniform cubic B-splines reproduce linear functions: inside, the refined grid is the plane's
  // own grid at a quarter of the spacing.
  int inside = 0;
  for (const Vec3& q : a) {
    CHECK(q.z() == 0.0);
    if (q.x() > 1 && q.x() < 3 && q.y() > 1 && q.y() < 3) {
      ++inside;
      CHECK(std::abs(4 * q.x() - std::round(4 * q.x())) < 1e-12);
      CHECK(std::abs(4 * q.y() - std::round(4 * q.y())) < 1e-12);
    }
  }
  CHECK(inside == 7 * 7);
}

TEST_CASE("a lattice is drawn as a closed skin over its nodes, or as nodes and springs") {
  auto scene = [](const std::string& draw) {
    return R"({"format": "reel/1", "duration": 1, "gravity": [0, 0, 0],
      "bodies": [{"type": "lattice", "name": "j", "size": [0.6, 0.4, 0.5], "resolution": [4, 3, 5], "node_radius": 0.02,
                  "rotation_deg": [10, 20, 30], "position": [1, 2, 3], "stiffness": 100)" + draw + "}]}";
  };
  World w = worldFromText(scene(""));
  DrawList list;
  w.draw(list);
  REQUIRE(list.meshes.size() == 1);
  CHECK(list.spheres.empty());
  CHECK(list.tubes.empty());
  const TriMesh& m = *list.meshes[0].mesh;
  CHECK(list.meshes[0].per_frame);
  CHECK(closedAndConsistent(m.indices));
  // Over the nodes' spheres: about the box grown by the node radius, less the rounding of its
  // edges and corners (two levels: a rounded box).
  const double box = 0.6 * 0.4 * 0.5, grown = 0.64 * 0.44 * 0.54;
  CHECK(volume(m) > 0.8 * box);
  CHECK(volume(m) < grown);
  // Every point faces out from the centre.
  const Vec3 c(1, 2, 3);
  for (std::size_t v = 0; v < m.vertexCount(); ++v) {
    const Vec3 p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
    const Vec3 n(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    CHECK((p - c).dot(n) > 0);
  }
  World s = worldFromText(scene(R"(, "draw": "springs")"));
  DrawList springs;
  s.draw(springs);
  CHECK(springs.meshes.empty());
  CHECK(springs.spheres.size() == 1);
  CHECK(springs.tubes.size() == 1);
  checkHas(badInputError(scene(R"(, "draw": "blob")")), "/bodies/0/draw");
  checkHas(badInputError(scene(R"(, "skin_levels": 7)")), "/bodies/0/skin_levels");
  // A skin's quads are limited: a 300x300x2 block has 179,998 outer cells, 2.9 million quads at 2 levels.
  checkHas(badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "lattice", "name": "j",
             "resolution": [300, 300, 2], "mass": 1000, "stiffness": 100}]})"), "/bodies/0/skin_levels: 2879968 skin quads");
}
