// Force terms, written once and shared by every mass-spring model (ropes, nets, lattices, and
// later cloth, fish bodies and faces). Conventions (Witkin & Baraff, "Physically Based Modeling",
// SIGGRAPH course notes; Terzopoulos et al. 1987):
//   spring s joins nodes a and b, r = x_b − x_a, L = |r|, û = r / L, e = L − l, ė = (v_b − v_a)·û;
//   force on a:  s = (c·e + γ_s·ė)·û,  force on b: −s   (Voigt element: elastic + viscous);
//   nodal drag:  −γ_i·v_i;   gravity: m_i·g.
#pragma once

#include <cmath>

#include "core/types.h"

namespace reel {

// Force on node a of a Voigt spring between a and b.
inline Vec3 springForce(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                        double stiffness, double damping, double rest) {
  const Vec3 r = xb - xa;
  const double len = r.norm();
  if (!(len > 1e-300)) return Vec3::Zero();  // coincident nodes: no direction, no force
  const Vec3 u = r * (1.0 / len);  // one division instead of three
  const double e = len - rest;
  const double edot = (vb - va).dot(u);
  return (stiffness * e + damping * edot) * u;
}

// Jacobians of springForce for the implicit integrator (Baraff & Witkin 1998, section 5):
//   ∂s/∂x_b = K = c·[û ûᵀ + max(0, 1 − l/L)·(I − û ûᵀ)]     (the transverse term is clamped at
//   zero for compressed springs so the system stays positive definite),
//   ∂s/∂v_b = D = γ_s·û ûᵀ;  ∂s/∂x_a = −K, ∂s/∂v_a = −D.
inline void springJacobians(const Vec3& xa, const Vec3& xb, double stiffness, double damping,
                            double rest, Mat3& K, Mat3& D) {
  const Vec3 r = xb - xa;
  const double len = r.norm();
  if (!(len > 1e-300)) {
    K.setZero();
    D.setZero();
    return;
  }
  const Vec3 u = r / len;
  const Mat3 uu = u * u.transpose();
  const double t = std::fmax(0.0, 1.0 - rest / len);
  K = stiffness * (uu + t * (Mat3::Identity() - uu));
  D = damping * uu;
}

}  // namespace reel
