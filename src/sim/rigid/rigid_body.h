// RigidBody: the bodies of one `rigid` scene entry (one body, or an array of copies). Every rigid
// entry steps in the coupling stage, after the bodies that push rigid bodies (liquids, cloth),
// and all of them are solved together: the first entry in stepping order runs the joint step
// (sim/rigid/solver.h) over every entry and keeps the solver's warm-start cache; the others'
// step does nothing. Each body moves its object's collider, so the World draws it and liquids,
// cloth, schools and fish meet it as a moving object.
#pragma once

#include <memory>
#include <vector>

#include "core/scene/rigid.h"
#include "sim/body.h"
#include "sim/rigid/rigid.h"
#include "sim/rigid/solver.h"

namespace reel {

class RigidBody final : public Body {
 public:
  RigidBody(std::string name, std::vector<RigidModel> models, std::vector<RigidState> states, int iterations);
  StepLimit stepLimit(IntegratorKind) const override { return {}; }
  bool coupled() const override { return true; }
  void step(StepContext& ctx) override;
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList&) const override {}  // the World draws its objects at their pose
  void statistics(std::vector<Statistic>& out) const override;

  const std::vector<RigidModel>& models() const { return models_; }
  const std::vector<RigidState>& states() const { return states_; }
  std::vector<RigidState>& states() { return states_; }
  int iterations() const { return iterations_; }
  const RigidSolverStats& solverStats() const { return stats_; }
  // Kinematic bodies take their state from their colliders (moved by their keys).
  void follow(const std::vector<Collider>& colliders);
  // The others pose their colliders from their state; h: the step just taken (surface velocities).
  void pose(std::vector<Collider>& colliders, double h);

 private:
  void refreshView();
  std::vector<RigidModel> models_;
  std::vector<RigidState> states_;
  int iterations_ = 10;
  enum class Role { Unknown, Leader, Member };
  Role role_ = Role::Unknown;         // the first entry leads the joint step
  std::vector<RigidBody*> entries_;   // the leader's: every rigid entry, in stepping order
  RigidSolverCache cache_;  // the joint step's, kept by the first entry
  RigidSolverStats stats_;
  std::vector<Vec3> x_view_, v_view_;  // centres of mass and velocities (dump)
  std::vector<double> mass_view_;
};

Result<std::unique_ptr<Body>> buildRigidBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
