// The cloth kind: a sheet on the shared spring network plus its own data (Cloth: triangles, air,
// grips, strain limiting, self-collision, tearing). Drawn as one mesh split along its tears
// (cloth_draw.cpp).
#pragma once

#include <memory>
#include <string>

#include "sim/cloth/cloth.h"
#include "sim/spring_network.h"

namespace reel {

class ClothBody final : public SpringNetworkBody {
 public:
  ClothBody(std::string name, std::string generator, const Material& material)
      : SpringNetworkBody(std::move(name), std::move(generator)), material_(material) {}
  void step(StepContext& ctx) override;
  void draw(DrawList& out) const override;
  // The clamps of its grips and the pegs of its other pinned nodes (cloth_draw.cpp).
  void drawHolds(DrawList& out) const;
  bool view(BodyView& out) const override;
  void statistics(std::vector<Statistic>& out) const override;
  Cloth& cloth() { return cloth_; }
  const Cloth& cloth() const { return cloth_; }
  // A sheet without grips on objects hands nothing back (Coupling): it steps beside others.
  std::ptrdiff_t togetherWork() const override {
    for (int k : cloth_.grip_collider)
      if (k >= 0) return -1;
    return parallelWork();
  }
  void heldBy(std::vector<std::size_t>& colliders) const override {
    for (int k : cloth_.grip_collider)
      if (k >= 0) colliders.push_back(static_cast<std::size_t>(k));
  }

 private:
  template <class Self, class Archive>
  static void fields(Self& self, Archive& a);
  void exportSurface(ContactExport& out) const override;
  void snapshotMore(StateWriter& w) const override;
  bool restoreMore(StateReader& r) override;
  Material material_;
  Cloth cloth_;
  // The sheet's border (edges of one intact triangle only: its rim and the lips of its tears),
  // kept for the count of intact triangles it was found at (tearing only ever lowers it).
  mutable std::vector<std::array<int, 2>> border_;
  mutable std::size_t border_at_ = static_cast<std::size_t>(-1);
  mutable std::vector<std::array<int, 2>> edges_of_;  // every edge of its triangles (a < b), once
  mutable std::vector<std::array<int, 2>> tris_of_;   // its one or two triangles (−1: one)
};

// The builder of the registry row `cloth`.
Result<std::unique_ptr<Body>> buildClothBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
