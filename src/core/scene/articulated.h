// The kind `articulated`: a tree of rigid links joined by hinge, universal, ball and fixed joints
// (a pendulum, a robot arm, a human figure), simulated in reduced coordinates, so its joints never
// come apart. Links are given in the scene, or made by a generator (`"figure": "human"`,
// core/figure.h). docs/articulated.md lists every key.
//
// Frames. Every link has its own frame, at its centre of mass. In the rest pose every link's frame
// is turned like its parent's (the root's: `rotation_deg`), and a joint's point is `anchor` in the
// child's frame and `parent_anchor` in the parent's. A joint's angles turn the child about the
// joint's point away from the rest pose: a hinge by θ about `axis` (parent frame); a universal by
// θ1 about `axis` (parent frame), then θ2 about `axis2` (child frame); a ball by the rotation
// vector r (child frame, |r| the angle). The root is free (6 degrees of freedom) or, with
// `fixed_base`, welded where it starts.
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/mass_properties.h"
#include "core/mesh.h"
#include "core/scene/body.h"
#include "core/scene/object.h"
#include "core/types.h"

namespace reel {

enum class JointType { Free, Hinge, Universal, Ball, Fixed };

// Degrees of freedom of a joint's motion (velocity coordinates).
inline int jointDofs(JointType t) {
  switch (t) {
    case JointType::Free: return 6;
    case JointType::Ball: return 3;
    case JointType::Universal: return 2;
    case JointType::Hinge: return 1;
    case JointType::Fixed: return 0;
  }
  return 0;
}

// A servo at a joint: a proportional-derivative torque toward target angles, τ = kp·(θ̄ − θ) − kd·θ̇,
// each component at most max_torque in size (a ball's: its rotation-vector error).
struct ServoDesc {
  double kp = 0.0;  // N·m/rad (0: no servo)
  double kd = 0.0;  // N·m·s/rad
  double max_torque = std::numeric_limits<double>::infinity();  // N·m
};

struct ArticulatedJointDesc {
  JointType type = JointType::Hinge;
  Vec3 axis{0, 0, 1};   // hinge, universal's first: unit, parent frame
  Vec3 axis2{1, 0, 0};  // universal's second: unit, child frame
  Vec3 anchor{0, 0, 0};         // the joint's point in the child's frame, m
  Vec3 parent_anchor{0, 0, 0};  // the same point in the parent's frame, m
  std::vector<double> angles;   // initial, rad (hinge 1, universal 2, ball 3: a rotation vector)
  // Limits, rad: hinge and universal, lower/upper per degree of freedom; ball, `cone`: the largest
  // angle of the joint's rotation. Empty / 0: none.
  std::vector<double> lower, upper;
  double cone = 0.0;
  double damping = 0.0;  // N·m·s/rad, on the joint's angular velocity
  double armature = 0.0;  // kg·m² added to each of the joint's rotations (a motor's reflected rotor inertia)
  ServoDesc servo;
  std::vector<double> target;  // rad, the servo's rest target (default the initial angles)
};

// A link's shape in its own frame: a sphere, a box (full size), a capsule (`length` between its
// caps' centres) or a cylinder (`length` its height), the last two along y; centred at `offset`
// from the centre of mass and turned by `rotation` (both zero for the scene's links; a URDF's
// collision origin sets them).
struct LinkShape {
  // Mesh: a robot's (URDF), drawn as itself, met as its convex hull; its mass comes from the file.
  enum class Kind { Sphere, Box, Capsule, Cylinder, Mesh } kind = Kind::Box;
  std::shared_ptr<const TriMesh> mesh;  // Mesh: in its own frame, before `scale`
  Vec3 scale{1, 1, 1};
  double radius = 0.0;  // m
  Vec3 size{0.1, 0.1, 0.1};  // m
  double length = 0.0;  // m
  Vec3 offset{0, 0, 0};  // m, link frame
  Mat3 rotation = Mat3::Identity();
};

struct ArticulatedLinkDesc {
  std::string name;
  int parent = -1;  // index of the parent link (earlier in the list); −1: the root
  ArticulatedJointDesc joint;  // to the parent (the root's: Free, or Fixed with fixed_base)
  LinkShape shape;
  MassProperties mass;  // in the link's frame: centre of mass at the origin
  Material material;
};

// Pose keyframes: at `time`, the servo targets of the joints it names (rad); between keys the
// targets move linearly, after the last they hold.
struct PoseKey {
  double time = 0.0;  // s
  std::vector<std::pair<int, std::vector<double>>> targets;  // link index (its joint) → angles
};

// A push: at `time`, an impulse through a link's centre of mass (a shove, a kick).
struct PushDesc {
  double time = 0.0;  // s
  int link = 0;
  Vec3 impulse{0, 0, 0};  // N·s, world
};

// A human figure's controllers (sim/articulated/controllers.h), in the supervisor's order.
struct ControllersDesc {
  bool balance = false;
  double position_gain = 4.0;  // rad of ankle lean per m of the centre of mass's offset
  double velocity_gain = 1.5;  // rad per m/s
  double margin = 0.02;        // m: the centre of mass this far inside the support still balances
  bool protect = false;
  double reach_deg = 80.0;     // how far the arms swing toward the fall
  bool stand_up = false;
  double stand_up_wait = 0.4;  // s: lying still this long before it gets up
  bool any() const { return balance || protect || stand_up; }
};

struct ArticulatedDesc final : BodyParams {
  std::vector<ArticulatedLinkDesc> links;  // parents before children; links[0] is the root
  Vec3 position{0, 0, 0};       // the root's centre of mass at the start, m
  Mat3 rotation = Mat3::Identity();  // the root's frame at the start
  Vec3 velocity{0, 0, 0};       // the root's centre of mass, m/s
  Vec3 angular_velocity{0, 0, 0};  // the root's, rad/s, world
  bool fixed_base = false;
  std::vector<PoseKey> poses;
  std::vector<PushDesc> pushes;
  bool gravity_compensation = false;  // servos add the torque that holds the links up against gravity
  ControllersDesc controllers;
  int iterations = 30;  // contact and limit solver passes per step
  std::vector<ObjectDesc> objects;  // one per link, at its start pose (colliders, drawn at the link's pose)
  std::span<const ObjectDesc> ownObjects() const override { return objects; }
  double contactRadius(double) const override { return 0.0; }
};

// The rotation a joint's angles make (child frame relative to the parent's rest-aligned frame).
Mat3 jointRotation(const ArticulatedJointDesc& j, std::span<const double> angles);

// Each link's frame (rotation, centre of mass) at the initial angles, in link order.
void startPoses(const ArticulatedDesc& d, std::vector<Mat3>& R, std::vector<Vec3>& x);

// The object a link is drawn and met as, placed at pose (R, x).
ObjectDesc linkObject(const ArticulatedLinkDesc& l, const Mat3& R, const Vec3& x, const std::string& body);

// A link's mass properties from its shape at a density (kg/m³), in the link's frame (a mesh's: zero;
// a robot file gives them).
MassProperties linkMass(const LinkShape& s, double density);

}  // namespace reel
