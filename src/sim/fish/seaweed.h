// The seaweed kind: strands of kelp pinned to the seabed, each a chain of nodes with stretch and
// bend springs on the shared spring network; buoyant, and dragged toward the water's flow, so the
// currents sway them. Drawn as ribbons.
#pragma once

#include <memory>
#include <string>

#include "core/scene/fish.h"
#include "sim/spring_network.h"

namespace reel {

class SeaweedBody final : public SpringNetworkBody {
 public:
  SeaweedBody(std::string name, const SeaweedDesc& desc, const Material& material)
      : SpringNetworkBody(std::move(name), "seaweed"), desc_(desc), material_(material) {}
  void step(StepContext& ctx) override;
  void draw(DrawList& out) const override;
  std::size_t strands() const { return net_.model.nodes() / static_cast<std::size_t>(desc_.segments + 1); }

 private:
  SeaweedDesc desc_;
  Material material_;
  std::vector<Vec3> lift_;  // buoyancy per node, N
};

Result<std::unique_ptr<Body>> buildSeaweedBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
