#include "sim/fluid/fluid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "core/error.h"
#include "core/lanes.h"
#include "core/parallel.h"
#include "core/profile.h"
#include "core/math.h"
#include "core/random.h"
#include "sim/fluid/fluid_dfsph.h"
#include "sim/fluid/fluid_diffuse.h"
#include "sim/fluid/fluid_pair.h"

namespace reel {
namespace {

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
    // (in double first: a tiny layer_dt must not overflow the conversion)
    const long long due = static_cast<long long>(
        std::min(static_cast<double>(e.max_layers), std::floor((std::min(t1, d.stop) - d.start) / e.layer_dt) + 1));
    long long& layers = fl.layers[k];
    for (; layers < due; ++layers) {
      const double t_layer = d.start + static_cast<double>(layers) * e.layer_dt;
      const double turn = 2.0 * std::numbers::pi * uniformAt(fl.seed, kEmitterStream + k, static_cast<std::uint64_t>(layers));
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
          listedGrid(fl).forEachNear(p, [&](int j) {
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
  if (fl.x_start.size() == n) permute(fl.x_start);
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

namespace {

// One block of the row grid's rows [r0, r1): each particle's neighbours within the reach (its
// square `reach2`) into the block's buffer, four candidates at a time (the grid's coordinates are
// padded past the end), the ones in reach kept by a left-pack (branch-free). Compiled for AVX2 and
// any x86-64 (core/lanes.h).
REEL_CLONED
void listRows(Fluid& fl, const RowGrid& g, double reach2, std::int64_t r0, std::int64_t r1, std::uint32_t block,
              std::vector<std::int32_t>& out) {
  const std::span<const std::int32_t> order = g.order();
  const double *gx = g.x(), *gy = g.y(), *gz = g.z();
  const Lane4 zero = {0, 0, 0, 0}, reach = zero + reach2;
  std::size_t count = 0;
  g.visitRows(r0, r1, [&](std::uint32_t e, std::span<const RowGrid::Run> runs) {
    const Lane4 xi = zero + gx[e], yi = zero + gy[e], zi = zero + gz[e];
    std::size_t need = count + 4;
    for (const RowGrid::Run& run : runs) need += run[1] - run[0];
    if (out.size() < need) out.resize(2 * need);
    std::int32_t* w = out.data();
    const std::size_t before = count;
    for (const RowGrid::Run& run : runs)
      for (std::uint32_t k = run[0]; k < run[1]; k += 4) {
        Lane4 px, py, pz;
        std::memcpy(&px, gx + k, sizeof px), std::memcpy(&py, gy + k, sizeof py), std::memcpy(&pz, gz + k, sizeof pz);
        const Lane4 d0 = px - xi, d1 = py - yi, d2 = pz - zi;
        const Mask4 at = Mask4{0, 1, 2, 3} + static_cast<long long>(k);
        const Mask4 in = (d0 * d0 + d1 * d1 + d2 * d2 < reach) & (at < static_cast<long long>(run[1])) & (at != static_cast<long long>(e));
        const unsigned bits = maskBits(in);
        Int4 ids;
        if (k + 4 <= order.size()) {
          std::memcpy(&ids, order.data() + k, sizeof ids);
        } else {
          for (std::uint32_t l = 0; l < 4; ++l) ids[l] = order[k + l < order.size() ? k + l : k];
        }
        const Int4 kept = leftPack(ids, bits);
        std::memcpy(w + count, &kept, sizeof kept);
        count += keptCount(bits);
      }
    const auto i = static_cast<std::size_t>(order[e]);
    fl.list_at[i] = {block, static_cast<std::uint32_t>(before)};
    fl.nbr_start[i + 1] = static_cast<std::uint32_t>(count - before);
  });
  out.resize(count);  // (its size: what the block's rows hold now)
}

}  // namespace

void buildNeighbours(Fluid& fl) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  if (!(fl.list_skin > 0)) fl.list_skin = fl.skin;
  fl.list_age = 0;
  const double reach = fl.cutoff_max + fl.list_skin, reach2 = reach * reach;
  fl.grid_current = false;  // (emitters and diffuse particles build it when they ask: listedGrid)
  // The search: a row grid at the reach (9 runs of sorted entries a particle, about 4 times the
  // sphere, where the hashed grid's 27 cells hold 6.4 times). Fixed blocks of rows list their
  // particles' neighbours in parallel, each particle's list in its block's buffer; then the lists
  // are copied in particle order (the same lists for any thread count).
  RowGrid& g = fl.rows;
  g.build(fl.x, reach);
  constexpr std::int64_t kRowsABlock = 16;
  const std::int64_t blocks = (g.rows() + kRowsABlock - 1) / kRowsABlock;
  fl.chunk_lists.resize(static_cast<std::size_t>(blocks));
  fl.list_at.resize(static_cast<std::size_t>(n));
  fl.nbr_start.assign(static_cast<std::size_t>(n) + 1, 0);
#pragma omp parallel for schedule(dynamic, 4) if (n >= parallelMin())
  for (std::int64_t c = 0; c < blocks; ++c)
    listRows(fl, g, reach2, c * kRowsABlock, std::min(g.rows(), (c + 1) * kRowsABlock), static_cast<std::uint32_t>(c),
             fl.chunk_lists[static_cast<std::size_t>(c)]);
  for (std::ptrdiff_t i = 0; i < n; ++i) fl.nbr_start[static_cast<std::size_t>(i) + 1] += fl.nbr_start[static_cast<std::size_t>(i)];
  fl.nbr.resize(fl.nbr_start.back());
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const std::int32_t* from = fl.chunk_lists[fl.list_at[i][0]].data() + fl.list_at[i][1];
    std::copy(from, from + (fl.nbr_start[i + 1] - fl.nbr_start[i]), fl.nbr.begin() + fl.nbr_start[i]);
  });
  // A block's buffer is kept for the next build, but not at many times what its rows now hold
  // (rows follow the liquid's box, and a block that once held a splash may now hold little).
  for (auto& buffer : fl.chunk_lists)
    if (buffer.capacity() > 65536 && buffer.capacity() > 4 * buffer.size()) buffer.shrink_to_fit();
  fl.x_built = fl.x;
  ++fl.rebuilds;
}

const BoxGrid& listedGrid(Fluid& fl) {
  if (!fl.grid_current) fl.grid.build(fl.x_built, fl.x_built, fl.cutoff_max + fl.list_skin);
  fl.grid_current = true;
  return fl.grid;
}

void rebuildGrid(Fluid& fl) { fl.grid_current = false; }

namespace {

// Rebuilds the neighbour list when a pair could have closed the skin since the last build (until
// then every pair closer than the cutoff is still listed), or when forced.
// The first and every 16th rebuild (32nd at a thin skin) first re-sort the particles along a Morton curve of their grid cells, so
// that neighbours in space are neighbours in memory.
// The skin: Fluid::skin (0.3 of the cutoff) while a list at it outlasts a check. Where the liquid
// moves so fast that it cannot (a poured stream falling at metres a second beside liquid at rest:
// the two largest displacements pass the skin in one step), the list is rebuilt at every check
// whatever its skin, and a skin of a twentieth of the default lists about half the entries
// ((1.015/1.3)³ of the row grid's candidates and of the force loop's first pass) for the same pairs
// inside the cutoff. (Where a list at the default skin lasts two checks, rebuilding a thin one at
// every check cost more: liquid_object 1.11x, mixing_liquids 1.19x.) The rate is measured at each
// rebuild the motion calls for, so the default comes back once the liquid slows. A liquid with
// foam keeps the default: its diffuse particles read the list and its grid after the step's motion
// (stepDiffuse), which a thin skin would no longer cover.
constexpr double kFastSkin = 0.05;  // of Fluid::skin
void refreshNeighbours(Fluid& fl, bool force) {
  profile::Scope stage(profile::Stage::Neighbours);
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  ++fl.list_age;
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
    const double moved = std::sqrt(d1) + std::sqrt(d2);
    rebuild = !(moved <= fl.list_skin);
    // (moved/age: how fast the closest-coming pair can close, per check; past the default skin in
    // one check, a list at that skin would be rebuilt at every check too)
    if (rebuild) fl.list_skin = std::isfinite(moved) && moved > fl.skin * static_cast<double>(fl.list_age) && !(fl.foam > 0) ? kFastSkin * fl.skin : fl.skin;
  }
  if (!rebuild) return;
  // (a thin list is rebuilt every step, at least twice as often as one at the default skin: it
  // re-sorts at every 32nd)
  if (fl.rebuilds % (fl.list_skin < fl.skin ? 32 : 16) == 0) sortParticles(fl);
  buildNeighbours(fl);
}

// The pair and viscous forces on particles [i0, i1) whose species meets every species in the
// seed's form (a = 2, b = 4, ε = 0), four entries at a time, in two passes: the first lists the
// entries of the particle's list inside the largest cutoff (a mask, not a branch: half the entries
// of a Verlet list lie in its skin), the second takes their forces, lane k the listed entries k,
// k+4, ... in order, and the lanes are added in a fixed order at the end. Compiled for AVX2 and
// for any x86-64 (core/lanes.h): both give the same bits.
void generalForces(const Fluid& fl, std::size_t i, const Vec3& gravity, Vec3* out);
REEL_CLONED
void seedFormForces(const Fluid& fl, std::ptrdiff_t i0, std::ptrdiff_t i1, const Vec3& gravity, Vec3* out) {
  const Fluid::Packed* P = fl.packed.data();
  const std::int32_t* nb = fl.nbr.data();
  const auto S = static_cast<std::size_t>(fl.species_count);
  const Lane4 zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
  const Lane4 cut_max2 = zero + fl.cutoff_max * fl.cutoff_max;  // the largest cutoff, squared
  thread_local std::vector<std::int32_t> inside;
  for (std::ptrdiff_t ii = i0; ii < i1; ++ii) {
    const auto i = static_cast<std::size_t>(ii);
    const Fluid::Packed& pi = P[i];
    const PairParams* row = &fl.pairs[static_cast<std::size_t>(pi.s) * S];
    const Lane4 xi0 = zero + pi.x[0], xi1 = zero + pi.x[1], xi2 = zero + pi.x[2];
    const Lane4 vi0 = zero + pi.v[0], vi1 = zero + pi.v[1], vi2 = zero + pi.v[2];
    Lane4 cut2 = zero + row[0].cutoff2, mass = zero + row[0].mass_product, al = zero + row[0].alpha, be = zero + row[0].beta;
    Lane4 mu = zero + row[0].visc_mu, icut = zero + row[0].inv_cutoff, cap2 = zero + row[0].cap_r2;
    Mask4 close = {0, 0, 0, 0};
    Lane4 a0 = zero, a1 = zero, a2 = zero;
    // Pass 1: the list's entries inside the largest cutoff (about half: the rest lie in the skin),
    // in the list's order, so that only they pay for the root and the division.
    const std::uint32_t begin = fl.nbr_start[i], end = fl.nbr_start[i + 1];
    if (inside.size() < end - begin + 8) inside.resize(2 * (end - begin) + 8);
    std::int32_t* in_list = inside.data();
    std::size_t m = 0;
    for (std::uint32_t e = begin; e < end; e += 4) {
      // Past the list's end a lane reads the particle itself: distance 0, left out.
      const std::int32_t j0 = nb[e], j1 = e + 1 < end ? nb[e + 1] : static_cast<std::int32_t>(i),
                         j2 = e + 2 < end ? nb[e + 2] : static_cast<std::int32_t>(i),
                         j3 = e + 3 < end ? nb[e + 3] : static_cast<std::int32_t>(i);
      const Fluid::Packed &q0 = P[j0], &q1 = P[j1], &q2 = P[j2], &q3 = P[j3];
      const Lane4 d0 = xi0 - Lane4{q0.x[0], q1.x[0], q2.x[0], q3.x[0]};
      const Lane4 d1 = xi1 - Lane4{q0.x[1], q1.x[1], q2.x[1], q3.x[1]};
      const Lane4 d2 = xi2 - Lane4{q0.x[2], q1.x[2], q2.x[2], q3.x[2]};
      const Lane4 r2 = d0 * d0 + d1 * d1 + d2 * d2;
      const Mask4 in = (r2 < cut_max2) & (r2 > zero);
      const unsigned bits = maskBits(in);
      const Int4 kept = leftPack(Int4{j0, j1, j2, j3}, bits);
      std::memcpy(in_list + m, &kept, sizeof kept);
      m += keptCount(bits);
    }
    for (std::size_t k = 0; k < 3; ++k) in_list[m + k] = static_cast<std::int32_t>(i);
    // Pass 2: their forces, four at a time; a lane past the end reads the particle itself (masked).
    for (std::size_t k = 0; k < m; k += 4) {
      const Fluid::Packed& q0 = P[in_list[k]];
      const Fluid::Packed& q1 = P[in_list[k + 1]];
      const Fluid::Packed& q2 = P[in_list[k + 2]];
      const Fluid::Packed& q3 = P[in_list[k + 3]];
      if (S > 1) {
        const PairParams* p[4] = {&row[q0.s], &row[q1.s], &row[q2.s], &row[q3.s]};
        for (int l = 0; l < 4; ++l) {
          cut2[l] = p[l]->cutoff2, mass[l] = p[l]->mass_product, al[l] = p[l]->alpha, be[l] = p[l]->beta;
          mu[l] = p[l]->visc_mu, icut[l] = p[l]->inv_cutoff, cap2[l] = p[l]->cap_r2;
        }
      }
      const Lane4 d0 = xi0 - Lane4{q0.x[0], q1.x[0], q2.x[0], q3.x[0]};
      const Lane4 d1 = xi1 - Lane4{q0.x[1], q1.x[1], q2.x[1], q3.x[1]};
      const Lane4 d2 = xi2 - Lane4{q0.x[2], q1.x[2], q2.x[2], q3.x[2]};
      const Lane4 r2 = d0 * d0 + d1 * d1 + d2 * d2;
      const Mask4 in = (r2 < cut2) & (r2 > zero);
      const Lane4 safe = in ? r2 : one;
      // The seed's exponents: m_i m_j (−α/r² + β/r⁴) = m_i m_j (β/r² − α)/r², one division;
      // inside the cap, at the cap's distance and scaled to keep the force's magnitude there.
      // A pair inside the repulsion's cap is rare (particles pressed together): it is only noted
      // here, and the particle's forces are then taken again by the general loop, which caps.
      close |= safe < cap2;
      const Lane4 inv = one / safe;
      const Lane4 c = in ? mass * (be * inv - al) * inv : zero;
      Lane4 r = safe;
      for (int l = 0; l < 4; ++l) r[l] = std::sqrt(r[l]);
      const Lane4 w = in ? mu * (one - r * icut) : zero;
      a0 += c * d0 + w * (Lane4{q0.v[0], q1.v[0], q2.v[0], q3.v[0]} - vi0);
      a1 += c * d1 + w * (Lane4{q0.v[1], q1.v[1], q2.v[1], q3.v[1]} - vi1);
      a2 += c * d2 + w * (Lane4{q0.v[2], q1.v[2], q2.v[2], q3.v[2]} - vi2);
    }
    if (close[0] | close[1] | close[2] | close[3])
      generalForces(fl, i, gravity, out);
    else
      out[i] = Vec3(pi.m * gravity.x() + hsum(a0), pi.m * gravity.y() + hsum(a1), pi.m * gravity.z() + hsum(a2));
  }
}

// The same forces for any exponents, one entry at a time.
void generalForces(const Fluid& fl, std::size_t i, const Vec3& gravity, Vec3* out) {
  const Fluid::Packed* P = fl.packed.data();
  const Fluid::Packed& pi = P[i];
  const double mi = pi.m;
  const PairParams* row = &fl.pairs[static_cast<std::size_t>(pi.s) * static_cast<std::size_t>(fl.species_count)];
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
  profile::Scope stage(profile::Stage::PairForces);
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const auto S = static_cast<std::size_t>(fl.species_count);
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
  const auto S = static_cast<std::size_t>(fl.species_count);
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

// Symplectic Euler over h, then adhesion and contacts with the scene's objects (a free body's
// collider is a convex part of the World's contact layer, which meets the particles there).
void moveAndCollide(Fluid& fl, const std::vector<Collider>& colliders, double h) {
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  const auto S = static_cast<std::size_t>(fl.species_count);
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    fl.v[i] += (h / fl.m[i]) * fl.f[i];
    fl.x[i] += h * fl.v[i];
  });
  if (colliders.empty()) return;
  profile::Scope stage(profile::Stage::Contacts);
  parallelFor(n, [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const auto si = static_cast<std::size_t>(fl.s[i]);
    const double range = fl.adhesion_range[si];
    for (std::size_t k = 0; k < colliders.size(); ++k) {
      const Collider& c = colliders[k];
      if (c.shape->free_body) continue;
      const Surface& sf = fl.surfaces[k * S + si];
      const double reach = c.shape->thickness + fl.radius;
      if (!c.near(fl.x[i], fl.radius + (sf.adhesion > 0 ? range : 0.0))) continue;
      if (c.clearOfParts(fl.x[i], reach + (sf.adhesion > 0 ? range : 0.0))) continue;  // deep in a container
      // Each part of the object (a container's floor and walls) on its own: a particle pressed into
      // a corner is kept out of both walls in the same step. A part's distance follows the moves
      // the parts before it made; adhesion pulls toward the nearest part only.
      double dk[ColliderShape::kMaxParts];
      Vec3 nk[ColliderShape::kMaxParts];
      const int parts = c.partDistances(fl.x[i], dk, nk);
      int nearest = 0;
      for (int q = 1; q < parts; ++q) nearest = dk[q] < dk[nearest] ? q : nearest;
      const Vec3 x0 = fl.x[i];
      for (int q = 0; q < parts; ++q) {
        const double d = dk[q] + (fl.x[i] - x0).dot(nk[q]);
        const Vec3& nrm = nk[q];
        if (d >= reach + (sf.adhesion > 0 ? range : 0.0)) continue;
        // Adhesion: an acceleration towards the surface, full in contact, fading to 0 one cutoff away.
        if (sf.adhesion > 0 && q == nearest) fl.v[i] -= (h * sf.adhesion * std::clamp(1.0 - (d - reach) / range, 0.0, 1.0)) * nrm;
        if (d < reach) contactNode(c, sf, reach, d, nrm, h, fl.x[i], fl.v[i]);
      }
    }
  });
}

}  // namespace

void stepFluid(Fluid& fl, const std::vector<Collider>& colliders, const Vec3& gravity, double h,
               double t0, double t1) {
  const bool added = emit(fl, t0, t1);
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  if (n == 0) {
    stepDiffuse(fl, gravity, t1);  // the last specks fly on and die out
    return;
  }
  refreshNeighbours(fl, added);
  fl.x_start = fl.x;
  const bool sph = fl.model == LiquidModel::Dfsph;
  if (sph) dfsphBegin(fl, colliders, h);
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
      if (sph) dfsphBegin(fl, colliders, hk);
      computeForces(fl, gravity);
    }
    if (fl.agitated) addThermalForces(fl, hk);
    if (sph) dfsphPressure(fl, hk);
    moveAndCollide(fl, colliders, hk);
  }
  stepDiffuse(fl, gravity, t1);
}

void removeParticles(Fluid& fl, const std::vector<std::uint8_t>& gone) {
  const std::size_t n = fl.x.size();
  // New ids: each particle's rank in order of creation among those left.
  std::vector<std::int32_t> rank(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (!gone[i]) rank[static_cast<std::size_t>(fl.id[i])] = 1;
  std::int32_t next = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t keep = rank[k];
    rank[k] = next;
    next += keep;
  }
  std::size_t w = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (gone[i]) continue;
    fl.x[w] = fl.x[i];
    fl.v[w] = fl.v[i];
    fl.s[w] = fl.s[i];
    fl.m[w] = fl.m[i];
    fl.id[w] = rank[static_cast<std::size_t>(fl.id[i])];
    ++w;
  }
  if (w == n) return;
  for (auto* a : {&fl.x, &fl.v}) a->resize(w);
  fl.s.resize(w);
  fl.m.resize(w);
  fl.id.resize(w);
  if (w == 0) {
    fl.x_built.clear();
    fl.nbr_start.clear();
    fl.nbr.clear();
    return;
  }
  buildNeighbours(fl);
}

void addParticle(Fluid& fl, const Vec3& x, const Vec3& v, int species) {
  fl.id.push_back(static_cast<std::int32_t>(fl.id.size()));
  fl.x.push_back(x);
  fl.v.push_back(v);
  fl.s.push_back(species);
  fl.m.push_back(fl.species_mass[static_cast<std::size_t>(species)]);
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

}  // namespace reel
