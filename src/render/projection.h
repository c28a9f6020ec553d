// Camera and light transforms (OpenGL conventions: right-handed view, clip z in [-1, 1]) and the
// scene's bounding sphere they are fitted to.
#pragma once

#include <Eigen/Core>

#include "core/drawlist.h"
#include "core/types.h"

namespace reel {

using Mat4f = Eigen::Matrix4f;
using Vec3f = Eigen::Vector3f;

// World → view: the eye at the origin looking down -z, `up_hint` roughly up.
Mat4f lookAt(const Vec3& eye, const Vec3& target, const Vec3& up_hint);
// View → clip for a vertical field of view in degrees.
Mat4f perspective(double fovy_deg, double aspect, double n, double f);
// View → clip for a symmetric box of half-size r.
Mat4f ortho(double r, double n, double f);

// A mesh wider than this (m) is a ground: it receives shadows and does not bound the scene.
inline constexpr double kGroundExtent = 100.0;

// The scene's bounding sphere from everything but grounds; around the camera's target with
// radius 5 when there is nothing to bound.
void sceneBounds(const DrawList& list, Vec3& center, double& radius);

// A flat ground: a mesh whose vertices all lie on one plane (within a millionth of its width),
// at least kGroundExtent along both axes of its largest triangle's shortest edge and across, and
// whose triangles cover the rectangle that bounds it there (no holes); that plane (a point on it,
// its unit normal).
struct GroundPlane {
  bool flat = false;
  Vec3 point{0, 0, 0}, normal{0, 0, 0};
};
GroundPlane groundPlane(const TriMesh& m);

}  // namespace reel
