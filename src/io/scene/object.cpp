// Objects' reader: the shape of each type, motion keys, surfaces, free bodies, appearance.
#include <memory>

#include "io/files.h"
#include "io/mesh_import.h"
#include "io/scene/reader.h"

namespace reel::io {
namespace {

void readSurface(Obj& so, Surface& sf) {
  sf.friction = so.number("friction", sf.friction, kNonNeg);
  sf.restitution = so.number("restitution", sf.restitution, kUnit);
  sf.adhesion = so.number("adhesion", sf.adhesion, Range::closed(0.0, 1e4));
}

}  // namespace

MeshObjectShape readMeshShape(Obj& o) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  MeshObjectShape s;
  s.position = o.vec3("position", s.position);
  s.rotation_deg = o.vec3("rotation_deg", s.rotation_deg);
  if (const Json* sc = o.raw("scale")) {
    if (sc->is_number()) {
      if (auto v = readNumber(*sc, childPath(p, "scale"), d, kPos)) s.scale = Vec3::Constant(*v);
    } else if (auto v = readVec3(*sc, childPath(p, "scale"), d, kPos)) {
      s.scale = *v;
    }
  }
  s.mesh = readMeshFile(o, "file", true, &s.file);
  return s;
}

namespace {

// The keys of each shape.
ObjectShape readShape(Obj& o, const std::string& type, bool& checker, double& checker_size) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  if (type == "plane") {
    PlaneShape s;
    s.point = o.vec3("point", s.point);
    s.normal = o.vec3("normal", s.normal);
    if (s.normal.norm() == 0) d.error(childPath(p, "normal"), "must not be the zero vector");
    else s.normal.normalize();
    if (auto e = o.numbers<2>("size", kPos)) s.extent = *e;
    if (o.has("tile")) {
      s.tile = o.number("tile", s.tile, kPos);
      if (s.extent) d.error(childPath(p, "tile"), "applies to a plane without size (a sized plane shows its texture once)");
    }
    checker = o.boolean("checker", false);
    checker_size = o.number("checker_size", checker_size, Range::closed(0.001, 100.0));
    return s;
  }
  if (type == "sphere") {
    SphereShape s;
    s.center = o.vec3("center", s.center);
    s.radius = o.number("radius", kPos, true).value_or(s.radius);
    return s;
  }
  // A box and a container: centre, size (required) and rotation.
  auto boxKeys = [&](auto& s) {
    s.center = o.vec3("center", s.center);
    s.size = o.vec3("size", Range::positive(), true).value_or(s.size);
    s.rotation_deg = o.vec3("rotation_deg", s.rotation_deg);
  };
  if (type == "box") {
    BoxShape s;
    boxKeys(s);
    return s;
  }
  if (type == "container") {
    ContainerShape s;
    boxKeys(s);
    s.wall = o.number("wall", s.wall, kPos);
    if (2 * s.wall >= s.size.minCoeff()) d.error(childPath(p, "wall"), "must be less than half the container's smallest size");
    return s;
  }
  if (type == "capsule") {
    CapsuleShape s;
    s.a = o.vec3("start", Range::any(), true).value_or(s.a);
    s.b = o.vec3("end", Range::any(), true).value_or(s.b);
    s.radius = o.number("radius", kPos, true).value_or(s.radius);
    return s;
  }
  return readMeshShape(o);
}

}  // namespace

void readMotion(Obj& o, ObjectDesc& ob) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  if (const Json* m = o.raw("motion")) {
    Obj mo(*m, childPath(p, "motion"), d);
    const std::string kp = childPath(mo.path(), "keys");
    const Json* keys = mo.raw("keys");
    if (!keys) {
      if (mo.ok()) d.error(kp, "missing required key");
    } else if (!keys->is_array() || keys->empty()) {
      d.error(kp, "expected a non-empty list of keyframes, got " + typeName(*keys));
    } else {
      for (std::size_t i = 0; i < keys->size(); ++i) {
        Obj k((*keys)[i], childPath(kp, i), d);
        MotionKey key;
        key.time = k.number("time", kNonNeg, true).value_or(0.0);
        key.position = k.vec3("position", ob.referencePoint());
        key.rotation_deg = k.vec3("rotation_deg", key.rotation_deg);
        k.finish();
        if (!ob.motion.empty() && key.time <= ob.motion.back().time)
          d.error(childPath(k.path(), "time"), "keyframe times must increase");
        ob.motion.push_back(key);
      }
    }
    mo.finish();
  }
}

void readSurfaces(Obj& o, Surface& surface, SpeciesSurfaces& species_surface) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  if (const Json* s = o.raw("surface")) {
    Obj so(*s, childPath(p, "surface"), d);
    readSurface(so, surface);
    // Per-species surfaces: {"species": {"honey": {"adhesion": 20}}}; unset keys keep the above.
    if (const Json* sp = so.raw("species")) {
      const std::string spp = childPath(so.path(), "species");
      if (!sp->is_object()) {
        d.error(spp, "expected an object of species name → surface, got " + typeName(*sp));
      } else {
        for (const auto& [name, val] : sp->items()) {
          Obj one(val, childPath(spp, name), d);
          Surface sf = surface;
          readSurface(one, sf);
          one.finish();
          species_surface.emplace_back(name, sf);
        }
      }
    }
    so.finish();
  }
}

void readObject(Obj& o, ObjectDesc& ob, const std::string& type) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  ob.shape = readShape(o, type, ob.checker, ob.checker_size);
  ob.thickness = o.number("thickness", 0.0, Range::closed(0.0, 10.0));
  readMotion(o, ob);
  readSurfaces(o, ob.surface, ob.species_surface);
  ob.free_body = o.boolean("dynamic", false);
  if (ob.free_body) {
    ob.mass = o.number("mass", kPos, true).value_or(ob.mass);
    if (ob.kind() == ObjectKind::Plane) d.error(childPath(p, "dynamic"), "a plane cannot be dynamic (it has no finite mass)");
    if (!ob.motion.empty()) d.error(childPath(p, "dynamic"), "an object moves by its keys or dynamically, not both");
  } else if (o.has("mass")) {
    d.error(childPath(p, "mass"), "only dynamic objects have a mass (set \"dynamic\": true)");
  }
  readMaterial(o, ob.material);
}

}  // namespace reel::io
