// Force terms, written once and shared by every mass-spring model (ropes, nets, lattices, and
// later cloth, fish bodies and faces). Conventions (Witkin & Baraff, "Physically Based Modeling",
// SIGGRAPH course notes; Terzopoulos et al. 1987):
//   spring s joins nodes a and b, r = x_b − x_a, L = |r|, û = r / L, e = L − l, ė = (v_b − v_a)·û;
//   force on a:  s = (c·e + γ_s·ė)·û,  force on b: −s   (Voigt element: elastic + viscous);
//   nodal drag:  −γ_i·v_i;   gravity: m_i·g.
#pragma once

#include <cmath>

#include "core/lanes.h"
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
// Both are combinations of û ûᵀ and I, so they are returned as û and t = max(0, 1 − l/L):
// K = c·[(1 − t)·û ûᵀ + t·I]. Coincident nodes (no direction) give û = 0 and t = 0: K = D = 0.
struct SpringJacobians {
  Vec3 u = Vec3::Zero();
  double t = 0.0;
  // K w, without forming the matrix.
  Vec3 K(double stiffness, const Vec3& w) const { return stiffness * ((1.0 - t) * u.dot(w) * u + t * w); }
};

inline SpringJacobians springJacobians(const Vec3& xa, const Vec3& xb, double rest) {
  SpringJacobians j;
  const Vec3 r = xb - xa;
  const double len = r.norm();
  if (!(len > 1e-300)) return j;
  j.u = r * (1.0 / len);
  j.t = std::fmax(0.0, 1.0 - rest / len);
  return j;
}

// springJacobians() and springForce() of four springs, a lane each (core/lanes.h): the same
// operations in the same order, so each lane has the bits of the one-spring form (coincident ends:
// û = 0, t = 0, no force). For the loops that take four springs at a time.
struct SpringJacobians4 {
  L3 u;
  Lane4 t;
};

[[gnu::always_inline]] inline SpringJacobians4 springJacobians4(const L3& xa, const L3& xb, const Lane4& rest) {
  const L3 r = xb - xa;
  const Lane4 len = sqrt4(dot(r, r)), one = splat(1.0);
  const Mask4 ok = len > 1e-300;
  const Lane4 safe = select(ok, len, one), t = one - rest / safe;
  return {select(ok, (one / safe) * r, L3{}), select(ok & (t > 0.0), t, splat(0.0))};
}

[[gnu::always_inline]] inline L3 springForce4(const L3& xa, const L3& xb, const L3& va, const L3& vb, const Lane4& k,
                                              const Lane4& d, const Lane4& rest) {
  const L3 r = xb - xa;
  const Lane4 len = sqrt4(dot(r, r)), one = splat(1.0);
  const Mask4 ok = len > 1e-300;
  const L3 u = select(ok, (one / select(ok, len, one)) * r, L3{});
  return select(ok, k * (len - rest) + d * dot(vb - va, u), splat(0.0)) * u;
}

}  // namespace reel
