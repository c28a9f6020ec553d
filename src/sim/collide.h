// Collision primitives shared by every particle-based body: signed distance and outward normal
// for planes, spheres, boxes, capsules and triangle meshes, keyframed motion of any of them, and
// one contact response for nodes.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/scene.h"
#include "core/types.h"
#include "sim/grid.h"

namespace reel {

// A triangle mesh as a collider: world-space triangles (at the authored pose) in a grid.
struct MeshShape {
  std::vector<Vec3> vertices;                 // m (vertices)
  std::vector<std::array<int, 3>> triangles;  // vertex indices, counter-clockwise from outside
  std::vector<Vec3> normals;                  // unit face normals (triangles)
  std::vector<Vec3> centres;                  // bounding-sphere centre of each triangle
  std::vector<double> radii;                  // and its radius, m (a cheap lower bound on distance)
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};             // the triangles' box grown by `reach`
  BoxGrid grid;                               // triangles by their boxes grown by `reach`
  double reach = 0.0;                         // m: points farther than this see no triangle
};

// What a collider is, authored once when the World is built and never changed after: an object's
// geometry in the scene's frame, its surface, and how it may move (its motion keys and the pivot
// they turn it about, or posed as a free body). Shared by every copy of the collider (a snapshot
// copies poses only).
struct ColliderShape {
  ObjectKind kind = ObjectKind::Plane;
  Vec3 p0{0, 0, 0};     // plane point, sphere/box centre, capsule end a
  Vec3 p1{0, 0, 0};     // capsule end b
  Vec3 half{0, 0, 0};   // box half extents; plane half width/height in x, z (0 = infinite)
  Mat3 R = Mat3::Identity();  // box / plane orientation (local → world)
  double radius = 0.0;  // sphere, capsule
  double wall = 0.0;    // container
  double thickness = 0.0;
  Surface surface;
  SpeciesSurfaces species_surface;  // per-species surfaces (liquids)
  std::shared_ptr<const MeshShape> mesh;  // kind Mesh
  // Keyframed motion: its pose at a time maps an authored point x to rot·(x − pivot) + pos.
  std::vector<MotionKey> keys;
  Vec3 pivot{0, 0, 0};
  bool free_body = false;  // a rigid body's: posed by its motion (sim/rigid/rigid_body.h), not by keys
  // A sphere around the authored shape (its thickness included); radius infinite for a plane.
  Vec3 bound_center{0, 0, 0};
  double bound_radius = 0.0;
  bool moving() const { return free_body || !keys.empty(); }
  // The pose at time t (keys interpolated: position linearly, rotation by slerp, held outside).
  void poseAt(double t, Mat3& r, Vec3& p) const;
  // Signed distance from an authored point p to the surface (negative inside) and the outward
  // normal there, authored. False when p is outside the collider's reach: beside a finite plane,
  // more than its thickness plus 5% of its smaller half-size below it, or farther than a mesh's
  // reach.
  bool distance(const Vec3& p, double& d, Vec3& n) const;
  // The same for each convex part the surface is made of (a container's floor and four walls; one
  // part for any other shape), each measured alone: what a point in a corner sees of both walls.
  // Returns how many of d[] and n[] are set (at most kMaxParts).
  static constexpr int kMaxParts = 5;
  int partDistances(const Vec3& p, double* d, Vec3* n) const;
  // Whether the authored point p lies farther than `margin` from every part for certain: a cheap
  // test before partDistances that answers true only deep in a container's cavity (a liquid's
  // particles, most of them far from the floor and walls).
  bool clearOfParts(const Vec3& p, double margin) const;
};

// Where a collider is and how it moves: the pose now and one step ago (surface velocities), and a
// free body's response to an impulse, set where it is posed (a figure meeting it solves the
// contact with both sides' masses). What a snapshot keeps of a collider.
struct ColliderPose {
  Mat3 rot = Mat3::Identity(), rot_prev = Mat3::Identity();
  Vec3 pos{0, 0, 0}, pos_prev{0, 0, 0};
  double dt = 0.0;  // time between the previous and the current pose, s
  double inv_mass = 0.0;  // 1/kg (free bodies)
  Mat3 inv_inertia = Mat3::Zero();  // world (free bodies)
  Vec3 centre{0, 0, 0};  // centre of mass (free bodies)
};

// A collider: its shape and its pose. Static colliders keep the identity pose.
struct Collider {
  std::shared_ptr<const ColliderShape> shape;
  ColliderPose pose;

  bool moving() const { return shape->moving(); }
  // Whether p may lie within `margin` of the surface (a cheap test before distance()).
  bool near(const Vec3& p, double margin) const {
    const double r = shape->bound_radius + margin;
    return !(r < 1e300) || (toAuthored(p) - shape->bound_center).squaredNorm() <= r * r;
  }
  // Moves to time t by its keys; the pose before becomes the previous one (surface velocities).
  void moveTo(double t, double dt_since);
  // Signed distance from p to the surface (negative inside) and the outward normal (see
  // ColliderShape::distance).
  bool distance(const Vec3& p, double& d, Vec3& n) const;
  // Per convex part (ColliderShape::partDistances), normals in the world.
  int partDistances(const Vec3& p, double* d, Vec3* n) const;
  bool clearOfParts(const Vec3& p, double margin) const { return shape->clearOfParts(moving() ? toAuthored(p) : p, margin); }
  // The authored point of the material point now at p, and back (the current pose).
  Vec3 toAuthored(const Vec3& p) const { return pose.rot.transpose() * (p - pose.pos) + shape->pivot; }
  Vec3 fromAuthored(const Vec3& a) const { return pose.rot * (a - shape->pivot) + pose.pos; }
  // Velocity of the surface point now at p (zero for a static collider), m/s.
  Vec3 velocityAt(const Vec3& p) const;
  // The angular velocity of its last move (rot_prev → rot over dt), rad/s, world.
  Vec3 angularVelocity() const;
};

// Whether the segment from a to b passes through an object (sphere tracing along it with each
// collider's signed distance, at least `step` at a time): what a fish cannot see through.
bool segmentBlocked(const std::vector<Collider>& colliders, const Vec3& a, const Vec3& b, double step);

// What the coupling stage hands the bodies moved by a system (rigid bodies, figures' links), per
// collider: the contact layer's impulses on their convex parts (points and surfaces pushed off
// them), a cloth's grips on what grips it, a figure's contacts on a rigid body. Gathered in a
// fixed order, then taken by the rigid system and the figures in the same step: equal and
// opposite, momentum kept.
struct Coupling {
  std::vector<Vec3> impulse;  // per collider: linear impulse handed to it this step, N·s
  std::vector<Vec3> angular;  // per collider: angular impulse about its reference point, N·m·s
  void reset(std::size_t colliders) {
    impulse.assign(colliders, Vec3::Zero());
    angular.assign(colliders, Vec3::Zero());
  }
  // Collider k (its reference point `centre`) takes the opposite of impulse J that a contact at
  // `at` gave a particle or node.
  void handBack(std::size_t k, const Vec3& at, const Vec3& centre, const Vec3& J) {
    impulse[k] -= J;
    angular[k] -= (at - centre).cross(J);
  }
};

// `reach`: how far from a mesh's surface points are still found (thickness plus contact radius
// and a margin for one step's motion).
Collider makeCollider(const ObjectDesc& o, double reach = 0.1);

// The triangles of a mesh already placed in the world (core's placeMesh), in a grid.
std::shared_ptr<MeshShape> makeMeshShape(const TriMesh& placed, double reach);

// Projects nodes that are closer than thickness + radius to a scene object (static or keyed: a
// free body's collider is a convex part of the contact layer, which meets points there) back
// onto the surface and applies restitution and Coulomb friction to their velocity relative to the
// surface (a velocity-level impulse per node):  v_n' = −e·v_n,  |v_t'| = max(0, |v_t| − μ(1 + e)|v_n|).
// Friction also takes back the tangential distance the step moved at the old velocity
// (x += h·(v_t' − v_t)), so static friction holds a node in place instead of letting it creep.
// Fixed nodes are left alone.
void resolveContacts(const std::vector<Collider>& colliders, double radius, double h, const std::uint8_t* fixed,
                     std::vector<Vec3>& x, std::vector<Vec3>& v);

// The response above for one node at signed distance d (< reach) along the outward normal n of
// collider c, with surface s.
void contactNode(const Collider& c, const Surface& s, double reach, double d, const Vec3& n, double h, Vec3& x,
                 Vec3& v);

}  // namespace reel
