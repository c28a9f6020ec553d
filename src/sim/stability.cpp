#include "sim/stability.h"

#include <cmath>

namespace reel {

double oscillatorBound(IntegratorKind kind, double w2, double beta) {
  const double inf = std::numeric_limits<double>::infinity();
  if (w2 <= 0 && beta <= 0) return inf;
  switch (kind) {
    case IntegratorKind::SymplecticEuler:
    case IntegratorKind::Verlet:
      // Positive root of w2 h² + 2β h − 4 = 0.
      if (w2 <= 0) return 2.0 / beta;
      return (-beta + std::sqrt(beta * beta + 4.0 * w2)) / w2;
    case IntegratorKind::ExplicitEuler: {
      const double disc = beta * beta / 4.0 - w2;
      if (disc < 0) return beta / w2;                   // underdamped
      return 2.0 / (beta / 2.0 + std::sqrt(disc));     // overdamped: most negative real λ
    }
    case IntegratorKind::Rk4: {
      const double disc = beta * beta / 4.0 - w2;
      const double lam = disc < 0 ? std::sqrt(w2) : beta / 2.0 + std::sqrt(disc);
      return 2.78 / lam;
    }
    case IntegratorKind::ImplicitEuler:
    case IntegratorKind::Bdf2: return inf;
  }
  return inf;
}

StepBound stableStep(const MassSpringModel& m, IntegratorKind kind) {
  StepBound out;
  if (implicitIntegrator(kind)) return out;
  const std::size_t n = m.nodes();
  std::vector<double> ksum(n, 0.0), csum(n, 0.0);
  const Springs& s = m.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    for (int end : {s.a[k], s.b[k]}) {
      ksum[static_cast<std::size_t>(end)] += s.stiffness[k];
      csum[static_cast<std::size_t>(end)] += s.damping[k];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (m.fixed[i]) continue;
    const double w2 = 2.0 * ksum[i] / m.mass[i];
    const double beta = (m.drag[i] + 2.0 * csum[i]) / m.mass[i];
    const double h = oscillatorBound(kind, w2, beta);
    if (h < out.h_max) {
      out.h_max = h;
      out.node = static_cast<int>(i);
      out.omega = std::sqrt(w2);
      out.beta = beta;
    }
  }
  return out;
}

}  // namespace reel
