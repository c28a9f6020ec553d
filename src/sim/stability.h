// Estimated largest stable step of an explicit integrator on a mass-spring model.
#pragma once

#include <limits>

#include "core/scene.h"
#include "sim/mass_spring.h"

namespace reel {

struct StepBound {
  double h_max = std::numeric_limits<double>::infinity();  // s; infinite: no bound
  int node = -1;        // node that sets the bound
  double omega = 0.0;   // its estimated highest angular frequency, rad/s
  double beta = 0.0;    // its estimated highest damping rate, 1/s
};

// Per free node i the Gershgorin bound of M⁻¹K gives ω_i² = 2 Σ_s c_s / m_i (exact for the
// highest mode of a uniform chain) and likewise β_i = (γ_i + 2 Σ_s γ_s) / m_i. Each integrator's
// bound for the damped oscillator x'' = −ω²x − βx' is then taken at the worst node:
//   symplectic Euler, Verlet:  h²ω² + 2hβ < 4   (exact for symplectic Euler);
//   explicit Euler:            |1 + hλ| < 1 for λ = −β/2 ± √(β²/4 − ω²): h < β/ω² when
//                              underdamped, so undamped springs are never stable;
//   RK4:                       h·|λ|max < 2.78 (its stability region reaches 2.78 along the
//                              negative real axis and 2.83 along the imaginary axis);
//   implicit Euler:            unconditionally stable (infinite bound).
StepBound stableStep(const MassSpringModel& m, IntegratorKind kind);

// The bound above for one oscillator x'' = −ω²x − βx' (w2 = ω²), s; infinite when w2 = β = 0.
double oscillatorBound(IntegratorKind kind, double w2, double beta);

}  // namespace reel
