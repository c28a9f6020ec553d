#include "sim/cloth/cloth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/random.h"
#include "sim/geometry.h"
#include "core/union_find.h"

namespace reel {

using Index = std::ptrdiff_t;

// --- building -------------------------------------------------------------------------------
namespace {

// The ids of a sheet's structural springs (horizontal, vertical) and of its cells' diagonals.
struct SheetSprings {
  std::vector<int> sh, sv, d1, d2;
};

// Nodes on the local x–z plane, centred on `position`; masses lumped by the area they stand for.
void clothNodes(const ClothDesc& d, Cloth& c, MassSpringDesc& out) {
  const int nx = d.resolution[0], ny = d.resolution[1];
  const Mat3 R = rotationFromEulerDeg(d.rotation_deg);
  const double cells = static_cast<double>(nx - 1) * (ny - 1);
  c.uv.reserve(2 * static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double fu = static_cast<double>(i) / (nx - 1), fv = static_cast<double>(j) / (ny - 1);
      const Vec3 local(d.size[0] * (fu - 0.5), 0.0, d.size[1] * (fv - 0.5));
      const double wi = (i == 0 || i == nx - 1) ? 0.5 : 1.0, wj = (j == 0 || j == ny - 1) ? 0.5 : 1.0;
      NodeDesc n;
      n.position = d.position + R * local;
      n.velocity = d.velocity;
      n.mass = d.mass * wi * wj / cells;
      n.damping = d.node_damping * wi * wj;
      out.nodes.push_back(n);
      c.uv.push_back(static_cast<float>(fu * d.uv_scale[0]));
      c.uv.push_back(static_cast<float>(fv * d.uv_scale[1]));
    }
  for (int p : d.pinned) out.nodes[static_cast<std::size_t>(p)].fixed = true;
  for (const GripDesc& g : d.grips)
    for (int p : g.nodes) {
      out.nodes[static_cast<std::size_t>(p)].fixed = true;
      c.grip_origin.push_back(out.nodes[static_cast<std::size_t>(p)].position);
    }
  c.grips = d.grips;

}

// Springs: structural (horizontal, then vertical), shear (two diagonals per cell), bend; and the
// threads each shear and bend spring needs.
SheetSprings clothSprings(const ClothDesc& d, Cloth& c, MassSpringDesc& out) {
  const int nx = d.resolution[0], ny = d.resolution[1];
  auto id = [nx](int i, int j) { return j * nx + i; };
  auto add = [&](int a, int b, const SpringParams& p, bool limited) {
    out.springs.push_back({a, b, p.stiffness, p.damping, -1.0});
    c.limited.push_back(limited ? 1 : 0);
    return static_cast<int>(out.springs.size() - 1);
  };
  SheetSprings ids;
  std::vector<int>& sh = ids.sh;
  std::vector<int>& sv = ids.sv;
  std::vector<int>& d1 = ids.d1;
  std::vector<int>& d2 = ids.d2;
  sh.assign(static_cast<std::size_t>((nx - 1) * ny), 0);
  sv.assign(static_cast<std::size_t>(nx * (ny - 1)), 0);
  d1.assign(static_cast<std::size_t>((nx - 1) * (ny - 1)), 0);
  d2.assign(d1.size(), 0);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) sh[static_cast<std::size_t>(j * (nx - 1) + i)] = add(id(i, j), id(i + 1, j), d.structural, true);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i < nx; ++i) sv[static_cast<std::size_t>(j * nx + i)] = add(id(i, j), id(i, j + 1), d.structural, true);
  c.structural = static_cast<int>(out.springs.size());
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const auto cell = static_cast<std::size_t>(j * (nx - 1) + i);
      d1[cell] = add(id(i, j), id(i + 1, j + 1), d.shear, true);
      d2[cell] = add(id(i + 1, j), id(i, j + 1), d.shear, true);
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i + 2 < nx; ++i) add(id(i, j), id(i + 2, j), d.bend, false);
  for (int j = 0; j + 2 < ny; ++j)
    for (int i = 0; i < nx; ++i) add(id(i, j), id(i, j + 2), d.bend, false);
  const std::size_t ns = out.springs.size();
  // The threads each shear and bend spring needs, in the order the springs were added.
  c.holds.assign(ns, {-1, -1, -1, -1});
  {
    std::size_t k = static_cast<std::size_t>(c.structural);
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const std::array<int, 4> cell = {sh[static_cast<std::size_t>(j * (nx - 1) + i)], sh[static_cast<std::size_t>((j + 1) * (nx - 1) + i)],
                                         sv[static_cast<std::size_t>(j * nx + i)], sv[static_cast<std::size_t>(j * nx + i + 1)]};
        c.holds[k++] = cell;
        c.holds[k++] = cell;
      }
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i + 2 < nx; ++i)
        c.holds[k++] = {sh[static_cast<std::size_t>(j * (nx - 1) + i)], sh[static_cast<std::size_t>(j * (nx - 1) + i + 1)], -1, -1};
    for (int j = 0; j + 2 < ny; ++j)
      for (int i = 0; i < nx; ++i)
        c.holds[k++] = {sv[static_cast<std::size_t>(j * nx + i)], sv[static_cast<std::size_t>((j + 1) * nx + i)], -1, -1};
  }
  c.spring_id.resize(ns);
  std::iota(c.spring_id.begin(), c.spring_id.end(), 0);
  c.intact.assign(ns, 1);

  return ids;
}

// Two triangles per cell, the diagonal alternating like a checkerboard (no preferred fold
// direction); counter-clockwise seen from local +y. Edges 01, 12, 20 name their springs. Then
// each triangle's neighbours and each node's triangles.
void clothTriangles(Cloth& c, const SheetSprings& ids, std::size_t nn, std::size_t ns) {
  const int nx = c.nx, ny = c.ny;
  auto id = [nx](int i, int j) { return j * nx + i; };
  const std::vector<int>& d1 = ids.d1;
  const std::vector<int>& d2 = ids.d2;
  auto H = [&](int i, int j) { return ids.sh[static_cast<std::size_t>(j * (nx - 1) + i)]; };
  auto V = [&](int i, int j) { return ids.sv[static_cast<std::size_t>(j * nx + i)]; };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int p00 = id(i, j), p10 = id(i + 1, j), p01 = id(i, j + 1), p11 = id(i + 1, j + 1);
      const auto cell = static_cast<std::size_t>(j * (nx - 1) + i);
      if ((i + j) % 2 == 0) {
        c.tris.push_back({p00, p11, p10});
        c.tri_springs.push_back({d1[cell], V(i + 1, j), H(i, j)});
        c.tris.push_back({p00, p01, p11});
        c.tri_springs.push_back({V(i, j), H(i, j + 1), d1[cell]});
      } else {
        c.tris.push_back({p00, p01, p10});
        c.tri_springs.push_back({V(i, j), d2[cell], H(i, j)});
        c.tris.push_back({p10, p01, p11});
        c.tri_springs.push_back({d2[cell], H(i, j + 1), V(i + 1, j)});
      }
    }
  const std::size_t nt = c.tris.size();
  // Neighbours across each edge: the (at most two) triangles that name the same spring.
  std::vector<std::array<int, 2>> by_spring(ns, {-1, -1});
  for (std::size_t t = 0; t < nt; ++t)
    for (int e = 0; e < 3; ++e) {
      auto& slot = by_spring[static_cast<std::size_t>(c.tri_springs[t][e])];
      (slot[0] < 0 ? slot[0] : slot[1]) = static_cast<int>(t);
    }
  c.tri_adj.resize(nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int e = 0; e < 3; ++e) {
      const auto& slot = by_spring[static_cast<std::size_t>(c.tri_springs[t][e])];
      c.tri_adj[t][e] = slot[0] == static_cast<int>(t) ? slot[1] : slot[0];
    }
  // Node → triangles.
  c.node_tri_start.assign(nn + 1, 0);
  for (const auto& t : c.tris)
    for (int k : t) ++c.node_tri_start[static_cast<std::size_t>(k) + 1];
  for (std::size_t i = 0; i < nn; ++i) c.node_tri_start[i + 1] += c.node_tri_start[i];
  c.node_tri.assign(3 * nt, 0);
  std::vector<int> fill(c.node_tri_start.begin(), c.node_tri_start.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k : c.tris[t]) c.node_tri[static_cast<std::size_t>(fill[static_cast<std::size_t>(k)]++)] = static_cast<int>(t);
  c.tri_alive.assign(nt, 1);

}

// Breaking strains, varied per spring from the seed.
void tearStrains(const ClothDesc& d, std::uint64_t seed, Cloth& c, const MassSpringDesc& out) {
  const std::size_t ns = out.springs.size();
  if (d.tear.strain > 0) {
    c.tear_strain.resize(ns);
    for (std::size_t s = 0; s < ns; ++s)
      c.tear_strain[s] = static_cast<int>(s) < c.structural
                             ? d.tear.strain * (1.0 + d.tear.variation * (2.0 * uniformAt(seed, 0x54454152ull /* "TEAR" */, s) - 1.0))
                             : std::numeric_limits<double>::infinity();
    // Threads at a pinned or gripped node never break: the hem or the clamp holds them.
    for (std::size_t s = 0; s < static_cast<std::size_t>(c.structural); ++s)
      if (out.nodes[static_cast<std::size_t>(out.springs[s].a)].fixed || out.nodes[static_cast<std::size_t>(out.springs[s].b)].fixed)
        c.tear_strain[s] = std::numeric_limits<double>::infinity();
  }
}

}  // namespace

MassSpringDesc buildCloth(const ClothDesc& d, std::uint64_t seed, Cloth& c) {
  MassSpringDesc out;
  c = Cloth{};
  c.nx = d.resolution[0];
  c.ny = d.resolution[1];
  clothNodes(d, c, out);
  const SheetSprings ids = clothSprings(d, c, out);
  clothTriangles(c, ids, out.nodes.size(), out.springs.size());
  tearStrains(d, seed, c, out);
  c.strain_limit = d.strain_limit;
  c.thickness = d.thickness;
  c.self_collision = d.self_collision;
  c.air = d.air;
  c.wetting = d.wetting;
  for (const NodeDesc& n : out.nodes) c.dry_mass.push_back(n.mass);
  if (d.wetting.absorbency > 0) {
    for (double m : c.dry_mass) c.capacity.push_back(d.wetting.absorbency * kFabricHolds * m);
    c.wet.assign(c.dry_mass.size(), 0.0);
    c.wet_species.assign(c.dry_mass.size(), 0);
  }
  return out;
}

// --- air ------------------------------------------------------------------------------------
void airForces(Cloth& c, const Wind& wind, double t, const std::vector<Vec3>& x,
               const std::vector<Vec3>& v) {
  const std::size_t nt = c.tris.size(), nn = x.size();
  c.tri_force.resize(nt);
  c.f_air.resize(nn);
  const AirDesc& air = c.air;
  const bool quadratic = air.drag != 0.0 || air.lift != 0.0;
  // The wind at the nodes (half as many as triangles); a triangle feels its corners' mean.
  c.wind.resize(nn);
  parallelFor(static_cast<Index>(nn), [&](Index i) { c.wind[i] = wind.at(x[i], t); });
  // Per triangle: the force on it, a third to each corner.
  parallelFor(static_cast<Index>(nt), [&](Index k) {
    if (!c.tri_alive[k]) {
      c.tri_force[k].setZero();
      return;
    }
    const auto& tri = c.tris[k];
    const Vec3 &a = x[tri[0]], &b = x[tri[1]], &cc = x[tri[2]];
    const Vec3 cr = (b - a).cross(cc - a);
    const double len = cr.norm();
    if (!(len > 1e-300)) {
      c.tri_force[k].setZero();
      return;
    }
    const double area = 0.5 * len;
    const Vec3 n = cr / len;
    const Vec3 w = (c.wind[tri[0]] + c.wind[tri[1]] + c.wind[tri[2]] - v[tri[0]] - v[tri[1]] - v[tri[2]]) / 3.0;
    // Terzopoulos et al. 1987, "Elastically deformable models": the viscous medium's force
    // along the normal, proportional to the normal part of the relative velocity.
    Vec3 f = (air.viscous * area * n.dot(w)) * n;
    const double speed = w.norm();
    if (quadratic && speed > 1e-12) {
      const Vec3 wh = w / speed;
      const double cosq = n.dot(wh);
      const double q = 0.5 * air.density * area * speed * speed;
      const Vec3 facing = cosq >= 0 ? n : Vec3(-n);
      const Vec3 l = facing - facing.dot(wh) * wh;  // |l| = sin θ
      f += (q * std::abs(cosq)) * (air.drag * wh + air.lift * l);
    }
    c.tri_force[k] = f / 3.0;
  });
  parallelFor(static_cast<Index>(nn), [&](Index i) {
    Vec3 f = Vec3::Zero();
    for (int e = c.node_tri_start[i]; e < c.node_tri_start[i + 1]; ++e) f += c.tri_force[static_cast<std::size_t>(c.node_tri[static_cast<std::size_t>(e)])];
    c.f_air[i] = f;
  });
}

// --- grips ----------------------------------------------------------------------------------
namespace {

// A grip's offset from where its nodes start, at time t.
Vec3 gripOffset(const GripDesc& g, double t) {
  if (g.keys.empty()) return std::min(std::max(t - g.start, 0.0), std::max(g.stop - g.start, 0.0)) * g.velocity;
  if (t <= g.keys.front().first) return g.keys.front().second;
  for (std::size_t k = 1; k < g.keys.size(); ++k)
    if (t < g.keys[k].first) {
      const auto& [t0, a] = g.keys[k - 1];
      const auto& [t1, b] = g.keys[k];
      return a + ((t - t0) / (t1 - t0)) * (b - a);
    }
  return g.keys.back().second;
}

// Its velocity over the step that starts at t (the slope of the segment t lies in).
Vec3 gripVelocity(const GripDesc& g, double t) {
  if (g.keys.empty()) return t >= g.start && t < g.stop ? g.velocity : Vec3::Zero();
  for (std::size_t k = 1; k < g.keys.size(); ++k)
    if (t >= g.keys[k - 1].first && t < g.keys[k].first)
      return (g.keys[k].second - g.keys[k - 1].second) / (g.keys[k].first - g.keys[k - 1].first);
  return Vec3::Zero();
}

}  // namespace

void gripVelocities(const Cloth& c, double t, const std::vector<Collider>& colliders, std::vector<Vec3>& v) {
  std::size_t n = 0;
  for (std::size_t gi = 0; gi < c.grips.size(); ++gi) {
    const GripDesc& g = c.grips[gi];
    const int k = c.grip_collider[gi];
    const Vec3 u = k < 0 ? gripVelocity(g, t) : Vec3::Zero();
    for (int p : g.nodes) {
      const Vec3& o = c.grip_origin[n++];
      const Collider* h = k < 0 ? nullptr : &colliders[static_cast<std::size_t>(k)];
      v[static_cast<std::size_t>(p)] = h ? h->velocityAt(h->fromAuthored(o)) : u;
    }
  }
}

void gripPositions(const Cloth& c, double t, const std::vector<Collider>& colliders, std::vector<Vec3>& x) {
  std::size_t n = 0;
  for (std::size_t gi = 0; gi < c.grips.size(); ++gi) {
    const GripDesc& g = c.grips[gi];
    const int k = c.grip_collider[gi];
    const Vec3 off = k < 0 ? gripOffset(g, t) : Vec3::Zero();
    for (int p : g.nodes) {
      const Vec3& o = c.grip_origin[n++];
      x[static_cast<std::size_t>(p)] = k < 0 ? Vec3(o + off) : colliders[static_cast<std::size_t>(k)].fromAuthored(o);
    }
  }
}

// --- strain limiting --------------------------------------------------------------------------
void limitStrain(Cloth& c, const MassSpringModel& m, double h, std::vector<Vec3>& x,
                 std::vector<Vec3>& v) {
  if (!(c.strain_limit > 0)) return;
  const Springs& sp = m.springs;
  const std::size_t ns = sp.size(), nn = x.size();
  c.corr.resize(2 * ns);  // per spring: the move of end a, then of end b
  c.x_in.resize(nn);      // per node: this sweep's move
  const double stretch = 1.0 + c.strain_limit;
  for (int sweep = 0; sweep < 4; ++sweep) {
    parallelFor(static_cast<Index>(ns), [&](Index s) {
      c.corr[2 * s].setZero();
      c.corr[2 * s + 1].setZero();
      if (!c.limited[s]) return;
      const int a = sp.a[s], b = sp.b[s];
      const Vec3 r = x[b] - x[a];
      const double len = r.norm(), lmax = stretch * sp.rest[s];
      const double wa = m.inv_mass[a], wb = m.inv_mass[b];
      if (!(len > lmax) || !std::isfinite(len) || wa + wb == 0.0) return;  // (a blown-up state is the state check's)
      const Vec3 fix = ((len - lmax) / (len * (wa + wb))) * r;  // shortens the spring to lmax
      c.corr[2 * s] = wa * fix;
      c.corr[2 * s + 1] = -wb * fix;
    });
    // Per node: the mean of the moves asked by its violated springs (Jacobi averaging).
    bool any = false;
    parallelFor(static_cast<Index>(nn), [&](Index i) {
      Vec3 d = Vec3::Zero();
      int k = 0;
      for (int e = m.incidence.start[i]; e < m.incidence.start[i + 1]; ++e) {
        const int code = m.incidence.entries[static_cast<std::size_t>(e)];
        const Vec3& q = c.corr[static_cast<std::size_t>(2 * (code >> 1) + (code & 1))];
        if (q.x() != 0.0 || q.y() != 0.0 || q.z() != 0.0) {
          d += q;
          ++k;
        }
      }
      c.x_in[i] = k > 0 ? Vec3(d / k) : Vec3::Zero();
    });
    for (std::size_t i = 0; i < nn && !any; ++i) any = c.x_in[i].x() != 0.0 || c.x_in[i].y() != 0.0 || c.x_in[i].z() != 0.0;
    if (!any) break;
    parallelFor(static_cast<Index>(nn), [&](Index i) {
      x[i] += c.x_in[i];
      v[i] += c.x_in[i] / h;
    });
  }
}

// --- self-collision ---------------------------------------------------------------------------
namespace {

// Largest move since the last pass, less the sheet's mean move: two nodes approach each other
// by at most twice that, so below a quarter of the gap no node can have crossed it. (A sheet
// flying as a whole does not trigger passes.) Sums in node order, maxima in any order.
bool selfPassDue(const Cloth& c, const std::vector<Vec3>& x, double gap) {
  const std::size_t nn = x.size();
  Vec3 mean_move = Vec3::Zero();
  for (std::size_t i = 0; i < nn; ++i) mean_move += x[i] - c.x_prev[i];
  mean_move /= static_cast<double>(nn);
  double moved = 0.0;
  for (std::size_t i = 0; i < nn; ++i) moved = std::max(moved, (x[i] - c.x_prev[i] - mean_move).squaredNorm());
  // (A non-finite state is left for the World's state check to report.)
  return std::sqrt(moved) >= 0.125 * gap && std::isfinite(moved);
}

// Boxes of the drawn triangles grown by the gap (the second sweep moves nodes by less than
// that, and its misses are caught by the next pass) in a grid, a cell about their mean size. A
// triangle stretched over more than eight cells is torn apart in all but name and sits out (an
// empty box, listed nowhere). Returns the mean size, −1 when no triangle is left.
double triangleBoxes(Cloth& c, const std::vector<Vec3>& x, double gap) {
  const std::size_t nt = c.tris.size();
  c.lo.resize(nt);
  c.hi.resize(nt);
  double mean = 0.0;
  int live = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = c.tris[t];
    const Vec3 &a = x[tri[0]], &b = x[tri[1]], &cc = x[tri[2]];
    c.lo[t] = a.cwiseMin(b).cwiseMin(cc) - Vec3::Constant(gap);
    c.hi[t] = a.cwiseMax(b).cwiseMax(cc) + Vec3::Constant(gap);
    if (c.tri_alive[t] && c.lo[t].allFinite() && c.hi[t].allFinite()) {
      mean += (c.hi[t] - c.lo[t]).maxCoeff();
      ++live;
    }
  }
  if (live == 0) return -1.0;
  mean /= live;
  const double cell = mean;
  for (std::size_t t = 0; t < nt; ++t)
    if (!c.tri_alive[t] || !((c.hi[t] - c.lo[t]).maxCoeff() <= 8 * cell))
      BoxGrid::unlist(c.lo[t], c.hi[t]);
  c.grid.build(c.lo, c.hi, cell);
  return mean;
}

// One node in a sweep: pushed out of every triangle (not its own) it is within the gap of, to the
// side it was on at the last pass; its velocity relative to the triangle loses its approaching
// normal part. The mean over the triangles it meets.
void sweepNode(Cloth& c, const MassSpringModel& m, std::size_t i, double gap, double depth, std::vector<Vec3>& x,
               std::vector<Vec3>& v) {
  if (m.fixed[i] || !c.hit[i]) return;
  c.hit[i] = 0;
  const Vec3 p = c.x_in[i], p0 = c.x_prev[i];
  Vec3 dx = Vec3::Zero(), dv = Vec3::Zero();
  int hits = 0;
  c.grid.forEachAt(p, [&](int t) {
    // The bucket lists every triangle near the cell: first the cheap test of the box.
    const Vec3 &lo = c.lo[static_cast<std::size_t>(t)], &hi = c.hi[static_cast<std::size_t>(t)];
    if (p.x() < lo.x() || p.y() < lo.y() || p.z() < lo.z() || p.x() > hi.x() || p.y() > hi.y() || p.z() > hi.z()) return;
    const auto& tri = c.tris[static_cast<std::size_t>(t)];
    if (tri[0] == static_cast<int>(i) || tri[1] == static_cast<int>(i) || tri[2] == static_cast<int>(i)) return;
    const double len = c.tri_double_area[static_cast<std::size_t>(t)];
    if (!(len > 1e-300)) return;
    const Vec3 &a = c.x_in[tri[0]], &b = c.x_in[tri[1]], &cc = c.x_in[tri[2]];
    const Vec3& n = c.tri_n[static_cast<std::size_t>(t)];
    const double dn = (p - a).dot(n);
    if (std::abs(dn) > depth) return;
    // Barycentric coordinates of p's projection on the triangle's plane.
    const Vec3 q = p - dn * n;
    const double wb = (q - a).cross(cc - a).dot(n) / len, wc = (b - a).cross(q - a).dot(n) / len;
    const double wa = 1.0 - wb - wc;
    if (wa < 0 || wb < 0 || wc < 0) return;
    // The side the node was on at the start of the step.
    const Vec3 &a0 = c.x_prev[tri[0]], &b0 = c.x_prev[tri[1]], &c0 = c.x_prev[tri[2]];
    const Vec3& n0 = c.tri_n0[static_cast<std::size_t>(t)];
    const double side0 = (p0 - (wa * a0 + wb * b0 + wc * c0)).dot(n0);
    const double s = side0 > 0 ? 1.0 : side0 < 0 ? -1.0 : (dn >= 0 ? 1.0 : -1.0);
    const double sd = s * dn;
    if (sd >= gap) return;
    dx += (gap - sd) * s * n;
    const Vec3 vt = wa * c.v_in[tri[0]] + wb * c.v_in[tri[1]] + wc * c.v_in[tri[2]];
    const double vn = (c.v_in[i] - vt).dot(s * n);
    if (vn < 0) dv -= vn * s * n;
    ++hits;
  });
  if (hits > 0) {
    c.hit[i] = 1;
    x[i] = p + dx / hits;
    v[i] = c.v_in[i] + dv / hits;
  }
}

}  // namespace

void selfCollide(Cloth& c, const MassSpringModel& m, std::vector<Vec3>& x, std::vector<Vec3>& v) {
  const std::size_t nt = c.tris.size(), nn = x.size();
  const double gap = 2.0 * c.thickness;
  if (c.x_prev.size() != nn) {  // the first step: the start is the reference
    c.x_prev = x;
    return;
  }
  // (A non-finite state is left for the World's state check to report.)
  if (!selfPassDue(c, x, gap)) return;
  ++c.self_passes;
  const double mean = triangleBoxes(c, x, gap);
  if (mean < 0.0) {
    c.x_prev = x;
    return;
  }
  // A node is caught when it is within the gap of a triangle's face, or has crossed it by less
  // than a typical edge (farther crossings are other layers of the sheet, not this contact).
  const double depth = std::max(mean - 4 * gap, 2 * gap);
  c.x_in.resize(nn);
  c.v_in.resize(nn);
  // Two sweeps: the second looks again only at the nodes the first one moved.
  c.hit.assign(nn, 1);
  // Per triangle, once a pass: the normal at the last pass (the side a node was on); once a
  // sweep: the unit normal and twice the area (not once per node that looks at it).
  c.tri_n0.resize(nt);
  c.tri_n.resize(nt);
  c.tri_double_area.resize(nt);
  parallelFor(static_cast<Index>(nt), [&](Index t) {
    const auto& tri = c.tris[static_cast<std::size_t>(t)];
    const Vec3 &a0 = c.x_prev[tri[0]], &b0 = c.x_prev[tri[1]], &c0 = c.x_prev[tri[2]];
    c.tri_n0[static_cast<std::size_t>(t)] = (b0 - a0).cross(c0 - a0);
  });
  for (int sweep = 0; sweep < 2; ++sweep) {
    c.x_in = x;
    c.v_in = v;
    parallelFor(static_cast<Index>(nt), [&](Index t) {
      const auto& tri = c.tris[static_cast<std::size_t>(t)];
      const Vec3 &a = c.x_in[tri[0]], &b = c.x_in[tri[1]], &cc = c.x_in[tri[2]];
      const Vec3 cr = (b - a).cross(cc - a);
      const double len = cr.norm();
      c.tri_double_area[static_cast<std::size_t>(t)] = len;
      c.tri_n[static_cast<std::size_t>(t)] = len > 1e-300 ? Vec3(cr / len) : Vec3::Zero();
    });
    parallelFor(static_cast<Index>(nn), [&](Index i) { sweepNode(c, m, static_cast<std::size_t>(i), gap, depth, x, v); });
  }
  c.x_prev = x;
}

// --- tearing ---------------------------------------------------------------------------------
void refreshTriangles(Cloth& c) {
  for (std::size_t t = 0; t < c.tris.size(); ++t) {
    bool alive = true;
    for (int e : c.tri_springs[t]) alive = alive && (e >= c.structural || c.intact[static_cast<std::size_t>(e)]);
    c.tri_alive[t] = alive ? 1 : 0;
  }
}

int tearSprings(Cloth& c, MassSpringModel& m, const std::vector<Vec3>& x) {
  if (c.tear_strain.empty()) return 0;
  Springs& sp = m.springs;
  const std::size_t ns = sp.size();
  auto overOf = [&](Index s) { return (x[sp.b[s]] - x[sp.a[s]]).norm() / ((1.0 + c.tear_strain[s]) * sp.rest[s]); };
  const double top = deterministicMax(static_cast<Index>(ns), overOf);
  if (!(top > 1.0)) return 0;
  // Which threads break in a step (Terzopoulos & Fleischer break every thread past its threshold;
  // with implicit Euler's long steps that takes a whole row at a clamp at once, or opens holes
  // everywhere in a sheet stretched evenly): with over = len/((1 + s)·l), a thread over 1 breaks
  // when it is the most over of the threads at its ends' nodes and at their neighbours, and
  // within half way of the most over thread of the sheet to 1. Under a slow pull only the most
  // loaded thread goes, its load moves to its neighbours and the next to go is at the tear's tip:
  // the tear runs step by step along the most loaded path. Under an impact every thread far past
  // its threshold goes at once.
  std::vector<double> over(ns);
  parallelFor(static_cast<Index>(ns), [&](Index s) { over[static_cast<std::size_t>(s)] = overOf(s); });
  const double cut = 1.0 + 0.5 * (top - 1.0);
  const Incidence& inc = m.incidence;
  const auto nn = static_cast<Index>(m.nodes());
  std::vector<double> at_node(m.nodes()), near_node(m.nodes());
  parallelFor(nn, [&](Index i) {
    double most = 0.0;
    for (int k = inc.start[i]; k < inc.start[i + 1]; ++k) most = std::max(most, over[static_cast<std::size_t>(inc.entries[k] / 2)]);
    at_node[static_cast<std::size_t>(i)] = most;
  });
  parallelFor(nn, [&](Index i) {
    double most = at_node[static_cast<std::size_t>(i)];
    for (int k = inc.start[i]; k < inc.start[i + 1]; ++k) most = std::max(most, at_node[static_cast<std::size_t>(inc.other[k])]);
    near_node[static_cast<std::size_t>(i)] = most;
  });
  // The threads that break, then the shear and bend springs that needed them.
  for (std::size_t s = 0; s < ns; ++s)
    if (over[s] > 1.0 && over[s] >= cut && over[s] >= near_node[static_cast<std::size_t>(sp.a[s])] &&
        over[s] >= near_node[static_cast<std::size_t>(sp.b[s])])
      c.intact[static_cast<std::size_t>(c.spring_id[s])] = 0;
  // Keep the springs that hold, in order (indices stay sorted, so the incidence order is fixed).
  std::size_t w = 0;
  for (std::size_t s = 0; s < ns; ++s) {
    const auto id = static_cast<std::size_t>(c.spring_id[s]);
    for (int t : c.holds[id])
      if (t >= 0 && !c.intact[static_cast<std::size_t>(t)]) c.intact[id] = 0;
    if (!c.intact[id]) continue;
    sp.a[w] = sp.a[s];
    sp.b[w] = sp.b[s];
    sp.stiffness[w] = sp.stiffness[s];
    sp.damping[w] = sp.damping[s];
    sp.rest[w] = sp.rest[s];
    c.spring_id[w] = c.spring_id[s];
    c.limited[w] = c.limited[s];
    c.tear_strain[w] = c.tear_strain[s];
    ++w;
  }
  for (auto* arr : {&sp.a, &sp.b}) arr->resize(w);
  for (auto* arr : {&sp.stiffness, &sp.damping, &sp.rest, &c.tear_strain}) arr->resize(w);
  c.spring_id.resize(w);
  c.limited.resize(w);
  m.incidence.build(m.nodes(), sp);
  refreshTriangles(c);
  const int n = static_cast<int>(ns - w);
  c.springs_broken += n;
  return n;
}

int clothPieces(std::size_t nodes, const Springs& s) {
  std::vector<int> parent(nodes);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t k = 0; k < s.size(); ++k) unite(parent, s.a[k], s.b[k]);
  int pieces = 0;
  for (std::size_t i = 0; i < nodes; ++i) pieces += findRoot(parent, static_cast<int>(i)) == static_cast<int>(i);
  return pieces;
}

}  // namespace reel
