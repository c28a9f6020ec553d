#include "sim/integrators.h"

#include <cmath>

#include "core/error.h"
#include "core/parallel.h"

namespace reel {
namespace {

using Index = std::ptrdiff_t;

void resize(std::vector<Vec3>& v, std::size_t n) {
  if (v.size() != n) v.assign(n, Vec3::Zero());
}

// Symplectic (semi-implicit) Euler: a = f/m, v += h·a, x += h·v_new.
void symplecticEuler(OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v, double h,
                     IntegratorWorkspace& ws) {
  const Index n = static_cast<Index>(x.size());
  resize(ws.a, x.size());
  dyn.acceleration(x.data(), v.data(), ws.a.data());
  parallelFor(n, [&](Index i) {
    v[i] += h * ws.a[i];
    x[i] += h * v[i];
  });
}

// Explicit (forward) Euler: x += h·v_old, v += h·a.
void explicitEuler(OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v, double h,
                   IntegratorWorkspace& ws) {
  const Index n = static_cast<Index>(x.size());
  resize(ws.a, x.size());
  dyn.acceleration(x.data(), v.data(), ws.a.data());
  parallelFor(n, [&](Index i) {
    x[i] += h * v[i];
    v[i] += h * ws.a[i];
  });
}

// Störmer–Verlet in velocity form. For forces that depend on position only, its positions are
// exactly those of the central second difference x⁺ = 2x − x⁻ + h²a. Velocity-dependent forces
// (damping) at the end of the step are evaluated at the predicted velocity v + h·a, which keeps
// the method second order without an implicit solve.
void verlet(OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v, double h,
            IntegratorWorkspace& ws) {
  const Index n = static_cast<Index>(x.size());
  resize(ws.a, x.size());
  resize(ws.vt, x.size());
  dyn.acceleration(x.data(), v.data(), ws.a.data());
  parallelFor(n, [&](Index i) {
    v[i] += (0.5 * h) * ws.a[i];       // half kick
    x[i] += h * v[i];                  // drift
    ws.vt[i] = v[i] + (0.5 * h) * ws.a[i];  // predicted end velocity
  });
  dyn.acceleration(x.data(), ws.vt.data(), ws.a.data());
  parallelFor(n, [&](Index i) { v[i] += (0.5 * h) * ws.a[i]; });  // second half kick
}

// Classical fourth-order Runge–Kutta on the first-order system (x, v)' = (v, a(x, v)).
void rk4(OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v, double h,
         IntegratorWorkspace& ws) {
  const std::size_t n = x.size();
  const Index ni = static_cast<Index>(n);
  for (auto* w : {&ws.a, &ws.xt, &ws.vt, &ws.dx, &ws.dv}) resize(*w, n);
  auto& a = ws.a;
  auto& xt = ws.xt;
  auto& vt = ws.vt;
  auto& dx = ws.dx;
  auto& dv = ws.dv;
  // k1
  dyn.acceleration(x.data(), v.data(), a.data());
  parallelFor(ni, [&](Index i) {
    dx[i] = v[i];
    dv[i] = a[i];
    xt[i] = x[i] + (0.5 * h) * v[i];
    vt[i] = v[i] + (0.5 * h) * a[i];
  });
  // k2
  dyn.acceleration(xt.data(), vt.data(), a.data());
  parallelFor(ni, [&](Index i) {
    dx[i] += 2.0 * vt[i];
    dv[i] += 2.0 * a[i];
    xt[i] = x[i] + (0.5 * h) * vt[i];
    vt[i] = v[i] + (0.5 * h) * a[i];
  });
  // k3
  dyn.acceleration(xt.data(), vt.data(), a.data());
  parallelFor(ni, [&](Index i) {
    dx[i] += 2.0 * vt[i];
    dv[i] += 2.0 * a[i];
    xt[i] = x[i] + h * vt[i];
    vt[i] = v[i] + h * a[i];
  });
  // k4 and the update
  dyn.acceleration(xt.data(), vt.data(), a.data());
  parallelFor(ni, [&](Index i) {
    dx[i] += vt[i];
    dv[i] += a[i];
    x[i] += (h / 6.0) * dx[i];
    v[i] += (h / 6.0) * dv[i];
  });
}

double dot(const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  return deterministicSum(static_cast<Index>(p.size()), [&](Index i) { return p[i].dot(q[i]); });
}

// The implicit integrators' linear system A Δv = rhs (after dyn.linearize() filled ws.rhs and
// ws.pinv, and prepareImplicit() ws.fixed), solved for ws.dv by conjugate gradients with a
// block-Jacobi preconditioner (each node's 3×3 diagonal block inverted: the springs' uuᵀ terms
// make that block far from diagonal; or a pair of nodes' 6×6 block, where the system names
// pairs). Fixed nodes are filtered out (their Δv is 0: the filter S of Baraff & Witkin's section
// 5.3 with every direction constrained). Each iteration is one
// product with A and three passes over the nodes (four with pairs), which also return the dot
// products (each a deterministic chunked sum).
// A system that solves directly (OdeSystem::solveDirect, as the scene's `implicit.solver` allows)
// takes no iteration and leaves no residual to speak of.
void solveLinearized(OdeSystem& dyn, IntegratorWorkspace& ws, const ImplicitSettings& set, StepStats* stats) {
  if (dyn.solveDirect(ws.rhs.data(), ws.dv.data())) {
    if (stats) stats->cg_iterations = 0, stats->cg_relative_residual = 0.0;
    return;
  }
  const Index ni = static_cast<Index>(ws.rhs.size());
  const std::uint8_t* fixed = ws.fixed.data();
  auto& dvel = ws.dv;
  // Warm start: the previous step's Δv (the workspace keeps it; zero on the first step), which
  // smooth motion changes little. r = S·(rhs − A·Δv), z = P⁻¹ r, p = z.
  const double bnorm = std::sqrt(deterministicSum(ni, [&](Index i) {
    if (fixed[i] || !dvel[i].allFinite()) dvel[i].setZero();
    return fixed[i] ? 0.0 : ws.rhs[i].squaredNorm();
  }));
  if (!(bnorm > 0.0)) parallelFor(ni, [&](Index i) { dvel[i].setZero(); });  // nothing to solve: Δv = 0
  dyn.applySystem(dvel.data(), ws.q.data());
  // z_i = P⁻¹ r: node i's block, or its rows of its pair's (which read the partner's r, so a
  // system with pairs updates r and z in two passes).
  const OdeSystem::PreconditionerPairs pairs = dyn.preconditionerPairs();
  auto precondition = [&](Index i) -> Vec3 {
    const int j = pairs.partner ? pairs.partner[i] : -1;
    if (j < 0) return ws.pinv[i] * ws.r[i];
    Eigen::Matrix<double, 6, 1> rr;
    rr << ws.r[i], ws.r[static_cast<std::size_t>(j)];
    return pairs.rows[i] * rr;
  };
  auto residual = [&](Index i) { ws.r[i] = fixed[i] ? Vec3::Zero() : Vec3(ws.rhs[i] - ws.q[i]); };
  if (pairs.partner) parallelFor(ni, residual);
  double rz = deterministicSum(ni, [&](Index i) {
    if (!pairs.partner) residual(i);
    ws.z[i] = precondition(i);
    ws.p[i] = ws.z[i];
    return ws.r[i].dot(ws.z[i]);
  });
  int it = 0;
  double rel = 0.0;
  if (bnorm > 0.0) {
    for (; it < set.cg_max_iterations; ++it) {
      dyn.applySystem(ws.p.data(), ws.q.data());
      const double pq = deterministicSum(ni, [&](Index i) {
        if (fixed[i]) ws.q[i].setZero();
        return ws.p[i].dot(ws.q[i]);
      });
      if (!(pq > 0.0)) {  // converged to round-off, or the system lost definiteness
        rel = std::sqrt(dot(ws.r, ws.r)) / bnorm;
        break;
      }
      const double alpha = rz / pq;
      std::array<double, 2> sums;
      if (!pairs.partner) {
        sums = deterministicSums<2>(ni, [&](Index i) {
          dvel[i] += alpha * ws.p[i];
          ws.r[i] -= alpha * ws.q[i];
          ws.z[i] = ws.pinv[i] * ws.r[i];
          return std::array<double, 2>{ws.r[i].squaredNorm(), ws.r[i].dot(ws.z[i])};
        });
      } else {
        sums[0] = deterministicSum(ni, [&](Index i) {
          dvel[i] += alpha * ws.p[i];
          ws.r[i] -= alpha * ws.q[i];
          return ws.r[i].squaredNorm();
        });
        sums[1] = deterministicSum(ni, [&](Index i) {
          ws.z[i] = precondition(i);
          return ws.r[i].dot(ws.z[i]);
        });
      }
      rel = std::sqrt(sums[0]) / bnorm;
      if (rel <= set.cg_tolerance) {
        ++it;
        break;
      }
      const double beta = sums[1] / rz;
      rz = sums[1];
      parallelFor(ni, [&](Index i) { ws.p[i] = ws.z[i] + beta * ws.p[i]; });
    }
  }
  if (stats) {
    stats->cg_iterations = it;
    stats->cg_relative_residual = rel;
  }
}

// Sizes the solver's arrays, reads the fixed nodes and tells the system the solver chosen.
void prepareImplicit(OdeSystem& dyn, std::size_t n, IntegratorWorkspace& ws, const ImplicitSettings& set) {
  REEL_CHECK(dyn.linearizable(), "implicit integrators need a linearizable system");
  dyn.setLinearSolver(set.solver);
  for (auto* w : {&ws.rhs, &ws.r, &ws.z, &ws.p, &ws.q, &ws.dv}) resize(*w, n);
  ws.pinv.resize(n);  // linearize fills every block (or the system does, before CG reads it)
  ws.fixed.resize(n);
  for (std::size_t i = 0; i < n; ++i) ws.fixed[i] = dyn.fixed(i) ? 1 : 0;
}

// Linearised backward Euler (Baraff & Witkin 1998, "Large Steps in Cloth Simulation", eq. 6):
// one Newton step, (M − h ∂f/∂v − h² ∂f/∂x) Δv = h (f₀ + h ∂f/∂x v₀), then x += h (v₀ + Δv).
void implicitEuler(OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v, double h,
                   IntegratorWorkspace& ws, const ImplicitSettings& set, StepStats* stats) {
  const Index ni = static_cast<Index>(x.size());
  prepareImplicit(dyn, x.size(), ws, set);
  dyn.linearize(x.data(), v.data(), v.data(), h, ws.rhs.data(), ws.pinv.data());
  solveLinearized(dyn, ws, set, stats);
  parallelFor(ni, [&](Index i) {
    v[i] += ws.dv[i];
    x[i] += h * v[i];
  });
}

// The second-order backward differentiation formula (BDF2; Hairer & Wanner, "Solving Ordinary
// Differential Equations II", §V.1), as Choi & Ko (2002) and Hauth & Etzmuss (2001) use it for
// cloth: x₊ = (4x − x₋)/3 + h' v₊ and v₊ = (4v − v₋)/3 + h' a(x₊, v₊) with h' = 2h/3, linearised
// at (x, v) as implicit Euler is. With Δv = v₊ − v it is implicit Euler's system at step h':
//   (M − h' ∂f/∂v − h'² ∂f/∂x) Δv = h' (f₀ + h' ∂f/∂x w) + M (v − v₋)/3,  w = v + (x − x₋)/(2h).
// Second order and L-stable: stiff modes are damped as by implicit Euler, slow ones are not
// (implicit Euler's error in a swimming fish's speed is first order in h; see docs/fish.md).
// Without a history of the same step and size, the step is implicit Euler's.
void bdf2(OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v, double h, IntegratorWorkspace& ws,
          const ImplicitSettings& set, StepStats* stats) {
  const std::size_t n = x.size();
  const Index ni = static_cast<Index>(n);
  if (ws.x_prev.size() != n || ws.v_prev.size() != n || ws.h_prev != h) {
    ws.x_prev = x, ws.v_prev = v, ws.h_prev = h;
    implicitEuler(dyn, x, v, h, ws, set, stats);
    return;
  }
  prepareImplicit(dyn, n, ws, set);
  resize(ws.w, n);
  const double hb = 2.0 * h / 3.0;
  // (A fixed node keeps implicit Euler's rules: w = v, x += h v; a body may pose it each step.)
  parallelFor(ni, [&](Index i) { ws.w[i] = ws.fixed[i] ? v[i] : Vec3(v[i] + (x[i] - ws.x_prev[i]) / (2.0 * h)); });
  dyn.linearize(x.data(), v.data(), ws.w.data(), hb, ws.rhs.data(), ws.pinv.data());
  parallelFor(ni, [&](Index i) {
    if (!ws.fixed[i]) ws.rhs[i] += (dyn.mass(static_cast<std::size_t>(i)) / 3.0) * (v[i] - ws.v_prev[i]);
  });
  solveLinearized(dyn, ws, set, stats);
  parallelFor(ni, [&](Index i) {
    const Vec3 x0 = x[i], v0 = v[i];
    v[i] = v0 + ws.dv[i];
    x[i] = ws.fixed[i] ? Vec3(x0 + h * v0) : Vec3((4.0 * x0 - ws.x_prev[i]) / 3.0 + hb * v[i]);
    ws.x_prev[i] = x0, ws.v_prev[i] = v0;
  });
}

}  // namespace

void integrate(IntegratorKind kind, OdeSystem& dyn, std::vector<Vec3>& x, std::vector<Vec3>& v,
               double h, IntegratorWorkspace& ws, const ImplicitSettings& implicit,
               StepStats* stats) {
  REEL_DCHECK(x.size() == dyn.size() && v.size() == dyn.size(), "state size mismatch");
  switch (kind) {
    case IntegratorKind::SymplecticEuler: return symplecticEuler(dyn, x, v, h, ws);
    case IntegratorKind::ExplicitEuler: return explicitEuler(dyn, x, v, h, ws);
    case IntegratorKind::Verlet: return verlet(dyn, x, v, h, ws);
    case IntegratorKind::Rk4: return rk4(dyn, x, v, h, ws);
    case IntegratorKind::ImplicitEuler: return implicitEuler(dyn, x, v, h, ws, implicit, stats);
    case IntegratorKind::Bdf2: return bdf2(dyn, x, v, h, ws, implicit, stats);
  }
  REEL_CHECK(false, "unknown integrator");
}

int evaluationsPerStep(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::Verlet: return 2;
    case IntegratorKind::Rk4: return 4;
    default: return 1;
  }
}

}  // namespace reel
