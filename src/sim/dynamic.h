// Objects with `"dynamic": true`: rigid props that gravity and the liquid move, and that push
// the liquid back. The liquid's contacts hand each object the impulses they took from the
// particles (sim/fluid); the object integrates them with gravity (symplectic Euler on the
// centre of mass, orientation by the exact rotation of ω·h), then meets the other objects
// through sample points on its surface (sequential impulses with restitution and Coulomb
// friction, and a projection out of the penetration).
#pragma once

#include <cstddef>
#include <vector>

#include "core/scene.h"
#include "core/types.h"
#include "sim/collide.h"

namespace reel {

struct DynamicObject {
  std::size_t collider = 0;  // index into the World's colliders
  double mass = 1.0;         // kg
  Mat3 inertia = Mat3::Identity();  // about the reference point, in the authored frame, kg·m²
  Vec3 v{0, 0, 0}, w{0, 0, 0};      // m/s of the reference point, rad/s
  std::vector<Vec3> samples;        // authored points on the surface (contacts with objects)
  double sample_radius = 0.0;       // m: spheres and capsules touch at their radius
  Vec3 impulse{0, 0, 0}, angular{0, 0, 0};  // N·s and N·m·s gathered during the step
};

// Mass properties and surface samples of an object (uniform density; the reference point is the
// centre of mass; a mesh takes the inertia of its bounding box).
DynamicObject makeDynamic(const ObjectDesc& o, std::size_t collider);

// Applies the gathered impulses and gravity over a step h, moves collider `self` (its previous
// pose kept, for surface velocities), and resolves contacts with every other non-dynamic collider.
void stepDynamic(DynamicObject& b, std::vector<Collider>& colliders, const Vec3& gravity, double h);

}  // namespace reel
