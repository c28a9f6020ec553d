// The objects as convex parts that bodies of links and shapes touch (rigid bodies, articulated
// figures): a whole shape, one of a container's boxes, one triangle of a mesh, or a plane's
// half-space; the parts near a box, and the contacts of a shape with a part (sim/rigid/contact.h).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "sim/collide.h"
#include "sim/rigid/contact.h"

namespace reel {

// A convex part of an object.
struct ObjectPart {
  std::size_t collider = 0;
  bool half_space = false;
  Vec3 normal{0, 1, 0};           // half-space: outward normal (authored), and its offset n·x
  double offset = 0.0;
  double half_w = 0.0, half_d = 0.0;  // a finite plane's half extents (0: infinite)
  Mat3 frame = Mat3::Identity();      // a plane's axes (x, normal, z), authored
  ConvexShape shape;              // authored frame (the collider's pose carries it)
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};  // authored bounds
};

// Every object's parts, built once from the colliders (their authored shapes; a collider's pose
// carries them). Free bodies' own colliders (rigid bodies, links) are left out unless asked for.
struct ObjectParts {
  std::vector<ObjectPart> parts;
  std::vector<std::pair<std::size_t, std::size_t>> mesh_parts;  // per collider: first part, count (meshes)
  bool built = false;
};

// `with_free`: free bodies' colliders too, except those in [skip_first, skip_end) (a figure's own
// links): a figure meets rigid bodies and other figures as parts.
void buildParts(const std::vector<Collider>& colliders, ObjectParts& cache, bool with_free = false,
                std::size_t skip_first = 0, std::size_t skip_end = 0);

// Whether two boxes overlap.
inline bool overlaps(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
}

// The parts whose box meets [lo, hi] (world), in part order (a mesh's triangles through its grid).
void partsNear(const ObjectParts& cache, const std::vector<Collider>& colliders, const Vec3& lo, const Vec3& hi,
               std::vector<std::uint32_t>& out);

// A collider's pose as a Pose of its authored frame.
Pose colliderPose(const Collider& c);

// Contacts of a shape at `pose` with an object part (A: the shape; the normal points to the part).
bool collidePart(const ConvexShape& shape, const Pose& pose, const ObjectPart& part, const Collider& c, double margin,
                 Manifold& m);

}  // namespace reel
