#include "sim/mass_spring.h"

#include "core/error.h"
#include "core/parallel.h"
#include "sim/forces.h"

namespace reel {

using Index = std::ptrdiff_t;

void Incidence::build(std::size_t nodes, const Springs& s) {
  start.assign(nodes + 1, 0);
  for (std::size_t k = 0; k < s.size(); ++k) {
    ++start[static_cast<std::size_t>(s.a[k]) + 1];
    ++start[static_cast<std::size_t>(s.b[k]) + 1];
  }
  for (std::size_t i = 0; i < nodes; ++i) start[i + 1] += start[i];
  entries.assign(2 * s.size(), 0);
  std::vector<int> fill(start.begin(), start.end() - 1);
  // Springs in index order: each node's list is sorted by spring index.
  for (std::size_t k = 0; k < s.size(); ++k) {
    entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(s.a[k])]++)] = static_cast<int>(2 * k);
    entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(s.b[k])]++)] = static_cast<int>(2 * k + 1);
  }
}

void buildMassSpring(const MassSpringDesc& desc, const Vec3& gravity, MassSpringModel& model,
                     MassSpringState& state) {
  const std::size_t n = desc.nodes.size();
  model = MassSpringModel{};
  model.gravity = gravity;
  model.mass.resize(n);
  model.inv_mass.resize(n);
  model.drag.resize(n);
  model.fixed.resize(n);
  state.x.resize(n);
  state.v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const NodeDesc& nd = desc.nodes[i];
    REEL_CHECK(nd.mass > 0.0, "node mass must be positive");
    model.mass[i] = nd.mass;
    model.fixed[i] = nd.fixed ? 1 : 0;
    model.inv_mass[i] = nd.fixed ? 0.0 : 1.0 / nd.mass;
    model.drag[i] = nd.damping;
    state.x[i] = nd.position;
    state.v[i] = nd.fixed ? Vec3::Zero() : nd.velocity;  // fixed nodes stay where they are
  }
  for (const SpringDesc& sd : desc.springs) {
    REEL_CHECK(sd.a >= 0 && sd.b >= 0 && static_cast<std::size_t>(sd.a) < n &&
                   static_cast<std::size_t>(sd.b) < n && sd.a != sd.b,
               "spring end out of range");
    const double rest = sd.rest_length >= 0.0
                            ? sd.rest_length
                            : (desc.nodes[static_cast<std::size_t>(sd.b)].position -
                               desc.nodes[static_cast<std::size_t>(sd.a)].position)
                                  .norm();
    model.springs.add(sd.a, sd.b, sd.stiffness, sd.damping, rest);
  }
  model.incidence.build(n, model.springs);
}

void MassSpringDynamics::gather(const std::vector<Vec3>& per_spring, std::size_t i,
                                Vec3& out) const {
  const auto& inc = m_.incidence;
  for (int e = inc.start[i]; e < inc.start[i + 1]; ++e) {
    const int code = inc.entries[static_cast<std::size_t>(e)];
    // ±1 times f is exact, so this equals out ± f bit for bit, without a branch to mispredict.
    const double sign = 1.0 - 2.0 * static_cast<double>(code & 1);
    out += sign * per_spring[static_cast<std::size_t>(code >> 1)];
  }
}

void MassSpringDynamics::acceleration(const Vec3* x, const Vec3* v, Vec3* a) {
  const Springs& sp = m_.springs;
  const Index ns = static_cast<Index>(sp.size());
  if (fs_.size() != sp.size()) fs_.resize(sp.size());
  // Per-spring Voigt forces on end a.
  parallelFor(ns, [&](Index s) {
    const int ia = sp.a[s], ib = sp.b[s];
    fs_[s] = springForce(x[ia], x[ib], v[ia], v[ib], sp.stiffness[s], sp.damping[s], sp.rest[s]);
  });
  spring_evals_ += sp.size();
  // Per node: gravity as an acceleration (exactly g, never m·g/m), drag and the springs' forces.
  const Vec3 g = m_.gravity;
  parallelFor(static_cast<Index>(m_.nodes()), [&](Index i) {
    if (m_.fixed[i]) {
      a[i].setZero();
      return;
    }
    Vec3 f = -m_.drag[i] * v[i];
    gather(fs_, static_cast<std::size_t>(i), f);
    if (external_) f += external_[i];
    a[i] = g + m_.inv_mass[i] * f;
  });
}

void MassSpringDynamics::linearize(const Vec3* x, const Vec3* v, double h, Vec3* rhs,
                                   Vec3* diag) {
  const Springs& sp = m_.springs;
  const Index ns = static_cast<Index>(sp.size());
  h_ = h;
  fs_.resize(sp.size());
  B_.resize(sp.size());
  // Per spring: w = s + h·K·(v_b − v_a) (end a's share of f₀ + h ∂f/∂x v₀), and B = h²K + hD.
  parallelFor(ns, [&](Index s) {
    const int ia = sp.a[s], ib = sp.b[s];
    Mat3 K, D;
    springJacobians(x[ia], x[ib], sp.stiffness[s], sp.damping[s], sp.rest[s], K, D);
    fs_[s] = springForce(x[ia], x[ib], v[ia], v[ib], sp.stiffness[s], sp.damping[s], sp.rest[s]) +
             h * (K * (v[ib] - v[ia]));
    B_[s] = (h * h) * K + h * D;
  });
  spring_evals_ += sp.size();
  // Per node: rhs = h (m g − γ v + Σ w), diag(A) = m + hγ + Σ diag(B).
  const Vec3 g = m_.gravity;
  const auto& inc = m_.incidence;
  parallelFor(static_cast<Index>(m_.nodes()), [&](Index i) {
    Vec3 f = m_.mass[i] * g - m_.drag[i] * v[i];
    gather(fs_, static_cast<std::size_t>(i), f);
    if (external_) f += external_[i];
    rhs[i] = h * f;
    Vec3 d = Vec3::Constant(m_.mass[i] + h * m_.drag[i]);
    for (int e = inc.start[i]; e < inc.start[i + 1]; ++e)
      d += B_[static_cast<std::size_t>(inc.entries[static_cast<std::size_t>(e)] >> 1)].diagonal();
    diag[i] = d;
  });
}

void MassSpringDynamics::applySystem(const Vec3* p, Vec3* out) {
  const Springs& sp = m_.springs;
  // Per spring y = B (p_a − p_b): + on a, − on b; then (M + hγ) p + Σ ±y per node.
  parallelFor(static_cast<Index>(sp.size()),
              [&](Index s) { fs_[s] = B_[s] * (p[sp.a[s]] - p[sp.b[s]]); });
  spring_products_ += sp.size();
  parallelFor(static_cast<Index>(m_.nodes()), [&](Index i) {
    Vec3 y = (m_.mass[i] + h_ * m_.drag[i]) * p[i];
    gather(fs_, static_cast<std::size_t>(i), y);
    out[i] = y;
  });
}

double kineticEnergy(const MassSpringModel& m, const MassSpringState& s) {
  return deterministicSum(static_cast<Index>(m.nodes()),
                          [&](Index i) { return 0.5 * m.mass[i] * s.v[i].squaredNorm(); });
}

double totalEnergy(const MassSpringModel& m, const MassSpringState& s) {
  const Springs& sp = m.springs;
  const double spring = deterministicSum(static_cast<Index>(sp.size()), [&](Index k) {
    const double e = (s.x[sp.b[k]] - s.x[sp.a[k]]).norm() - sp.rest[k];
    return 0.5 * sp.stiffness[k] * e * e;
  });
  const double grav = deterministicSum(static_cast<Index>(m.nodes()), [&](Index i) {
    return m.fixed[i] ? 0.0 : -m.mass[i] * m.gravity.dot(s.x[i]);
  });
  return kineticEnergy(m, s) + spring + grav;
}

}  // namespace reel
