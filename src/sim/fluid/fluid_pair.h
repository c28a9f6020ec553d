// The fluid's pair force as scalars, shared by its build (stable step, rest distances) and its
// force loops.
#pragma once

#include <cmath>

#include "sim/fluid/fluid.h"

namespace reel {

// x^e, by multiplication when e is a small whole number (ie ≥ 0).
inline double power(double x, double e, int ie) {
  switch (ie) {
    case 0: return 1.0;
    case 1: return x;
    case 2: return x * x;
    case 3: return x * x * x;
    case 4: { const double y = x * x; return y * y; }
    case 5: { const double y = x * x; return y * y * x; }
    case 6: { const double y = x * x * x; return y * y; }
    case 7: { const double y = x * x * x; return y * y * x; }
    case 8: { const double y = x * x; const double z = y * y; return z * z; }
    default: return std::pow(x, e);
  }
}

// The scalar c with g_ij = c·(x_i − x_j), at distance r; inside cap_r the force's magnitude stays
// what it is at cap_r (PairParams::cap_r).
inline double pairCoefficient(const PairParams& p, double mi, double mj, double r) {
  const double rc = r < p.cap_r ? p.cap_r : r;
  const double c = mi * mj * (-p.alpha / power(rc + p.epsilon, p.a, p.ia) + p.beta / power(rc, p.b, p.ib));
  return r < p.cap_r ? c * (p.cap_r / r) : c;
}

// The radial force (positive: repulsive) between particles of masses mi, mj at distance r.
inline double radialForce(const PairParams& p, double mi, double mj, double r) { return pairCoefficient(p, mi, mj, r) * r; }

}  // namespace reel
