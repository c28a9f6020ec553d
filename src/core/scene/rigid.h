// The kind `rigid`: rigid bodies (a sphere, box, capsule, cylinder or closed mesh each) that move
// by Newton–Euler dynamics, touch each other and every object with friction, and exchange
// momentum with cloth, liquids and every body of nodes through the coupling stage. An entry is one
// body, or an `array` of copies on a grid. A `"dynamic": true` object is read as a rigid entry of
// one body that moves that object. docs/rigid.md lists every key.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/mass_properties.h"
#include "core/scene/body.h"
#include "core/scene/object.h"
#include "core/types.h"

namespace reel {

// One rigid body: the object it is (its shape at its start pose, surface, material, motion keys
// for a kinematic one), its mass properties and how it starts to move.
struct RigidItem {
  std::string name;        // the entry's name, or name/k for the k-th copy of an array
  std::size_t object = 0;  // its object: index into RigidDesc::objects, or the scene's (scene_object)
  // Mass, centre of mass and inertia about it, of the object as placed at t = 0 (world axes).
  MassProperties mass;
  Mat3 axes = Mat3::Identity();  // the body frame at t = 0 (the shape's own axes: rotation_deg)
  Vec3 velocity{0, 0, 0};          // of the centre of mass, m/s
  Vec3 angular_velocity{0, 0, 0};  // rad/s, world frame
  bool kinematic = false;          // fixed or moved by keys: infinite mass
  Vec3 force{0, 0, 0};             // constant, at the centre of mass, world frame, N
  Vec3 torque{0, 0, 0};            // constant, world frame, N·m
  double linear_damping = 0.0;     // 1/s: v loses this share per second (0: none)
  double angular_damping = 0.0;    // 1/s: ω likewise
};

struct RigidDesc final : BodyParams {
  std::vector<ObjectDesc> objects;  // the entry's own objects (colliders, drawn at the body's pose)
  std::vector<RigidItem> items;
  // The scene object a `"dynamic": true` object's body moves (its items index the scene's objects).
  bool scene_object = false;
  int iterations = 4;      // solver sub-steps per step (the most any entry asks for)
  double sleep_time = 0.5; // s at rest before an island of bodies sleeps; 0: never
  std::span<const ObjectDesc> ownObjects() const override { return objects; }
  double contactRadius(double) const override { return 0.0; }
};

}  // namespace reel
