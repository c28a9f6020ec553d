// Collision primitives shared by every particle-based body: signed distance and outward normal
// for planes, spheres, boxes and capsules, and one contact response for nodes.
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "core/types.h"

namespace reel {

struct Collider {
  ObjectKind kind = ObjectKind::Plane;
  Vec3 p0{0, 0, 0};     // plane point, sphere/box centre, capsule end a
  Vec3 p1{0, 0, 0};     // capsule end b
  Vec3 half{0, 0, 0};   // box half extents; plane half width/height in x, z (0 = infinite)
  Mat3 R = Mat3::Identity();  // box / plane orientation (local → world)
  double radius = 0.0;  // sphere, capsule
  double thickness = 0.0;
  Surface surface;

  // Signed distance from p to the surface (negative inside) and the outward normal there.
  // Returns false when p is outside the collider's reach: beside a finite plane, or more than
  // its thickness plus 5% of its smaller half-size below it.
  bool distance(const Vec3& p, double& d, Vec3& n) const;
};

Collider makeCollider(const ObjectDesc& o);

// Projects nodes that are closer than thickness + radius back onto the surface and applies
// restitution and Coulomb friction to their velocity (a velocity-level impulse per node):
//   v_n' = −e·v_n,  |v_t'| = max(0, |v_t| − μ(1 + e)|v_n|).
// Friction also takes back the tangential distance the step moved at the old velocity
// (x += h·(v_t' − v_t)), so static friction holds a node in place instead of letting it creep.
// Fixed nodes are left alone.
void resolveContacts(const std::vector<Collider>& colliders, double radius, double h,
                     const std::uint8_t* fixed, std::vector<Vec3>& x, std::vector<Vec3>& v);

}  // namespace reel
