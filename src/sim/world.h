// World: owns the simulated bodies and the colliders of one scene, and advances them frame by
// frame (DESIGN 2). Time always comes from integer counters: t = step / (fps · substeps).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/drawlist.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/snapshot.h"
#include "sim/cloth/cloth.h"
#include "sim/collide.h"
#include "sim/dynamic.h"
#include "sim/fluid/fluid.h"
#include "sim/integrators.h"
#include "sim/mass_spring.h"
#include "sim/stability.h"

namespace reel {

// A state whose speed or distance from the origin passes these is a runaway (exit 3).
inline constexpr double kRunawaySpeed = 1e4;     // m/s
inline constexpr double kRunawayDistance = 1e6;  // m
// substeps × automatic subdivision stays below this (10 million steps per frame).
inline constexpr double kMaxStepsPerFrame = 1e7;

struct MassSpringBody {
  std::string name, generator;
  double radius = 0.0;  // contact radius of the nodes, m
  Material material;
  MassSpringModel model;
  MassSpringState state;
  std::unique_ptr<MassSpringDynamics> dynamics;  // refers to `model`
  IntegratorWorkspace workspace;
  StepBound bound;
  std::unique_ptr<Cloth> cloth;  // a cloth body's sheet data; null for other bodies
};

class World {
 public:
  // Builds the bodies and colliders; refuses (BadInput) a step above an explicit integrator's
  // stability bound unless the scene sets `auto_substeps`, in which case steps are subdivided.
  static Result<World> create(const SceneDesc& scene);

  // Advances from the current frame k to k + 1: substeps × step(h). Fails with an Unstable
  // error naming frame, time, body, node and quantity when the state goes bad.
  Status advanceFrame();

  int frame() const { return frame_; }
  double time() const { return static_cast<double>(frame_) / fps_; }
  // Steps taken per frame (substeps × any automatic subdivision) and the step length.
  int stepsPerFrame() const { return substeps_ * inner_; }
  double stepSize() const { return 1.0 / (static_cast<double>(fps_) * stepsPerFrame()); }

  const std::vector<std::unique_ptr<MassSpringBody>>& bodies() const { return bodies_; }
  const std::vector<std::unique_ptr<Fluid>>& fluids() const { return fluids_; }
  const std::vector<DynamicObject>& dynamics() const { return dynamics_; }
  const std::vector<Collider>& colliders() const { return colliders_; }
  void snapshot(FrameSnapshot& out) const;
  // Fills the list of things to draw at the current frame: camera, lights, background, the
  // objects (meshes built once) and every body (nodes as spheres, springs as tubes).
  void emit(DrawList& out) const;
  // FNV-1a of every body's positions and velocities (determinism checks).
  std::uint64_t stateHash() const;
  const StepStats& lastStepStats() const { return stats_; }
  // Implicit steps whose conjugate-gradient solve stopped before reaching its tolerance, and the
  // worst relative residual among them.
  long long unconvergedSteps() const { return cg_unconverged_; }
  double worstResidual() const { return cg_worst_; }

 private:
  Status checkState(const std::string& name, const char* what, const std::vector<Vec3>& x,
                    const std::vector<Vec3>& v, const StepBound& bound, long long step) const;

  IntegratorKind integrator_ = IntegratorKind::SymplecticEuler;
  ImplicitSettings implicit_;
  int fps_ = 30, substeps_ = 1, inner_ = 1;
  int frame_ = 0;
  long long step_ = 0;  // steps taken since time 0
  std::vector<Collider> colliders_;
  std::vector<std::size_t> moving_objects_;  // objects with motion keys
  std::vector<std::size_t> posed_objects_;   // objects drawn at a pose: keyframed or dynamic
  std::vector<DynamicObject> dynamics_;
  Vec3 gravity_{0, -9.78, 0};
  Wind wind_;
  // What emit() needs of the scene.
  CameraDesc camera_;
  RenderDesc render_;
  std::vector<LightDesc> lights_;
  std::vector<DrawMesh> object_meshes_;
  std::vector<Vec3> object_pivots_;
  std::vector<std::unique_ptr<MassSpringBody>> bodies_;
  std::vector<std::unique_ptr<Fluid>> fluids_;
  std::vector<Material> fluid_materials_;
  std::vector<StepBound> fluid_bounds_;
  StepStats stats_;
  long long cg_unconverged_ = 0;
  double cg_worst_ = 0.0;
};

}  // namespace reel
