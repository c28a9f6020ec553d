// Small geometric queries shared by the colliders and self-collision.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/types.h"

namespace reel {

// The point of triangle (a, b, c) closest to p, as barycentric weights (wa, wb, wc), sum 1.
// Regions by the signs of the projections onto the edges (Voronoi regions of the vertices,
// edges and face; the method of Ericson, "Real-Time Collision Detection", 5.1.5).
inline Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = va + vb + vc;
  if (!(denom > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return {1 - v - w, v, w};
}

// The parameter t in [0, 1] of the point a + t·(b − a) of segment a–b closest to p.
inline double closestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  if (!(dd > 0)) return 0.0;  // a point
  return std::clamp((p - a).dot(d) / dd, 0.0, 1.0);
}

// Closest points of segments p1–q1 and p2–q2 as parameters s, t in [0, 1] of p1 + s·(q1 − p1) and
// p2 + t·(q2 − p2). The squared distance is a convex quadratic in (s, t): its unconstrained
// minimum is clamped to the unit square one parameter at a time (Ericson, "Real-Time Collision
// Detection", 5.1.9). Parallel segments get s = 0 (any point of the overlap is as close).
inline void closestSegmentSegment(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2,
                                  double& s, double& t) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  // One or both segments a point
  if (!(a > 0) && !(e > 0)) {
    s = t = 0.0;
    return;
  }
  if (!(a > 0)) {
    s = 0.0;
    t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = d1.dot(r);
  if (!(e > 0)) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  // s on the lines' common perpendicular, then t for that s; a clamped t moves s once more
  const double b = d1.dot(d2), denom = a * e - b * b;
  s = denom > 1e-12 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  t = (b * s + f) / e;
  if (t < 0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

// Whether segment p→q crosses triangle (a, b, c) (Möller–Trumbore with the segment parameter in
// [0, 1]). A segment (nearly) in the triangle's plane does not cross it.
inline bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                   const Vec3& c) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 s1 = d.cross(e2);
  const double det = e1.dot(s1);
  if (!(std::abs(det) > 1e-12 * d.norm() * e1.norm() * e2.norm())) return false;
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = s.dot(s1) * inv;
  if (u < 0 || u > 1) return false;
  const Vec3 s2 = s.cross(e1);
  const double v = d.dot(s2) * inv;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(s2) * inv;
  return t >= 0 && t <= 1;
}

}  // namespace reel
