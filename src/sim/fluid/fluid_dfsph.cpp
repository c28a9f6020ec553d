// Divergence-free SPH (Bender & Koschier 2015, 2017) on the liquid's particles, with walls as the
// kernel's volume they fill (a flat-wall approximation of Koschier & Bender's 2017 density maps:
// each convex part of a scene object, as a container's floor and walls, a flat wall at its distance).
//
// In relative form, for particles of rest volumes V = m/ρ₀ (several species of several densities
// in one liquid, after Solenthaler & Pajarola 2008's number density):
//   ρ̂_i = V_i W(0) + Σ_j V_j W_ij + Φ_i                    (1 at rest; Φ_i: the walls' share)
//   Dρ̂_i/Dt = Σ_j V_j (v_i − v_j)·∇W_ij + (v_i − v_wall)·∇Φ_i
//   Δv_i = −(h V_i/m_i) [Σ_j (p_i + p_j) V_j ∇W_ij + p_i ∇Φ_i]     (momentum kept between particles)
// A particle's own pressure p_i changes its density by −h² p_i/α_i with
//   α_i = 1 / (V_i [ |Σ_j V_j ∇W_ij + ∇Φ_i|²/m_i + Σ_j |V_j ∇W_ij|²/m_j ]),
// so the Jacobi iteration sets p_i = α_i e_i/h² from the error e_i left: the density solve the
// predicted compression e_i = ρ̂_i + h Dρ̂_i/Dt − 1 (the compression it starts with taken out over
// at least H/kSoundSpeed), the divergence solve e_i = h Dρ̂_i/Dt. Only
// compression is corrected (e clamped at 0: a free surface may open), and the divergence only where
// a particle's neighbourhood is at least kDenseEnough full (after Bender & Koschier's neighbour
// count), until the mean error is below kDensityTolerance (kDivergenceTolerance) of rest.
#include "sim/fluid/fluid_dfsph.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/parallel.h"
#include "core/profile.h"

namespace reel {
namespace {

constexpr double kDensityTolerance = 1e-3;     // mean compression left by the density solve
constexpr double kDivergenceTolerance = 1e-3;  // mean compression a step at the divergence left would make
constexpr double kDenseEnough = 0.8;           // of rest density: the divergence is solved there
constexpr int kMaxIterations = 100;
// A compression the step starts with (particles pressed together by a contact, a nozzle, a fast
// collision) is taken out no faster than over the time the kernel's reach takes at this speed, m/s
// (a speed of sound, as weakly compressible SPH takes ten times the flow's): with a very short step
// the density solve would otherwise pull an overlap apart at overlap/h, tens of m/s.
constexpr double kSoundSpeed = 20.0;

// Jacobi iterations on the working velocities sph.u: error(i) the compression particle i would
// reach (its pressure is set from it), then every velocity moved by the pressures. Stops at the
// tolerance after at least `least` iterations, or at kMaxIterations.
template <class Error>
void jacobi(Fluid& fl, double h, double tolerance, int least, Error&& error) {
  auto& S = fl.sph;
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const double inv_h2 = 1.0 / (h * h);
  for (int it = 0; it < kMaxIterations; ++it) {
    const double total = deterministicSum(n, [&](std::ptrdiff_t ii) {
      const auto i = static_cast<std::size_t>(ii);
      const double e = std::max(error(i), 0.0);
      S.pressure[i] = e * S.factor[i] * inv_h2;
      return e;
    });
    if (it >= least && total <= tolerance * static_cast<double>(n)) return;
    ++S.iterations;
    parallelFor(n, [&](std::ptrdiff_t ii) {
      const auto i = static_cast<std::size_t>(ii);
      const double pi = S.pressure[i];
      Vec3 acc = pi * S.wall_grad[i];
      for (std::uint32_t e = S.start[i]; e < S.start[i + 1]; ++e)
        acc += (pi + S.pressure[static_cast<std::size_t>(S.nbr[e])]) * S.grad[e];
      S.u[i] -= (h * fl.species_volume[static_cast<std::size_t>(fl.s[i])] / fl.m[i]) * acc;
    });
  }
}

// Dρ̂_i/Dt at the working velocities.
double densityRate(const Fluid& fl, std::size_t i) {
  const auto& S = fl.sph;
  double d = S.wall_grad[i].dot(S.u[i]) - S.wall_flux[i];
  for (std::uint32_t e = S.start[i]; e < S.start[i + 1]; ++e)
    d += S.grad[e].dot(S.u[i] - S.u[static_cast<std::size_t>(S.nbr[e])]);
  return d;
}

}  // namespace

double cubicKernel(double r, double H) {
  const double q = r / H, sigma = 8.0 / (std::numbers::pi * H * H * H);
  if (q <= 0.5) return sigma * (6.0 * q * q * (q - 1.0) + 1.0);
  if (q < 1.0) return 2.0 * sigma * (1.0 - q) * (1.0 - q) * (1.0 - q);
  return 0.0;
}

double cubicKernelSlope(double r, double H) {
  const double q = r / H, sigma = 8.0 / (std::numbers::pi * H * H * H);
  if (q <= 0.5) return sigma / H * 6.0 * q * (3.0 * q - 2.0);
  if (q < 1.0) return -sigma / H * 6.0 * (1.0 - q) * (1.0 - q);
  return 0.0;
}

void setupDfsph(Fluid& fl, const std::vector<double>& density) {
  fl.model = LiquidModel::Dfsph;
  double v_max = 0.0;
  fl.species_volume.clear();
  for (std::size_t k = 0; k < fl.species_mass.size(); ++k) {
    fl.species_volume.push_back(fl.species_mass[k] / density[k]);
    v_max = std::max(v_max, fl.species_volume.back());
  }
  const double H = 2.0 * std::cbrt(v_max);
  fl.kernel_support = H;
  // A(z) = 2π ∫_z^H W(r) r dr by Simpson's rule, then Φ(z) = ∫_z^H A by the trapezoid rule from
  // the top (Φ(0) = ½ to 10⁻⁵).
  const int N = kWallTable;
  fl.wall_area.assign(N + 1, 0.0);
  fl.wall_volume.assign(N + 1, 0.0);
  for (int k = 0; k <= N; ++k) {
    const double z = H * k / N;
    constexpr int M = 64;
    const double dr = (H - z) / M;
    double sum = 0.0;
    for (int q = 0; q <= M; ++q) {
      const double r = z + q * dr, f = cubicKernel(r, H) * r;
      sum += (q == 0 || q == M ? 1.0 : (q % 2 ? 4.0 : 2.0)) * f;
    }
    fl.wall_area[static_cast<std::size_t>(k)] = 2.0 * std::numbers::pi * sum * dr / 3.0;
  }
  for (int k = N - 1; k >= 0; --k)
    fl.wall_volume[static_cast<std::size_t>(k)] =
        fl.wall_volume[static_cast<std::size_t>(k) + 1] +
        0.5 * (H / N) * (fl.wall_area[static_cast<std::size_t>(k)] + fl.wall_area[static_cast<std::size_t>(k) + 1]);
  // The particles' lattice is discrete: a layer half a spacing from a flat wall has neighbours
  // filling 0.85 of its kernel where the continuum beyond half a spacing leaves 0.81, so with Φ at
  // its distance the first layer would start 3.8% compressed (and pressed away from the wall, a
  // column rising 5% when released). The wall is taken a little farther, by the offset that
  // makes that layer's density exactly rest (0.083 spacing; a wall's edge then starts 1.9% over).
  const double sp = 0.5 * H, V = sp * sp * sp;
  double half = 0.0;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      for (int k = 0; k <= 2; ++k) half += V * cubicKernel(sp * std::sqrt(static_cast<double>(i * i + j * j + k * k)), H);
  fl.wall_offset = 0.0;
  double lo = 0.0, hi = 0.5 * H;
  for (int it = 0; it < 60; ++it) {
    fl.wall_offset = 0.5 * (lo + hi);
    (wallVolume(fl, 0.5 * sp, nullptr) > 1.0 - half ? lo : hi) = fl.wall_offset;
  }
}

double wallVolume(const Fluid& fl, double d, double* area) {
  const double t = std::clamp((d + fl.wall_offset) / fl.kernel_support, 0.0, 1.0) * kWallTable;
  const auto k = std::min(static_cast<std::size_t>(t), static_cast<std::size_t>(kWallTable) - 1);
  const double f = t - static_cast<double>(k);
  if (area) *area = (1.0 - f) * fl.wall_area[k] + f * fl.wall_area[k + 1];
  return (1.0 - f) * fl.wall_volume[k] + f * fl.wall_volume[k + 1];
}

void dfsphBegin(Fluid& fl, const std::vector<Collider>& colliders, double h) {
  profile::Scope stage(profile::Stage::PairForces);
  auto& S = fl.sph;
  const std::size_t n = fl.x.size();
  const auto sn = static_cast<std::ptrdiff_t>(n);
  S.density.resize(n);
  S.factor.resize(n);
  S.pressure.resize(n);
  S.wall_flux.resize(n);
  S.wall_grad.resize(n);
  S.u.resize(n);
  const double H = fl.kernel_support, H2 = H * H, w0 = cubicKernel(0.0, H);
  // The solver's list: each particle's Verlet entries inside the reach, in the list's order.
  S.start.assign(n + 1, 0);
  parallelFor(sn, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    std::uint32_t count = 0;
    for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
      const double r2 = (fl.x[i] - fl.x[static_cast<std::size_t>(fl.nbr[e])]).squaredNorm();
      count += r2 < H2 && r2 > 0.0;
    }
    S.start[i + 1] = count;
  });
  for (std::size_t i = 0; i < n; ++i) S.start[i + 1] += S.start[i];
  S.nbr.resize(S.start[n]);
  S.grad.resize(S.start[n]);
  parallelFor(sn, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const Vec3& xi = fl.x[i];
    // The walls: each scene object within the kernel's reach, as a flat wall at its distance.
    double phi = 0.0, flux = 0.0;
    Vec3 wall = Vec3::Zero();
    for (const Collider& c : colliders) {
      if (c.shape->free_body || !c.near(xi, H)) continue;
      double d[ColliderShape::kMaxParts];
      Vec3 nrm[ColliderShape::kMaxParts];
      const int parts = c.partDistances(xi, d, nrm);
      for (int k = 0; k < parts; ++k) {
        if (!(d[k] - c.shape->thickness + fl.wall_offset < H)) continue;
        double area;
        phi += wallVolume(fl, d[k] - c.shape->thickness, &area);
        const Vec3 g = -area * nrm[k];
        wall += g;
        if (c.moving()) flux += g.dot(c.velocityAt(xi));
      }
    }
    S.wall_grad[i] = wall;
    S.wall_flux[i] = flux;
    // The particles.
    const double Vi = fl.species_volume[static_cast<std::size_t>(fl.s[i])];
    double rho = Vi * w0 + phi, s2 = 0.0;
    Vec3 sum = wall;
    std::uint32_t out = S.start[i];
    for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
      const auto j = static_cast<std::size_t>(fl.nbr[e]);
      const Vec3 d = xi - fl.x[j];
      const double r2 = d.squaredNorm();
      if (!(r2 < H2) || r2 == 0.0) continue;
      const double r = std::sqrt(r2), Vj = fl.species_volume[static_cast<std::size_t>(fl.s[j])];
      rho += Vj * cubicKernel(r, H);
      const Vec3 g = (Vj * cubicKernelSlope(r, H) / r) * d;
      S.nbr[out] = fl.nbr[e];
      S.grad[out++] = g;
      sum += g;
      s2 += g.squaredNorm() / fl.m[j];
    }
    S.density[i] = rho;
    const double den = Vi * (sum.squaredNorm() / fl.m[i] + s2);
    S.factor[i] = den > 0 ? 1.0 / den : 0.0;
    S.u[i] = fl.v[i];
  });
  jacobi(fl, h, kDivergenceTolerance, 1, [&](std::size_t i) {
    return S.density[i] >= kDenseEnough ? h * densityRate(fl, i) : 0.0;
  });
  std::copy(S.u.begin(), S.u.end(), fl.v.begin());
}

void dfsphPressure(Fluid& fl, double h) {
  profile::Scope stage(profile::Stage::PairForces);
  auto& S = fl.sph;
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    S.u[i] = fl.v[i] + (h / fl.m[i]) * fl.f[i];
  });
  const double share = std::min(1.0, h * kSoundSpeed / fl.kernel_support);
  jacobi(fl, h, kDensityTolerance, 2, [&](std::size_t i) {
    const double start = S.density[i] - 1.0;
    return (start > 0 ? share * start : start) + h * densityRate(fl, i);
  });
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    fl.f[i] = (fl.m[i] / h) * (S.u[i] - fl.v[i]);
  });
}

}  // namespace reel
