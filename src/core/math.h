// Small geometric helpers shared by sim and render.
#pragma once

#include <Eigen/Geometry>

#include "core/types.h"

namespace reel {

inline constexpr double kPi = 3.14159265358979323846;

// Rotation from XYZ Euler angles in degrees: first about x, then y, then z (R = Rz·Ry·Rx).
inline Mat3 rotationFromEulerDeg(const Vec3& deg) {
  const Vec3 r = deg * (kPi / 180.0);
  return (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

// Rotation taking +y onto the unit vector n (shortest arc); fixes the in-plane axes of a plane.
inline Mat3 rotationFromUp(const Vec3& n) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitY(), n.normalized()).toRotationMatrix();
}

}  // namespace reel
