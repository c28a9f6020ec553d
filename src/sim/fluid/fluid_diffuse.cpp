#include "sim/fluid/fluid_diffuse.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/parallel.h"
#include "core/random.h"
#include "sim/body.h"

namespace reel {

namespace {

// Φ(I) = (min(I, τ_max) − min(I, τ_min))/(τ_max − τ_min): a potential clamped into 0..1 (§4.1).
double clampPotential(double I, double lo, double hi) { return (std::min(I, hi) - std::min(I, lo)) / (hi - lo); }

// Seeding (§4.2): a particle seeds Φ_k·Φ_ta·foam·kSeedRate diffuse particles a second, Φ_k from its
// speed (1..3 m/s: a ball landing in reel's small-scale scenes, not a block settling; the paper's
// kinetic energy) and Φ_ta from its trapped air (5..14 m/s). A churned particle at foam 1 seeds
// 400 a second.
constexpr double kSeedRate = 400.0;
// Bubbles (§4.3): buoyancy k_b (2: they rise at one g net of the liquid's weight) and drag k_d
// (the share of the gap to the liquid's velocity closed each tick).
constexpr double kBuoyancy = 2.0, kDrag = 0.5;
// Classification by the liquid's kernel density around a diffuse particle, as a share of a bulk's:
// under 0.1 spray, over 0.75 a bubble, foam between (a flat surface is about 0.5).
constexpr double kSprayBelow = 0.1, kBubbleAbove = 0.75;

}  // namespace

double trappedAir(const Fluid& fl, std::size_t i) {
  double ta = 0;
  for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
    const auto j = static_cast<std::size_t>(fl.nbr[e]);
    const double cutoff = fl.pairOf(i, j).cutoff;
    const Vec3 xij = fl.x[i] - fl.x[j], vij = fl.v[i] - fl.v[j];
    const double r = xij.norm(), u = vij.norm();
    if (!(r < cutoff) || !(r > 0) || !(u > 0)) continue;
    ta += u * (1.0 - vij.dot(xij) / (u * r)) * (1.0 - r / cutoff);
  }
  return ta;
}

void stepDiffuse(Fluid& fl, const Vec3& gravity, double t1) {
  if (!(fl.foam > 0)) return;
  const double dt = t1 - fl.diffuse_time;
  if (!(dt >= kDiffuseTick * (1.0 - 1e-9))) return;
  fl.diffuse_time = t1;
  ++fl.diffuse_ticks;
  const std::size_t n = fl.x.size();
  const bool listed = fl.nbr_start.size() == n + 1 && fl.x_built.size() == n;
  // 1. Each diffuse particle: the liquid around it (kernel W = 1 − r/c over the particles within
  // the cutoff c, found through the liquid's grid, built at x_built within half a skin of x), its
  // kind, and its motion.
  const double c = fl.cutoff_max;
  const double spacing = fl.packed_spacing;
  const double bulk = kPi * c * c * c / (3.0 * spacing * spacing * spacing);  // ∫W dV / spacing³
  const std::size_t m = fl.diffuse_x.size();
  const BoxGrid* grid = listed && m > 0 ? &listedGrid(fl) : nullptr;
  parallelFor(static_cast<std::ptrdiff_t>(m), [&](std::ptrdiff_t kk) {
    const auto k = static_cast<std::size_t>(kk);
    Vec3& x = fl.diffuse_x[k];
    Vec3& v = fl.diffuse_v[k];
    double w_sum = 0;
    Vec3 vf = Vec3::Zero();
    if (grid)
      grid->forEachNear(x, [&](std::int32_t j) {
        const auto jj = static_cast<std::size_t>(j);
        if (jj >= n) return;
        const double r = (fl.x[jj] - x).norm();
        if (!(r < c)) return;
        const double w = 1.0 - r / c;
        w_sum += w;
        vf += w * fl.v[jj];
      });
    const double share = w_sum / bulk;
    DiffuseKind kind = share < kSprayBelow ? DiffuseKind::Spray : share > kBubbleAbove ? DiffuseKind::Bubble : DiffuseKind::Foam;
    if (w_sum > 0) vf /= w_sum;
    switch (kind) {
      case DiffuseKind::Spray:  // ballistic; ages twice as fast (droplets that fly off the scene)
        v += dt * gravity;
        fl.diffuse_life[k] -= 2.0 * dt;
        break;
      case DiffuseKind::Foam:  // carried on the surface
        v = vf;
        fl.diffuse_life[k] -= dt;
        break;
      case DiffuseKind::Bubble:  // rises through the bulk, dragged along by it; does not age
        v += -kBuoyancy * dt * gravity + kDrag * (vf - v);
        break;
    }
    x += dt * v;
    fl.diffuse_kind[k] = static_cast<std::uint8_t>(kind);
  });
  // Those at the end of their life, or gone astray (as a restored state is checked), leave; the
  // rest keep their order.
  std::vector<std::uint8_t> keep(m);
  for (std::size_t k = 0; k < m; ++k)
    keep[k] = fl.diffuse_life[k] > 0 && fl.diffuse_x[k].squaredNorm() <= kRunawayDistance * kRunawayDistance &&
              fl.diffuse_v[k].squaredNorm() <= kRunawaySpeed * kRunawaySpeed;
  auto compact = [&](auto& a) {
    std::size_t w = 0;
    for (std::size_t k = 0; k < m; ++k)
      if (keep[k]) a[w++] = a[k];
    a.resize(w);
  };
  compact(fl.diffuse_x);
  compact(fl.diffuse_v);
  compact(fl.diffuse_life);
  compact(fl.diffuse_kind);
  compact(fl.diffuse_id);
  if (!listed || n == 0) return;
  // 2. Seeding: each particle's rate from its speed and trapped air (in parallel, each its own),
  // then the new ones in slot order, each drawing its random numbers by its serial number.
  std::vector<double> rate(n, 0.0);
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const double speed = clampPotential(fl.v[i].norm(), 1.0, 3.0);
    if (speed > 0) rate[i] = fl.foam * kSeedRate * speed * clampPotential(trappedAir(fl, i), 5.0, 14.0);
  });
  // Random streams: each new particle's numbers by its serial number; each liquid particle's
  // whether-to-seed draw by its id, indexed by the tick.
  constexpr std::uint64_t kStream = 0xD1FF05E, kSeedStream = 0x5EED0000000ull;
  auto draw = [&](std::uint64_t slot) { return uniformAt(fl.seed, kStream, 8 * static_cast<std::uint64_t>(fl.diffuse_made) + slot); };
  for (std::size_t i = 0; i < n && fl.diffuse_x.size() < kMaxDiffuse; ++i) {
    if (!(rate[i] > 0)) continue;
    // The expected count this tick, its fraction seeded with that probability.
    const double expected = rate[i] * dt;
    const double u = uniformAt(fl.seed, kSeedStream + static_cast<std::uint64_t>(fl.id[i]), static_cast<std::uint64_t>(fl.diffuse_ticks));
    const auto count = static_cast<int>(std::floor(expected) + (u < expected - std::floor(expected) ? 1 : 0));
    // Uniformly in a cylinder about the particle's path this tick: radius its own, as long as
    // its travel (§4.2), moving with it and a little outwards.
    const Vec3 vi = fl.v[i];
    const double speed = vi.norm();
    const Vec3 axis = speed > 0 ? Vec3(vi / speed) : Vec3::UnitY();
    const Vec3 e1 = perpendicular(axis), e2 = axis.cross(e1);
    for (int q = 0; q < count && fl.diffuse_x.size() < kMaxDiffuse; ++q) {
      const double r = fl.radius * std::sqrt(draw(0)), theta = 2.0 * kPi * draw(1), along = draw(2) * speed * dt;
      const Vec3 out = std::cos(theta) * e1 + std::sin(theta) * e2;
      fl.diffuse_x.push_back(fl.x[i] + r * out + along * axis);
      fl.diffuse_v.push_back(vi + 0.2 * speed * (r / fl.radius) * out);
      fl.diffuse_life.push_back(fl.foam_life * (0.5 + draw(3)));
      fl.diffuse_kind.push_back(static_cast<std::uint8_t>(DiffuseKind::Foam));
      fl.diffuse_id.push_back(fl.diffuse_made);
      ++fl.diffuse_made;
    }
  }
}

}  // namespace reel
