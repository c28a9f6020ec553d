// The reader of the kind `rigid`, and the rigid body of a `"dynamic": true` object.
#include <cmath>

#include "core/format.h"
#include "core/math.h"
#include "core/scene/rigid.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

constexpr int kCylinderSlices = 32;  // sides of a cylinder's drawn mesh and contact prism

// The mass properties of an object's shape as placed (world axes), at a density; a mesh must be a
// closed, outward, non-self-intersecting solid.
Result<MassProperties> objectMass(const ObjectDesc& o, double density) {
  switch (o.kind()) {
    case ObjectKind::Sphere: {
      const auto& s = o.as<SphereShape>();
      return placed(sphereMass(s.radius, density), Mat3::Identity(), s.center);
    }
    case ObjectKind::Box: {
      const auto& s = o.as<BoxShape>();
      return placed(boxMass(s.size, density), rotationFromEulerDeg(s.rotation_deg), s.center);
    }
    case ObjectKind::Capsule: {
      const auto& s = o.as<CapsuleShape>();
      const Vec3 ab = s.b - s.a;
      const Mat3 R = ab.norm() > 0 ? rotationFromUp(ab) : Mat3::Identity();
      return placed(capsuleMass(ab.norm(), s.radius, density), R, 0.5 * (s.a + s.b));
    }
    case ObjectKind::Container: {
      const auto& s = o.as<ContainerShape>();
      const Mat3 R = rotationFromEulerDeg(s.rotation_deg);
      std::vector<MassProperties> parts;
      for (const auto& [c, size] : containerBoxes(s.size, s.wall)) parts.push_back(placed(boxMass(size, density), R, s.center + R * c));
      return combined(parts);
    }
    case ObjectKind::Mesh: {
      const auto& s = o.as<MeshObjectShape>();
      return solidMassProperties(placeMesh(*s.mesh, s.scale, rotationFromEulerDeg(s.rotation_deg), s.position), density);
    }
    case ObjectKind::Plane:
      break;
  }
  return Error(ErrorKind::BadInput, "a plane has no finite mass");
}

// Mass properties at a density, or scaled to a given mass; an error is reported at `path`.
std::optional<MassProperties> massOf(Obj& o, const ObjectDesc& ob, double density, std::optional<double> mass,
                                     const std::string& path) {
  auto m = objectMass(ob, density);
  if (!m.ok()) {
    o.diag().error(path, m.error().messages.front());
    return std::nullopt;
  }
  return mass ? withMass(m.value(), *mass) : m.value();
}

// A shape moved by `shift`.
void moveShape(PlaneShape& s, const Vec3& shift) { s.point += shift; }
void moveShape(SphereShape& s, const Vec3& shift) { s.center += shift; }
void moveShape(BoxShape& s, const Vec3& shift) { s.center += shift; }
void moveShape(CapsuleShape& s, const Vec3& shift) {
  s.a += shift;
  s.b += shift;
}
void moveShape(MeshObjectShape& s, const Vec3& shift) { s.position += shift; }
void moveShape(ContainerShape& s, const Vec3& shift) { s.center += shift; }

// A unit quaternion [w, x, y, z] as a rotation (`orientation`).
std::optional<Mat3> readOrientation(Obj& o) {
  auto q = o.numbers<4>("orientation");
  if (!q) return std::nullopt;
  Eigen::Quaterniond Q((*q)[0], (*q)[1], (*q)[2], (*q)[3]);
  if (!(Q.norm() > 1e-12)) {
    o.diag().error(childPath(o.path(), "orientation"), "a zero-length quaternion is no rotation");
    return std::nullopt;
  }
  return Mat3(Q.normalized().toRotationMatrix());
}

}  // namespace

std::shared_ptr<const BodyParams> readRigidBody(Obj& o, BodyDesc& body, const SceneDesc&) {
  auto r = std::make_shared<RigidDesc>();
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  const std::string shape = o.choice("shape", "box", {"sphere", "box", "capsule", "cylinder", "mesh"});
  // The body frame at its start: where the shape's reference point is, and how it is turned.
  const Vec3 position = o.vec3("position", Vec3::Zero());
  Mat3 R = rotationFromEulerDeg(o.vec3("rotation_deg", Vec3::Zero()));
  if (auto q = readOrientation(o)) {
    R = *q;
    if (o.has("rotation_deg")) d.error(childPath(p, "orientation"), "give rotation_deg or orientation, not both");
  }
  // The shape, as an object placed at the start pose.
  ObjectDesc ob;
  ob.name = body.name;
  ob.path = p;
  const Vec3 euler = eulerDegFromRotation(R);
  const bool round = shape == "capsule" || shape == "cylinder";
  const double radius = round || shape == "sphere" ? o.number("radius", shape == "capsule" ? 0.25 : 0.5, kLength) : 0.0;
  const double length = round ? o.number("length", 1.0, shape == "capsule" ? Range::closed(0.0, 1e4) : kLength) : 0.0;
  if (shape == "sphere") {
    ob.shape = SphereShape{position, radius};
  } else if (shape == "box") {
    ob.shape = BoxShape{position, o.vec3("size", Vec3(1, 1, 1), kLength), euler};
  } else if (shape == "capsule") {
    const Vec3 axis = R * Vec3(0, 0.5 * length, 0);
    ob.shape = CapsuleShape{position - axis, position + axis, radius};
  } else if (shape == "cylinder") {
    auto mesh = std::make_shared<TriMesh>(makeCylinder(radius, length, kCylinderSlices));
    ob.shape = MeshObjectShape{"cylinder", mesh, position, Vec3(1, 1, 1), euler};
  } else {
    MeshObjectShape s = readMeshShape(o);
    s.position = position;
    s.rotation_deg = euler;
    ob.shape = s;
  }
  readSurfaces(o, ob.surface, ob.species_surface);
  readMotion(o, ob);
  readMaterial(o, body.material);
  ob.material = body.material;
  const bool fixed = o.boolean("fixed", false);
  if (fixed && !ob.motion.empty()) d.error(childPath(p, "fixed"), "a body is fixed or moved by its keys, not both");
  ob.free_body = !fixed && ob.motion.empty();
  // Mass: a density or a total mass.
  const double density = o.number("density", 1000.0, kPos);
  const std::optional<double> mass = o.number("mass", kPos);
  if (mass && o.has("density")) d.error(childPath(p, "mass"), "give density or mass, not both");
  RigidItem item;
  item.axes = R;
  item.kinematic = !ob.free_body;
  item.velocity = o.vec3("velocity", Vec3::Zero());
  item.angular_velocity = o.vec3("angular_velocity", Vec3::Zero());
  item.force = o.vec3("force", Vec3::Zero());
  item.torque = o.vec3("torque", Vec3::Zero());
  item.linear_damping = o.number("linear_damping", 0.0, Range::closed(0.0, 1e6));
  item.angular_damping = o.number("angular_damping", 0.0, Range::closed(0.0, 1e6));
  for (const char* key : {"velocity", "angular_velocity", "force", "torque"})
    if (item.kinematic && o.has(key)) d.error(childPath(p, key), "a fixed or keyed body moves only as it is told");

  r->iterations = o.integer("iterations", r->iterations, 1, 1000);
  r->sleep_time = o.number("sleep_time", r->sleep_time, Range::closed(0.0, 1e6));
  // Copies on a grid: `array` {count [nx, ny, nz], spacing [dx, dy, dz] m}.
  std::array<long long, 3> count{1, 1, 1};
  Vec3 spacing(1, 1, 1);
  readObjectKey(o, "array", [&](Obj& ao) {
    if (auto c = ao.integers<3>("count", 1, 100'000, true)) count = *c;
    spacing = ao.vec3("spacing", spacing);
  });
  const bool is_mesh = ob.kind() == ObjectKind::Mesh;
  if (is_mesh && !ob.as<MeshObjectShape>().mesh) return r;  // its error is reported
  std::optional<MassProperties> mp;
  if (shape == "cylinder") {
    mp = placed(cylinderMass(radius, length, density), R, position);
    if (mass) mp = withMass(*mp, *mass);
  } else {
    mp = massOf(o, ob, density, mass, childPath(p, shape == "mesh" ? "file" : "shape"));
  }
  if (!mp) return r;
  if (!(std::isfinite(mp->mass) && mp->mass > 0 && mp->inertia.allFinite() && mp->inertia.diagonal().minCoeff() > 0)) {
    d.error(childPath(p, "shape"), "the body's mass properties are not usable (mass " + formatNumber(mp->mass, 3) +
                                       " kg): check its size, density and mass");
    return r;
  }
  const long long copies = count[0] * count[1] * count[2];
  if (copies > 100'000) {
    d.error(childPath(p, "array"), std::to_string(copies) + " copies, more than the limit of 100000");
    return r;
  }
  for (long long k = 0; k < copies; ++k) {
    const Vec3 shift(spacing.x() * static_cast<double>(k % count[0]), spacing.y() * static_cast<double>((k / count[0]) % count[1]),
                     spacing.z() * static_cast<double>(k / (count[0] * count[1])));
    ObjectDesc copy = ob;
    RigidItem it = item;
    if (copies > 1) copy.name = it.name = body.name + "/" + std::to_string(k);
    else it.name = body.name;
    std::visit([&](auto& s) { moveShape(s, shift); }, copy.shape);
    for (MotionKey& key : copy.motion) key.position += shift;
    it.object = r->objects.size();
    it.mass = *mp;
    it.mass.center_of_mass += shift;
    r->objects.push_back(std::move(copy));
    r->items.push_back(std::move(it));
  }
  return r;
}

std::shared_ptr<const RigidDesc> rigidFromObject(const ObjectDesc& ob, std::size_t index, Diagnostics& d) {
  auto r = std::make_shared<RigidDesc>();
  r->scene_object = true;
  auto m = objectMass(ob, 1.0);
  if (!m.ok()) {
    d.error(childPath(ob.path, "dynamic"), m.error().messages.front());
    return r;
  }
  RigidItem it;
  it.name = ob.name;
  it.object = index;
  it.mass = withMass(m.value(), ob.mass);
  r->items.push_back(std::move(it));
  return r;
}

}  // namespace reel::io
