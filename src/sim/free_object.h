// Free objects (scene key `"dynamic": true`): rigid props that gravity and the liquid move, and
// that push the liquid back. The liquid's contacts hand each object the impulses they took from
// the particles (through the coupling stage, sim/body.h); the object integrates them with gravity
// (symplectic Euler on the centre of mass, orientation by the exact rotation of ω·h), then meets
// the other objects through sample points on its surface (sequential impulses with restitution
// and Coulomb friction, and a projection out of the penetration). Its pose is its collider's.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/scene.h"
#include "core/types.h"
#include "sim/body.h"
#include "sim/collide.h"

namespace reel {

struct FreeObject {
  std::size_t collider = 0;  // index into the World's colliders: its shape and pose
  double mass = 1.0;         // kg
  Mat3 inertia = Mat3::Identity();  // about the reference point, in the authored frame, kg·m²
  Vec3 v{0, 0, 0}, w{0, 0, 0};      // m/s of the reference point, rad/s
  std::vector<Vec3> samples;        // authored points on the surface (contacts with objects)
  double sample_radius = 0.0;       // m: spheres and capsules touch at their radius
};

// Mass properties and surface samples of an object (uniform density; the reference point is the
// centre of mass; a mesh takes the inertia of its bounding box).
FreeObject makeFreeObject(const ObjectDesc& o, std::size_t collider);

// Applies the impulses handed to it this step (N·s, N·m·s) and gravity over a step h, moves its
// collider (its previous pose kept, for surface velocities), and resolves contacts with every
// collider that is neither itself nor a free object.
void stepFreeObject(FreeObject& b, std::vector<Collider>& colliders, const Vec3& impulse, const Vec3& angular,
                    const Vec3& gravity, double h);

// A free object as a body: it steps in the coupling stage, after the bodies that push it. It is
// drawn as its object (the World draws objects at their pose) and not dumped.
class FreeObjectBody final : public Body {
 public:
  FreeObjectBody(std::string name, FreeObject object, const Collider& c)
      : Body(std::move(name)), object_(std::move(object)), pos_(c.pos), rot_(c.rot) {}
  StepLimit stepLimit(IntegratorKind) const override { return {}; }
  bool coupled() const override { return true; }
  void step(StepContext& ctx) override;
  Status checkState(const StepContext&) const override { return {}; }
  bool view(BodyView&) const override { return false; }
  void snapshot(StateBlob& out) const override;
  bool restore(const StateBlob& in) override;
  void hash(Hasher& h) const override;
  void draw(DrawList&) const override {}
  const FreeObject& object() const { return object_; }

 private:
  FreeObject object_;
  Vec3 pos_;  // the pose its step left its collider in
  Mat3 rot_;
};

}  // namespace reel
