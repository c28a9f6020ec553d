// Mesh objects imported with assimp: formats, colours, placement, bad files.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

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
