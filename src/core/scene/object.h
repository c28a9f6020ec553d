// Objects of a scene: colliders and props, static, moved by keyframes, or (`"dynamic": true`)
// free bodies moved by gravity and the liquid's push. Each has one shape of its own kind.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/mesh.h"
#include "core/scene/material.h"
#include "core/types.h"

namespace reel {

// The order of the shapes in ObjectShape.
enum class ObjectKind { Plane, Sphere, Box, Capsule, Mesh, Container };

struct PlaneShape {
  Vec3 point{0, 0, 0}, normal{0, 1, 0};
  std::optional<std::array<double, 2>> extent;  // `size` [w, h], m; infinite when absent
  double tile = 4.0;  // infinite: the texture repeats every `tile` m
};
struct SphereShape {
  Vec3 center{0, 0, 0};
  double radius = 0.5;  // m
};
struct BoxShape {
  Vec3 center{0, 0, 0};
  Vec3 size{1, 1, 1};          // full extents, m
  Vec3 rotation_deg{0, 0, 0};  // XYZ Euler angles, degrees
};
// A segment from a to b, swept by a sphere.
struct CapsuleShape {
  Vec3 a{0, 0, 0}, b{0, 1, 0};
  double radius = 0.5;  // m
};
// Imported triangles, placed by x ↦ R·(scale ⊙ x) + position (R from rotation_deg).
struct MeshObjectShape {
  std::string file;
  std::shared_ptr<const TriMesh> mesh;
  Vec3 position{0, 0, 0};
  Vec3 scale{1, 1, 1};
  Vec3 rotation_deg{0, 0, 0};
};
// An open box: floor and four walls.
struct ContainerShape {
  Vec3 center{0, 0, 0};
  Vec3 size{1, 1, 1};  // outer extents, m
  double wall = 0.05;  // wall and floor thickness, m
  Vec3 rotation_deg{0, 0, 0};
};
using ObjectShape = std::variant<PlaneShape, SphereShape, BoxShape, CapsuleShape, MeshObjectShape, ContainerShape>;

// A keyframe of an object's motion: where its reference point is (sphere and box centre, plane
// point, capsule midpoint, mesh position) and how it is turned from its authored orientation.
struct MotionKey {
  double time = 0.0;           // s
  Vec3 position{0, 0, 0};      // m
  Vec3 rotation_deg{0, 0, 0};  // XYZ Euler angles about the reference point, degrees
};

struct ObjectDesc {
  std::string name, path;  // path: JSON path of the object, e.g. /objects/0
  ObjectShape shape;
  bool checker = false;    // drawn as a checkerboard
  double checker_size = 0.5;  // m: its squares
  double thickness = 0.0;  // contact offset added to the surface, m
  Surface surface;
  // Per-species surfaces for liquids: species name → surface (keys not given keep `surface`'s).
  SpeciesSurfaces species_surface;
  // A free body (scene key `dynamic`, or a rigid body's object): moved by the rigid-body solver
  // (core/scene/rigid.h), momentum exchanged both ways with liquids and nodes.
  bool free_body = false;
  double mass = 1.0;  // kg (`dynamic` objects)
  Material material;
  std::vector<MotionKey> motion;  // keyframes (times increasing); empty: static

  ObjectKind kind() const { return static_cast<ObjectKind>(shape.index()); }
  template <class S>
  const S& as() const { return std::get<S>(shape); }
  // The reference point that motion keys place (see MotionKey).
  Vec3 referencePoint() const {
    struct Ref {
      Vec3 operator()(const PlaneShape& s) const { return s.point; }
      Vec3 operator()(const SphereShape& s) const { return s.center; }
      Vec3 operator()(const BoxShape& s) const { return s.center; }
      Vec3 operator()(const CapsuleShape& s) const { return 0.5 * (s.a + s.b); }
      Vec3 operator()(const MeshObjectShape& s) const { return s.position; }
      Vec3 operator()(const ContainerShape& s) const { return s.center; }
    };
    return std::visit(Ref{}, shape);
  }
};

}  // namespace reel
