#include "sim/springs/springs_body.h"

#include "sim/springs/generators.h"

namespace reel {
namespace {

Result<std::unique_ptr<Body>> make(const BodyDesc& desc, const BuildContext& ctx, const MassSpringDesc& nodes) {
  auto b = std::make_unique<SpringsBody>(desc.name, desc.type, desc.material);
  if (Status st = buildNetwork(*b, nodes, desc, ctx, desc.node_radius); !st) return st.error();
  // Its springs are threads that meet other bodies' (a lattice meets them with its skin instead).
  if (desc.type != "lattice") {
    std::vector<std::array<int, 2>> edges;
    for (const SpringDesc& s : nodes.springs) edges.push_back({s.a, s.b});
    b->setEdges(std::move(edges));
  }
  return std::unique_ptr<Body>(std::move(b));
}

}  // namespace

void SpringsBody::step(StepContext& ctx) {
  net_.integrate(ctx);
  net_.contacts(ctx);
}

Result<std::unique_ptr<Body>> buildMassSpringBody(const BodyDesc& desc, const BuildContext& ctx) {
  return make(desc, ctx, desc.as<MassSpringDesc>());
}
Result<std::unique_ptr<Body>> buildRopeBody(const BodyDesc& desc, const BuildContext& ctx) {
  return make(desc, ctx, buildRope(desc.as<RopeDesc>()));
}
Result<std::unique_ptr<Body>> buildNetBody(const BodyDesc& desc, const BuildContext& ctx) {
  return make(desc, ctx, buildNet(desc.as<NetDesc>()));
}
Result<std::unique_ptr<Body>> buildLatticeBody(const BodyDesc& desc, const BuildContext& ctx) {
  const LatticeDesc& l = desc.as<LatticeDesc>();
  auto b = make(desc, ctx, buildLattice(l));
  if (!b.ok()) return b;
  // Its outer faces, each quad as two triangles, meet the other bodies.
  const std::vector<std::array<int, 4>> skin = latticeSkin(l);
  std::vector<std::array<int, 3>> surface;
  for (const auto& q : skin) {
    surface.push_back({q[0], q[1], q[2]});
    surface.push_back({q[0], q[2], q[3]});
  }
  static_cast<SpringsBody*>(b.value().get())->setSurface(std::move(surface));
  if (l.draw == LatticeDesc::Draw::Skin) {
    const int nodes = l.resolution[0] * l.resolution[1] * l.resolution[2];
    static_cast<SpringsBody*>(b.value().get())->setSkin(std::make_shared<SubdivisionSurface>(nodes, skin, l.skin_levels));
  }
  return b;
}

}  // namespace reel
