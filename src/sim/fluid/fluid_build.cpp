// Building a liquid: its pair table, surfaces, particles and nozzles, and its stable step.
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/math.h"
#include "core/random.h"
#include "sim/fluid/fluid.h"
#include "sim/fluid/fluid_dfsph.h"
#include "sim/fluid/fluid_pair.h"

namespace reel {
namespace {

int wholeExponent(double e) { return e == std::floor(e) && e >= 0 && e <= 8 ? static_cast<int>(e) : -1; }

// An orthonormal pair perpendicular to the unit vector d.
void perpendicular(const Vec3& d, Vec3& u, Vec3& w) {
  const Vec3 helper = std::abs(d.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  u = helper.cross(d).normalized();
  w = d.cross(u);
}

constexpr std::uint64_t kJitterStream = 0xF1D0ull << 16;

}  // namespace

PairParams makePair(double alpha, double beta, double a, double b, double epsilon, double cutoff, double viscosity) {
  PairParams p;
  p.alpha = alpha;
  p.beta = beta;
  p.a = a;
  p.b = b;
  p.epsilon = epsilon;
  p.cutoff = cutoff;
  p.cutoff2 = cutoff * cutoff;
  p.viscosity = viscosity;
  p.ia = wholeExponent(a);
  p.ib = wholeExponent(b);
  p.cap_r = kRepulsionCap * restDistance(p);
  p.cap_r2 = p.cap_r * p.cap_r;
  return p;
}

Vec3 pairForce(const PairParams& p, double mi, double mj, const Vec3& xi, const Vec3& xj) {
  const Vec3 d = xi - xj;
  const double r2 = d.squaredNorm();
  if (!(r2 < p.cutoff2) || r2 == 0.0) return Vec3::Zero();
  return pairCoefficient(p, mi, mj, std::sqrt(r2)) * d;
}

namespace {

// The largest r in (0, from) where g turns positive: g is sampled at at(k), k = 1..n (decreasing),
// from `from` down, and the first sign change is bisected. 0 when g stays ≤ 0 at every sample.
template <class G, class At>
double firstPositiveBelow(double from, int n, At&& at, G&& g, int iterations) {
  double hi = from;
  for (int k = 1; k <= n; ++k) {
    const double lo = at(k);
    if (g(lo) > 0) {
      double a = lo, b = hi;  // g(a) > 0 ≥ g(b)
      for (int it = 0; it < iterations; ++it) {
        const double mid = 0.5 * (a + b);
        (g(mid) > 0 ? a : b) = mid;
      }
      return 0.5 * (a + b);
    }
    hi = lo;
  }
  return 0.0;
}

// Calls f(r) for the distance of every point of a cubic lattice of spacing d (but the origin)
// that lies inside the cutoff.
template <class F>
void forLattice(double d, double cutoff, F&& f) {
  const int M = static_cast<int>(std::floor(cutoff / d));
  for (int i = -M; i <= M; ++i)
    for (int j = -M; j <= M; ++j)
      for (int k = -M; k <= M; ++k) {
        const double r = d * std::sqrt(static_cast<double>(i * i + j * j + k * k));
        if (r > 0 && r < cutoff) f(r);
      }
}

}  // namespace

double restDistance(const PairParams& p) {
  if (p.beta <= 0 || p.alpha <= 0) return 0.0;
  auto phi = [&](double r) { return -p.alpha / power(r + p.epsilon, p.a, p.ia) + p.beta / power(r, p.b, p.ib); };
  if (phi(p.cutoff) > 0) return 0.0;  // still repulsive at the cutoff: no rest distance inside
  // Down from the cutoff (log-spaced to 10⁻⁴ of it), the outermost sign change.
  constexpr int n = 400;
  return firstPositiveBelow(p.cutoff, n, [&](int k) { return p.cutoff * std::pow(1e-4, static_cast<double>(k) / n); },
                            phi, 100);
}

double bulkSpacing(const PairParams& p) {
  if (p.alpha <= 0 || p.beta <= 0) return 0.0;
  auto virial = [&](double d) {
    double v = 0.0;
    forLattice(d, p.cutoff, [&](double r) { v += radialForce(p, 1.0, 1.0, r) * r; });
    return v;
  };
  // Down from the cutoff to a sixth of it, the first spacing where the lattice pushes outwards.
  constexpr int n = 600;
  return firstPositiveBelow(p.cutoff, n, [&](int k) { return p.cutoff * (1.0 - (5.0 / 6.0) * k / n); }, virial, 60);
}

namespace {

// The pair parameters of species i with j: a species with itself uses its own values, two
// species the mean of theirs, unless an interaction sets them; then what the force loop needs.
PairParams pairOf(const FluidDesc& d, std::size_t i, std::size_t j) {
  const SpeciesDesc &A = d.species[i], &B = d.species[j];
  auto mean = [](double x, double y) { return 0.5 * (x + y); };
  double alpha = mean(A.alpha, B.alpha), beta = mean(A.beta, B.beta), a = mean(A.a, B.a), b = mean(A.b, B.b);
  double eps = mean(A.epsilon, B.epsilon), cut = mean(A.cutoff, B.cutoff), visc = mean(A.viscosity, B.viscosity);
  if (d.model == LiquidModel::Dfsph) {
    // No pair force: pressure keeps the particles apart; the viscosity acts over the kernel's reach.
    alpha = beta = eps = 0.0, a = 2.0, b = 4.0;
    cut = 2.0 * d.sphSpacing();
  }
  for (const InteractionDesc& in : d.interactions) {
    if (!((in.s == static_cast<int>(i) && in.t == static_cast<int>(j)) ||
          (in.s == static_cast<int>(j) && in.t == static_cast<int>(i))))
      continue;
    visc = in.viscosity.value_or(visc);
    if (d.model == LiquidModel::Dfsph) continue;  // (the reader refuses the rest there)
    alpha = in.alpha.value_or(alpha);
    beta = in.beta.value_or(beta);
    a = in.a.value_or(a);
    b = in.b.value_or(b);
    eps = in.epsilon.value_or(eps);
    cut = in.cutoff.value_or(cut);
  }
  PairParams p = makePair(alpha, beta, a, b, eps, cut, visc);
  const double mi = A.mass, mj = B.mass;
  p.mass_product = mi * mj;
  p.visc_mu = visc * mi * mj / (mi + mj);
  p.inv_cutoff = 1.0 / cut;
  p.seed_form = p.ia == 2 && p.ib == 4 && eps == 0.0;
  const double kT = 0.5 * (mi * A.agitation * A.agitation + mj * B.agitation * B.agitation);
  p.sigma = std::sqrt(2.0 * p.visc_mu * kT);
  return p;
}

// Blocks: a cubic lattice filling [min, max], each point jittered from the seed; points inside an
// object are left out.
void addBlocks(Fluid& fl, const FluidDesc& d, const std::vector<Collider>& colliders, std::uint64_t seed) {
  for (const FluidBlockDesc& b : d.blocks) {
    const std::array<long long, 3> n{b.along(0), b.along(1), b.along(2)};
    for (long long k = 0; k < n[2]; ++k)
      for (long long j = 0; j < n[1]; ++j)
        for (long long i = 0; i < n[0]; ++i) {
          Vec3 p = b.min + b.spacing * Vec3(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5, static_cast<double>(k) + 0.5);
          if (b.jitter > 0) {
            const auto id = static_cast<std::uint64_t>(fl.x.size());
            for (int a = 0; a < 3; ++a)
              p[a] += b.jitter * b.spacing * (2.0 * uniformAt(seed, kJitterStream + static_cast<std::uint64_t>(a), id) - 1.0);
          }
          bool inside = false;
          for (const Collider& c : colliders) {
            double dist;
            Vec3 nrm;
            inside = inside || (c.distance(p, dist, nrm) && dist < c.shape->thickness + d.radius);
          }
          if (inside) continue;
          fl.id.push_back(static_cast<std::int32_t>(fl.id.size()));
          fl.x.push_back(p);
          fl.v.push_back(b.velocity);
          fl.s.push_back(b.species);
          fl.m.push_back(fl.species_mass[static_cast<std::size_t>(b.species)]);
        }
  }
}

}  // namespace

Fluid buildFluid(const FluidDesc& d, const std::string& name, const std::vector<Collider>& colliders,
                 std::uint64_t seed) {
  Fluid fl;
  fl.name = name;
  fl.seed = seed;
  fl.species_count = static_cast<int>(d.species.size());
  REEL_CHECK(fl.species_count >= 1, "a fluid needs a species");
  const auto S = static_cast<std::size_t>(fl.species_count);
  for (const SpeciesDesc& sp : d.species) {
    fl.species_names.push_back(sp.name);
    fl.species_mass.push_back(sp.mass);
    fl.species_color.push_back(sp.color);
  }
  // Pair table.
  fl.pairs.resize(S * S);
  for (std::size_t i = 0; i < S; ++i)
    for (std::size_t j = 0; j < S; ++j) {
      const PairParams p = pairOf(d, i, j);
      fl.agitated = fl.agitated || p.sigma > 0;
      fl.pairs[i * S + j] = p;
    }
  if (d.model == LiquidModel::Dfsph) {
    std::vector<double> density;
    for (const SpeciesDesc& sp : d.species) density.push_back(sp.density);
    setupDfsph(fl, density);
  }
  fl.cutoff_max = 0.0;
  for (const PairParams& p : fl.pairs) fl.cutoff_max = std::max(fl.cutoff_max, p.cutoff);
  fl.skin = 0.3 * fl.cutoff_max;
  if (d.model == LiquidModel::Dfsph) {
    // The particles' spacing: what the step's splitting and the drawing take as their distance.
    fl.ref_spacing = fl.packed_spacing = 0.5 * fl.kernel_support;
  } else {
    const double d0 = bulkSpacing(fl.pairs[0]);
    fl.ref_spacing = d0 > 0 ? 0.65 * d0 : 2.0 * d.radius;
    // A settled liquid packs its nearest neighbours at about 0.8 of the lattice spacing.
    fl.packed_spacing = d0 > 0 ? 0.8 * d0 : 2.0 * d.radius;
  }
  fl.radius = d.radius;
  fl.max_particles = d.max_particles;
  fl.draw = d.draw;
  fl.surface_cell = d.surface_cell > 0 ? d.surface_cell : d.radius;
  fl.surface_kernel = d.surface_kernel > 0 ? d.surface_kernel : 4.0 * d.radius;
  fl.surface_iso = d.surface_iso;
  fl.surface_anisotropic = d.surface_anisotropic;
  fl.surface_smoothing = d.surface_smoothing;
  fl.foam = d.foam;
  fl.foam_life = d.foam_life;
  fl.shutter = d.shutter;
  // Surfaces per collider and species.
  fl.surfaces.reserve(colliders.size() * S);
  for (const Collider& o : colliders)
    for (std::size_t k = 0; k < S; ++k) fl.surfaces.push_back(surfaceFor(o.shape->surface, o.shape->species_surface, fl.species_names[k]));
  for (std::size_t k = 0; k < S; ++k) fl.adhesion_range.push_back(fl.pairs[k * S + k].cutoff);
  addBlocks(fl, d, colliders, seed);
  for (const FluidParticlesDesc& p : d.particles)
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
      fl.id.push_back(static_cast<std::int32_t>(fl.id.size()));
      fl.x.push_back(p.positions[i]);
      fl.v.push_back(i < p.velocities.size() ? p.velocities[i] : Vec3::Zero());
      fl.s.push_back(p.species);
      fl.m.push_back(fl.species_mass[static_cast<std::size_t>(p.species)]);
    }
  for (const EmitterDesc& e : d.emitters) {
    FluidEmitter fe;
    fe.desc = e;
    fe.disc = hexDisc(e.radius, e.spacing);
    perpendicular(e.direction, fe.u, fe.w);
    fe.layer_dt = static_cast<double>(fe.disc.size()) / e.rate;
    fe.max_layers = e.layers();
    fl.emitters.push_back(std::move(fe));
    fl.layers.push_back(0);
  }
  const auto cap = static_cast<std::size_t>(std::min<long long>(fl.max_particles, static_cast<long long>(fl.x.size()) + d.emitted()));
  fl.x.reserve(cap);
  fl.v.reserve(cap);
  fl.s.reserve(cap);
  fl.m.reserve(cap);
  return fl;
}

StepBound fluidStableStep(const Fluid& fl) {
  StepBound out;
  const auto S = static_cast<std::size_t>(fl.species_count);
  for (std::size_t i = 0; i < S; ++i)
    for (std::size_t j = 0; j < S; ++j) {
      const PairParams& p = fl.pairs[i * S + j];
      const double mi = fl.species_mass[i], mj = fl.species_mass[j];
      const double d0 = bulkSpacing(p);
      const double d = std::min(d0 > 0 ? 0.65 * d0 : 2.0 * fl.radius, p.cutoff);
      double ksum = 0.0, csum = 0.0;
      forLattice(d, p.cutoff, [&](double r) {
        const double dr = 1e-4 * r;
        ksum += std::abs(radialForce(p, mi, mj, r + dr) - radialForce(p, mi, mj, r - dr)) / (2 * dr) +
                std::abs(radialForce(p, mi, mj, r)) / r;
        csum += p.viscosity * mi * mj / (mi + mj) * (1.0 - r / p.cutoff);
      });
      const double w2 = 2.0 * ksum / mi;
      const double beta = 2.0 * csum / mi;
      const double h = oscillatorBound(IntegratorKind::SymplecticEuler, w2, beta);
      if (h < out.h_max) {
        out.h_max = h;
        out.node = static_cast<int>(i * S + j);
        out.omega = std::sqrt(w2);
        out.beta = beta;
      }
    }
  return out;
}

}  // namespace reel
