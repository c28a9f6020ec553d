// The springs kinds' readers: explicit nodes and springs (`mass_spring`) and the generators
// `rope`, `net` and `lattice`.
#include <memory>

#include "core/scene/mass_spring.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

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
  l.draw = o.choice("draw", "skin", {"skin", "springs"}) == "skin" ? LatticeDesc::Draw::Skin : LatticeDesc::Draw::Springs;
  l.skin_levels = o.integer("skin_levels", l.skin_levels, 0, 4);
  // The skin's quads: the block's outer faces, four times as many at each level.
  const long long cells = 2 * ((nx - 1) * (ny - 1) + (ny - 1) * (nz - 1) + (nz - 1) * (nx - 1));
  constexpr long long kMaxSkinQuads = 1 << 21;
  if (l.draw == LatticeDesc::Draw::Skin && cells << (2 * l.skin_levels) > kMaxSkinQuads)
    o.diag().error(childPath(o.path(), "skin_levels"),
                   std::to_string(cells << (2 * l.skin_levels)) + " skin quads, more than the limit of " +
                       std::to_string(kMaxSkinQuads) + ": fewer skin_levels, or \"draw\": \"springs\"");
}

template <class D, void (*Read)(Obj&, D&)>
std::shared_ptr<const BodyParams> readAs(Obj& o) {
  auto d = std::make_shared<D>();
  Read(o, *d);
  return d;
}

}  // namespace

std::shared_ptr<const BodyParams> readMassSpringBody(Obj& o, BodyDesc&, const SceneDesc&) {
  return readAs<MassSpringDesc, readMassSpring>(o);
}
std::shared_ptr<const BodyParams> readRopeBody(Obj& o, BodyDesc&, const SceneDesc&) { return readAs<RopeDesc, readRope>(o); }
std::shared_ptr<const BodyParams> readNetBody(Obj& o, BodyDesc&, const SceneDesc&) { return readAs<NetDesc, readNet>(o); }
std::shared_ptr<const BodyParams> readLatticeBody(Obj& o, BodyDesc&, const SceneDesc&) {
  return readAs<LatticeDesc, readLattice>(o);
}

}  // namespace reel::io
