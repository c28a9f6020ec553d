// The food kind: plankton that drifts with the water and is eaten by fish (sim/fish/fish_body.h).
// Particles are emitted at random points of a box at a rate, up to a number alive; each step a
// particle within a biting fish's mouth is eaten: it is gone, and the meal is listed for that
// fish's body to read (fish and food each change only themselves; the list says who ate what).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/scene/fish.h"
#include "sim/body.h"
#include "sim/shared_view.h"

namespace reel {

class FoodBody final : public Body {
 public:
  FoodBody(std::string name, const FoodDesc& desc, const Material& material, std::uint64_t seed);
  StepLimit stepLimit(IntegratorKind) const override { return {StepBound{}, "of food '" + name() + "'", ""}; }
  void step(StepContext& ctx) override;
  void show(SharedView& out, int self) override;
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList& out) const override;
  void statistics(std::vector<Statistic>& out) const override;

  const std::vector<Vec3>& particles() const { return x_; }
  // Each particle's emission number: what names it while others are eaten around it.
  const std::vector<std::int64_t>& ids() const { return id_; }
  // Meals of the last step this body took.
  const std::vector<FoodMeal>& meals() const { return meals_; }

 private:
  void emit(std::int64_t upto);
  FoodDesc desc_;
  Material material_;
  std::uint64_t seed_ = 0;
  // State.
  std::vector<Vec3> x_, v_;
  std::vector<std::int64_t> id_;  // emission number of each particle (its random stream)
  std::int64_t emitted_ = 0, eaten_ = 0;
  std::vector<FoodMeal> meals_;
};

Result<std::unique_ptr<Body>> buildFoodBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
