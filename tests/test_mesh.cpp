// Mesh objects imported with assimp: formats, colours, placement, bad files.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "core/math.h"
#include "core/scene_view.h"
#include "helpers.h"
#include "io/mesh_import.h"
#include "render/renderer.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;
namespace fs = std::filesystem;

namespace {

fs::path meshDir() {
  const fs::path d = fs::temp_directory_path() / "reel_mesh_test";
  fs::create_directories(d);
  return d;
}

// A unit cube centred at the origin, as OBJ (quads, triangulated on import).
const char* kCubeObj = R"(v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
)";

// A square in the x–z plane facing +y, with a colour per vertex, as ASCII PLY.
const char* kSquarePly = R"(ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
element face 2
property list uchar int vertex_indices
end_header
-1 0 -1 255 0 0
-1 0 1 255 0 0
1 0 1 255 0 0
1 0 -1 255 0 0
3 0 1 2
3 0 2 3
)";

const char* kTriStl = R"(solid t
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 1 0
endloop
endfacet
endsolid t
)";

}  // namespace

TEST_CASE("OBJ, PLY and STL import as triangles with normals, colours where given") {
  const fs::path d = meshDir();
  std::ofstream(d / "cube.obj") << kCubeObj;
  std::ofstream(d / "square.ply") << kSquarePly;
  std::ofstream(d / "tri.stl") << kTriStl;
  auto cube = io::importMesh((d / "cube.obj").string());
  REQUIRE(cube.ok());
  CHECK(cube.value().triangleCount() == 12);
  for (float x : cube.value().positions) CHECK(std::abs(std::abs(x) - 0.5f) < 1e-6f);
  CHECK(cube.value().normals.size() == cube.value().positions.size());
  CHECK(cube.value().colors.empty());
  auto sq = io::importMesh((d / "square.ply").string());
  REQUIRE(sq.ok());
  CHECK(sq.value().triangleCount() == 2);
  REQUIRE(sq.value().colors.size() == sq.value().positions.size());
  CHECK(sq.value().colors[0] == doctest::Approx(1.0));
  CHECK(sq.value().colors[1] == doctest::Approx(0.0));
  auto tri = io::importMesh((d / "tri.stl").string());
  REQUIRE(tri.ok());
  CHECK(tri.value().triangleCount() == 1);
}

TEST_CASE("bad mesh files are clean errors naming the path") {
  const fs::path d = meshDir();
  std::ofstream(d / "cube.obj") << kCubeObj;
  std::ofstream(d / "garbage.ply") << "ply\nthis is not a ply file\n";
  std::ofstream(d / "empty.obj") << "# nothing\n";
  std::ofstream(d / "model.fbx") << "x";
  const std::string file = (d / "scene.json").string();
  auto errors = [&](const std::string& obj) {
    auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "objects": [)" + obj + "]}", file);
    return r.ok() ? std::string() : r.error().messages.front();
  };
  CHECK(errors(R"({"type": "mesh", "file": "cube.obj"})").empty());
  CHECK(errors(R"({"type": "mesh", "file": "nope.obj"})").find("/objects/0/file: \"nope.obj\": no such file") != std::string::npos);
  CHECK(errors(R"({"type": "mesh", "file": "model.fbx"})").find("unsupported file type") != std::string::npos);
  CHECK(errors(R"({"type": "mesh", "file": "garbage.ply"})").find("/objects/0/file: \"garbage.ply\": ") != std::string::npos);
  CHECK(errors(R"({"type": "mesh", "file": "empty.obj"})").find("/objects/0/file") != std::string::npos);
  CHECK(errors(R"({"type": "mesh", "file": "../x.obj"})").find("/objects/0/file") != std::string::npos);
  CHECK(errors(R"({"type": "mesh"})").find("/objects/0/file: missing required key") != std::string::npos);
  CHECK(errors(R"({"type": "mesh", "file": "cube.obj", "scale": 0})").find("/objects/0/scale: must be > 0") != std::string::npos);
}

TEST_CASE("a mesh object is placed by scale, rotation and position, and drawn in its vertex colours") {
  const fs::path d = meshDir();
  std::ofstream(d / "square.ply") << kSquarePly;
  std::ofstream(d / "s.json") << R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 64, "height": 48, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 3, 0.000001], "target": [0, 0, 0], "fov_deg": 40},
    "lights": [{"type": "ambient", "intensity": 1}],
    "objects": [{"type": "mesh", "file": "square.ply", "scale": [0.25, 1, 0.25], "rotation_deg": [0, 45, 0],
                 "position": [0.5, 0, 0], "color": [1, 1, 1]}]})";
  auto scene = app::loadScene((d / "s.json").string());
  REQUIRE(scene.ok());
  auto w = app::makeWorld(scene.value());
  REQUIRE(w.ok());
  DrawList list;
  setSceneView(scene.value(), w.value().time(), list);
  w.value().draw(list);
  REQUIRE(list.meshes.size() == 1);
  // The square's corner (1, 0, 1) → scaled (0.25, 0, 0.25) → turned 45° about y → (0.354, 0, 0) → +0.5.
  const auto& p = list.meshes[0].mesh->positions;
  double max_x = -1e9;
  for (std::size_t i = 0; i < p.size(); i += 3) max_x = std::max(max_x, double(p[i]));
  CHECK(max_x == doctest::Approx(0.5 + 0.25 * std::sqrt(2.0)).epsilon(1e-6));
  auto ctx = gl::createContext(gl::Backend::OSMesa);
  REQUIRE(ctx.ok());
  RenderSettings rs;
  rs.width = 64;
  rs.height = 48;
  rs.samples = 1;
  auto r = Renderer::create(*ctx.value(), rs, findShaderDir());
  REQUIRE(r.ok());
  Image img;
  REQUIRE(r.value()->draw(list, img).ok());
  // Its centre (0.5, 0, 0) is 0.5 m right of the image centre: 0.5/3/tan(20°)·24 = 11 pixels.
  int red = 0;
  for (int y = 20; y < 28; ++y)
    for (int x = 40; x < 46; ++x) red += img.pixel(x, y)[0] == 255 && img.pixel(x, y)[1] == 0;
  CHECK(red == 48);
  CHECK(img.pixel(32, 24)[0] == 0);  // the image centre is background
}

TEST_CASE("the fish mesh: closed, outward, one unit long, with unit normals and few triangles") {
  for (int detail : {0, 1, 2}) {
    CAPTURE(detail);
    const TriMesh m = makeFishMesh(detail);
    const std::size_t nv = m.vertexCount(), nt = m.triangleCount();
    if (detail == 0) CHECK((nt >= 50 && nt <= 70));
    if (detail == 1) CHECK((nt >= 200 && nt <= 400));
    if (detail == 2) CHECK(nt > 400);
    REQUIRE(m.normals.size() == 3 * nv);
    REQUIRE(m.uvs.size() == 2 * nv);
    REQUIRE(m.colors.size() == 3 * nv);
    Vec3 lo = Vec3::Constant(1e9), hi = -lo;
    for (std::size_t i = 0; i < nv; ++i) {
      const Vec3 p(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      CHECK(Vec3(m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]).norm() == doctest::Approx(1.0).epsilon(1e-5));
    }
    CHECK(hi.z() == doctest::Approx(0.0).epsilon(1e-6));  // the head
    CHECK(lo.z() == doctest::Approx(-1.0).epsilon(1e-6));  // the tail's tips
    CHECK(hi.x() == doctest::Approx(-lo.x()).epsilon(1e-6));  // symmetric
    CHECK((hi.y() - lo.y() > 0.2 && hi.y() - lo.y() < 0.5));  // deeper than wide
    CHECK((hi.x() - lo.x() > 0.08 && hi.x() - lo.x() < hi.y() - lo.y()));
    // Closed and consistently wound: with vertices welded by position (UV seams, fin borders),
    // every directed edge is met once the other way round.
    std::map<std::array<long, 3>, std::uint32_t> weld;
    std::vector<std::uint32_t> id(nv);
    for (std::size_t i = 0; i < nv; ++i) {
      const std::array<long, 3> key{std::lround(m.positions[3 * i] * 1e5), std::lround(m.positions[3 * i + 1] * 1e5),
                                    std::lround(m.positions[3 * i + 2] * 1e5)};
      id[i] = weld.emplace(key, static_cast<std::uint32_t>(weld.size())).first->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    double volume = 0;  // by the divergence theorem: positive when the faces point outward
    for (std::size_t t = 0; t < nt; ++t) {
      const std::uint32_t* f = &m.indices[3 * t];
      for (int k = 0; k < 3; ++k) ++edges[{id[f[k]], id[f[(k + 1) % 3]]}];
      auto P = [&](std::uint32_t v) { return Vec3(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]); };
      volume += P(f[0]).dot(P(f[1]).cross(P(f[2]))) / 6;
    }
    int unmatched = 0;
    for (const auto& [e, n] : edges) unmatched += (n != 1 || edges.count({e.second, e.first}) == 0 ||
                                                   edges.at({e.second, e.first}) != 1);
    CHECK(unmatched == 0);
    CHECK(volume > 0.005);
  }
}

TEST_CASE("a plane without size repeats its texture every 4 m; a sized plane shows it once") {
  const TriMesh tiled = makeQuad(400, 400, 4), once = makeQuad(3, 2);
  CHECK(*std::max_element(tiled.uvs.begin(), tiled.uvs.end()) == doctest::Approx(100.0));
  CHECK(*std::max_element(once.uvs.begin(), once.uvs.end()) == doctest::Approx(1.0));
}

TEST_CASE("the icosphere: 20·4^s triangles, every vertex on the sphere, every face outward") {
  for (int s : {0, 1, 2}) {
    const TriMesh m = makeIcosphere(0.5, s);
    CHECK(m.triangleCount() == static_cast<std::size_t>(20 * (1 << (2 * s))));
    CHECK(m.vertexCount() == static_cast<std::size_t>(10 * (1 << (2 * s)) + 2));  // Euler: V = F/2 + 2
    for (std::size_t v = 0; v < m.vertexCount(); ++v)
      CHECK(Vec3(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]).norm() == doctest::Approx(0.5).epsilon(1e-6));
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
      Vec3 p[3];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t i = m.indices[3 * t + static_cast<std::size_t>(k)];
        p[k] = Vec3(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
      }
      CHECK((p[1] - p[0]).cross(p[2] - p[0]).dot(p[0] + p[1] + p[2]) > 0);
    }
  }
}

TEST_CASE("assimp's own test models: which load, and why the others are refused") {
  // tests/data/assimp/README.md: unmodified files from assimp's repository. Each loads with its
  // triangle count, or is refused with the reason in plain words (never "cannot import:" alone).
  const fs::path d = fs::path(REEL_SOURCE_DIR) / "tests" / "data" / "assimp";
  struct Model {
    const char* file;
    std::size_t triangles;  // 0: refused
    const char* why;        // part of the refusal
  };
  const Model models[] = {
      {"OBJ/box.obj", 12, ""},
      {"OBJ/number_formats.obj", 1, ""},
      {"OBJ/concave_polygon.obj", 0, ""},  // (triangulated; count checked > 0 below)
      {"PLY/cube.ply", 12, ""},
      {"PLY/cube_binary.ply", 12, ""},
      {"PLY/cube_binary_header_with_RN_newline.ply", 12, ""},
      {"PLY/cube_binary_starts_with_nl.ply", 12, ""},  // its data begins with a newline byte
      {"PLY/float-color.ply", 1, ""},
      {"STL/triangle.stl", 1, ""},
      {"STL/triangle_with_two_solids.stl", 2, ""},
      {"glTF2/BoxBadNormals-glTF-Binary/BoxBadNormals.glb", 12, ""},
      {"glTF2/cameras/Cameras.gltf", 2, ""},
      {"OBJ/testline.obj", 0, "holds no triangles (its faces are points or lines)"},
      {"OBJ/point_cloud.obj", 0, "contains no faces"},
      {"PLY/points.ply", 0, "contains no faces"},
      {"PLY/issue623.ply", 0, ":14: vertex 0: too few values"},  // its face element is missing
      {"STL/triangle_with_empty_solid.stl", 0, "contains no vertices"},
      {"glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", 0, "holds non-finite coordinates"},
      {"glTF2/RecursiveNodes/RecursiveNodes.gltf", 0, "the nodes form a cycle"},
      {"glTF2/TestNoRootNode/NoScene.gltf", 0, "no scene"},
      {"glTF2/TestNoRootNode/SceneWithoutNodes.gltf", 0, "holds nothing to draw (no meshes in its scene)"},
      {"glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf", 0, "has no faces"},
  };
  int loaded = 0, refused = 0;
  for (const Model& m : models) {
    CAPTURE(m.file);
    auto mesh = io::importMesh((d / m.file).string());
    if (*m.why == '\0') {
      REQUIRE_MESSAGE(mesh.ok(), (mesh.ok() ? "" : mesh.error().headline()));
      if (m.triangles > 0) CHECK(mesh.value().triangleCount() == m.triangles);
      else CHECK(mesh.value().triangleCount() > 0);
      ++loaded;
    } else {
      REQUIRE(!mesh.ok());
      const std::string why = mesh.error().headline();
      CHECK(why.find(m.why) != std::string::npos);
      CHECK(why.substr(why.size() - std::min<std::size_t>(why.size(), 16)) != "cannot import: ");
      ++refused;
    }
  }
  MESSAGE(loaded << " of assimp's test models load, " << refused << " are refused with the reason");
  // The binary cube whose data begins with 0x0A is the same unit cube as the plain binary one, moved.
  auto nl = io::importMesh((d / "PLY/cube_binary_starts_with_nl.ply").string());
  auto plain = io::importMesh((d / "PLY/cube_binary.ply").string());
  REQUIRE(nl.ok());
  REQUIRE(plain.ok());
  auto extent = [](const TriMesh& t, int axis) {
    float lo = 1e30f, hi = -1e30f;
    for (std::size_t i = static_cast<std::size_t>(axis); i < t.positions.size(); i += 3) lo = std::min(lo, t.positions[i]), hi = std::max(hi, t.positions[i]);
    return hi - lo;
  };
  for (int a = 0; a < 3; ++a) CHECK(extent(nl.value(), a) == doctest::Approx(extent(plain.value(), a)));
}

TEST_CASE("a PLY header line that is not PLY's (a Blender export's \"Created by\") is read past") {
  const fs::path d = test::freshDir("ply_created");
  std::ofstream(d / "tri.ply") << "ply\nformat ascii 1.0\nCreated by Blender 2.47\nelement vertex 3\nproperty float x\n"
                                  "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  auto m = io::importMesh((d / "tri.ply").string());
  REQUIRE_MESSAGE(m.ok(), (m.ok() ? "" : m.error().headline()));
  CHECK(m.value().triangleCount() == 1);
}

TEST_CASE("smooth normals follow the surface, not its triangulation: a dome with mirrored diagonals") {
  // A dome z = −(x² + y²)/2R over a grid whose diagonals mirror about x = 0, as a face's skin's do:
  // the angle-weighted normals (Thürmer & Wüthrich 1998) stay within half a degree of the
  // dome's on the mirror line; the area-weighted ones bend there (the seam down a face's chin).
  constexpr int N = 8;
  constexpr double h = 0.01, R = 0.05;
  std::vector<Vec3> p;
  for (int j = -N; j <= N; ++j)
    for (int i = -N; i <= N; ++i) p.emplace_back(i * h, j * h, -((i * h) * (i * h) + (j * h) * (j * h)) / (2 * R));
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>((j + N) * (2 * N + 1) + (i + N)); };
  std::vector<std::uint32_t> tris;
  for (int j = -N; j < N; ++j)
    for (int i = -N; i < N; ++i) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i, j + 1), d = at(i + 1, j + 1);
      if (i < 0) tris.insert(tris.end(), {a, b, d, a, d, c});
      else tris.insert(tris.end(), {a, b, c, b, d, c});
    }
  const std::vector<Vec3> angle = angleNormals(p, tris), area = areaNormals(p, tris);
  auto err = [&](const std::vector<Vec3>& n, int i, int j) {
    const Vec3 exact = Vec3(i * h / R, j * h / R, 1.0).normalized();
    return std::acos(std::clamp(n[at(i, j)].normalized().dot(exact), -1.0, 1.0)) * 180.0 / kPi;
  };
  double worst_angle = 0, worst_area = 0;
  for (int j = -N + 1; j < N; ++j) worst_angle = std::max(worst_angle, err(angle, 0, j)), worst_area = std::max(worst_area, err(area, 0, j));
  MESSAGE("on the mirror line: angle-weighted within " << worst_angle << "°, area-weighted " << worst_area << "°");
  CHECK(worst_angle < 0.5);
  CHECK(worst_area > 3 * worst_angle);
  // Unit, and +y for a point no triangle touches.
  for (const Vec3& n : angle) CHECK(n.norm() == doctest::Approx(1.0));
  const std::vector<Vec3> lone = angleNormals(std::vector<Vec3>{Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}, {0, 1, 2});
  CHECK(lone[3] == Vec3::UnitY());
  CHECK(lone[0] == Vec3::UnitZ());
}
