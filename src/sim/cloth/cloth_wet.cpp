// An absorbent sheet's liquid: wicking, drainage, the mass it adds; the pins' reaction.
#include <algorithm>

#include "sim/cloth/cloth.h"
#include "sim/forces.h"

namespace reel {

void wetNode(Cloth& c, MassSpringModel& m, Vec3& vi, std::size_t i, double dm, const Vec3& u) {
  const double before = m.mass[i];
  c.wet[i] = std::max(0.0, c.wet[i] + dm);
  const double after = c.dry_mass[i] + c.wet[i];
  if (!m.fixed[i] && dm > 0) vi = (before * vi + dm * u) * (1.0 / after);
  setNodeMass(m, i, after);
}

void spreadWetness(Cloth& c, MassSpringModel& m, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                   const Vec3& gravity, double h) {
  if (c.capacity.empty()) return;
  const Springs& sp = m.springs;
  const std::size_t nn = c.wet.size();
  // Moves dm from i to j: j takes i's momentum of that mass, i keeps its velocity.
  auto move = [&](std::size_t i, std::size_t j, double dm) {
    if (!(dm > 0)) return;
    const Vec3 u = v[i];
    wetNode(c, m, v[i], i, -dm, u);
    wetNode(c, m, v[j], j, dm, u);
    c.wet_species[j] = c.wet_species[i];
  };
  // Wicking along the threads, one spring after another in index order (deterministic): the
  // flux equalises wetness relative to capacity; rate·h is capped so no flux overshoots.
  const double wick = std::min(0.2, kWickRate * h);
  for (std::size_t s = 0; s < sp.size(); ++s) {
    if (c.spring_id[s] >= c.structural) continue;
    const auto a = static_cast<std::size_t>(sp.a[s]), b = static_cast<std::size_t>(sp.b[s]);
    const double sa = c.wet[a] / c.capacity[a], sb = c.wet[b] / c.capacity[b];
    const double flux = wick * (sa - sb) * std::min(c.capacity[a], c.capacity[b]);
    if (flux > 0) move(a, b, flux);
    else move(b, a, -flux);
  }
  // Drainage: liquid beyond capacity runs to the lowest structural neighbour below.
  const double g = gravity.norm();
  if (!(g > 0)) return;
  const Vec3 down = gravity / g;
  const double drain = std::min(0.5, kDrainRate * h);
  for (std::size_t i = 0; i < nn; ++i) {
    const double free = c.wet[i] - c.capacity[i];
    if (!(free > 0)) continue;
    std::size_t low = i;
    double depth = 0.0;
    for (int e = m.incidence.start[i]; e < m.incidence.start[i + 1]; ++e) {
      const auto s = static_cast<std::size_t>(m.incidence.entries[static_cast<std::size_t>(e)] / 2);
      if (c.spring_id[s] >= c.structural) continue;
      const auto j = static_cast<std::size_t>(m.incidence.other[static_cast<std::size_t>(e)]);
      const double dj = down.dot(x[j] - x[i]);
      if (dj > depth) depth = dj, low = j;
    }
    if (low != i) move(i, low, drain * free);
  }
}

namespace {

// Per node: the springs' pull and the weight on a held (fixed) node (zero on the others).
void heldForces(const MassSpringModel& m, const MassSpringState& s, std::vector<Vec3>& held) {
  held.assign(m.nodes(), Vec3::Zero());
  for (std::size_t i = 0; i < m.nodes(); ++i)
    if (m.fixed[i]) held[i] += m.mass[i] * m.gravity;
  const Springs& sp = m.springs;
  for (std::size_t k = 0; k < sp.size(); ++k) {
    const auto a = static_cast<std::size_t>(sp.a[k]), b = static_cast<std::size_t>(sp.b[k]);
    if (!m.fixed[a] && !m.fixed[b]) continue;
    const Vec3 f = springForce(s.x[a], s.x[b], s.v[a], s.v[b], sp.stiffness[k], sp.damping[k], sp.rest[k]);
    if (m.fixed[a]) held[a] += f;
    if (m.fixed[b]) held[b] -= f;
  }
}

}  // namespace

Vec3 supportForce(const Cloth& c, const MassSpringModel& m, const MassSpringState& s) {
  std::vector<Vec3> held;  // springs, weight and liquid on the held nodes
  heldForces(m, s, held);
  Vec3 sum = Vec3::Zero();
  for (const Vec3& f : held) sum += f;
  return -(sum + c.pin_liquid_force);
}

void handBackGrips(const Cloth& c, const MassSpringModel& m, const MassSpringState& s, double h,
                   const std::vector<Collider>& colliders, Coupling& coupling) {
  bool any = false;
  for (int k : c.grip_collider) any = any || k >= 0;
  if (!any) return;
  std::vector<Vec3> held;
  heldForces(m, s, held);
  // The holder pulls the nodes along its path (−held); the nodes pull it back (+held) for h.
  for (std::size_t gi = 0; gi < c.grips.size(); ++gi) {
    const int k = c.grip_collider[gi];
    if (k < 0) continue;
    const Collider& col = colliders[static_cast<std::size_t>(k)];
    for (int p : c.grips[gi].nodes) {
      const auto i = static_cast<std::size_t>(p);
      coupling.handBack(static_cast<std::size_t>(k), s.x[i], col.pose.pos, -h * held[i]);
    }
  }
}

}  // namespace reel
