#include "sim/object_draw.h"

#include "core/math.h"
#include "core/mesh.h"
#include "sim/draw_material.h"

namespace reel {
namespace {

struct ShapeMesh {
  TriMesh operator()(const PlaneShape& s) const {
    // A plane of given size shows its texture once across it (a poster, a rug on the floor); an
    // unbounded one (a floor, a seabed) repeats it every `tile` m (4 by default) instead of
    // stretching it over 400 m.
    TriMesh m = s.extent ? makeQuad((*s.extent)[0], (*s.extent)[1]) : makeQuad(400.0, 400.0, s.tile);
    m.transform(rotationFromUp(s.normal), s.point);
    return m;
  }
  TriMesh operator()(const SphereShape& s) const {
    TriMesh m = makeUvSphere(s.radius, 48, 24);
    m.transform(Mat3::Identity(), s.center);
    return m;
  }
  TriMesh operator()(const BoxShape& s) const {
    TriMesh m = makeBox(s.size);
    m.transform(rotationFromEulerDeg(s.rotation_deg), s.center);
    return m;
  }
  // Floor and four walls, as five boxes in one mesh.
  TriMesh operator()(const ContainerShape& s) const {
    TriMesh m;
    for (const auto& [centre, size] : containerBoxes(s.size, s.wall)) {
      TriMesh part = makeBox(size);
      part.transform(Mat3::Identity(), centre);
      const auto base = static_cast<std::uint32_t>(m.vertexCount());
      m.positions.insert(m.positions.end(), part.positions.begin(), part.positions.end());
      m.normals.insert(m.normals.end(), part.normals.begin(), part.normals.end());
      m.uvs.insert(m.uvs.end(), part.uvs.begin(), part.uvs.end());
      for (std::uint32_t i : part.indices) m.indices.push_back(base + i);
    }
    m.transform(rotationFromEulerDeg(s.rotation_deg), s.center);
    return m;
  }
  TriMesh operator()(const CapsuleShape& s) const { return makeCapsule(s.a, s.b, s.radius, 32, 16); }
  TriMesh operator()(const MeshObjectShape& s) const {
    return placeMesh(*s.mesh, s.scale, rotationFromEulerDeg(s.rotation_deg), s.position);
  }
};

}  // namespace

DrawMesh objectMesh(const ObjectDesc& o) {
  DrawMesh d;
  d.mesh = std::make_shared<const TriMesh>(std::visit(ShapeMesh{}, o.shape));
  d.material = drawMaterial(o.material);
  d.material.checker = o.checker;
  d.material.checker_size = o.checker_size;
  d.material.double_sided = o.kind() == ObjectKind::Plane;
  return d;
}

}  // namespace reel
