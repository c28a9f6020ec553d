// The school kind: a School (school.h) as a body. It reads the colliders (obstacles, and an object
// predator) and, when its predator is another school, that school's agents; drawn as instanced
// fish (school_draw.cpp).
#pragma once

#include <memory>
#include <string>

#include "sim/body.h"
#include "sim/school/school.h"
#include "sim/shared_view.h"

namespace reel {

class SchoolBody final : public Body {
 public:
  SchoolBody(School school, const Material& material, int predator_object)
      : Body(school.name), material_(material), school_(std::move(school)), predator_object_(predator_object) {}
  StepLimit stepLimit(IntegratorKind integrator) const override;
  void step(StepContext& ctx) override;
  void show(SharedView& out, int self) override;
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList& out) const override;
  void statistics(std::vector<Statistic>& out) const override;
  std::vector<std::string> notes(double h) const override;

  School& school() { return school_; }
  const School& school() const { return school_; }

 private:
  template <class State, class Archive>
  static void fields(State& s, Archive& a);
  SchoolView sees(const StepContext& ctx) const;  // its predator, the other bodies' points
  double watchRadius() const override { return school_.desc.avoid_margin; }
  Material material_;
  School school_;
  int predator_object_ = -1;  // the collider of an object predator
};

// The builder of the registry row `school`.
Result<std::unique_ptr<Body>> buildSchoolBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
