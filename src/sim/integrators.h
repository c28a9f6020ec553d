// Time integrators, selected by name (core/scene.h: IntegratorKind), written once for any
// second-order system x'' = a(x, v). Fixed nodes have a = 0 and v = 0, so explicit methods
// leave them in place; implicit Euler filters them out of its linear system.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "core/types.h"

namespace reel {

// A second-order system x'' = a(x, v) over nodes, as the integrators see it.
class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual std::size_t size() const = 0;
  virtual bool fixed(std::size_t i) const = 0;
  // a = M⁻¹ f(x, v); zero for fixed nodes.
  virtual void acceleration(const Vec3* x, const Vec3* v, Vec3* a) = 0;

  // --- for implicit Euler (Baraff & Witkin 1998) and BDF2 -----------------------------------
  // The step solves A Δv = rhs with A = M − h ∂f/∂v − h² ∂f/∂x and rhs = h (f + h ∂f/∂x w),
  // both linearised at (x, v); implicit Euler takes w = v, BDF2 its own w and h.
  virtual bool linearizable() const { return false; }
  // Linearise at (x, v) for step h: fills rhs and, for the preconditioner, the inverse of each
  // node's 3×3 diagonal block of A (block Jacobi). A system that prepares a direct solve
  // (solveDirect) may fill block_inverse later, when CG first needs it (solveDirect returning
  // false, or a product asked for): the array must stay alive until the next linearize().
  virtual void linearize(const Vec3* /*x*/, const Vec3* /*v*/, const Vec3* /*w*/, double /*h*/, Vec3* /*rhs*/,
                         Mat3* /*block_inverse*/) {}
  virtual double mass(std::size_t /*i*/) const { return 1.0; }
  // out = A p on the free nodes, with A from the last linearize(); out is 0 at fixed nodes (their
  // rows are never used: Δv is 0 there), and their preconditioner blocks need not be A's.
  virtual void applySystem(const Vec3* /*p*/, Vec3* /*out*/) {}
  // Optional, valid after linearize(): nodes the preconditioner takes in pairs, inverting a pair's
  // 6×6 block of A together where the two are coupled far more strongly to each other than to the
  // rest (a face's skin node and the fascia node under it, across a few millimetres of tissue).
  // partner[i] is i's partner (−1: none, then block_inverse[i] serves) and rows[i] the three rows
  // of the pair block's inverse that give z_i from (r_i, r_partner).
  struct PreconditionerPairs {
    const int* partner = nullptr;
    const Eigen::Matrix<double, 3, 6>* rows = nullptr;
  };
  virtual PreconditionerPairs preconditionerPairs() const { return {}; }
  // The scene's choice of linear solver (ImplicitSettings::solver), given before linearize().
  virtual void setLinearSolver(LinearSolver) {}
  // Optional, valid after linearize(): solves A Δv = rhs directly (Δv = 0 at fixed nodes) and
  // returns true, or returns false to leave the solve to conjugate gradients (the system cannot,
  // the solver chosen is CG, or, with auto, a direct solve would cost more than kDirectIterations
  // of CG). A system that solves directly may skip what only CG's products and preconditioner
  // need, and must have it ready whenever it returns false.
  virtual bool solveDirect(const Vec3* /*rhs*/, Vec3* /*dv*/) { return false; }
};

// Scratch arrays reused across steps (resized on demand).
struct IntegratorWorkspace {
  std::vector<Vec3> a, xt, vt, dx, dv;    // explicit methods
  std::vector<Vec3> rhs, r, z, p, q;         // conjugate gradients
  std::vector<Mat3> pinv;                    // block-Jacobi preconditioner
  std::vector<std::uint8_t> fixed;           // the system's fixed nodes, read once per step
  // BDF2's history: the state one step back and that step's length (empty or 0: none yet, or
  // the node count or the step changed; the next step is then implicit Euler's).
  std::vector<Vec3> x_prev, v_prev, w;
  double h_prev = 0.0;
  void forgetHistory() { x_prev.clear(), v_prev.clear(), h_prev = 0.0; }
};

struct StepStats {
  int cg_iterations = 0;
  double cg_relative_residual = 0.0;
};

// Advances (x, v) by one step h with the chosen integrator.
void integrate(IntegratorKind kind, OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v,
               double h, IntegratorWorkspace& ws, const ImplicitSettings& implicit,
               StepStats* stats = nullptr);

// Force evaluations one step of each integrator makes (1 for the Eulers, 2 Verlet, 4 RK4, 1 + the
// linearisation for implicit Euler).
int evaluationsPerStep(IntegratorKind kind);

}  // namespace reel
