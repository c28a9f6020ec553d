#include "sim/fluid/fluid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/isosurface.h"
#include "core/lanes.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/random.h"

namespace reel {
namespace {

// x^e, by multiplication when e is a small whole number (ie ≥ 0).
inline double power(double x, double e, int ie) {
  switch (ie) {
    case 0: return 1.0;
    case 1: return x;
    case 2: return x * x;
    case 3: return x * x * x;
    case 4: { const double y = x * x; return y * y; }
    case 5: { const double y = x * x; return y * y * x; }
    case 6: { const double y = x * x * x; return y * y; }
    case 7: { const double y = x * x * x; return y * y * x; }
    case 8: { const double y = x * x; const double z = y * y; return z * z; }
    default: return std::pow(x, e);
  }
}

// The scalar c with g_ij = c·(x_i − x_j), at distance r.
inline double pairCoefficient(const PairParams& p, double mi, double mj, double r) {
  return mi * mj * (-p.alpha / power(r + p.epsilon, p.a, p.ia) + p.beta / power(r, p.b, p.ib));
}

// The radial force (positive: repulsive) between particles of masses mi, mj at distance r.
double radialForce(const PairParams& p, double mi, double mj, double r) { return pairCoefficient(p, mi, mj, r) * r; }

int wholeExponent(double e) { return e == std::floor(e) && e >= 0 && e <= 8 ? static_cast<int>(e) : -1; }

// An orthonormal pair perpendicular to the unit vector d.
void perpendicular(const Vec3& d, Vec3& u, Vec3& w) {
  const Vec3 helper = std::abs(d.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  u = helper.cross(d).normalized();
  w = d.cross(u);
}

constexpr std::uint64_t kJitterStream = 0xF1D0ull << 16;
constexpr std::uint64_t kEmitterStream = 0xE311ull << 16;

// Emits the layers of every emitter due by t1; returns whether any particle was added. A layer
// released at t in (t0, t1] starts (t0 − t)·speed along the nozzle, so that after this step's
// motion it is where it would be had it left exactly at t.
bool emit(Fluid& fl, double t0, double t1) {
  bool added = false;
  for (std::size_t k = 0; k < fl.emitters.size(); ++k) {
    FluidEmitter& e = fl.emitters[k];
    const EmitterDesc& d = e.desc;
    if (t1 < d.start) continue;
    const long long due =
        std::min(e.max_layers, static_cast<long long>(std::floor((std::min(t1, d.stop) - d.start) / e.layer_dt)) + 1);
    for (; e.layers < due; ++e.layers) {
      const double t_layer = d.start + static_cast<double>(e.layers) * e.layer_dt;
      const double turn = 2.0 * std::numbers::pi * uniformAt(fl.seed, kEmitterStream + k, static_cast<std::uint64_t>(e.layers));
      const double c = std::cos(turn), sn = std::sin(turn);
      const Vec3 vel = d.speed * d.direction;
      // A nozzle cannot push into liquid: a point closer than half the spacing to a particle
      // (one listed in the grid, which has moved less than the skin since) is skipped.
      const std::size_t listed = std::min(fl.x_built.size(), fl.x.size());
      const double clear2 = 0.25 * d.spacing * d.spacing;
      for (const auto& q : e.disc) {
        if (static_cast<long long>(fl.x.size()) >= fl.max_particles) return added;
        const double u = c * q[0] - sn * q[1], w = sn * q[0] + c * q[1];
        const Vec3 p = d.position + u * e.u + w * e.w + (t0 - t_layer) * vel;
        bool occupied = false;
        if (listed > 0)
          fl.grid.forEachNear(p, [&](int j) {
            occupied = occupied || (static_cast<std::size_t>(j) < listed && (fl.x[static_cast<std::size_t>(j)] - p).squaredNorm() < clear2);
          });
        if (occupied) {
          ++fl.skipped;
          continue;
        }
        fl.id.push_back(static_cast<std::int32_t>(fl.id.size()));
        fl.x.push_back(p);
        fl.v.push_back(vel);
        fl.s.push_back(d.species);
        fl.m.push_back(fl.species_mass[static_cast<std::size_t>(d.species)]);
        added = true;
      }
    }
  }
  return added;
}

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

Fluid buildFluid(const FluidDesc& d, const std::string& name, const std::vector<ObjectDesc>& objects,
                 const std::vector<Collider>& colliders, std::uint64_t seed) {
  Fluid fl;
  fl.name = name;
  fl.seed = seed;
  fl.S = static_cast<int>(d.species.size());
  REEL_CHECK(fl.S >= 1, "a fluid needs a species");
  const auto S = static_cast<std::size_t>(fl.S);
  for (const SpeciesDesc& sp : d.species) {
    fl.species_names.push_back(sp.name);
    fl.species_mass.push_back(sp.mass);
    fl.species_color.push_back(sp.color);
  }
  // Pair table: a species with itself uses its own values, two species the mean of theirs,
  // unless an interaction sets them.
  fl.pairs.resize(S * S);
  for (std::size_t i = 0; i < S; ++i)
    for (std::size_t j = 0; j < S; ++j) {
      const SpeciesDesc &A = d.species[i], &B = d.species[j];
      auto mean = [](double x, double y) { return 0.5 * (x + y); };
      double alpha = mean(A.alpha, B.alpha), beta = mean(A.beta, B.beta), a = mean(A.a, B.a), b = mean(A.b, B.b);
      double eps = mean(A.epsilon, B.epsilon), cut = mean(A.cutoff, B.cutoff), visc = mean(A.viscosity, B.viscosity);
      for (const InteractionDesc& in : d.interactions) {
        if (!((in.s == static_cast<int>(i) && in.t == static_cast<int>(j)) ||
              (in.s == static_cast<int>(j) && in.t == static_cast<int>(i))))
          continue;
        alpha = in.alpha.value_or(alpha);
        beta = in.beta.value_or(beta);
        a = in.a.value_or(a);
        b = in.b.value_or(b);
        eps = in.epsilon.value_or(eps);
        cut = in.cutoff.value_or(cut);
        visc = in.viscosity.value_or(visc);
      }
      PairParams p = makePair(alpha, beta, a, b, eps, cut, visc);
      const double mi = A.mass, mj = B.mass;
      p.mm = mi * mj;
      p.visc_mu = visc * mi * mj / (mi + mj);
      p.inv_cutoff = 1.0 / cut;
      p.seed_form = p.ia == 2 && p.ib == 4 && eps == 0.0;
      const double kT = 0.5 * (mi * A.agitation * A.agitation + mj * B.agitation * B.agitation);
      p.sigma = std::sqrt(2.0 * p.visc_mu * kT);
      fl.agitated = fl.agitated || p.sigma > 0;
      fl.pairs[i * S + j] = p;
    }
  fl.cutoff_max = 0.0;
  for (const PairParams& p : fl.pairs) fl.cutoff_max = std::max(fl.cutoff_max, p.cutoff);
  fl.skin = 0.3 * fl.cutoff_max;
  {
    const double d0 = bulkSpacing(fl.pairs[0]);
    fl.ref_spacing = d0 > 0 ? 0.65 * d0 : 2.0 * d.radius;
  }
  fl.radius = d.radius;
  fl.max_particles = d.max_particles;
  fl.draw = d.draw;
  fl.surface_cell = d.surface_cell > 0 ? d.surface_cell : d.radius;
  fl.surface_kernel = d.surface_kernel > 0 ? d.surface_kernel : 4.0 * d.radius;
  fl.surface_iso = d.surface_iso;
  // Surfaces per collider and species; dynamic objects by collider.
  fl.surfaces.reserve(objects.size() * S);
  for (const ObjectDesc& o : objects) {
    for (std::size_t k = 0; k < S; ++k) {
      Surface sf = o.surface;
      for (const auto& [sp, surf] : o.species_surface)
        if (sp == fl.species_names[k]) sf = surf;
      fl.surfaces.push_back(sf);
    }
    fl.dyn_of.push_back(o.dynamic ? fl.dynamic_count++ : -1);
  }
  // Blocks: a cubic lattice filling [min, max], each point jittered from the seed.
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
            inside = inside || (c.distance(p, dist, nrm) && dist < c.thickness + d.radius);
          }
          if (inside) continue;
          fl.id.push_back(static_cast<std::int32_t>(fl.id.size()));
          fl.x.push_back(p);
          fl.v.push_back(b.velocity);
          fl.s.push_back(b.species);
          fl.m.push_back(fl.species_mass[static_cast<std::size_t>(b.species)]);
        }
  }
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
  const auto S = static_cast<std::size_t>(fl.S);
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

void sortParticles(Fluid& fl) {
  const std::size_t n = fl.x.size();
  const double inv = 1.0 / (fl.cutoff_max + fl.skin);
  // Morton code of the cell (21 bits per axis, wrapping), ties broken by the particle's id.
  auto spread = [](std::uint64_t v) {
    v &= 0x1FFFFF;
    v = (v | v << 32) & 0x1F00000000FFFFull;
    v = (v | v << 16) & 0x1F0000FF0000FFull;
    v = (v | v << 8) & 0x100F00F00F00F00Full;
    v = (v | v << 4) & 0x10C30C30C30C30C3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
  };
  std::vector<std::pair<std::uint64_t, std::int32_t>> key(n);
  for (std::size_t k = 0; k < n; ++k) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double c = std::floor(fl.x[k][a] * inv);
      const auto ic = static_cast<std::int64_t>(std::isfinite(c) ? std::clamp(c, -1e15, 1e15) : 0.0);
      code |= spread(static_cast<std::uint64_t>(ic)) << a;
    }
    key[k] = {code, fl.id[k]};
  }
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return key[p] < key[q]; });
  auto permute = [&](auto& a) {
    auto copy = a;
    for (std::size_t k = 0; k < n; ++k) a[k] = copy[order[k]];
  };
  permute(fl.x);
  permute(fl.v);
  permute(fl.s);
  permute(fl.m);
  permute(fl.id);
  fl.x_built.clear();
}

void fluidById(Fluid& fl) {
  const std::size_t n = fl.x.size();
  fl.x_by_id.resize(n);
  fl.v_by_id.resize(n);
  fl.s_by_id.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(fl.id[k]);
    fl.x_by_id[i] = fl.x[k];
    fl.v_by_id[i] = fl.v[k];
    fl.s_by_id[i] = fl.s[k];
  }
}

void buildNeighbours(Fluid& fl) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const double reach = fl.cutoff_max + fl.skin, reach2 = reach * reach;
  fl.grid.build(fl.x, fl.x, reach);
  // The positions in the grid's bucket order, so that a bucket's candidates are read from
  // consecutive memory.
  const std::span<const std::int32_t> items = fl.grid.items();
  const auto E = static_cast<std::ptrdiff_t>(items.size());
  fl.cell_x.resize(items.size() * 3);
  double* cx = fl.cell_x.data();
  parallelFor(E, [&](std::ptrdiff_t e) {
    const Vec3& p = fl.x[static_cast<std::size_t>(items[static_cast<std::size_t>(e)])];
    double* c3 = cx + 3 * static_cast<std::size_t>(e);
    c3[0] = p.x(), c3[1] = p.y(), c3[2] = p.z();
  });
  // One pass: fixed chunks of particles list their neighbours in parallel, then the chunks are
  // joined in order (the same list for any thread count). Consecutive particles mostly share a
  // cell (they are sorted along a Morton curve), so the 27 buckets are looked up once per run.
  constexpr std::ptrdiff_t kChunk = 2048;
  const std::ptrdiff_t chunks = (n + kChunk - 1) / kChunk;
  fl.chunk_lists.resize(static_cast<std::size_t>(chunks));
  fl.nbr_start.assign(static_cast<std::size_t>(n) + 1, 0);
#pragma omp parallel for schedule(dynamic, 1) if (n >= kParallelMin)
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    std::vector<std::int32_t>& out = fl.chunk_lists[static_cast<std::size_t>(c)];
    std::size_t count = 0;
    std::uint32_t near[27];
    int nnear = 0;
    std::array<std::int64_t, 3> cell{};
    for (std::ptrdiff_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
      const Vec3 xi = fl.x[static_cast<std::size_t>(i)];
      const std::array<std::int64_t, 3> ci = fl.grid.cellOf(xi);
      if (i == c * kChunk || ci != cell) {
        nnear = fl.grid.nearBuckets(xi, near);
        cell = ci;
      }
      const std::size_t before = count;
      for (int q = 0; q < nnear; ++q) {
        const std::uint32_t b0 = fl.grid.bucketBegin(near[q]), b1 = fl.grid.bucketEnd(near[q]);
        if (out.size() < count + (b1 - b0)) out.resize(2 * (count + (b1 - b0)));
        std::int32_t* w = out.data();
        // Branch-free: every candidate is written, and kept (the count advances) when in reach.
        for (std::uint32_t e = b0; e < b1; ++e) {
          const double* c3 = cx + 3 * static_cast<std::size_t>(e);
          const double d0 = c3[0] - xi.x(), d1 = c3[1] - xi.y(), d2 = c3[2] - xi.z();
          const std::int32_t j = items[e];
          w[count] = j;
          count += static_cast<std::size_t>((d0 * d0 + d1 * d1 + d2 * d2 < reach2) & (j != i));
        }
      }
      fl.nbr_start[static_cast<std::size_t>(i) + 1] = static_cast<std::uint32_t>(count - before);
    }
    out.resize(count);
  }
  for (std::ptrdiff_t i = 0; i < n; ++i) fl.nbr_start[static_cast<std::size_t>(i) + 1] += fl.nbr_start[static_cast<std::size_t>(i)];
  fl.nbr.resize(fl.nbr_start.back());
  parallelFor(chunks, [&](std::ptrdiff_t c) {
    const auto& part = fl.chunk_lists[static_cast<std::size_t>(c)];
    std::copy(part.begin(), part.end(), fl.nbr.begin() + fl.nbr_start[static_cast<std::size_t>(c * kChunk)]);
  });
  fl.x_built = fl.x;
  ++fl.rebuilds;
}

namespace {

// Rebuilds the neighbour list when a pair could have closed the skin since the last build (until
// then every pair closer than the cutoff is still listed), or when forced.
// The first and every 16th rebuild first re-sort the particles along a Morton curve of their grid cells, so
// that neighbours in space are neighbours in memory.
void refreshNeighbours(Fluid& fl, bool force) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  bool rebuild = force || fl.x_built.size() != fl.x.size();
  if (!rebuild) {
    // A pair missing from the list must have closed the skin: it can only have done so if the two
    // largest displacements since the build add up to more than the skin (sharper than "one
    // particle moved half the skin" when a few particles fly and the rest sit still).
    double d1 = 0.0, d2 = 0.0;
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const double d2i = (fl.x[static_cast<std::size_t>(i)] - fl.x_built[static_cast<std::size_t>(i)]).squaredNorm();
      if (!(d2i <= d1)) {  // also catches NaN
        d2 = d1;
        d1 = d2i;
      } else if (d2i > d2) {
        d2 = d2i;
      }
    }
    rebuild = !(std::sqrt(d1) + std::sqrt(d2) <= fl.skin);
  }
  if (!rebuild) return;
  if (fl.rebuilds % 16 == 0) sortParticles(fl);
  buildNeighbours(fl);
}

// The pair and viscous forces on particles [i0, i1) whose species meets every species in the
// seed's form (a = 2, b = 4, ε = 0), four list entries at a time: lane k takes the entries k, k+4,
// ... of the particle's list, in order, and the lanes are added in a fixed order at the end. The
// cutoff is a mask, not a branch (half the entries of a Verlet list lie in its skin). Compiled for
// AVX2 and for any x86-64 (core/lanes.h): both give the same bits.
REEL_CLONED
void seedFormForces(const Fluid& fl, std::ptrdiff_t i0, std::ptrdiff_t i1, const Vec3& gravity, Vec3* out) {
  const Fluid::Packed* P = fl.packed.data();
  const std::int32_t* nb = fl.nbr.data();
  const auto S = static_cast<std::size_t>(fl.S);
  const Lane4 zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
  for (std::ptrdiff_t ii = i0; ii < i1; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    const Fluid::Packed& pi = P[i];
    const PairParams* row = &fl.pairs[static_cast<std::size_t>(pi.s) * S];
    const Lane4 xi0 = zero + pi.x[0], xi1 = zero + pi.x[1], xi2 = zero + pi.x[2];
    const Lane4 vi0 = zero + pi.v[0], vi1 = zero + pi.v[1], vi2 = zero + pi.v[2];
    Lane4 cut2 = zero + row[0].cutoff2, mm = zero + row[0].mm, al = zero + row[0].alpha, be = zero + row[0].beta;
    Lane4 mu = zero + row[0].visc_mu, icut = zero + row[0].inv_cutoff;
    Lane4 a0 = zero, a1 = zero, a2 = zero;
    const std::uint32_t end = fl.nbr_start[i + 1];
    for (std::uint32_t e = fl.nbr_start[i]; e < end; e += 4) {
      // Past the list's end a lane reads the particle itself: distance 0, masked out below.
      const Fluid::Packed& q0 = P[nb[e]];
      const Fluid::Packed& q1 = e + 1 < end ? P[nb[e + 1]] : pi;
      const Fluid::Packed& q2 = e + 2 < end ? P[nb[e + 2]] : pi;
      const Fluid::Packed& q3 = e + 3 < end ? P[nb[e + 3]] : pi;
      if (S > 1) {
        const PairParams* p[4] = {&row[q0.s], &row[q1.s], &row[q2.s], &row[q3.s]};
        for (int k = 0; k < 4; ++k) {
          cut2[k] = p[k]->cutoff2, mm[k] = p[k]->mm, al[k] = p[k]->alpha, be[k] = p[k]->beta;
          mu[k] = p[k]->visc_mu, icut[k] = p[k]->inv_cutoff;
        }
      }
      const Lane4 d0 = xi0 - Lane4{q0.x[0], q1.x[0], q2.x[0], q3.x[0]};
      const Lane4 d1 = xi1 - Lane4{q0.x[1], q1.x[1], q2.x[1], q3.x[1]};
      const Lane4 d2 = xi2 - Lane4{q0.x[2], q1.x[2], q2.x[2], q3.x[2]};
      const Lane4 r2 = d0 * d0 + d1 * d1 + d2 * d2;
      const Mask4 in = (r2 < cut2) & (r2 > zero);
      const Lane4 safe = in ? r2 : one;
      // The seed's exponents: m_i m_j (−α/r² + β/r⁴) = m_i m_j (β/r² − α)/r², one division.
      const Lane4 inv = one / safe;
      const Lane4 c = in ? mm * (be * inv - al) * inv : zero;
      Lane4 r = safe;
      for (int k = 0; k < 4; ++k) r[k] = std::sqrt(r[k]);
      const Lane4 w = in ? mu * (one - r * icut) : zero;
      a0 += c * d0 + w * (Lane4{q0.v[0], q1.v[0], q2.v[0], q3.v[0]} - vi0);
      a1 += c * d1 + w * (Lane4{q0.v[1], q1.v[1], q2.v[1], q3.v[1]} - vi1);
      a2 += c * d2 + w * (Lane4{q0.v[2], q1.v[2], q2.v[2], q3.v[2]} - vi2);
    }
    out[i] = Vec3(pi.m * gravity.x() + hsum(a0), pi.m * gravity.y() + hsum(a1), pi.m * gravity.z() + hsum(a2));
  }
}

// The same forces for any exponents, one entry at a time.
void generalForces(const Fluid& fl, std::size_t i, const Vec3& gravity, Vec3* out) {
  const Fluid::Packed* P = fl.packed.data();
  const Fluid::Packed& pi = P[i];
  const double mi = pi.m;
  const PairParams* row = &fl.pairs[static_cast<std::size_t>(pi.s) * static_cast<std::size_t>(fl.S)];
  double f0 = mi * gravity.x(), f1 = mi * gravity.y(), f2 = mi * gravity.z();
  for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
    const Fluid::Packed& pj = P[fl.nbr[e]];
    const double d0 = pi.x[0] - pj.x[0], d1 = pi.x[1] - pj.x[1], d2 = pi.x[2] - pj.x[2];
    const double r2 = d0 * d0 + d1 * d1 + d2 * d2;
    const PairParams& p = row[pj.s];
    if (!(r2 < p.cutoff2) || r2 == 0.0) continue;
    const double r = std::sqrt(r2), c = pairCoefficient(p, mi, pj.m, r);
    const double w = p.visc_mu * (1.0 - r * p.inv_cutoff);
    f0 += c * d0 + w * (pj.v[0] - pi.v[0]);
    f1 += c * d1 + w * (pj.v[1] - pi.v[1]);
    f2 += c * d2 + w * (pj.v[2] - pi.v[2]);
  }
  out[i] = Vec3(f0, f1, f2);
}

// Pair and viscous forces plus gravity, gathered per particle in a fixed order (the list's, or
// its four lanes' then the lanes in order: deterministic). The force loop reads each neighbour's position, velocity, mass and species from one 64-byte record
// (one cache line) instead of four arrays.
void computeForces(Fluid& fl, const Vec3& gravity) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const auto S = static_cast<std::size_t>(fl.S);
  fl.f.resize(fl.x.size());
  fl.packed.resize(fl.x.size());
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    Fluid::Packed& q = fl.packed[i];
    q.x[0] = fl.x[i].x(), q.x[1] = fl.x[i].y(), q.x[2] = fl.x[i].z();
    q.v[0] = fl.v[i].x(), q.v[1] = fl.v[i].y(), q.v[2] = fl.v[i].z();
    q.m = fl.m[i];
    q.s = fl.s[i];
  });
  // Species whose every pair has the seed's form take the four-lane loop.
  std::vector<char> seed_row(S, 1);
  for (std::size_t a = 0; a < S; ++a)
    for (std::size_t b = 0; b < S; ++b) seed_row[a] = seed_row[a] && fl.pairs[a * S + b].seed_form;
  parallelBlocks(n, 64, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (std::ptrdiff_t i = begin; i < end;) {
      // A run of particles of one kind goes to one call.
      const bool fast = seed_row[static_cast<std::size_t>(fl.s[static_cast<std::size_t>(i)])];
      std::ptrdiff_t k = i + 1;
      while (k < end && bool(seed_row[static_cast<std::size_t>(fl.s[static_cast<std::size_t>(k)])]) == fast) ++k;
      if (fast) {
        seedFormForces(fl, i, k, gravity, fl.f.data());
      } else {
        for (std::ptrdiff_t q = i; q < k; ++q) generalForces(fl, static_cast<std::size_t>(q), gravity, fl.f.data());
      }
      i = k;
    }
  });
  fl.pair_tests += static_cast<long long>(fl.nbr.size());
}

// Thermal agitation, the random force of dissipative particle dynamics (Hoogerbrugge & Koelman
// 1992; Español & Warren 1995, fluctuation–dissipation): for each pair inside the cutoff,
//   F_ij = σ_ij · √(1 − r/cutoff) · θ_ij / √h,   F_ji = −F_ij,   σ² = 2·γμ·kT,
// θ_ij a vector of three independent numbers of unit variance drawn from the seed by the step
// and the two particles' ids, so that with the viscosity the liquid keeps a thermal speed of
// `agitation` per axis and momentum is still conserved exactly. This is the "heating" that
// melts Terzopoulos, Platt & Fleischer's solids into liquids: it keeps a resting liquid from
// jamming into a glass.
void addThermalForces(Fluid& fl, double h) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const auto S = static_cast<std::size_t>(fl.S);
  const std::uint64_t draw = static_cast<std::uint64_t>(fl.thermal_draws++);
  const double root3 = std::sqrt(3.0), inv_sqrt_h = 1.0 / std::sqrt(h);
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const PairParams* row = &fl.pairs[static_cast<std::size_t>(fl.s[i]) * S];
    Vec3 add = Vec3::Zero();
    for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
      const auto j = static_cast<std::size_t>(fl.nbr[e]);
      const PairParams& p = row[fl.s[j]];
      if (p.sigma == 0.0) continue;
      const double r2 = (fl.x[i] - fl.x[j]).squaredNorm();
      if (!(r2 < p.cutoff2)) continue;
      const std::int32_t a = std::min(fl.id[i], fl.id[j]), b = std::max(fl.id[i], fl.id[j]);
      const std::uint64_t pair = static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint32_t>(b);
      Vec3 theta;
      for (int c = 0; c < 3; ++c) theta[c] = root3 * (2.0 * uniformAt(fl.seed ^ (0x7E33ull << 40), draw * 3 + static_cast<std::uint64_t>(c), pair) - 1.0);
      const double sign = fl.id[i] < fl.id[j] ? 1.0 : -1.0;
      add += (sign * p.sigma * std::sqrt(1.0 - std::sqrt(r2) * p.inv_cutoff) * inv_sqrt_h) * theta;
    }
    fl.f[i] += add;
  });
}

// Symplectic Euler over h, then adhesion and contacts; the impulses particles take from dynamic
// objects go, opposite, to the objects.
void moveAndCollide(Fluid& fl, const std::vector<Collider>& colliders, std::vector<DynamicObject>& dynamics,
                    double h) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const auto S = static_cast<std::size_t>(fl.S);
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    fl.v[i] += (h / fl.m[i]) * fl.f[i];
    fl.x[i] += h * fl.v[i];
  });
  if (colliders.empty()) return;
  const auto D = static_cast<std::size_t>(fl.dynamic_count);
  if (D > 0) fl.imp.assign(static_cast<std::size_t>(n) * D, Vec3::Zero());
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const auto si = static_cast<std::size_t>(fl.s[i]);
    const double range = fl.pairs[si * S + si].cutoff;
    for (std::size_t k = 0; k < colliders.size(); ++k) {
      const Collider& c = colliders[k];
      double d;
      Vec3 nrm;
      if (!c.distance(fl.x[i], d, nrm)) continue;
      const Surface& sf = fl.surfaces[k * S + si];
      const double reach = c.thickness + fl.radius;
      if (d >= reach + (sf.adhesion > 0 ? range : 0.0)) continue;
      const Vec3 v_before = fl.v[i];
      // Adhesion: an acceleration towards the surface, full in contact, fading to 0 one cutoff away.
      if (sf.adhesion > 0) fl.v[i] -= (h * sf.adhesion * std::clamp(1.0 - (d - reach) / range, 0.0, 1.0)) * nrm;
      if (d < reach) contactNode(c, sf, reach, d, nrm, h, fl.x[i], fl.v[i]);
      if (fl.dyn_of[k] >= 0) fl.imp[i * D + static_cast<std::size_t>(fl.dyn_of[k])] += fl.m[i] * (fl.v[i] - v_before);
    }
  });
  // Each dynamic object takes the opposite of the particles' impulses, summed in index order.
  for (DynamicObject& obj : dynamics) {
    const int q = obj.collider < fl.dyn_of.size() ? fl.dyn_of[obj.collider] : -1;
    if (q < 0) continue;
    const Vec3 centre = colliders[obj.collider].pos;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
      const Vec3& J = fl.imp[i * D + static_cast<std::size_t>(q)];
      if (J.isZero()) continue;
      obj.impulse -= J;
      obj.angular -= (fl.x[i] - centre).cross(J);
    }
  }
}

}  // namespace

void stepFluid(Fluid& fl, const std::vector<Collider>& colliders, std::vector<DynamicObject>& dynamics,
               const Vec3& gravity, double h, double t0, double t1) {
  const bool added = emit(fl, t0, t1);
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  if (n == 0) return;
  refreshNeighbours(fl, added);
  computeForces(fl, gravity);
  // A violent moment (an impact, a splash squeezed against a wall) can push particles much closer
  // than the stable step assumes. Then the step is split so that no particle moves more than 5%
  // of the spacing through its acceleration, nor 40% through its speed, in one part (at most 16).
  const double a_max = deterministicMax(n, [&](std::ptrdiff_t i) {
    return fl.f[static_cast<std::size_t>(i)].norm() / fl.m[static_cast<std::size_t>(i)];
  });
  const double v_max = deterministicMax(n, [&](std::ptrdiff_t i) { return fl.v[static_cast<std::size_t>(i)].norm(); });
  const double ref = fl.ref_spacing;
  const double parts = std::max({1.0, std::sqrt(a_max * h * h / (0.05 * ref)), v_max * h / (0.4 * ref)});
  const int k = std::isfinite(parts) ? static_cast<int>(std::min(16.0, std::ceil(parts))) : 1;
  if (k > 1) fl.split_steps += k - 1;
  const double hk = h / k;
  for (int part = 0; part < k; ++part) {
    if (part > 0) {
      refreshNeighbours(fl, false);
      computeForces(fl, gravity);
    }
    if (fl.agitated) addThermalForces(fl, hk);
    moveAndCollide(fl, colliders, dynamics, hk);
  }
}

double kineticEnergy(const Fluid& fl) {
  return deterministicSum(static_cast<std::ptrdiff_t>(fl.x.size()), [&](std::ptrdiff_t i) {
    return 0.5 * fl.m[static_cast<std::size_t>(i)] * fl.v[static_cast<std::size_t>(i)].squaredNorm();
  });
}

Vec3 momentum(const Fluid& fl) {
  Vec3 p;
  for (int a = 0; a < 3; ++a)
    p[a] = deterministicSum(static_cast<std::ptrdiff_t>(fl.x.size()), [&](std::ptrdiff_t i) {
      return fl.m[static_cast<std::size_t>(i)] * fl.v[static_cast<std::size_t>(i)][a];
    });
  return p;
}

namespace {

// Each particle's colour: its species colour blended with its neighbours' (weights (1 − r/c)²
// inside the pair cutoff), so where species mix their colours mix, and a pure region keeps its own.
std::vector<Vec3> blendedColors(const Fluid& fl) {
  const std::size_t n = fl.x.size();
  std::vector<Vec3> c(n);
  const auto S = static_cast<std::size_t>(fl.S);
  const bool listed = fl.nbr_start.size() == n + 1;
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    Vec3 sum = fl.species_color[static_cast<std::size_t>(fl.s[i])];
    double wsum = 1.0;
    if (S > 1 && listed)
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
        const auto j = static_cast<std::size_t>(fl.nbr[e]);
        const PairParams& p = fl.pairs[static_cast<std::size_t>(fl.s[i]) * S + static_cast<std::size_t>(fl.s[j])];
        const double r = (fl.x[i] - fl.x[j]).norm();
        if (r >= p.cutoff) continue;
        const double w = (1.0 - r / p.cutoff) * (1.0 - r / p.cutoff);
        sum += w * fl.species_color[static_cast<std::size_t>(fl.s[j])];
        wsum += w;
      }
    c[i] = sum / wsum;
  });
  return c;
}

// The liquid's surface: the particles' density splatted on a grid with the kernel
// W(q) = (1 − q²)³, q = r/R, normalised by the density of a bulk at the species' rest spacing,
// cut at `surface_iso`. Colours are the splatted particle colours, darkened with the depth of
// liquid behind the surface (colour^(1 + 1.5·density one kernel radius inside): Beer–Lambert-like).
TriMesh liquidSurface(const Fluid& fl, const std::vector<Vec3>& colors) {
  const std::size_t n = fl.x.size();
  if (n == 0) return {};
  const double R = fl.surface_kernel;
  double cell = fl.surface_cell;
  Vec3 lo = fl.x[0], hi = fl.x[0];
  for (const Vec3& p : fl.x) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo -= Vec3::Constant(R + 2 * cell);
  hi += Vec3::Constant(R + 2 * cell);
  auto dimsFor = [&](double c) {
    return std::array<double, 3>{std::ceil((hi.x() - lo.x()) / c) + 1, std::ceil((hi.y() - lo.y()) / c) + 1,
                                 std::ceil((hi.z() - lo.z()) / c) + 1};
  };
  // At most 16 million nodes: a coarser grid when the liquid spreads wide.
  while ([&] { auto d = dimsFor(cell); return d[0] * d[1] * d[2] > 1.6e7; }()) cell *= 1.25;
  cell = std::max(cell, 1e-6);
  const auto dd = dimsFor(cell);
  GridField f;
  f.dims = {static_cast<int>(dd[0]), static_cast<int>(dd[1]), static_cast<int>(dd[2])};
  f.origin = lo;
  f.cell = cell;
  f.value.assign(static_cast<std::size_t>(dd[0] * dd[1] * dd[2]), 0.0f);
  f.color.assign(3 * f.value.size(), 0.0f);
  // A settled liquid packs its nearest neighbours at about 0.8 of the lattice spacing.
  double spacing = 0.8 * bulkSpacing(fl.pairs[0]);
  if (!(spacing > 0)) spacing = 2.0 * fl.radius;
  const double bulk = 0.6383 * R * R * R / (spacing * spacing * spacing);  // ∫W dV / spacing³
  const int reach = static_cast<int>(std::ceil(R / cell));
  for (std::size_t p = 0; p < n; ++p) {
    const Vec3& x = fl.x[p];
    if (!x.allFinite()) continue;
    const Vec3 g = (x - lo) / cell;
    const int ci = static_cast<int>(std::lround(g.x())), cj = static_cast<int>(std::lround(g.y())),
              ck = static_cast<int>(std::lround(g.z()));
    for (int k = std::max(0, ck - reach); k <= std::min(f.dims[2] - 1, ck + reach); ++k)
      for (int j = std::max(0, cj - reach); j <= std::min(f.dims[1] - 1, cj + reach); ++j)
        for (int i = std::max(0, ci - reach); i <= std::min(f.dims[0] - 1, ci + reach); ++i) {
          const double q2 = (lo + cell * Vec3(i, j, k) - x).squaredNorm() / (R * R);
          if (q2 >= 1.0) continue;
          const double w = (1 - q2) * (1 - q2) * (1 - q2) / bulk;
          const std::size_t id = f.index(i, j, k);
          f.value[id] += static_cast<float>(w);
          for (int a = 0; a < 3; ++a) f.color[3 * id + static_cast<std::size_t>(a)] += static_cast<float>(w * colors[p][a]);
        }
  }
  for (std::size_t id = 0; id < f.value.size(); ++id)
    if (f.value[id] > 0)
      for (int a = 0; a < 3; ++a) f.color[3 * id + static_cast<std::size_t>(a)] /= f.value[id];
  TriMesh m = isosurface(f, fl.surface_iso);
  for (std::size_t v = 0; v < m.vertexCount(); ++v) {
    const Vec3 p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
    const Vec3 nv(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    const double depth = std::clamp(f.sample(p - R * nv), 0.0, 1.0);
    for (int a = 0; a < 3; ++a) {
      float& c = m.colors[3 * v + static_cast<std::size_t>(a)];
      c = static_cast<float>(std::pow(std::clamp(static_cast<double>(c), 1e-3, 1.0), 1.0 + 1.5 * depth));
    }
  }
  return m;
}

}  // namespace

void emitFluid(const Fluid& fl, const Material& material, DrawList& out) {
  if (fl.x.empty()) return;
  DrawMaterial dm;
  dm.color = Vec3(1, 1, 1);  // the species colours carry the albedo
  dm.specular = material.specular;
  dm.shininess = material.shininess;
  dm.opacity = material.opacity;
  const std::vector<Vec3> colors = blendedColors(fl);
  if (fl.draw == FluidDraw::Surface) {
    DrawMesh mesh;
    mesh.mesh = std::make_shared<const TriMesh>(liquidSurface(fl, colors));
    mesh.per_frame = true;
    mesh.material = dm;
    if (mesh.mesh->triangleCount() > 0) out.meshes.push_back(std::move(mesh));
    return;
  }
  DrawSpheres sp;
  sp.radius = static_cast<float>(fl.radius);
  sp.material = dm;
  sp.centers.reserve(3 * fl.x.size());
  sp.colors.reserve(3 * fl.x.size());
  for (std::size_t i = 0; i < fl.x.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      sp.centers.push_back(static_cast<float>(fl.x[i][a]));
      sp.colors.push_back(static_cast<float>(colors[i][a]));
    }
  out.spheres.push_back(std::move(sp));
}

}  // namespace reel
