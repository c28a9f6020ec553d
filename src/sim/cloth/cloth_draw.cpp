// What a cloth gives the renderer: its intact triangles as one mesh, split along tears.
#include <numeric>

#include "core/math.h"
#include "sim/cloth/cloth_body.h"
#include "sim/draw_material.h"
#include "core/union_find.h"

namespace reel {
namespace {
constexpr double kWetDarkening = 0.45;  // albedo lost when soaked
}  // namespace

TriMesh clothMesh(const Cloth& c, const std::vector<Vec3>& x) {
  const std::size_t nt = c.tris.size();
  // Corners (3 per triangle) joined across the edges two drawn triangles share: each class is
  // one vertex, so a node on a tear gets a vertex (and a normal) per side.
  std::vector<int> parent(3 * nt);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t t = 0; t < nt; ++t) {
    if (!c.tri_alive[t]) continue;
    for (int e = 0; e < 3; ++e) {
      const int u = c.tri_adj[t][e];
      if (u < static_cast<int>(t) || !c.tri_alive[static_cast<std::size_t>(u)]) continue;
      for (int k : {e, (e + 1) % 3}) {
        const int node = c.tris[t][k];
        const auto& other = c.tris[static_cast<std::size_t>(u)];
        const int ku = other[0] == node ? 0 : other[1] == node ? 1 : 2;
        unite(parent, static_cast<int>(3 * t) + k, 3 * u + ku);
      }
    }
  }
  TriMesh mesh;
  std::vector<int> vert(3 * nt, -1);
  std::vector<Vec3> normal;
  for (std::size_t t = 0; t < nt; ++t) {
    if (!c.tri_alive[t]) continue;
    const auto& tri = c.tris[t];
    const Vec3 cr = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);  // area-weighted normal
    for (int k = 0; k < 3; ++k) {
      const int root = findRoot(parent, static_cast<int>(3 * t) + k);
      int& vi = vert[static_cast<std::size_t>(root)];
      if (vi < 0) {
        vi = static_cast<int>(mesh.vertexCount());
        const auto node = static_cast<std::size_t>(tri[k]);
        mesh.addVertex(x[node], Vec3::UnitY(), c.uv[2 * node], c.uv[2 * node + 1]);
        if (!c.capacity.empty()) {
          // Wet fabric is darker (light scatters less out of a soaked weave) and glossier.
          const double soaked = std::min(1.0, c.wet[node] / c.capacity[node]);
          const auto shade = static_cast<float>(1.0 - kWetDarkening * soaked);
          mesh.colors.insert(mesh.colors.end(), {shade, shade, shade});
          mesh.gloss.push_back(static_cast<float>(soaked));
        }
        normal.push_back(Vec3::Zero());
      }
      normal[static_cast<std::size_t>(vi)] += cr;
      mesh.indices.push_back(static_cast<std::uint32_t>(vi));
    }
  }
  for (std::size_t i = 0; i < normal.size(); ++i) {
    const double len = normal[i].norm();
    const Vec3 n = len > 0 ? Vec3(normal[i] / len) : Vec3::UnitY();
    for (int k = 0; k < 3; ++k) mesh.normals[3 * i + k] = static_cast<float>(n[k]);
  }
  return mesh;
}

void ClothBody::draw(DrawList& out) const {
  DrawMesh sheet;
  sheet.mesh = std::make_shared<const TriMesh>(clothMesh(cloth_, net_.state.x));
  sheet.per_frame = true;
  sheet.material = drawMaterial(material_);
  sheet.material.double_sided = true;
  // An absorbent sheet's wet sheen needs the highlight compiled in.
  if (!cloth_.capacity.empty()) sheet.material.specular = std::max(sheet.material.specular, 1e-3);
  if (sheet.mesh->triangleCount() > 0) out.meshes.push_back(std::move(sheet));
  drawHolds(out);
}

// What holds the sheet, so that a pull or a pin has a visible cause: a bar along each grip's
// nodes (a clamp) and a peg at every other pinned node, dark metal, a little thicker than the cloth.
void ClothBody::drawHolds(DrawList& out) const {
  const std::vector<Vec3>& x = net_.state.x;
  const double r = std::max(0.008, 2.0 * cloth_.thickness);
  DrawMaterial metal;
  metal.color = Vec3(0.18, 0.19, 0.21);
  metal.specular = 0.5;
  metal.shininess = 50;
  DrawTubes bars;
  bars.radius = static_cast<float>(r);
  bars.material = metal;
  std::vector<char> held(x.size(), 0);
  auto put = [](std::vector<float>& v, const Vec3& p) {
    for (int a = 0; a < 3; ++a) v.push_back(static_cast<float>(p[a]));
  };
  for (const GripDesc& g : cloth_.grips)
    for (std::size_t k = 0; k < g.nodes.size(); ++k) {
      held[static_cast<std::size_t>(g.nodes[k])] = g.nodes.size() > 1;
      if (k == 0) continue;
      put(bars.ends, x[static_cast<std::size_t>(g.nodes[k - 1])]);
      put(bars.ends, x[static_cast<std::size_t>(g.nodes[k])]);
    }
  DrawSpheres pegs;
  pegs.radius = static_cast<float>(1.3 * r);
  pegs.material = metal;
  const std::vector<std::uint8_t>& fixed = net_.model.fixed;
  for (std::size_t i = 0; i < x.size() && i < fixed.size(); ++i)
    if (fixed[i] && !held[i]) put(pegs.centers, x[i]);
  if (!bars.ends.empty()) out.tubes.push_back(std::move(bars));
  if (!pegs.centers.empty()) out.spheres.push_back(std::move(pegs));
}

}  // namespace reel
