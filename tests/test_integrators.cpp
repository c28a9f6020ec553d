// Integrators against exact solutions: free fall (exact discrete solutions), the undamped and
// damped oscillator (closed form) with the convergence order of each method, energy behaviour.
#include <doctest/doctest.h>

#include <cmath>

#include "core/math.h"
#include "helpers.h"

using namespace reel;
using namespace reel::test;

TEST_CASE("free fall matches each integrator's exact discrete solution") {
  const Vec3 g(0.3, -9.78, 0.1), x0(1, 2, 3), v0(0.5, 4.0, -1.0);
  const double h = 0.01;
  const int n = 200;
  for (IntegratorKind k : allIntegrators()) {
    CAPTURE(integratorName(k));
    MassSpringDesc d;
    d.nodes.push_back({x0, v0, 2.5, 0.0, false});
    System s(d, g);
    for (int i = 0; i < n; ++i) s.step(k, h);
    const double nn = n;
    // x_n = x0 + n h v0 + c h² g, with c = n(n+1)/2 for methods that move with the new velocity,
    // n(n−1)/2 for explicit Euler and n²/2 (the exact parabola) for Verlet and RK4.
    double c = nn * nn / 2.0;
    if (k == IntegratorKind::SymplecticEuler || k == IntegratorKind::ImplicitEuler) c = nn * (nn + 1) / 2.0;
    if (k == IntegratorKind::ExplicitEuler) c = nn * (nn - 1) / 2.0;
    const Vec3 x = x0 + nn * h * v0 + c * h * h * g;
    const Vec3 v = v0 + nn * h * g;
    CHECK((s.state.x[0] - x).norm() <= 1e-11 * x.norm());
    CHECK((s.state.v[0] - v).norm() <= 1e-11 * v.norm());
  }
}

namespace {

// Max error of the oscillator's displacement over [0, T] against the closed form.
double oscillatorError(IntegratorKind k, double w2, double beta, double h, double T) {
  const double m = 0.5, u0 = 0.1;
  System s(oscillator(m, w2 * m, beta * m, u0), Vec3::Zero());
  const int n = static_cast<int>(std::lround(T / h));
  double err = 0.0;
  for (int i = 1; i <= n; ++i) {
    s.step(k, h);
    err = std::max(err, std::abs((s.state.x[1].x() - 1.0) - oscillatorExact(w2, beta, u0, i * h)));
  }
  return err;
}

double order(IntegratorKind k, double w2, double beta, double h) {
  const double T = 2.0;
  return std::log2(oscillatorError(k, w2, beta, h, T) / oscillatorError(k, w2, beta, h / 2, T));
}

struct Expect {
  IntegratorKind kind;
  double order;
};
const Expect kOrders[] = {{IntegratorKind::SymplecticEuler, 1}, {IntegratorKind::ExplicitEuler, 1},
                          {IntegratorKind::Verlet, 2}, {IntegratorKind::Rk4, 4},
                          {IntegratorKind::ImplicitEuler, 1}};

}  // namespace

TEST_CASE("undamped oscillator: error vs the closed form halves at the method's order") {
  const double w2 = 4.0 * kPi * kPi;  // 1 Hz
  for (const Expect& e : kOrders) {
    CAPTURE(integratorName(e.kind));
    const double h = e.order == 4 ? 4e-3 : 1e-3;
    CHECK(oscillatorError(e.kind, w2, 0.0, h, 2.0) < (e.order == 1 ? 0.05 : 1e-4));
    CHECK(order(e.kind, w2, 0.0, h) == doctest::Approx(e.order).epsilon(0.1));
  }
}

TEST_CASE("damped oscillator: error vs the closed form halves at the method's order") {
  const double w2 = 4.0 * kPi * kPi, beta = 1.5;
  for (const Expect& e : kOrders) {
    CAPTURE(integratorName(e.kind));
    const double h = e.order == 4 ? 4e-3 : 1e-3;
    CHECK(order(e.kind, w2, beta, h) == doctest::Approx(e.order).epsilon(0.1));
  }
}

TEST_CASE("energy drift of the undamped oscillator over 100 periods") {
  const double m = 1.0, k = 4.0 * kPi * kPi, u0 = 0.1, h = 0.01;  // ωh ≈ 0.063
  const double e0 = 0.5 * k * u0 * u0;
  auto finalEnergy = [&](IntegratorKind kind, double& max_rel) {
    System s(oscillator(m, k, 0.0, u0), Vec3::Zero());
    max_rel = 0.0;
    double e = e0;
    for (int i = 0; i < 10000; ++i) {
      s.step(kind, h);
      e = totalEnergy(s.model, s.state);
      max_rel = std::max(max_rel, std::abs(e - e0) / e0);
    }
    return e;
  };
  double dev = 0;
  // Symplectic methods: bounded oscillation of the energy, no drift.
  const double se = finalEnergy(IntegratorKind::SymplecticEuler, dev);
  CHECK(dev < 0.04);  // O(ωh) oscillation
  CHECK(std::abs(se - e0) / e0 < 0.04);
  finalEnergy(IntegratorKind::Verlet, dev);
  CHECK(dev < 1e-3);  // O((ωh)²)
  // RK4: a tiny monotone loss.
  const double r4 = finalEnergy(IntegratorKind::Rk4, dev);
  CHECK(r4 < e0);
  CHECK(dev < 1e-4);
  // Explicit Euler gains energy without bound: (1 + (ωh)²) per step.
  const double ee = finalEnergy(IntegratorKind::ExplicitEuler, dev);
  CHECK(ee > 100.0 * e0);
  // Implicit Euler loses it: (1 + (ωh)²)⁻¹ per step.
  const double ie = finalEnergy(IntegratorKind::ImplicitEuler, dev);
  CHECK(ie < 0.01 * e0);
}

namespace {

// A force term pulling node 1 toward an anchor, f = −k (x − a), stiffness H = k I on node 1 only.
struct AnchorTerm final : ForceTerm {
  Vec3 anchor{0, 0, 0};
  double k = 0.0;
  void addForces(const Vec3* x, Vec3* f) override { f[1] += -k * (x[1] - anchor); }
  void linearize(const Vec3* x, Vec3* f, Mat3* diag) override {
    addForces(x, f);
    diag[1] += k * Mat3::Identity();
  }
  void addProduct(const Vec3* p, double s, Vec3* out) override { out[1] += s * k * p[1]; }
  void prepareProduct(const Vec3* p, double s) override { p1 = s * k * p[1]; }
  void addProductTo(std::ptrdiff_t i0, std::ptrdiff_t i1, Vec3* out) const override {
    if (i0 <= 1 && 1 < i1) out[1] += p1;
  }
  Vec3 p1 = Vec3::Zero();
};

}  // namespace

TEST_CASE("a force term of the mass-spring system: explicit force and implicit Euler's exact linear step") {
  // Node 0 fixed, node 1 free (m = 2), no springs, no gravity; the term anchors node 1 at the
  // origin with k = 1e4, far stiffer than the step resolves.
  // With a velocity v₀ the step is Δv = −h k (d + h v₀)/(m + h²k) (the term's force at the step's
  // end as linearised, f − h H v₀).
  const Vec3 d0(0.3, -0.1, 0.2), v0(1.5, 0.5, -2.0);
  MassSpringDesc d;
  d.nodes.push_back({Vec3(5, 0, 0), Vec3::Zero(), 1.0, 0.0, true});
  d.nodes.push_back({d0, v0, 2.0, 0.0, false});
  AnchorTerm term;
  term.k = 1e4;
  System s(d, Vec3::Zero());
  s.dyn.setForceTerm(&term);
  std::vector<Vec3> a(2);
  s.dyn.acceleration(s.state.x.data(), s.state.v.data(), a.data());
  CHECK((a[1] - (-1e4 / 2.0) * d0).norm() < 1e-9);
  const double h = 0.1;
  s.step(IntegratorKind::ImplicitEuler, h);
  const Vec3 v1 = v0 - h * 1e4 * (d0 + h * v0) / (2.0 + h * h * 1e4);
  CHECK((s.state.v[1] - v1).norm() < 1e-9);
  CHECK((s.state.x[1] - (d0 + h * v1)).norm() < 1e-9);
}

TEST_CASE("preconditioner pairs: each pair's rows invert its 6x6 block of A; the step is the same, in fewer iterations") {
  // A strip of 24 columns, each a top and a bottom node 2 mm apart joined by a stiff spring
  // (the strong coupling a pair is for), the tops and the bottoms chained by soft springs, each
  // bottom held to a fixed anchor; pushed out of rest and moving.
  MassSpringDesc d;
  const int cols = 24;
  for (int c = 0; c < cols; ++c) {
    const double x = 0.01 * c;
    d.nodes.push_back({Vec3(x, 0.002 + 0.0003 * (c % 3), 0.0004 * c), Vec3(0.1 * (c % 5), -0.2, 0.05), 1e-3, 0.0, false});  // top
    d.nodes.push_back({Vec3(x + 0.0005, 0, 0), Vec3(0, 0.1, -0.03 * (c % 2)), 1e-3, 0.0, false});  // bottom
    d.nodes.push_back({Vec3(x, -0.005, 0), Vec3::Zero(), 1e-3, 0.0, true});  // anchor
  }
  for (int c = 0; c < cols; ++c) {
    const int t = 3 * c, b = 3 * c + 1, a = 3 * c + 2;
    d.springs.push_back({t, b, 2e4, 1.0, 0.0015});
    d.springs.push_back({b, a, 50.0, 0.0, -1.0});
    if (c + 1 < cols) {
      d.springs.push_back({t, t + 3, 20.0, 0.0, -1.0});
      d.springs.push_back({b, b + 3, 20.0, 0.0, -1.0});
      d.springs.push_back({t, b + 3, 10.0, 0.0, -1.0});
    }
  }
  const double h = 1.0 / 60.0;
  auto run = [&](bool paired, int* iterations) {
    System s(d, Vec3(0, -9.8, 0));
    if (paired) {
      std::vector<std::array<int, 2>> pairs;
      for (int c = 0; c < cols; ++c) pairs.push_back({3 * c, 3 * c + 1});
      s.dyn.setPreconditionerPairs(pairs);
    }
    s.implicit = {1e-10, 1000, false, LinearSolver::Cg};  // (the pairs are CG's preconditioner)
    StepStats stats;
    integrate(IntegratorKind::ImplicitEuler, s.dyn, s.state.x, s.state.v, h, s.ws, s.implicit, &stats);
    *iterations = stats.cg_iterations;
    if (paired) {
      // A's blocks by products with unit vectors, against each pair's rows.
      const std::size_t n = s.model.nodes();
      const OdeSystem::PreconditionerPairs pp = s.dyn.preconditionerPairs();
      REQUIRE(pp.partner != nullptr);
      std::vector<Vec3> e(n, Vec3::Zero()), out(n);
      for (int c = 0; c < cols; ++c) {
        const int t = 3 * c, b = 3 * c + 1;
        CHECK(pp.partner[t] == b);
        CHECK(pp.partner[b] == t);
        CHECK(pp.partner[3 * c + 2] == -1);
        Eigen::Matrix<double, 6, 6> P;
        for (int col = 0; col < 6; ++col) {
          e.assign(n, Vec3::Zero());
          e[static_cast<std::size_t>(col < 3 ? t : b)][col % 3] = 1.0;
          s.dyn.applySystem(e.data(), out.data());
          P.col(col) << out[static_cast<std::size_t>(t)], out[static_cast<std::size_t>(b)];
        }
        Eigen::Matrix<double, 6, 6> swapped;  // (b, t) order, as b's rows read (r_b, r_t)
        swapped << P.block<3, 3>(3, 3), P.block<3, 3>(3, 0), P.block<3, 3>(0, 3), P.block<3, 3>(0, 0);
        const Eigen::Matrix<double, 3, 6> It = pp.rows[t] * P, Ib = pp.rows[b] * swapped;
        Eigen::Matrix<double, 3, 6> want;
        want << Mat3::Identity(), Mat3::Zero();
        CHECK((It - want).norm() < 1e-5);  // (the blocks are rounded to single precision)
        CHECK((Ib - want).norm() < 1e-5);
      }
    }
    return s.state.v;
  };
  int plain = 0, paired = 0;
  const std::vector<Vec3> v0 = run(false, &plain), v1 = run(true, &paired);
  double dv = 0, scale = 0;
  for (std::size_t i = 0; i < v0.size(); ++i) dv = std::max(dv, (v1[i] - v0[i]).norm()), scale = std::max(scale, v0[i].norm());
  CHECK(dv <= 1e-6 * scale);  // (both solves to a residual of 1e-10 of a stiff system)
  CAPTURE(plain);
  CAPTURE(paired);
  CHECK(paired < plain);
}
