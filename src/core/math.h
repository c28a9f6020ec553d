// Small geometric helpers shared by sim and render.
#pragma once

#include <algorithm>
#include <cmath>

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

// The XYZ Euler angles in degrees of a rotation (the inverse of rotationFromEulerDeg).
inline Vec3 eulerDegFromRotation(const Mat3& R) {
  const Vec3 zyx = R.eulerAngles(2, 1, 0);
  return Vec3(zyx[2], zyx[1], zyx[0]) * (180.0 / kPi);
}

// Rotation taking +y onto the unit vector n (shortest arc); fixes the in-plane axes of a plane.
inline Mat3 rotationFromUp(const Vec3& n) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitY(), n.normalized()).toRotationMatrix();
}

// 0 below e0, 1 above e1 (or the reverse when e1 < e0), a cubic between with no kink at either end.
inline double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Uniform Catmull–Rom between p1 (s = 0) and p2 (s = 1), p0 and p3 its neighbours:
// p(s) = ½[2p1 + (p2 − p0)s + (2p0 − 5p1 + 4p2 − p3)s² + (3p1 − p0 − 3p2 + p3)s³].
template <class T>
T catmullRom(const T& p0, const T& p1, const T& p2, const T& p3, double s) {
  return 0.5 * (2.0 * p1 + (p2 - p0) * s + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * (s * s) +
                (3.0 * p1 - p0 - 3.0 * p2 + p3) * (s * s * s));
}

// A unit vector perpendicular to unit d, fixed for each d.
inline Vec3 perpendicular(const Vec3& d) {
  const Vec3 a = std::abs(d.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  return a.cross(d).normalized();
}

// d made unit, or `fallback` when d is (nearly) zero.
inline Vec3 unitOr(const Vec3& d, const Vec3& fallback) {
  const double n = d.norm();
  return n > 1e-12 ? Vec3(d / n) : fallback;
}

// A direction uniform on the sphere from two uniforms in [0, 1).
inline Vec3 sphereDirection(double u, double w) {
  const double z = 2 * u - 1, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * w;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace reel
