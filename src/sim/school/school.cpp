#include "sim/school/school.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <span>
#include <cmath>
#include <cstring>
#include <numbers>

#include <Eigen/Geometry>

#include "core/lanes.h"
#include "core/parallel.h"
#include "core/random.h"
#include "sim/grid.h"

namespace reel {
namespace {

constexpr std::uint64_t kStartStream = 0x5C0, kNoiseStream = 0x5C1;

// ---- Couzin, Krause, James, Ruxton & Franks, "Collective memory and spatial sorting in animal
// groups", J. Theor. Biol. 218:1–11 (2002). Agent i sees neighbours outside the blind cone behind
// it (the perception angle α is the field of view). Neighbours closer than r_r repel, and take
// priority: d_r = −Σ r̂_ij. Otherwise agents within [r_r, r_o) align, d_o = Σ v̂_j including the
// focal agent's own v̂_i, and agents within [r_o, r_a) attract, d_a = Σ r̂_ij. With both,
// d = ½(d̂_o + d̂_a) (each made unit first, so that neither zone wins by its count); with
// either alone, that one; with none, or a zero sum, the agent keeps its heading.
struct Perception {
  double rr2, ro2, ra2, cos_half;
  Perception(const CouzinDesc& c, double fov_deg)
      : rr2(c.r_repulsion * c.r_repulsion), ro2(c.r_orientation * c.r_orientation),
        ra2(c.r_attraction * c.r_attraction), cos_half(std::cos(fov_deg * kPi / 360.0)) {}
};

struct ZoneSums {
  Vec3 dr{0, 0, 0}, d_o{0, 0, 0}, da{0, 0, 0};
  int nr = 0, no = 0, na = 0;
  Vec3 direction(const Vec3& ui) const {
    Vec3 d = ui;
    if (nr > 0) d = dr;
    else if (no > 0 && na > 0) d = 0.5 * (unitOr(d_o + ui, ui) + unitOr(da, ui));
    else if (no > 0) d = d_o + ui;
    else if (na > 0) d = da;
    return unitOr(d, ui);
  }
};

// A run [begin, end) of sorted agents to scan.
using Range32 = RowGrid::Run;

// Sorted agents: positions (a RowGrid's copies) and headings, coordinate by coordinate.
struct SortedView {
  const double *x, *y, *z, *ux, *uy, *uz;
};

// Four consecutive doubles (an out-parameter: a vector returned by value would change the ABI
// between the clones).
[[gnu::always_inline]] inline void load4(const double* p, Lane4& v) { std::memcpy(&v, p, sizeof v); }

// The zone sums of the agent at xi heading ui over the sorted agents of `ranges` (skipping entry
// `self`), four candidates at a time (core/lanes.h: the same bits with or without AVX), in two
// passes: the first lists the candidates the agent perceives (within r_a, outside the blind
// cone: about a quarter of them), the second sums their zones, so that only those pay for the
// root and the division of r̂. The blind cone test r·u ≥ cos(α/2)|r| is made without a root: for
// α > 180° it holds when r·u ≥ 0 or (r·u)² ≤ cos²(α/2)|r|², for α ≤ 180° when r·u ≥ 0 and
// (r·u)² ≥ cos²(α/2)|r|².
// Inlined into the AVX2 clone of its caller (couzinRows).
[[gnu::always_inline]] inline ZoneSums couzinZones(const SortedView& s, std::span<const Range32> ranges,
                                                   std::uint32_t self, const Vec3& xi, const Vec3& ui,
                                                   const Perception& p) {
  const Lane4 zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
  const Lane4 x0 = zero + xi.x(), x1 = zero + xi.y(), x2 = zero + xi.z();
  const Lane4 u0 = zero + ui.x(), u1 = zero + ui.y(), u2 = zero + ui.z();
  const Lane4 rr2 = zero + p.rr2, ro2 = zero + p.ro2, ra2 = zero + p.ra2, c2 = zero + p.cos_half * p.cos_half;
  // All round (360°): everyone is seen, whatever the rounding of the squared test.
  const Mask4 wide = Mask4{0, 0, 0, 0} + (p.cos_half < 0 ? -1ll : 0ll), step = {0, 1, 2, 3};
  const Mask4 all_round = Mask4{0, 0, 0, 0} + (p.cos_half <= -1.0 ? -1ll : 0ll);
  // Pass 1: the perceived entries, in the order of the runs.
  thread_local std::vector<std::uint32_t> seen;
  std::size_t total = 4;
  for (const Range32& rg : ranges) total += rg[1] - rg[0] + 3;
  if (seen.size() < total) seen.resize(total);
  std::uint32_t* list = seen.data();
  std::size_t m = 0;
  for (const Range32& rg : ranges)
    for (std::uint32_t k = rg[0]; k < rg[1]; k += 4) {
      const Mask4 idx = step + static_cast<long long>(k);
      const Mask4 live = (idx < static_cast<long long>(rg[1])) & (idx != static_cast<long long>(self));
      Lane4 d0, d1, d2;
      load4(s.x + k, d0), load4(s.y + k, d1), load4(s.z + k, d2);
      d0 -= x0, d1 -= x1, d2 -= x2;
      const Lane4 r2 = d0 * d0 + d1 * d1 + d2 * d2, dot = d0 * u0 + d1 * u1 + d2 * u2;
      const Mask4 ahead = dot >= zero, wide_ok = ahead | (dot * dot <= c2 * r2), narrow_ok = ahead & (dot * dot >= c2 * r2);
      const Mask4 in = live & (r2 < ra2) & (r2 > zero) & (all_round | (wide ? wide_ok : narrow_ok));
      for (int l = 0; l < 4; ++l) list[m] = k + static_cast<std::uint32_t>(l), m -= static_cast<std::size_t>(in[l]);
    }
  for (std::size_t l = 0; l < 3; ++l) list[m + l] = list[0];  // (a whole group of four to read)
  // Pass 2: the zones of the perceived.
  Lane4 r0s = zero, r1s = zero, r2s = zero, o0s = zero, o1s = zero, o2s = zero, a0s = zero, a1s = zero, a2s = zero;
  Lane4 nr = zero, no = zero, na = zero;
  for (std::size_t k = 0; k < m; k += 4) {
    const std::uint32_t* e = list + k;
    const Mask4 live = (step + static_cast<long long>(k)) < static_cast<long long>(m);
    const Lane4 d0 = Lane4{s.x[e[0]], s.x[e[1]], s.x[e[2]], s.x[e[3]]} - x0;
    const Lane4 d1 = Lane4{s.y[e[0]], s.y[e[1]], s.y[e[2]], s.y[e[3]]} - x1;
    const Lane4 d2 = Lane4{s.z[e[0]], s.z[e[1]], s.z[e[2]], s.z[e[3]]} - x2;
    const Lane4 r2 = d0 * d0 + d1 * d1 + d2 * d2;
    const Mask4 rep = live & (r2 < rr2), ori = live & ~rep & (r2 < ro2), att = live & ~rep & ~ori;
    Lane4 len = live ? r2 : one;
    for (int l = 0; l < 4; ++l) len[l] = std::sqrt(len[l]);
    const Lane4 inv = one / len;
    const Lane4 wr = rep ? inv : zero, wa = att ? inv : zero;
    r0s -= wr * d0, r1s -= wr * d1, r2s -= wr * d2;
    a0s += wa * d0, a1s += wa * d1, a2s += wa * d2;
    o0s += ori ? Lane4{s.ux[e[0]], s.ux[e[1]], s.ux[e[2]], s.ux[e[3]]} : zero;
    o1s += ori ? Lane4{s.uy[e[0]], s.uy[e[1]], s.uy[e[2]], s.uy[e[3]]} : zero;
    o2s += ori ? Lane4{s.uz[e[0]], s.uz[e[1]], s.uz[e[2]], s.uz[e[3]]} : zero;
    nr += rep ? one : zero, no += ori ? one : zero, na += att ? one : zero;
  }
  ZoneSums z;
  z.dr = Vec3(hsum(r0s), hsum(r1s), hsum(r2s));
  z.d_o = Vec3(hsum(o0s), hsum(o1s), hsum(o2s));
  z.da = Vec3(hsum(a0s), hsum(a1s), hsum(a2s));
  z.nr = static_cast<int>(hsum(nr)), z.no = static_cast<int>(hsum(no)), z.na = static_cast<int>(hsum(na));
  return z;
}

// The noise of the model: d turned by a Gaussian angle of s.d. σ about a random axis
// perpendicular to it (a spherically wrapped Gaussian), from the decision's stream.
Vec3 wrappedGaussian(const Vec3& d, double sigma, std::uint64_t seed, std::int64_t decision, std::size_t i) {
  if (sigma <= 0) return d;
  const auto st = kNoiseStream ^ (static_cast<std::uint64_t>(decision) << 12);
  const double u1 = uniformAt(seed, st, 3 * i), u2 = uniformAt(seed, st, 3 * i + 1), u3 = uniformAt(seed, st, 3 * i + 2);
  const double g = std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2 * kPi * u2);
  const Vec3 e1 = perpendicular(d), e2 = d.cross(e1);
  const Vec3 k = std::cos(2 * kPi * u3) * e1 + std::sin(2 * kPi * u3) * e2;
  const double a = sigma * g;
  return (d * std::cos(a) + k.cross(d) * std::sin(a)).normalized();
}

}  // namespace

// ---- Steering both models share (and the artificial fish): what the surroundings ask of an
// agent this moment.

namespace {

// Reynolds (1999), "containment" and "obstacle avoidance": probes at the agent and ahead of it
// along its heading; a surface nearer a probe than the margin pushes along its normal, more
// urgently the nearer it is and the sooner the agent gets there. `distance(probe, d, n)` gives
// the surface's signed distance and outward normal (false: none near).
template <class Distance>
void avoidSurface(const Vec3& x, const Vec3& ahead, double m, Steering& s, Distance&& distance) {
  double best = 0.0;
  Vec3 bn{0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const double f = 0.5 * k;  // probes at 0, ½ and 1 of the look-ahead
    double dist;
    Vec3 n{0, 0, 0};
    if (!distance(x + f * ahead, dist, n)) continue;
    const double urgency = std::clamp(1.0 - dist / m, 0.0, 1.0) * (1.0 - 0.4 * f);
    if (urgency > best) best = urgency, bn = n;
  }
  s.push += best * bn;
  s.avoid = std::max(s.avoid, best);
}

}  // namespace

void avoidObstacles(const std::vector<Collider>& cs, const Vec3& x, const Vec3& ahead, double m, Steering& s) {
  for (const Collider& c : cs)
    avoidSurface(x, ahead, m, s, [&](const Vec3& p, double& d, Vec3& n) { return c.distance(p, d, n); });
}

// Other bodies (a sheet, a rope, a liquid, fish) as their points: the nearest point's surface
// (its contact radius) within the margin of a probe, its normal away from that point.
void avoidPoints(const BodyPoints& b, const Vec3& x, const Vec3& ahead, double m, Steering& s) {
  avoidSurface(x, ahead, m, s, [&](const Vec3& probe, double& d, Vec3& n) {
    d = m;
    b.grid.forEachNear(probe, [&](int j) {
      const Vec3 r = probe - b.x[static_cast<std::size_t>(j)];
      const double len = r.norm();
      const double dist = len - b.r[static_cast<std::size_t>(j)];
      if (dist < d && len > 1e-12) d = dist, n = r / len;
    });
    return d < m;
  });
}

void containBounds(const SchoolBoundsDesc& b, const Vec3& p, Steering& s) {
  auto wall = [&](double depth, const Vec3& inward) {  // depth: how far into the margin, m
    const double urgency = std::clamp(depth / b.margin, 0.0, 1.0);
    s.push += urgency * inward;
    s.avoid = std::max(s.avoid, urgency);
  };
  if (b.sphere) {
    const Vec3 r = p - b.center;
    const double dist = r.norm();
    if (dist > 1e-12) wall(dist - (b.radius - b.margin), -r / dist);
    return;
  }
  for (int k = 0; k < 3; ++k) {
    wall(p[k] - (b.max[k] - b.margin), -Vec3::Unit(k));
    wall((b.min[k] + b.margin) - p[k], Vec3::Unit(k));
  }
}

namespace {

// Flight: away from the nearest predator point inside the fear radius, more urgently the nearer
// it is, and mostly sideways from its path (the "fountain" escape of fish schools, Pitcher &
// Parrish 1993): the part of r along the predator's heading is kept at a third.
void fleePredator(const SchoolDesc& d, const SchoolView& pv, const Vec3& x, Steering& s) {
  const double fr = d.predator->fear_radius;
  double best = fr;
  Vec3 heading{0, 0, 0};
  if (pv.points) {
    for (std::size_t k = 0; k < pv.points->size(); ++k) {
      const Vec3 r = x - (*pv.points)[k];
      const double dist = r.norm();
      if (dist < best && dist > 1e-12) best = dist, s.away = r / dist, heading = (*pv.velocities)[k];
    }
  } else if (pv.object) {
    double dist;
    Vec3 n;
    if (pv.object->distance(x, dist, n) && dist < best) best = std::max(dist, 0.0), s.away = n, heading = pv.object->velocityAt(x);
  }
  if (best >= fr) return;
  s.fear = 1.0 - best / fr;
  const Vec3 h = unitOr(heading, Vec3::Zero());
  s.away = unitOr(s.away - (2.0 / 3.0) * s.away.dot(h) * h, s.away);
}

Steering steering(const School& sc, const std::vector<Collider>& cs, const SchoolView& pv, std::size_t i,
                  double t) {
  const SchoolDesc& d = sc.desc;
  Steering s;
  const double speed = sc.v[i].norm();
  const Vec3 u = sc.v[i] / speed;
  avoidObstacles(cs, sc.x[i], speed * d.look_ahead * u, d.avoid_margin, s);
  if (pv.bodies) avoidPoints(*pv.bodies, sc.x[i], speed * d.look_ahead * u, d.avoid_margin, s);
  if (d.bounds) containBounds(*d.bounds, sc.x[i] + 0.5 * speed * d.look_ahead * u, s);
  if (d.predator) fleePredator(d, pv, sc.x[i], s);
  if (d.goal && sc.informed[i]) s.goal = unitOr(d.goal->target.at(t) - sc.x[i], Vec3::Zero());
  return s;
}

// A desired direction d under the steering, in priority order: the goal (Couzin, Krause, Franks &
// Levin, Nature 433:513–516, 2005: d' = (d + ω ĝ)/|d + ω ĝ|), then flight from a predator, then
// walls and obstacles (no component into them, and a push out along their normals).
Vec3 steerDirection(const SchoolDesc& d, const Steering& s, Vec3 dir) {
  if (d.goal) dir = unitOr(dir + d.goal->weight * s.goal, dir);
  if (s.fear > 0) dir = unitOr((1 - s.fear) * dir + 3 * s.fear * s.away, dir);
  if (s.avoid > 0) {
    const Vec3 n = unitOr(s.push, Vec3::Zero());
    const double into = dir.dot(n);
    if (into < 0) dir -= std::min(1.0, 2 * s.avoid) * into * n;
    dir = unitOr(dir + 2 * s.avoid * n, dir);
  }
  return dir;
}

// ---- The neighbour pass: the agents sorted into a RowGrid at the perception radius (rows of the
// y–z plane, each by x), their headings copied in that order, and the rows visited in parallel,
// each agent with the runs of sorted agents around it.
SortedView sortAgents(School& sc, double r, bool unit_headings) {
  const std::size_t n = sc.size();
  sc.rows.build(sc.x, r);
  const std::span<const std::int32_t> order = sc.rows.order();
  SortedHeadings& s = sc.sorted;
  for (auto* a : {&s.ux, &s.uy, &s.uz}) a->resize(n + 4);
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t e) {
    const auto i = static_cast<std::size_t>(order[static_cast<std::size_t>(e)]);
    const Vec3 u = unit_headings ? Vec3(sc.v[i].normalized()) : sc.v[i];
    s.ux[e] = u.x(), s.uy[e] = u.y(), s.uz[e] = u.z();
  });
  for (std::size_t e = n; e < n + 4; ++e) s.ux[e] = s.uy[e] = s.uz[e] = 0.0;
  return {sc.rows.x(), sc.rows.y(), sc.rows.z(), s.ux.data(), s.uy.data(), s.uz.data()};
}

// Boids: decide(i, e, ranges, sorted) for agent i, its sorted entry e, the runs of sorted entries
// around it and the sorted agents.
template <class F>
void forEachAgent(School& sc, double r, bool unit_headings, F&& decide) {
  const SortedView so = sortAgents(sc, r, unit_headings);
  const std::span<const std::int32_t> order = sc.rows.order();
  parallelBlocks(static_cast<std::ptrdiff_t>(sc.rows.rows()), 16, [&](std::ptrdiff_t r0, std::ptrdiff_t r1) {
    sc.rows.visitRows(r0, r1, [&](std::uint32_t e, std::span<const Range32> runs) {
      decide(static_cast<std::size_t>(order[e]), e, runs, so);
    });
  }, static_cast<std::ptrdiff_t>(sc.size()));
}

// The social direction of every agent of rows [r0, r1) into sc.social, one function compiled for
// AVX-512 and AVX2 where the CPU has them (core/lanes.h), the row walk and the zone sums inlined
// into it.
REEL_CLONED_WIDE
void couzinRows(School& sc, const SortedView& so, const Perception& p, std::int64_t r0, std::int64_t r1) {
  const std::span<const std::int32_t> order = sc.rows.order();
  sc.rows.visitRows(r0, r1, [&](std::uint32_t e, std::span<const Range32> runs) __attribute__((always_inline)) {
    const auto i = static_cast<std::size_t>(order[e]);
    const Vec3 xi(so.x[e], so.y[e], so.z[e]), ui(so.ux[e], so.uy[e], so.uz[e]);  // (sorted: in cache)
    sc.social[i] = couzinZones(so, runs, e, xi, ui, p).direction(ui);
  });
}

void couzinDecide(School& sc, const std::vector<Collider>& cs, const SchoolView& pv, double t) {
  const SchoolDesc& d = sc.desc;
  CouzinDesc now = d.couzin;
  now.r_orientation = d.couzin.orientationAt(t);
  const Perception p(now, d.field_of_view_deg);
  const SortedView so = sortAgents(sc, d.couzin.r_attraction, true);
  sc.social.resize(sc.size());
  parallelBlocks(static_cast<std::ptrdiff_t>(sc.rows.rows()), 16, [&](std::ptrdiff_t r0, std::ptrdiff_t r1) {
    couzinRows(sc, so, p, r0, r1);
  }, static_cast<std::ptrdiff_t>(sc.size()));
  parallelFor(static_cast<std::ptrdiff_t>(sc.size()), [&](std::ptrdiff_t i) {
    const Steering s = steering(sc, cs, pv, static_cast<std::size_t>(i), t);
    const Vec3 dir = steerDirection(d, s, sc.social[i]);
    sc.desired[i] = wrappedGaussian(dir, d.couzin.noise, sc.seed, sc.decisions, static_cast<std::size_t>(i));
    // Avoiding a wall or fleeing may turn faster than the social turning rate (up to 4θ).
    sc.turn[i] = 1.0 + 3.0 * std::max(s.avoid, s.fear);
  });
  ++sc.decisions;
}

// ---- Reynolds, "Flocks, herds, and schools: a distributed behavioral model", SIGGRAPH '87, and
// "Steering behaviors for autonomous characters", GDC '99. Each behaviour asks for an
// acceleration; the budget max_accel is spent in priority order (avoidance first), each request
// taken whole while it fits and the last one cut to what is left ("prioritized acceleration
// allocation", 1987).
struct Budget {
  Vec3 total{0, 0, 0};
  double left;
  explicit Budget(double a) : left(a) {}
  void ask(const Vec3& a) {
    const double m = a.norm();
    if (left <= 0 || m == 0) return;
    total += m <= left ? a : Vec3(a * (left / m));
    left -= std::min(m, left);
  }
};

void boidsDecide(School& sc, const std::vector<Collider>& cs, const SchoolView& pv, double t) {
  const SchoolDesc& d = sc.desc;
  const BoidsDesc& b = d.boids;
  const double cos_half = std::cos(d.field_of_view_deg * kPi / 360.0);
  const double rs2 = b.separation_radius * b.separation_radius, ra2 = b.alignment_radius * b.alignment_radius,
               rc2 = b.cohesion_radius * b.cohesion_radius, r2max = std::max({rs2, ra2, rc2});
  sc.steer.resize(sc.size());
  forEachAgent(sc, d.interactionRadius(), false,
               [&](std::size_t i, std::uint32_t e, std::span<const Range32> ranges, const SortedView& so) {
    const Vec3 xi = sc.x[i], vi = sc.v[i], ui = vi.normalized();
    Vec3 sep{0, 0, 0}, vel{0, 0, 0}, cen{0, 0, 0};
    int na = 0, nc = 0;
    for (const Range32& rg : ranges)
      for (std::uint32_t k = rg[0]; k < rg[1]; ++k) {
        if (k == e) continue;
        const Vec3 xj(so.x[k], so.y[k], so.z[k]), r = xj - xi;
        const double d2 = r.squaredNorm();
        if (d2 == 0.0 || d2 >= r2max) continue;
        const double dist = std::sqrt(d2);
        if (r.dot(ui) < cos_half * dist) continue;  // behind, unseen
        if (d2 < rs2) sep -= r / dist * (1.0 - dist / b.separation_radius);
        if (d2 < ra2) vel += Vec3(so.ux[k], so.uy[k], so.uz[k]), ++na;
        if (d2 < rc2) cen += xj, ++nc;
      }
    const Steering s = steering(sc, cs, pv, i, t);
    const double vmax = b.max_speed, amax = b.max_accel;
    Budget budget(amax);
    if (s.avoid > 0) budget.ask(amax * s.avoid * unitOr(steerDirection(d, s, ui) * vmax - vi, Vec3::Zero()));
    if (s.fear > 0) budget.ask(amax * s.fear * unitOr(s.away * vmax - vi, Vec3::Zero()));
    budget.ask(b.separation_weight * vmax * sep);
    if (na > 0) budget.ask(b.alignment_weight * (vel / na - vi));
    if (nc > 0) budget.ask(b.cohesion_weight * (unitOr(cen / nc - xi, ui) * vmax - vi));
    if (d.goal && sc.informed[i]) budget.ask(d.goal->weight * (s.goal * vmax - vi));
    sc.steer[i] = budget.total;
  });
}

// Nothing ends a step inside an object: an agent that the steering did not keep out is put back
// on the surface plus its half-thickness, its velocity along the surface.
void keepOut(const std::vector<Collider>& cs, double clearance, Vec3& x, Vec3& v) {
  for (const Collider& c : cs) {
    double dist;
    Vec3 n;
    if (!c.distance(x, dist, n) || dist >= clearance) continue;
    x += (clearance - dist) * n;
    const double vn = v.dot(n);
    if (vn < 0) {
      const double speed = v.norm();
      v = unitOr(v - vn * n, perpendicular(n)) * speed;
    }
  }
}

}  // namespace

Vec3 couzinDirection(const CouzinDesc& c, double field_of_view_deg, const Vec3& xi, const Vec3& vi,
                     const std::vector<Vec3>& nx, const std::vector<Vec3>& nv) {
  std::vector<double> a[6];
  for (auto& v : a) v.assign(nx.size() + 4, 0.0);
  for (std::size_t j = 0; j < nx.size(); ++j) {
    const Vec3 u = nv[j].normalized();
    for (int k = 0; k < 3; ++k) a[k][j] = nx[j][k], a[3 + k][j] = u[k];
  }
  const SortedView s{a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data()};
  const Range32 all{0, static_cast<std::uint32_t>(nx.size())};
  const Vec3 ui = vi.normalized();
  return couzinZones(s, {&all, 1}, UINT32_MAX, xi, ui, Perception(c, field_of_view_deg)).direction(ui);
}

Vec3 turnToward(const Vec3& from, const Vec3& to, double max_angle) {
  if (max_angle >= kPi) return to;  // any turn is within reach
  return turnToward(from, to, std::cos(max_angle), std::sin(max_angle));
}

Vec3 turnToward(const Vec3& from, const Vec3& to, double cos_max, double sin_max) {
  if (from.dot(to) >= cos_max) return to;  // within reach: taken whole
  Vec3 k = from.cross(to);
  const double kn = k.norm();
  k = kn > 1e-12 ? Vec3(k / kn) : perpendicular(from);
  return (from * cos_max + k.cross(from) * sin_max).normalized();
}

School makeSchool(const SchoolDesc& d, const std::string& name, std::uint64_t seed) {
  School s;
  s.name = name;
  s.desc = d;
  s.seed = seed;
  const std::size_t n = d.agentCount();
  s.x.resize(n);
  s.v.resize(n);
  s.speed.resize(n);
  s.informed.resize(n);
  s.tint.resize(3 * n);
  auto u = [&](std::size_t i, int k) { return uniformAt(seed, kStartStream, 16 * i + static_cast<std::size_t>(k)); };
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 heading;
    double speed = d.speed;
    if (!d.agents.empty()) {
      const SchoolAgentDesc& a = d.agents[i];
      s.x[i] = a.position;
      heading = a.heading ? *a.heading : sphereDirection(u(i, 3), u(i, 4));
      if (a.speed) speed = *a.speed;
    } else {
      s.x[i] = d.start.point(u(i, 0), u(i, 1), u(i, 2));
      heading = d.start.heading ? *d.start.heading : sphereDirection(u(i, 3), u(i, 4));
    }
    if (d.model == SchoolModel::Boids) speed = std::clamp(speed, d.boids.min_speed, d.boids.max_speed);
    s.speed[i] = speed;
    s.v[i] = heading * speed;
    s.informed[i] = d.goal && u(i, 5) < d.goal->informed;
    // A tint: brightness and a little hue, around 1.
    const double b = 1.0 + d.color_variation * (2 * u(i, 6) - 1), hue = 0.5 * d.color_variation * (2 * u(i, 7) - 1);
    s.tint[3 * i] = static_cast<float>(b * (1 + hue));
    s.tint[3 * i + 1] = static_cast<float>(b);
    s.tint[3 * i + 2] = static_cast<float>(b * (1 - hue));
  }
  s.desired.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.desired[i] = s.v[i].normalized();
  s.turn.assign(n, 1.0);
  s.phase.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.phase[i] = 2 * kPi * u(i, 8);
  return s;
}

void stepSchool(School& sc, const std::vector<Collider>& cs, const SchoolView& pv, double t0, double h) {
  const SchoolDesc& d = sc.desc;
  const auto n = static_cast<std::ptrdiff_t>(sc.size());
  if (n == 0) return;
  if (d.model == SchoolModel::Couzin) {
    // The model decides at t = kτ (every step when the step is τ or longer), then turns toward its
    // decision at θ per second, so that a step of exactly τ is the paper's discrete model.
    const double tau = d.couzin.reaction_time;
    if (h >= tau * (1 - 1e-9) || t0 >= static_cast<double>(sc.decisions) * tau - 1e-9 * tau) {
      couzinDecide(sc, cs, pv, t0);
      if (h < tau) sc.decisions = std::max(sc.decisions, static_cast<std::int64_t>(std::floor(t0 / tau + 1e-9)) + 1);
    }
    const double theta = d.couzin.max_turn_deg_per_s * kPi / 180.0, a1 = std::min(theta * h, kPi);
    const double c1 = std::cos(a1), s1 = std::sin(a1);
    parallelFor(n, [&](std::ptrdiff_t i) {
      const Vec3 from = sc.v[i].normalized();
      const Vec3 u = sc.turn[i] == 1.0 ? turnToward(from, sc.desired[i], c1, s1)
                                       : turnToward(from, sc.desired[i], theta * sc.turn[i] * h);
      sc.v[i] = u * sc.speed[i];
    });
  } else {
    boidsDecide(sc, cs, pv, t0);
    const BoidsDesc& b = d.boids;
    parallelFor(n, [&](std::ptrdiff_t i) {
      const Vec3 v = sc.v[i] + h * sc.steer[i];
      const double s = v.norm();
      sc.v[i] = unitOr(v, sc.v[i].normalized()) * std::clamp(s, b.min_speed, b.max_speed);
    });
  }
  // Swim; the tail beats once per 0.7 body lengths travelled (Bainbridge, J. Exp. Biol. 35, 1958:
  // a fish advances about 0.6–0.8 of its length per tail beat), at least once a second.
  const double stride = 0.7 * d.length, clearance = 0.1 * d.length;
  parallelFor(n, [&](std::ptrdiff_t i) {
    sc.x[i] += h * sc.v[i];
    if (!cs.empty()) keepOut(cs, clearance, sc.x[i], sc.v[i]);
    const double f = std::max(1.0, sc.v[i].norm() / stride);
    const double ph = sc.phase[i] + 2 * kPi * f * h;
    sc.phase[i] = ph < 2 * kPi ? ph : std::fmod(ph, 2 * kPi);  // (fmod of a smaller one: itself)
  });
}

SchoolOrder schoolOrder(const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
  SchoolOrder o;
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  if (n == 0) return o;
  const double inv = 1.0 / static_cast<double>(n);
  const auto c = deterministicSums<3>(n, [&](std::ptrdiff_t i) { return std::array<double, 3>{x[i].x(), x[i].y(), x[i].z()}; });
  o.centroid = Vec3(c[0], c[1], c[2]) * inv;
  const auto s = deterministicSums<6>(n, [&](std::ptrdiff_t i) {
    const Vec3 u = unitOr(v[i], Vec3::Zero()), r = unitOr(x[i] - o.centroid, Vec3::Zero()), m = r.cross(u);
    return std::array<double, 6>{u.x(), u.y(), u.z(), m.x(), m.y(), m.z()};
  });
  o.polarization = Vec3(s[0], s[1], s[2]).norm() * inv;
  o.milling = Vec3(s[3], s[4], s[5]).norm() * inv;
  if (n < 2) return o;
  // Nearest neighbours from a grid whose cell is about the mean spacing; an agent with nothing in
  // the 27 cells around it (or nothing nearer than a cell) is searched over all.
  Vec3 lo = x[0], hi = x[0];
  for (const Vec3& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double cell = std::max(1e-6, 2.0 * (hi - lo).maxCoeff() / std::cbrt(static_cast<double>(n)));
  BoxGrid g;
  g.build(x, x, cell);
  o.nearest = deterministicSum(n, [&](std::ptrdiff_t i) {
    double best = INFINITY;
    g.forEachNear(x[i], [&](std::int32_t j) {
      if (j != i) best = std::min(best, (x[j] - x[i]).squaredNorm());
    });
    if (!(best <= cell * cell))
      for (std::ptrdiff_t j = 0; j < n; ++j)
        if (j != i) best = std::min(best, (x[j] - x[i]).squaredNorm());
    return std::sqrt(best);
  }) * inv;
  return o;
}

}  // namespace reel
