// The rigid-body narrow phase: contact manifolds between convex shapes (a point, segment or
// polytope core swept by a sphere) and of a shape with a half-space.
//
// Conventions, for every pair:
//  - the normal is unit, in world space, and points from A toward B;
//  - a contact point's position is the midpoint between the two surfaces along the normal (so it
//    does not depend on which shape is called A), its depth the overlap along the normal
//    (negative: a gap of that size, a speculative contact within the margin);
//  - at most 4 points: the deepest, then those spanning the largest area;
//  - ids name the touching features (reference face, incident face, clipped vertex or edge; edge
//    pair; capsule end), so a resting contact keeps its ids from step to step.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "core/types.h"
#include "sim/rigid/hull.h"

namespace reel {

enum class CoreKind { Point, Segment, Polytope };

// A convex shape: a core (point a; segment a–b; or polytope) swept by a sphere of `radius`
// (sphere = point + r; capsule = segment + r; box/cylinder/hull = polytope with radius 0).
struct ConvexShape {
  CoreKind kind = CoreKind::Point;
  double radius = 0.0;                         // m
  Vec3 a{0, 0, 0}, b{0, 0, 0};                 // local frame, m
  std::shared_ptr<const ConvexPolytope> poly;  // kind Polytope
};

// Local → world: x ↦ R·x + p.
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 p{0, 0, 0};
};

struct ContactPoint {
  Vec3 position{0, 0, 0};  // world, m: midway between A's and B's surfaces along the normal
  double depth = 0.0;      // m: overlap along the normal; negative = separated by that much
  std::uint32_t id = 0;    // feature key, the same from step to step while the same features touch
};

struct Manifold {
  Vec3 normal{0, 1, 0};  // unit, world, pointing from A toward B
  int count = 0;         // 0..4
  std::array<ContactPoint, 4> points;
};

// Contacts of A and B whose surfaces are closer than `margin` (≥ 0) or overlap. Returns false
// (count 0) when farther apart.
bool collide(const ConvexShape& A, const Pose& pa, const ConvexShape& B, const Pose& pb,
             double margin, Manifold& out);

// Contacts of A with the half-space {x : n·x ≤ offset} (world; n unit, pointing out of the solid).
// The normal of the result points from A toward the half-space: −n.
bool collideHalfSpace(const ConvexShape& A, const Pose& pa, const Vec3& n, double offset,
                      double margin, Manifold& out);

// World-space bounding box of the shape (with its radius).
void shapeBounds(const ConvexShape& s, const Pose& p, Vec3& lo, Vec3& hi);

}  // namespace reel
