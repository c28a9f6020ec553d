#include "sim/springs/springs_body.h"

#include "sim/springs/generators.h"

namespace reel {
namespace {

Result<std::unique_ptr<Body>> make(const BodyDesc& desc, const BuildContext& ctx, const MassSpringDesc& nodes) {
  auto b = std::make_unique<SpringsBody>(desc.name, desc.type, desc.material);
  if (Status st = buildNetwork(*b, nodes, desc, ctx, desc.node_radius); !st) return st.error();
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
  return make(desc, ctx, buildLattice(desc.as<LatticeDesc>()));
}

}  // namespace reel
