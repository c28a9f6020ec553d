// The `cloth` kind's reader: the sheet, its springs, mass, air, grips, tearing, self-collision.
#include <memory>

#include "core/scene/cloth.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

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
  // The liquid on the sheet: its surface, porosity and absorbency.
  readSurfaces(o, c.wetting.surface, c.wetting.species_surface);
  c.wetting.porosity = o.number("porosity", 0.0, kUnit);
  c.wetting.absorbency = o.number("absorbency", 0.0, kUnit);
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
        if (go.has("object")) {
          for (const char* key : {"velocity", "start", "stop", "keys"})
            if (go.has(key)) d.error(childPath(go.path(), key), "a grip held by an object moves with it, not by " + std::string(key));
          grip.object = go.string("object").value_or("");
        } else if (go.has("keys")) {
          for (const char* key : {"velocity", "start", "stop"})
            if (go.has(key)) d.error(childPath(go.path(), key), "a grip moves by its keys or by a velocity, not both");
          readList(go, "keys", [&](Obj& ko) {
            const double t = ko.number("time", kNonNeg, true).value_or(0.0);
            const Vec3 off = ko.vec3("offset", Vec3::Zero());
            if (!grip.keys.empty() && t <= grip.keys.back().first)
              d.error(childPath(ko.path(), "time"), "keyframe times must increase");
            grip.keys.emplace_back(t, off);
          });
        } else {
          grip.velocity = go.vec3("velocity", grip.velocity);
          grip.start = go.number("start", 0.0, kNonNeg);
          grip.stop = go.number("stop", std::numeric_limits<double>::infinity(), kNonNeg);
          if (grip.stop <= grip.start) d.error(childPath(go.path(), "stop"), "must be after start");
        }
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

}  // namespace

std::shared_ptr<const BodyParams> readClothBody(Obj& o, BodyDesc&, const SceneDesc&) {
  auto c = std::make_shared<ClothDesc>();
  readCloth(o, *c);
  return c;
}

}  // namespace reel::io
