// World: owns the bodies and the colliders of one scene, and advances them frame by frame
// (DESIGN 2). Time always comes from integer counters: t = step / (fps · steps per frame).
//
// A step: keyframed objects move to the step's end; every body steps (the scene's bodies in
// scene order, each checked for a bad state); then the coupling stage: the contact layer (every
// body's points, triangles, threads and convex parts against every other's; a pair of kinds with
// a law of its own, InteractionRow: liquid ↔ cloth, as the layer's hook), the figures (in
// parallel, each publishing in order), and last the systems that step a kind's bodies together
// (BodySystem: the rigid bodies, taking what the others handed their objects, sim/body.h:
// Coupling). The World knows no body kind: the builders and systems come from the registry of
// kinds (app/body_kinds.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/drawlist.h"
#include "core/error.h"
#include "core/frame_view.h"
#include "core/scene.h"
#include "core/state_blob.h"
#include "sim/body.h"
#include "sim/collide.h"
#include "sim/contact_layer.h"
#include "sim/shared_view.h"
#include "sim/water.h"
#include "sim/wind.h"

namespace reel {

// substeps × automatic subdivision stays below this (10 million steps per frame).
inline constexpr double kMaxStepsPerFrame = 1e7;

// The complete state of a World at a frame: restore() into a World built from the same scene
// resumes the run bit for bit.
struct WorldSnapshot {
  int frame = 0;
  long long step = 0;
  std::vector<ColliderPose> colliders;  // each collider's pose (its shape never changes)
  std::vector<StateBlob> bodies;
  std::vector<StateBlob> systems;  // the World's systems (the rigid bodies' warm-start cache)
  SolverStats solver;
  CameraRig camera;
};

class World {
 public:
  // Builds the colliders and, through `kinds`, the bodies; refuses (BadInput) a step above an
  // explicit integrator's stability bound unless the scene sets `auto_substeps`, in which case
  // steps are subdivided.
  // `interactions`: the contact laws of pairs of kinds (the registry's hooks of the contact layer).
  // `check_only`: built for `reel check`, never stepped: no body prepares (Body::prepare).
  static Result<World> create(const SceneDesc& scene, std::span<const BodyKindRow> kinds,
                              std::span<const InteractionRow> interactions = {}, bool check_only = false);

  // Advances from the current frame k to k + 1: substeps × step(h). Fails with an Unstable
  // error naming frame, time, body, node and quantity when the state goes bad.
  Status advanceFrame();

  int frame() const { return frame_; }
  double time() const { return static_cast<double>(frame_) / fps_; }
  // Steps taken per frame (substeps × any automatic subdivision) and the step length.
  int stepsPerFrame() const { return substeps_ * subdivision_; }
  double stepSize() const { return 1.0 / (static_cast<double>(fps_) * stepsPerFrame()); }

  // The scene's bodies in scene order, then the free objects.
  const std::vector<std::unique_ptr<Body>>& bodies() const { return bodies_; }
  // The first body of type T, or nullptr.
  template <class T>
  const T* first() const {
    for (const auto& b : bodies_)
      if (const T* t = dynamic_cast<const T*>(b.get())) return t;
    return nullptr;
  }
  const std::vector<Collider>& colliders() const { return colliders_; }
  // The contact layer (its last step's proxies and counts).
  const ContactLayer& contacts() const { return contacts_; }
  // The camera rig's state when the scene's camera follows or frames a body, else nullptr: hand
  // it to setSceneView.
  const CameraRig* cameraRig() const { return camera_.active ? &camera_ : nullptr; }

  // The state a dump shows of the current frame.
  void view(FrameView& out) const;
  // Adds what to draw at the current frame: the objects (meshes built once, moving ones at their
  // pose) and every body. The camera, lights and look come from the scene, not from here.
  void draw(DrawList& out) const;
  // FNV-1a of every body's positions and velocities (determinism checks).
  std::uint64_t stateHash() const;
  // The complete state now, and back to it (BadInput when the snapshot is not of this scene).
  WorldSnapshot snapshot() const;
  Status restore(const WorldSnapshot& s);

  const StepStats& lastStepStats() const { return solver_.last; }
  // Implicit steps whose conjugate-gradient solve stopped before reaching its tolerance, and the
  // worst relative residual among them.
  long long unconvergedSteps() const { return solver_.unconverged; }
  // How many body steps ran side by side with others, each on one thread (stepTogether).
  long long sideBySideSteps() const { return side_by_side_; }
  double worstResidual() const { return solver_.worst_residual; }

 private:
  Status buildBodies(const SceneDesc& scene, std::span<const BodyKindRow> kinds, const std::vector<std::size_t>& first_object,
                     bool check_only);
  IntegratorKind integrator_ = IntegratorKind::SymplecticEuler;
  ImplicitSettings implicit_;
  int fps_ = 30, substeps_ = 1;
  int subdivision_ = 1;  // automatic subdivision of each substep (auto_substeps)
  int frame_ = 0;
  long long step_ = 0;  // steps taken since time 0
  std::vector<Collider> colliders_;
  std::vector<std::size_t> moving_objects_;  // objects with motion keys
  std::vector<std::size_t> posed_objects_;   // objects drawn at a pose: keyframed or free
  std::vector<DrawMesh> object_meshes_;      // authored, built once
  std::vector<Vec3> object_pivots_;
  Vec3 gravity_{0, -9.78, 0};
  Wind wind_;
  Water water_;
  std::vector<std::unique_ptr<Body>> bodies_;
  SharedView shown_;  // what the bodies show one another (Body::show), built once
  // The points of the bodies that have them, for the bodies that steer around others
  // (Body::watchRadius), gathered at the start of each step; none when no body watches.
  BodyPoints body_points_;
  std::vector<std::size_t> watched_;  // the bodies whose points they are
  ContactProxies watch_proxies_;      // (scratch)
  void gatherBodyPoints();
  std::vector<std::size_t> alone_;  // the coupled bodies that step alone (figures), in scene order
  std::vector<std::array<std::size_t, 2>> own_objects_;  // per body: its own objects' colliders [first, end)
  std::vector<std::uint8_t> solved_;  // per collider: its figure stepped already this step (StepContext::solved)
  bool aloneNear() const;  // whether the reach of two bodies that step alone may overlap this step
  Status stepAlone(StepContext& ctx);
  std::vector<std::size_t> together_;      // (scratch) a run of bodies that step side by side, in scene order
  std::vector<SolverStats> together_stats_;  // (scratch) their solvers' statistics, kept apart
  long long side_by_side_ = 0;
  std::vector<double> step_time_;  // per body: its last step's wall time when it stepped in a run, s (scheduling only)
  Status stepTogether(StepContext& ctx);
  struct System {
    std::unique_ptr<BodySystem> solver;
    std::vector<std::size_t> members;  // bodies, in scene order
  };
  std::vector<System> systems_;      // in the registry's order of kinds
  std::vector<char> in_system_;      // per body: stepped by a system
  struct Hooked {
    std::size_t points, surface;  // bodies
    std::unique_ptr<ContactHook> hook;
  };
  std::vector<Hooked> hooks_;  // the pairs of bodies with a contact law of their own, in order
  ContactLayer contacts_;            // every body's points and triangles against every other's
  Coupling coupling_;
  SolverStats solver_;
  CameraRigDesc camera_desc_;
  int camera_body_ = -1;  // the body the camera follows or frames
  CameraRig camera_;
  void advanceCamera();
};

}  // namespace reel
