#include "io/scene_loader.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include <unistd.h>

#include "core/patterns.h"
#include "io/files.h"
#include "io/mesh_import.h"
#include "io/png.h"
#include "io/json_reader.h"

namespace reel::io {
namespace {

const Range kPos = Range::positive();
const Range kNonNeg = Range::nonNegative();
const Range kUnit = Range::closed(0.0, 1.0);

// --- appearance (stored for the renderer) ---------------------------------------------------
void readMaterial(Obj& o, Material& m) {
  m.color = o.vec3("color", m.color, kNonNeg);
  if (auto tex = o.string("texture")) {
    auto r = resolveAsset(o.diag().file(), *tex, {".png"}, kMaxTextureBytes);
    auto img = r.ok() ? readPng(r.value(), kMaxTexturePixels) : Result<Image>(r.error());
    if (img.ok()) {
      m.texture = r.value();
      m.texture_image = std::make_shared<const Image>(std::move(img.value()));
    } else if (r.ok()) {
      o.diag().error(childPath(o.path(), "texture"), "\"" + *tex + "\": " + img.error().headline());
    } else
      o.diag().error(childPath(o.path(), "texture"), r.error().headline());
  }
  if (o.has("pattern")) {
    const std::string pat = o.choice("pattern", "", {std::string(kPatternNames[0])});
    if (!m.texture.empty())
      o.diag().error(childPath(o.path(), "pattern"), "give texture or pattern, not both");
    else if (!pat.empty()) {
      m.texture = "pattern:" + pat;
      m.texture_image = std::make_shared<const Image>(makePattern(pat, 512));
    }
  }
  m.specular = o.number("specular", m.specular, kUnit);
  m.shininess = o.number("shininess", m.shininess, kPos);
  m.opacity = o.number("opacity", m.opacity, kUnit);
}

void readRender(const Json& j, RenderDesc& r, Diagnostics& d) {
  Obj o(j, "/render", d);
  r.width = o.integer("width", r.width, 16, 16384);
  r.height = o.integer("height", r.height, 16, 16384);
  if (auto s = o.integer("samples", 1, 4)) {
    if (*s == 3)
      d.error("/render/samples", "must be 1, 2 or 4, got 3");
    else
      r.samples = static_cast<int>(*s);
  }
  if (const Json* bg = o.raw("background")) {
    if (bg->is_object()) {
      Obj g(*bg, "/render/background", d);
      r.background_top = g.vec3("top", r.background_top, kNonNeg);
      r.background_bottom = g.vec3("bottom", r.background_bottom, kNonNeg);
      g.finish();
    } else if (auto c = readVec3(*bg, "/render/background", d, kNonNeg)) {
      r.background_top = r.background_bottom = *c;
    }
  }
  r.tonemap = o.choice("tonemap", r.tonemap, {"none", "aces"});
  if (const Json* f = o.raw("fog")) {
    Obj g(*f, "/render/fog", d);
    r.fog_color = g.vec3("color", r.fog_color, kNonNeg);
    r.fog_density = g.number("density", r.fog_density, kNonNeg);
    g.finish();
  }
  o.finish();
}

void readCamera(const Json& j, CameraDesc& c, Diagnostics& d) {
  Obj o(j, "/camera", d);
  c.position = o.vec3("position", c.position);
  c.target = o.vec3("target", c.target);
  c.up = o.vec3("up", c.up);
  c.fov_deg = o.number("fov_deg", c.fov_deg, Range{0.0, 180.0, true, true});
  if (c.up.norm() == 0) d.error("/camera/up", "must not be the zero vector");
  if ((c.position - c.target).norm() == 0) d.error("/camera/target", "must differ from the camera position");
  if (const Json* keys = o.raw("keys")) {
    if (!keys->is_array()) {
      d.error("/camera/keys", "expected a list of keyframes, got " + typeName(*keys));
    } else {
      for (std::size_t i = 0; i < keys->size(); ++i) {
        const std::string p = childPath("/camera/keys", i);
        Obj k((*keys)[i], p, d);
        CameraKey key;
        key.time = k.number("time", kNonNeg, true).value_or(0.0);
        key.position = k.vec3("position", c.position);
        key.target = k.vec3("target", c.target);
        key.fov_deg = k.number("fov_deg", c.fov_deg, Range{0.0, 180.0, true, true});
        k.finish();
        if (!c.keys.empty() && key.time <= c.keys.back().time)
          d.error(childPath(p, "time"), "keyframe times must increase");
        c.keys.push_back(key);
      }
    }
  }
  o.finish();
}

void readLights(const Json& j, std::vector<LightDesc>& lights, Diagnostics& d) {
  if (!j.is_array()) {
    d.error("/lights", "expected a list of lights, got " + typeName(j));
    return;
  }
  if (j.size() > 8) d.error("/lights", "at most 8 lights, got " + std::to_string(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = childPath("/lights", i);
    Obj o(j[i], p, d);
    LightDesc l;
    const std::string type = o.choice("type", "", {"directional", "point", "ambient"});
    if (!o.has("type") && o.ok()) d.error(childPath(p, "type"), "missing required key");
    l.color = o.vec3("color", l.color, kNonNeg);
    l.intensity = o.number("intensity", l.intensity, kNonNeg);
    if (type == "directional") {
      l.kind = LightKind::Directional;
      l.direction = o.vec3("direction", l.direction);
      if (l.direction.norm() == 0) d.error(childPath(p, "direction"), "must not be the zero vector");
      l.shadows = o.boolean("shadows", false);
    } else if (type == "point") {
      l.kind = LightKind::Point;
      l.position = o.vec3("position", Range::any(), true).value_or(l.position);
      l.shadows = o.boolean("shadows", false);
    } else if (type == "ambient") {
      l.kind = LightKind::Ambient;
    }
    if (!type.empty()) o.finish();
    lights.push_back(l);
  }
  if (std::count_if(lights.begin(), lights.end(), [](const LightDesc& l) { return l.shadows; }) > 2)
    d.error("/lights", "at most 2 lights may cast shadows");
}

// --- objects: colliders and props ------------------------------------------------------------
void readSurface(Obj& so, Surface& sf) {
  sf.friction = so.number("friction", sf.friction, kNonNeg);
  sf.restitution = so.number("restitution", sf.restitution, kUnit);
  sf.adhesion = so.number("adhesion", sf.adhesion, Range::closed(0.0, 1e4));
}

void readObject(Obj& o, ObjectDesc& ob, const std::string& type) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  if (type == "plane") {
    ob.kind = ObjectKind::Plane;
    ob.point = o.vec3("point", ob.point);
    ob.normal = o.vec3("normal", ob.normal);
    if (ob.normal.norm() == 0) d.error(childPath(p, "normal"), "must not be the zero vector");
    else ob.normal.normalize();
    if (auto s = o.numbers<2>("size", kPos)) ob.extent = *s;
    ob.checker = o.boolean("checker", false);
  } else if (type == "sphere") {
    ob.kind = ObjectKind::Sphere;
    ob.center = o.vec3("center", ob.center);
    ob.radius = o.number("radius", kPos, true).value_or(ob.radius);
  } else if (type == "box") {
    ob.kind = ObjectKind::Box;
    ob.center = o.vec3("center", ob.center);
    ob.size = o.vec3("size", Range::positive(), true).value_or(ob.size);
    ob.rotation_deg = o.vec3("rotation_deg", ob.rotation_deg);
  } else if (type == "container") {
    ob.kind = ObjectKind::Container;
    ob.center = o.vec3("center", ob.center);
    ob.size = o.vec3("size", Range::positive(), true).value_or(ob.size);
    ob.rotation_deg = o.vec3("rotation_deg", ob.rotation_deg);
    ob.wall = o.number("wall", ob.wall, kPos);
    if (2 * ob.wall >= ob.size.minCoeff()) d.error(childPath(p, "wall"), "must be less than half the container's smallest size");
  } else if (type == "capsule") {
    ob.kind = ObjectKind::Capsule;
    ob.a = o.vec3("start", Range::any(), true).value_or(ob.a);
    ob.b = o.vec3("end", Range::any(), true).value_or(ob.b);
    ob.radius = o.number("radius", kPos, true).value_or(ob.radius);
  } else if (type == "mesh") {
    ob.kind = ObjectKind::Mesh;
    ob.position = o.vec3("position", ob.position);
    ob.rotation_deg = o.vec3("rotation_deg", ob.rotation_deg);
    if (const Json* sc = o.raw("scale")) {
      if (sc->is_number()) {
        if (auto v = readNumber(*sc, childPath(p, "scale"), d, kPos)) ob.scale = Vec3::Constant(*v);
      } else if (auto v = readVec3(*sc, childPath(p, "scale"), d, kPos)) {
        ob.scale = *v;
      }
    }
    if (auto f = o.string("file", true)) {
      ob.file = *f;
      auto r = resolveAsset(d.file(), *f, {std::begin(kMeshExtensions), std::end(kMeshExtensions)}, kMaxMeshBytes);
      auto mesh = r.ok() ? importMesh(r.value()) : Result<TriMesh>(r.error());
      if (mesh.ok())
        ob.mesh = std::make_shared<const TriMesh>(std::move(mesh.value()));
      else
        d.error(childPath(p, "file"), r.ok() ? "\"" + *f + "\": " + mesh.error().headline() : mesh.error().headline());
    }
  }
  ob.thickness = o.number("thickness", 0.0, Range::closed(0.0, 10.0));
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
  if (const Json* s = o.raw("surface")) {
    Obj so(*s, childPath(p, "surface"), d);
    readSurface(so, ob.surface);
    // Per-species surfaces: {"species": {"honey": {"adhesion": 20}}}; unset keys keep the above.
    if (const Json* sp = so.raw("species")) {
      const std::string spp = childPath(so.path(), "species");
      if (!sp->is_object()) {
        d.error(spp, "expected an object of species name → surface, got " + typeName(*sp));
      } else {
        for (const auto& [name, val] : sp->items()) {
          Obj one(val, childPath(spp, name), d);
          Surface sf = ob.surface;
          readSurface(one, sf);
          one.finish();
          ob.species_surface.emplace_back(name, sf);
        }
      }
    }
    so.finish();
  }
  ob.dynamic = o.boolean("dynamic", false);
  if (ob.dynamic) {
    ob.mass = o.number("mass", kPos, true).value_or(ob.mass);
    if (ob.kind == ObjectKind::Plane) d.error(childPath(p, "dynamic"), "a plane cannot be dynamic (it has no finite mass)");
    if (!ob.motion.empty()) d.error(childPath(p, "dynamic"), "an object moves by its keys or dynamically, not both");
  } else if (o.has("mass")) {
    d.error(childPath(p, "mass"), "only dynamic objects have a mass (set \"dynamic\": true)");
  }
  readMaterial(o, ob.material);
}

// --- bodies ------------------------------------------------------------------------------------
using NodeNames = std::vector<std::pair<std::string, std::vector<long long>>>;

// Reads a list of nodes (`pinned`, a grip's `nodes`): each entry a node index (negative counts
// from the end), a grid coordinate list of `dims` indices, or a name of one node or a group
// (a corner, an edge). Writes resolved node indices.
void readPins(Obj& o, const std::vector<long long>& dims, long long nodes, const NodeNames& names,
              std::vector<int>& out, const std::string& key = "pinned", bool required = false) {
  const Json* j = o.raw(key);
  Diagnostics& d = o.diag();
  const std::string p = childPath(o.path(), key);
  if (!j) {
    if (required && o.ok()) d.error(p, "missing required key");
    return;
  }
  if (!j->is_array()) {
    d.error(p, "expected a list of nodes, got " + typeName(*j));
    return;
  }
  for (std::size_t k = 0; k < j->size(); ++k) {
    const Json& e = (*j)[k];
    const std::string ep = childPath(p, k);
    if (e.is_string()) {
      const std::string s = e.get<std::string>();
      auto it = std::find_if(names.begin(), names.end(), [&](auto& n) { return n.first == s; });
      if (it != names.end()) {
        for (long long n : it->second) out.push_back(static_cast<int>(n));
        continue;
      }
      std::vector<std::string> opts;
      for (auto& n : names) opts.push_back(n.first);
      const std::string near = nearest(s, opts);
      d.error(ep, "unknown node name \"" + s + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
    } else if (e.is_array()) {
      if (e.size() != dims.size()) {
        d.error(ep, "expected " + std::to_string(dims.size()) + " grid indices, got " + typeName(e));
        continue;
      }
      long long idx = 0, stride = 1;
      bool good = true;
      for (std::size_t a = 0; a < dims.size(); ++a) {
        auto v = readInteger(e[a], childPath(ep, a), d, -dims[a], dims[a] - 1);
        if (!v) { good = false; continue; }
        idx += (*v < 0 ? *v + dims[a] : *v) * stride;
        stride *= dims[a];
      }
      if (good) out.push_back(static_cast<int>(idx));
    } else if (e.is_number()) {
      if (auto v = readInteger(e, ep, d, -nodes, nodes - 1))
        out.push_back(static_cast<int>(*v < 0 ? *v + nodes : *v));
      else if (e.is_number_integer())
        d.error(ep, "the body has " + std::to_string(nodes) + " nodes (indices 0.." +
                        std::to_string(nodes - 1) + ", or negative from the end)");
    } else {
      d.error(ep, "expected a node index, grid indices or a name, got " + typeName(e));
    }
  }
}

void readMassSpring(Obj& o, MassSpringDesc& ms) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  const Json* nodes = o.raw("nodes");
  if (!nodes) {
    if (o.ok()) d.error(childPath(p, "nodes"), "missing required key");
  } else if (!nodes->is_array() || nodes->empty()) {
    d.error(childPath(p, "nodes"), "expected a non-empty list of nodes, got " + typeName(*nodes));
  } else if (static_cast<long long>(nodes->size()) > kMaxBodyNodes) {
    d.error(childPath(p, "nodes"), "more than " + std::to_string(kMaxBodyNodes) + " nodes");
  } else {
    for (std::size_t i = 0; i < nodes->size(); ++i) {
      Obj n((*nodes)[i], childPath(childPath(p, "nodes"), i), d);
      NodeDesc nd;
      nd.position = n.vec3("position", Range::any(), true).value_or(nd.position);
      nd.velocity = n.vec3("velocity", nd.velocity);
      nd.mass = n.number("mass", kPos, true).value_or(nd.mass);
      if (nd.mass < kMinNodeMass) {
        d.error(childPath(n.path(), "mass"), "must be at least 1e-12 kg");
        nd.mass = 1.0;
      }
      nd.damping = n.number("damping", 0.0, kNonNeg);
      nd.fixed = n.boolean("fixed", false);
      n.finish();
      ms.nodes.push_back(nd);
    }
  }
  const long long nn = static_cast<long long>(ms.nodes.size());
  const Json* springs = o.raw("springs");
  if (!springs) return;
  const std::string sp = childPath(p, "springs");
  if (!springs->is_array()) {
    d.error(sp, "expected a list of springs, got " + typeName(*springs));
    return;
  }
  for (std::size_t k = 0; k < springs->size(); ++k) {
    const std::string kp = childPath(sp, k);
    Obj s((*springs)[k], kp, d);
    SpringDesc sd;
    auto ends = s.integers<2>("nodes", 0, std::max(0ll, nn - 1), true);
    sd.stiffness = s.number("stiffness", kNonNeg, true).value_or(0.0);
    sd.damping = s.number("damping", 0.0, kNonNeg);
    sd.rest_length = s.number("rest_length", -1.0, kPos);
    s.finish();
    if (!ends) continue;
    sd.a = static_cast<int>((*ends)[0]);
    sd.b = static_cast<int>((*ends)[1]);
    if (sd.a == sd.b) {
      d.error(childPath(kp, "nodes"), "a spring needs two different nodes");
      continue;
    }
    if (sd.rest_length < 0 && nn > 0 &&
        (ms.nodes[static_cast<std::size_t>(sd.a)].position - ms.nodes[static_cast<std::size_t>(sd.b)].position).norm() == 0) {
      d.error(kp, "nodes " + std::to_string(sd.a) + " and " + std::to_string(sd.b) +
                      " start at the same point, so the default rest length would be 0; give rest_length");
      continue;
    }
    ms.springs.push_back(sd);
  }
}

// A generator's total mass shared by its nodes must leave each a usable mass.
void checkNodeMass(Obj& o, double mass, long long nodes) {
  if (nodes > 0 && mass / static_cast<double>(nodes) < kMinNodeMass)
    o.diag().error(childPath(o.path(), "mass"), "gives each of the " + std::to_string(nodes) +
                                                    " nodes less than 1e-12 kg");
}

SpringParams readSpring(Obj& o, const std::string& stiff_key, const std::string& damp_key,
                        const SpringParams* fallback) {
  SpringParams s;
  if (fallback) {
    s.stiffness = o.number(stiff_key, fallback->stiffness, kNonNeg);
    s.damping = o.number(damp_key, fallback->damping, kNonNeg);
  } else {
    s.stiffness = o.number(stiff_key, kNonNeg, true).value_or(0.0);
    s.damping = o.number(damp_key, 0.0, kNonNeg);
  }
  return s;
}

void readRope(Obj& o, RopeDesc& r) {
  r.start = o.vec3("start", Range::any(), true).value_or(r.start);
  r.end = o.vec3("end", Range::any(), true).value_or(r.end);
  r.segments = static_cast<int>(o.integer("segments", 1, kMaxBodyNodes - 1).value_or(r.segments));
  r.length = o.number("length", -1.0, kPos);
  r.mass = o.number("mass", r.mass, kPos);
  r.spring = readSpring(o, "stiffness", "damping", nullptr);
  r.node_damping = o.number("node_damping", 0.0, kNonNeg);
  r.velocity = o.vec3("velocity", r.velocity);
  if (r.length < 0 && (r.end - r.start).norm() == 0)
    o.diag().error(childPath(o.path(), "end"), "must differ from start (or give length)");
  const long long n = r.segments + 1;
  checkNodeMass(o, r.mass, n);
  readPins(o, {n}, n, {{"start", {0}}, {"end", {n - 1}}}, r.pinned);
}

// The placement keys of a sheet (net or cloth): position, rotation, size and resolution.
void readSheet(Obj& o, Vec3& position, Vec3& rotation_deg, std::array<double, 2>& size, std::array<int, 2>& resolution) {
  position = o.vec3("position", position);
  rotation_deg = o.vec3("rotation_deg", rotation_deg);
  if (auto s = o.numbers<2>("size", kPos)) size = *s;
  if (auto r = o.integers<2>("resolution", 2, 1 << 16)) resolution = {static_cast<int>((*r)[0]), static_cast<int>((*r)[1])};
  const long long n = static_cast<long long>(resolution[0]) * resolution[1];
  if (n > kMaxBodyNodes)
    o.diag().error(childPath(o.path(), "resolution"), std::to_string(n) + " nodes, more than the limit of " + std::to_string(kMaxBodyNodes));
}

// The corners of an nx × ny sheet by name.
NodeNames cornerNames(long long nx, long long ny) {
  return {{"corner_00", {0}}, {"corner_10", {nx - 1}}, {"corner_01", {(ny - 1) * nx}}, {"corner_11", {nx * ny - 1}}};
}

void readNet(Obj& o, NetDesc& net) {
  readSheet(o, net.position, net.rotation_deg, net.size, net.resolution);
  const long long nx = net.resolution[0], ny = net.resolution[1];
  net.mass = o.number("mass", net.mass, kPos);
  checkNodeMass(o, net.mass, nx * ny);
  net.structural = readSpring(o, "stiffness", "damping", nullptr);
  net.shear = readSpring(o, "shear_stiffness", "shear_damping", &net.structural);
  net.node_damping = o.number("node_damping", 0.0, kNonNeg);
  net.velocity = o.vec3("velocity", net.velocity);
  readPins(o, {nx, ny}, nx * ny, cornerNames(nx, ny), net.pinned);
}

void readLattice(Obj& o, LatticeDesc& l) {
  l.position = o.vec3("position", l.position);
  l.rotation_deg = o.vec3("rotation_deg", l.rotation_deg);
  l.size = o.vec3("size", l.size, kPos);
  if (auto r = o.integers<3>("resolution", 2, 1 << 12))
    l.resolution = {static_cast<int>((*r)[0]), static_cast<int>((*r)[1]), static_cast<int>((*r)[2])};
  const long long nx = l.resolution[0], ny = l.resolution[1], nz = l.resolution[2];
  if (nx * ny * nz > kMaxBodyNodes)
    o.diag().error(childPath(o.path(), "resolution"), std::to_string(nx * ny * nz) + " nodes, more than the limit of " + std::to_string(kMaxBodyNodes));
  l.mass = o.number("mass", l.mass, kPos);
  checkNodeMass(o, l.mass, nx * ny * nz);
  l.edge = readSpring(o, "stiffness", "damping", nullptr);
  l.face = readSpring(o, "face_stiffness", "face_damping", &l.edge);
  l.body = readSpring(o, "body_stiffness", "body_damping", &l.edge);
  l.node_damping = o.number("node_damping", 0.0, kNonNeg);
  l.velocity = o.vec3("velocity", l.velocity);
  readPins(o, {nx, ny, nz}, nx * ny * nz, {}, l.pinned);
}

// A sheet's named nodes: its corners and its four edges.
NodeNames clothNames(long long nx, long long ny) {
  NodeNames n = cornerNames(nx, ny);
  std::vector<long long> x0, x1, z0, z1;
  for (long long j = 0; j < ny; ++j) {
    x0.push_back(j * nx);
    x1.push_back(j * nx + nx - 1);
  }
  for (long long i = 0; i < nx; ++i) {
    z0.push_back(i);
    z1.push_back((ny - 1) * nx + i);
  }
  n.push_back({"edge_x0", x0});
  n.push_back({"edge_x1", x1});
  n.push_back({"edge_z0", z0});
  n.push_back({"edge_z1", z1});
  return n;
}

void readCloth(Obj& o, ClothDesc& c) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  readSheet(o, c.position, c.rotation_deg, c.size, c.resolution);
  const long long nx = c.resolution[0], ny = c.resolution[1];
  const bool has_mass = o.has("mass"), has_density = o.has("density");
  if (has_mass && has_density) d.error(childPath(p, "density"), "give mass or density, not both");
  if (has_density) {
    if (auto rho = o.number("density", kPos)) c.mass = *rho * c.size[0] * c.size[1];
  } else {
    c.mass = o.number("mass", c.mass, kPos);
  }
  checkNodeMass(o, c.mass / 4.0, nx * ny);  // a corner holds a quarter of a cell's mass
  c.structural = readSpring(o, "stiffness", "damping", &c.structural);
  c.shear = readSpring(o, "shear_stiffness", "shear_damping", &c.shear);
  c.bend = readSpring(o, "bend_stiffness", "bend_damping", &c.bend);
  c.node_damping = o.number("node_damping", 0.0, kNonNeg);
  c.velocity = o.vec3("velocity", c.velocity);
  c.thickness = o.number("thickness", c.thickness, Range{0.0, 1.0, true, false});
  c.self_collision = o.boolean("self_collision", false);
  c.strain_limit = o.number("strain_limit", 0.0, kNonNeg);
  if (auto uv = o.numbers<2>("uv_scale", kPos)) c.uv_scale = *uv;
  const NodeNames names = clothNames(nx, ny);
  readPins(o, {nx, ny}, nx * ny, names, c.pinned);
  if (const Json* t = o.raw("tear")) {
    Obj to(*t, childPath(p, "tear"), d);
    c.tear.strain = to.number("strain", kPos, true).value_or(0.0);
    c.tear.variation = to.number("variation", 0.0, Range{0.0, 1.0, false, true});  // below 1: no thread breaks at rest
    to.finish();
  }
  if (const Json* a = o.raw("air")) {
    Obj ao(*a, childPath(p, "air"), d);
    c.air.viscous = ao.number("viscous", 0.0, kNonNeg);
    c.air.drag = ao.number("drag", 0.0, kNonNeg);
    c.air.lift = ao.number("lift", 0.0, kNonNeg);
    c.air.density = ao.number("density", c.air.density, kPos);
    ao.finish();
  }
  if (const Json* g = o.raw("grips")) {
    const std::string gp = childPath(p, "grips");
    if (!g->is_array()) {
      d.error(gp, "expected a list of grips, got " + typeName(*g));
    } else {
      for (std::size_t k = 0; k < g->size(); ++k) {
        Obj go((*g)[k], childPath(gp, k), d);
        GripDesc grip;
        readPins(go, {nx, ny}, nx * ny, names, grip.nodes, "nodes", true);
        grip.velocity = go.vec3("velocity", grip.velocity);
        grip.start = go.number("start", 0.0, kNonNeg);
        grip.stop = go.number("stop", std::numeric_limits<double>::infinity(), kNonNeg);
        if (grip.stop <= grip.start) d.error(childPath(go.path(), "stop"), "must be after start");
        go.finish();
        c.grips.push_back(std::move(grip));
      }
    }
  }
  // A node may be held by one thing only.
  std::vector<std::uint8_t> held(static_cast<std::size_t>(nx * ny <= kMaxBodyNodes ? nx * ny : 0), 0);
  if (!held.empty()) {
    for (int n : c.pinned) held[static_cast<std::size_t>(n)] = 1;
    for (std::size_t k = 0; k < c.grips.size(); ++k)
      for (int n : c.grips[k].nodes) {
        if (held[static_cast<std::size_t>(n)]) {
          d.error(childPath(childPath(childPath(p, "grips"), k), "nodes"), "node " + std::to_string(n) + " is already pinned or gripped");
          break;
        }
        held[static_cast<std::size_t>(n)] = 1;
      }
  }
}

// --- the particle fluid ------------------------------------------------------------------------
// Particles one machine holds: half its memory at about 1 KiB per particle (state, neighbour
// list, drawing), at most 50 million.
long long defaultMaxParticles() {
  const long long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 4'000'000;
  return std::clamp(pages / 2 * (page / 1024), 10'000ll, 50'000'000ll);
}

// A species named by `key` (default: the first), as an index.
int readSpecies(Obj& o, const std::vector<std::string>& names, const std::string& key = "species") {
  if (names.empty()) return 0;
  const std::string n = o.choice(key, names[0], names);
  const auto it = std::find(names.begin(), names.end(), n);
  return it == names.end() ? 0 : static_cast<int>(it - names.begin());
}

// A list at `key` whose entries are objects, each passed to f(Obj&).
template <class F>
void readList(Obj& o, const std::string& key, F&& f, bool required = false) {
  const Json* j = o.raw(key);
  const std::string p = childPath(o.path(), key);
  if (!j) {
    if (required && o.ok()) o.diag().error(p, "missing required key");
    return;
  }
  if (!j->is_array()) {
    o.diag().error(p, "expected a list, got " + typeName(*j));
    return;
  }
  for (std::size_t k = 0; k < j->size(); ++k) {
    Obj e((*j)[k], childPath(p, k), o.diag());
    f(e);
    e.finish();
  }
}

void readFluid(Obj& o, FluidDesc& fd, double duration) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  std::vector<std::string> names;
  readList(o, "species", [&](Obj& so) {
    SpeciesDesc sp;
    sp.path = so.path();
    sp.name = so.string("name", true).value_or("");
    if (so.ok() && sp.name.empty() && so.has("name")) d.error(childPath(so.path(), "name"), "must not be empty");
    if (std::find(names.begin(), names.end(), sp.name) != names.end())
      d.error(childPath(so.path(), "name"), "duplicate species \"" + sp.name + "\"");
    sp.mass = so.number("mass", sp.mass, kPos);
    sp.alpha = so.number("alpha", sp.alpha, kNonNeg);
    sp.beta = so.number("beta", sp.beta, kNonNeg);
    sp.a = so.number("a", sp.a, Range{0.0, 16.0, true, false});
    sp.b = so.number("b", sp.b, Range{0.0, 16.0, true, false});
    sp.epsilon = so.number("epsilon", sp.epsilon, kNonNeg);
    sp.cutoff = so.number("cutoff", sp.cutoff, Range{0.0, 10.0, true, false});
    sp.viscosity = so.number("viscosity", sp.viscosity, kNonNeg);
    sp.agitation = so.number("agitation", sp.agitation, Range::closed(0.0, 100.0));
    if (sp.agitation > 0 && sp.viscosity == 0)
      d.error(childPath(so.path(), "agitation"), "needs viscosity > 0 (the random kicks and the viscous drag balance at the thermal speed)");
    sp.color = so.vec3("color", sp.color, kNonNeg);
    if (sp.alpha > 0 && sp.beta == 0)
      d.error(childPath(so.path(), "beta"), "must be > 0 when alpha > 0 (attraction without repulsion collapses the liquid)");
    names.push_back(sp.name);
    fd.species.push_back(sp);
  }, true);
  if (o.ok() && o.raw("species") && fd.species.empty()) d.error(childPath(p, "species"), "needs at least one species");
  readList(o, "interactions", [&](Obj& io) {
    InteractionDesc in;
    in.path = io.path();
    const Json* pair = io.raw("species");
    const std::string pp = childPath(io.path(), "species");
    if (!pair) {
      if (io.ok()) d.error(pp, "missing required key");
    } else if (!pair->is_array() || pair->size() != 2 || !(*pair)[0].is_string() || !(*pair)[1].is_string()) {
      d.error(pp, "expected two species names, got " + typeName(*pair));
    } else {
      int idx[2] = {0, 0};
      for (int k = 0; k < 2; ++k) {
        const std::string n = (*pair)[static_cast<std::size_t>(k)].get<std::string>();
        const auto it = std::find(names.begin(), names.end(), n);
        if (it == names.end()) {
          const std::string near = nearest(n, names);
          d.error(childPath(pp, static_cast<std::size_t>(k)),
                  "unknown species \"" + n + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
        } else {
          idx[k] = static_cast<int>(it - names.begin());
        }
      }
      in.s = idx[0];
      in.t = idx[1];
    }
    auto opt = [&](const char* key, Range r) -> std::optional<double> { return io.number(key, r); };
    in.alpha = opt("alpha", kNonNeg);
    in.beta = opt("beta", kNonNeg);
    in.a = opt("a", Range{0.0, 16.0, true, false});
    in.b = opt("b", Range{0.0, 16.0, true, false});
    in.epsilon = opt("epsilon", kNonNeg);
    in.cutoff = opt("cutoff", Range{0.0, 10.0, true, false});
    in.viscosity = opt("viscosity", kNonNeg);
    fd.interactions.push_back(in);
  });
  const long long limit = o.integer("max_particles", 1ll, 50'000'000ll).value_or(0);
  fd.max_particles = limit > 0 ? limit : defaultMaxParticles();
  double min_spacing = 0.0;
  double total = 0.0;
  readList(o, "blocks", [&](Obj& bo) {
    FluidBlockDesc b;
    b.species = readSpecies(bo, names);
    b.min = bo.vec3("min", Range::any(), true).value_or(b.min);
    b.max = bo.vec3("max", Range::any(), true).value_or(b.max);
    b.spacing = bo.number("spacing", kPos, true).value_or(b.spacing);
    b.jitter = bo.number("jitter", 0.0, Range::closed(0.0, 0.5));
    b.velocity = bo.vec3("velocity", b.velocity);
    if ((b.max - b.min).minCoeff() <= 0) d.error(childPath(bo.path(), "max"), "must be above min on every axis");
    else {
      const double n = b.count();
      if (n > static_cast<double>(fd.max_particles))
        d.error(bo.path(), "holds " + (n < 1e15 ? std::to_string(static_cast<long long>(n)) : std::string("over 10^15")) +
                               " particles, more than max_particles = " + std::to_string(fd.max_particles));
      total += n;
      if (total > static_cast<double>(defaultMaxParticles()) * 4)  // far beyond any limit: stop counting
        total = static_cast<double>(defaultMaxParticles()) * 4;
    }
    min_spacing = min_spacing > 0 ? std::min(min_spacing, b.spacing) : b.spacing;
    fd.blocks.push_back(b);
  });
  readList(o, "particles", [&](Obj& po) {
    FluidParticlesDesc pd;
    pd.species = readSpecies(po, names);
    for (const char* key : {"positions", "velocities"}) {
      const Json* j = po.raw(key);
      const std::string kp = childPath(po.path(), key);
      if (!j) {
        if (std::string(key) == "positions" && po.ok()) d.error(kp, "missing required key");
        continue;
      }
      if (!j->is_array() || j->size() > 10'000'000) {
        d.error(kp, "expected a list of [x, y, z], got " + typeName(*j));
        continue;
      }
      auto& out = std::string(key) == "positions" ? pd.positions : pd.velocities;
      for (std::size_t k = 0; k < j->size(); ++k)
        if (auto v = readVec3((*j)[k], childPath(kp, k), d, Range::any())) out.push_back(*v);
    }
    if (!pd.velocities.empty() && pd.velocities.size() != pd.positions.size())
      d.error(childPath(po.path(), "velocities"), "must list one velocity per position (" +
                                                  std::to_string(pd.positions.size()) + "), got " +
                                                  std::to_string(pd.velocities.size()));
    total += static_cast<double>(pd.positions.size());
    fd.particles.push_back(std::move(pd));
  });
  fd.radius = o.number("radius", min_spacing > 0 ? 0.5 * min_spacing : fd.radius, Range{0.0, 10.0, true, false});
  readList(o, "emitters", [&](Obj& eo) {
    EmitterDesc e;
    e.species = readSpecies(eo, names);
    e.position = eo.vec3("position", Range::any(), true).value_or(e.position);
    e.direction = eo.vec3("direction", e.direction);
    if (e.direction.norm() == 0) d.error(childPath(eo.path(), "direction"), "must not be the zero vector");
    else e.direction.normalize();
    e.speed = eo.number("speed", e.speed, Range{0.0, 1e3, true, false});
    e.radius = eo.number("radius", e.radius, Range{0.0, 100.0, true, false});
    e.rate = eo.number("rate", kPos, true).value_or(e.rate);
    e.start = eo.number("start", 0.0, kNonNeg);
    e.stop = std::min(eo.number("stop", duration, kNonNeg), duration);
    e.spacing = eo.number("spacing", 2.0 * fd.radius, Range{0.0, 100.0, true, false});
    if (e.stop <= e.start) {
      d.error(childPath(eo.path(), "stop"), "must be after start (and start before the scene ends)");
      e.stop = e.start;
    } else if (e.radius / e.spacing > 200) {
      d.error(childPath(eo.path(), "radius"), "holds too many particles per layer for its spacing");
    } else {
      // Layers leave perLayer()/rate s apart and travel speed × that: they must not overlap.
      const double gap = e.speed * static_cast<double>(e.perLayer()) / e.rate;
      if (gap < 0.5 * e.spacing)
        d.error(childPath(eo.path(), "rate"), "packs its layers " + std::to_string(gap) + " m apart, closer than half the spacing (" +
                                                   std::to_string(0.5 * e.spacing) + " m): lower the rate, or raise speed or radius");
      else
        total += static_cast<double>(e.layers() * e.perLayer());
    }
    fd.emitters.push_back(e);
  });
  if (total > static_cast<double>(fd.max_particles))
    d.error(p, "would hold " + (total >= static_cast<double>(defaultMaxParticles()) * 4 ? std::string("far more") : std::to_string(static_cast<long long>(total))) +
                   " particles (blocks, particles and emitters), more than max_particles = " + std::to_string(fd.max_particles));
  if (o.ok() && total == 0 && fd.emitters.empty()) d.error(p, "has no particles: give blocks, particles or emitters");
  const std::string draw = o.choice("draw", "spheres", {"spheres", "surface"});
  fd.draw = draw == "surface" ? FluidDraw::Surface : FluidDraw::Spheres;
  fd.surface_cell = o.number("surface_cell", 0.0, Range::closed(0.0, 10.0));
  fd.surface_kernel = o.number("surface_kernel", 0.0, Range::closed(0.0, 10.0));
  fd.surface_iso = o.number("surface_iso", fd.surface_iso, Range{0.0, 10.0, true, false});
  if (fd.surface_cell > 0 && fd.surface_kernel > 0 && fd.surface_kernel / fd.surface_cell > 16)
    d.error(childPath(p, "surface_kernel"), "must be at most 16 surface cells");
  if (fd.surface_cell == 0 && fd.surface_kernel > 0 && fd.surface_kernel / fd.radius > 16)
    d.error(childPath(p, "surface_kernel"), "must be at most 16 particle radii");
}

// Nodes and springs a body will have, from its description (without building it).
std::pair<long long, long long> bodySize(const BodyDesc& b) {
  struct V {
    std::pair<long long, long long> operator()(const MassSpringDesc& d) const {
      return {static_cast<long long>(d.nodes.size()), static_cast<long long>(d.springs.size())};
    }
    std::pair<long long, long long> operator()(const RopeDesc& d) const { return {d.segments + 1ll, d.segments}; }
    std::pair<long long, long long> operator()(const NetDesc& d) const {
      const long long x = d.resolution[0], y = d.resolution[1];
      return {x * y, (x - 1) * y + x * (y - 1) + 2 * (x - 1) * (y - 1)};
    }
    std::pair<long long, long long> operator()(const FluidDesc&) const { return {0, 0}; }  // max_particles
    std::pair<long long, long long> operator()(const ClothDesc& d) const {
      return clothCounts(d.resolution[0], d.resolution[1]);
    }
    std::pair<long long, long long> operator()(const LatticeDesc& d) const {
      const long long x = d.resolution[0], y = d.resolution[1], z = d.resolution[2];
      const long long edges = (x - 1) * y * z + x * (y - 1) * z + x * y * (z - 1);
      const long long faces = 2 * ((x - 1) * (y - 1) * z + (x - 1) * y * (z - 1) + x * (y - 1) * (z - 1));
      return {x * y * z, edges + faces + 4 * (x - 1) * (y - 1) * (z - 1)};
    }
  };
  return std::visit(V{}, b.shape);
}

const std::vector<std::string> kObjectTypes = {"plane", "sphere", "box", "capsule", "mesh", "container"};
const std::vector<std::string> kBodyTypes = {"mass_spring", "rope", "net", "lattice", "cloth", "fluid"};

// Reads `name` and `type` of an object or body; checks the name is unique.
std::pair<std::string, std::string> readIdentity(Obj& o, const std::vector<std::string>& types,
                                                 std::size_t index, std::set<std::string>& names) {
  std::string type = o.choice("type", "", types);
  if (o.ok() && !o.has("type")) o.diag().error(childPath(o.path(), "type"), "missing required key");
  std::string name = o.string("name").value_or((type.empty() ? "item" : type) + "_" + std::to_string(index));
  if (name.empty()) o.diag().error(childPath(o.path(), "name"), "must not be empty");
  else if (!names.insert(name).second)
    o.diag().error(childPath(o.path(), "name"), "duplicate name \"" + name + "\" (every object and body needs its own)");
  return {name, type};
}

// "line:col" (both from 1) of a byte offset.
std::string lineCol(const std::string& text, std::size_t at) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

}  // namespace

Result<SceneDesc> parseScene(const std::string& text, const std::string& file) {
  Json root;
  try {
    root = Json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const Json::parse_error& e) {
    // Position from the byte offset; the reason from nlohmann's message, cut short (it quotes
    // the whole failing token, which can be megabytes).
    const std::size_t at = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
    std::string what = e.what();
    const std::size_t colon = what.find(": ", what.find("parse error"));
    what = colon == std::string::npos ? what : what.substr(colon + 2);
    if (what.size() > 200) what = what.substr(0, 200) + "...";
    return Error(ErrorKind::BadInput, file + ":" + lineCol(text, at) + ": " + what);
  } catch (const Json::exception& e) {
    // Number overflow (1e999): nlohmann gives no position, so find the literal.
    const std::string what = e.what();
    const std::string key = "number overflow parsing '";
    const std::size_t k = what.find(key);
    if (k != std::string::npos) {
      const std::string lit = what.substr(k + key.size(), what.find('\'', k + key.size()) - k - key.size());
      const std::size_t at = text.find(lit);
      return Error(ErrorKind::BadInput, file + ":" + lineCol(text, at == std::string::npos ? 0 : at) + ": number " +
                                            lit.substr(0, 40) + " is too large (numbers must be finite)");
    }
    return Error(ErrorKind::BadInput, file + ": " + what.substr(0, 200));
  }

  Diagnostics d(file);
  SceneDesc s;
  s.file = file;
  Obj o(root, "", d);
  if (!o.ok()) return Error(ErrorKind::BadInput, d.lines());

  if (auto f = o.string("format", true); f && *f != "reel/1")
    d.error("/format", "unsupported format \"" + *f + "\" (this reel reads \"reel/1\")");
  s.name = o.string("name").value_or(std::filesystem::path(file).stem().string());
  s.duration = o.number("duration", Range{0.0, 1e6, true, false}, true).value_or(s.duration);
  s.fps = o.integer("fps", s.fps, 1, 1000);
  s.substeps = o.integer("substeps", s.substeps, 1, 1000000);
  if (auto seed = o.integer("seed", 0, 9007199254740991ll)) s.seed = static_cast<std::uint64_t>(*seed);
  s.gravity = o.vec3("gravity", s.gravity);
  if (const Json* w = o.raw("wind")) {
    Obj wo(*w, "/wind", d);
    s.wind.velocity = wo.vec3("velocity", s.wind.velocity);
    s.wind.gust = wo.number("gust", 0.0, kNonNeg);
    s.wind.gust_period = wo.number("gust_period", s.wind.gust_period, kPos);
    wo.finish();
  }
  std::vector<std::string> integrators(kIntegratorNames.begin(), kIntegratorNames.end());
  s.integrator = *integratorFromName(o.choice("integrator", "symplectic_euler", integrators));
  s.auto_substeps = o.boolean("auto_substeps", false);
  if (const Json* im = o.raw("implicit")) {
    Obj io(*im, "/implicit", d);
    s.implicit.cg_tolerance = io.number("cg_tolerance", s.implicit.cg_tolerance, Range{0.0, 1.0, true, true});
    s.implicit.cg_max_iterations = io.integer("cg_max_iterations", s.implicit.cg_max_iterations, 1, 100000);
    io.finish();
  }
  if (s.frameCount() < 1) d.error("/duration", "too short for one frame at this fps");

  if (const Json* r = o.raw("render")) readRender(*r, s.render, d);
  if (const Json* c = o.raw("camera")) readCamera(*c, s.camera, d);
  if (const Json* l = o.raw("lights")) {
    s.has_lights = true;
    readLights(*l, s.lights, d);
  }

  std::set<std::string> names;
  if (const Json* objs = o.raw("objects")) {
    if (!objs->is_array()) {
      d.error("/objects", "expected a list of objects, got " + typeName(*objs));
    } else {
      for (std::size_t i = 0; i < objs->size(); ++i) {
        Obj ob(objs->at(i), childPath("/objects", i), d);
        ObjectDesc od;
        od.path = ob.path();
        auto [name, type] = readIdentity(ob, kObjectTypes, i, names);
        od.name = name;
        if (type.empty()) continue;  // unknown type: its keys cannot be checked
        readObject(ob, od, type);
        ob.finish();
        if (od.kind == ObjectKind::Mesh && !od.mesh) continue;  // its error is reported
        s.objects.push_back(std::move(od));
      }
    }
  }
  if (const Json* bodies = o.raw("bodies")) {
    if (!bodies->is_array()) {
      d.error("/bodies", "expected a list of bodies, got " + typeName(*bodies));
    } else {
      for (std::size_t i = 0; i < bodies->size(); ++i) {
        Obj bo(bodies->at(i), childPath("/bodies", i), d);
        BodyDesc bd;
        bd.path = bo.path();
        auto [name, type] = readIdentity(bo, kBodyTypes, i, names);
        bd.name = name;
        bd.type = type;
        if (type.empty()) continue;
        if (type == "mass_spring") {
          MassSpringDesc ms;
          readMassSpring(bo, ms);
          bd.shape = std::move(ms);
        } else if (type == "rope") {
          RopeDesc r;
          readRope(bo, r);
          bd.shape = std::move(r);
        } else if (type == "net") {
          NetDesc n;
          readNet(bo, n);
          bd.shape = std::move(n);
        } else if (type == "lattice") {
          LatticeDesc l;
          readLattice(bo, l);
          bd.shape = std::move(l);
        } else if (type == "cloth") {
          ClothDesc c;
          readCloth(bo, c);
          bd.shape = std::move(c);
        } else if (type == "fluid") {
          FluidDesc f;
          readFluid(bo, f, s.duration);
          bd.shape = std::move(f);
          bd.material.specular = 0.5;  // liquids shine unless told otherwise
          bd.material.shininess = 64.0;
        }
        readMaterial(bo, bd.material);
        bd.node_radius = bo.number("node_radius", bd.node_radius, kPos);
        bo.finish();
        s.bodies.push_back(std::move(bd));
      }
    }
  }
  // Totals over all bodies, so that no scene can exhaust the machine's memory.
  long long nodes = 0, springs = 0;
  for (const BodyDesc& b : s.bodies) {
    const auto [bn, bs] = bodySize(b);
    nodes += bn;
    springs += bs;
  }
  // Per-species surfaces must name a species of some fluid.
  std::vector<std::string> species;
  for (const BodyDesc& b : s.bodies)
    if (const auto* f = std::get_if<FluidDesc>(&b.shape))
      for (const SpeciesDesc& sp : f->species) species.push_back(sp.name);
  for (const ObjectDesc& ob : s.objects)
    for (const auto& [name, sf] : ob.species_surface)
      if (std::find(species.begin(), species.end(), name) == species.end()) {
        const std::string near = nearest(name, species);
        d.error(childPath(childPath(childPath(ob.path, "surface"), "species"), name),
                "unknown species \"" + name + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
      }
  if (nodes > kMaxSceneNodes)
    d.error("/bodies", std::to_string(nodes) + " nodes in all, more than the limit of " + std::to_string(kMaxSceneNodes));
  if (springs > kMaxSceneSprings)
    d.error("/bodies", std::to_string(springs) + " springs in all, more than the limit of " + std::to_string(kMaxSceneSprings));
  o.finish();
  if (!d.empty()) return Error(ErrorKind::BadInput, d.lines());
  return s;
}

Result<SceneDesc> loadScene(const std::string& path) {
  auto text = readFile(path, kMaxSceneBytes);
  if (!text.ok()) return text.error();
  return parseScene(text.value(), path);
}

}  // namespace reel::io
