// Basic numeric types shared by every reel module.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace reel {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;  // a point or vector in world space, SI units
using Mat3 = Eigen::Matrix3d;

}  // namespace reel
