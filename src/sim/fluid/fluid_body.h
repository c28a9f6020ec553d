// The liquid kind: the discrete particle fluid (fluid.h) as a body. Its contacts hand free objects
// the impulses they take (the coupling stage); drawn as spheres or a surface (fluid_draw.cpp).
#pragma once

#include <memory>
#include <string>

#include "sim/body.h"
#include "sim/fluid/fluid.h"

namespace reel {

// The pipes of the liquid's nozzles (those with `nozzle`): each a metal cylinder 4 radii long (at
// least 8 cm) whose mouth is the emitter's disc, its wall a quarter radius thick (at least 3 mm);
// null when there are none.
std::shared_ptr<const TriMesh> nozzleMesh(const Fluid& fluid);

class FluidBody final : public Body {
 public:
  FluidBody(Fluid fluid, std::string generator, const Material& material)
      : Body(fluid.name), generator_(std::move(generator)), material_(material), fluid_(std::move(fluid)),
        bound_(fluidStableStep(fluid_)), nozzles_(nozzleMesh(fluid_)) {}
  StepLimit stepLimit(IntegratorKind integrator) const override;
  void step(StepContext& ctx) override;
  std::ptrdiff_t togetherWork() const override { return static_cast<std::ptrdiff_t>(fluid_.x.size()); }
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList& out) const override;
  std::vector<std::string> notes(double h) const override;
  // Its particles meet every other body through the World's contact layer.
  bool exportsContacts() const override { return true; }
  void exportContacts(ContactExport& out) const override;
  void importContacts(std::span<const Vec3> x, std::span<const Vec3> v) override;
  void dropPoints(std::span<const std::uint8_t> gone) override;

  Fluid& fluid() { return fluid_; }
  const Fluid& fluid() const { return fluid_; }
  const StepBound& bound() const { return bound_; }

 private:
  template <class State, class Archive>
  static void fields(State& s, Archive& a);
  // The state in order of creation (dumps, hashes).
  const Fluid& byId() const;
  std::string generator_;  // the scene type that built it
  Material material_;
  mutable Fluid fluid_;  // mutable: view() and hash() fill its by-id scratch arrays
  StepBound bound_;
  std::shared_ptr<const TriMesh> nozzles_;  // the emitters' pipes, made once (null: none)
  mutable std::vector<double> inv_mass_;  // scratch: 1/kg per particle slot (contacts)
};

// The builder of the registry row `fluid`.
Result<std::unique_ptr<Body>> buildFluidBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
