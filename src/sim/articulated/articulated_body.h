// ArticulatedBody: one `articulated` scene entry, a tree of links (sim/articulated/articulated.h).
// Each link is an object of its own (BodyParams::ownObjects), posed from the state every step, so
// the World draws it and cloth, liquids and fish meet it as a moving object; what they hand its
// links in the coupling stage it takes as impulses, which is why it steps there. It touches the
// scene's objects (ground, stairs, boxes) through the rigid bodies' narrow phase (sim/rigid/parts.h).
#pragma once

#include <memory>
#include <vector>

#include "core/scene/articulated.h"
#include "sim/articulated/articulated.h"
#include "sim/articulated/controllers.h"
#include "sim/articulated/stand_up.h"
#include "sim/body.h"
#include "sim/rigid/parts.h"

namespace reel {

class ArticulatedBody final : public Body {
 public:
  ArticulatedBody(std::string name, ArticulatedModel model, ArticulatedState state);
  StepLimit stepLimit(IntegratorKind) const override { return {}; }
  bool coupled() const override { return true; }
  bool stepsAlone() const override { return true; }
  void step(StepContext& ctx) override;
  void publish(StepContext& ctx) override;
  Status checkState(const StepContext& ctx) const override;
  bool view(BodyView& out) const override;
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList&) const override {}  // the World draws its links' objects at their pose
  void statistics(std::vector<Statistic>& out) const override;
  // Its links as convex parts of the contact layer, each answering as a free body of its own mass
  // (its joints not counted, as when another figure meets it).
  bool exportsConvex() const override { return true; }
  void exportConvex(ContactExport& out) const override;

  const ArticulatedModel& model() const { return model_; }
  const ArticulatedState& state() const { return state_; }
  ArticulatedState& state() { return state_; }
  // Kinematics of the current state (link poses, velocities, spatial inertias).
  const ArtKinematics& kinematics() const { return view_k_; }
  int contacts() const { return contacts_; }
  ControllerKind activeController() const { return active_; }
  const StandUpState& standUpState() const { return stand_; }

 private:
  void smoothStep(StepContext& ctx, VecX& v_star, bool& moved);
  void constrain(StepContext& ctx, VecX& v);
  void refresh();
  void pose(std::vector<Collider>& colliders, double h) const;
  ArticulatedModel model_;
  ArticulatedState state_;
  ArtScratch s_;
  struct Gains {
    VecX kp, kd, damp, cap;  // per velocity: servo gains, joint damping, torque limit
  } gains_;
  ObjectParts parts_;
  ArtKinematics view_k_;  // of the state (views, energies)
  std::vector<Vec3> x_view_, v_view_;
  std::vector<double> mass_view_;
  int contacts_ = 0;
  bool singular_ = false;
  std::vector<std::uint32_t> candidates_;  // object parts near the figure (scratch, see constrain)
  int candidate_age_ = 0;                  // steps since they were listed  // a step met a joint-space inertia it could not factorise (exit 3)
  HumanRoles roles_;
  // The feet's contacts of the last step (the supervisor's support polygon). Recomputed by every
  // step before use, so a resumed run's first step sees what the uninterrupted run's saw only if
  // they are part of the snapshot: they are.
  std::vector<Vec3> foot_points_;
  bool left_down_ = false, right_down_ = false;
  ControllerKind active_ = ControllerKind::None;
  StandUpState stand_;
  // Impulses the figure's contacts gave free bodies (rigid bodies, other figures' links) this
  // step: handed back when it publishes.
  struct Handback {
    std::size_t collider;
    Vec3 at, impulse;
  };
  std::vector<Handback> handbacks_;
};

Result<std::unique_ptr<Body>> buildArticulatedBody(const BodyDesc& desc, const BuildContext& ctx);

}  // namespace reel
