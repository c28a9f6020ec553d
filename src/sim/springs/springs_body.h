// The springs kinds: the seed's explicit nodes and springs (`mass_spring`) and its generators
// `rope`, `net` and `lattice` (generators.h), one body type over the shared spring network. Drawn
// as spheres at the nodes and tubes along the springs (springs_draw.cpp).
#pragma once

#include <memory>
#include <string>

#include "core/scene/mass_spring.h"
#include "core/subdivision.h"
#include "sim/spring_network.h"

namespace reel {

class SpringsBody final : public SpringNetworkBody {
 public:
  SpringsBody(std::string name, std::string generator, const Material& material)
      : SpringNetworkBody(std::move(name), std::move(generator)), material_(material) {}
  void step(StepContext& ctx) override;
  std::ptrdiff_t togetherWork() const override { return parallelWork(); }  // (it reads only the objects)
  void draw(DrawList& out) const override;
  // Draws a smooth skin over the nodes instead of the nodes and springs (a lattice's).
  void setSkin(std::shared_ptr<const SubdivisionSurface> skin) { skin_ = std::move(skin); }

 private:
  Material material_;  // nodes are drawn at their contact radius, net_.radius
  std::shared_ptr<const SubdivisionSurface> skin_;
};

// Builders of the registry rows mass_spring, rope, net and lattice.
Result<std::unique_ptr<Body>> buildMassSpringBody(const BodyDesc& desc, const BuildContext& ctx);
Result<std::unique_ptr<Body>> buildRopeBody(const BodyDesc& desc, const BuildContext& ctx);
Result<std::unique_ptr<Body>> buildNetBody(const BodyDesc& desc, const BuildContext& ctx);
Result<std::unique_ptr<Body>> buildLatticeBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
