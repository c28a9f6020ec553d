// RigidBody: the bodies of one `rigid` scene entry (one body, or an array of copies). The World's
// rigid system (RigidSystem, the kind's BodySystem) steps every entry together in the coupling
// stage, after the bodies that push rigid bodies (liquids, cloth) and the figures: one joint step
// (sim/rigid/solver.h) whose warm-start cache the system keeps. Each body moves its object's
// collider, so the World draws it and liquids, cloth, schools and fish meet it as a moving object.
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
  // Never called: the World's RigidSystem steps every rigid entry.
  void step(StepContext& ctx) override;
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList&) const override {}  // the World draws its objects at their pose
  void statistics(std::vector<Statistic>& out) const override;
  // Its bodies as convex parts of the contact layer (a kinematic one with infinite mass).
  bool exportsConvex() const override { return true; }
  void exportConvex(ContactExport& out) const override;

  const std::vector<RigidModel>& models() const { return models_; }
  const std::vector<RigidState>& states() const { return states_; }
  std::vector<RigidState>& states() { return states_; }
  int iterations() const { return iterations_; }
  // The joint step's figures (every rigid entry's together, from the World's system).
  const RigidSolverStats& solverStats() const { return *joint_; }
  // Kinematic bodies take their state from their colliders (moved by their keys).
  void follow(const std::vector<Collider>& colliders);
  // The others pose their colliders from their state; h: the step just taken (surface velocities).
  void pose(std::vector<Collider>& colliders, double h);

 private:
  void refreshView();
  std::vector<RigidModel> models_;
  std::vector<RigidState> states_;
  int iterations_ = 10;
  friend class RigidSystem;
  static inline const RigidSolverStats kNoStats{};
  const RigidSolverStats* joint_ = &kNoStats;  // the system's figures
  bool reports_joint_ = true;  // the first entry writes the joint figures into the statistics
  std::vector<Vec3> x_view_, v_view_;  // centres of mass and velocities (dump)
  std::vector<double> mass_view_;
};

// The World's system of rigid bodies: the joint step of every entry, and its warm-start cache.
class RigidSystem final : public BodySystem {
 public:
  void adopt(std::vector<Body*> members) override;
  void step(StepContext& ctx) override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;

 private:
  std::vector<RigidBody*> entries_;  // in scene order
  RigidSolverCache cache_;
  RigidSolverStats stats_;
};

Result<std::unique_ptr<Body>> buildRigidBody(const BodyDesc& desc, const BuildContext& ctx);
std::unique_ptr<BodySystem> makeRigidSystem();

}  // namespace reel
