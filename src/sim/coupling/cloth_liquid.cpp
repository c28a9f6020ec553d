#include "sim/coupling/cloth_liquid.h"

#include <algorithm>
#include <cmath>

#include "core/hash.h"
#include "core/parallel.h"
#include "sim/cloth/cloth_body.h"
#include "sim/fluid/fluid_body.h"
#include "sim/geometry.h"

namespace reel {
namespace {

// A particle's closest drawn triangle: barycentric weights of the closest point, the normal
// towards the particle's side, and the gap (negative: it has crossed the sheet this step).
struct SheetContact {
  int tri = -1;
  Vec3 w{0, 0, 0};
  Vec3 normal{0, 1, 0};
  double gap = 0.0;
};

struct Exchange {
  Exchange(Fluid& f, Cloth& cl, SpringNetwork& net, double step)
      : fl(f), c(cl), m(net.model), x(net.state.x), v(net.state.v), h(step) {}
  Fluid& fl;
  std::uint64_t liquid = 0;  // FNV hash of the liquid's name
  Cloth& c;
  MassSpringModel& m;
  std::vector<Vec3>& x;
  std::vector<Vec3>& v;
  double h;
  std::vector<Surface> surface;  // per species
  std::vector<double> range;     // adhesion range per species (0: not sticky), m
  double reach = 0.0;            // contact distance: thickness plus particle radius, m
  double grow = 0.0;             // how far from a triangle particles are looked for, m
  std::vector<int> alive;        // drawn triangles
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};  // the box of their grown boxes: particles outside meet none
  std::vector<double> edge;       // each one's largest extent over the step, m
  // Area-weighted normals of the triangles (triangles) and their sums at the nodes (nodes): now
  // and a step back, the pseudo-normals that tell the sides of an edge or a corner.
  std::vector<Vec3> tri_n1, tri_n0, node_n1, node_n0;
  std::vector<SheetContact> contact;  // per particle slot
};

// The normals now and a step back (x − h·v).
void buildNormals(Exchange& e) {
  const Cloth& c = e.c;
  const std::size_t nt = c.tris.size(), nn = e.x.size();
  e.tri_n1.assign(nt, Vec3::Zero());
  e.tri_n0.assign(nt, Vec3::Zero());
  parallelFor(static_cast<std::ptrdiff_t>(e.alive.size()), [&](std::ptrdiff_t k) {
    const int t = e.alive[static_cast<std::size_t>(k)];
    const auto& tri = c.tris[static_cast<std::size_t>(t)];
    const auto a = static_cast<std::size_t>(tri[0]), b = static_cast<std::size_t>(tri[1]), d = static_cast<std::size_t>(tri[2]);
    e.tri_n1[static_cast<std::size_t>(t)] = (e.x[b] - e.x[a]).cross(e.x[d] - e.x[a]);
    const Vec3 pa = e.x[a] - e.h * e.v[a], pb = e.x[b] - e.h * e.v[b], pd = e.x[d] - e.h * e.v[d];
    e.tri_n0[static_cast<std::size_t>(t)] = (pb - pa).cross(pd - pa);
  });
  e.node_n1.assign(nn, Vec3::Zero());
  e.node_n0.assign(nn, Vec3::Zero());
  parallelFor(static_cast<std::ptrdiff_t>(nn), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    for (int k = c.node_tri_start[i]; k < c.node_tri_start[i + 1]; ++k) {
      const auto t = static_cast<std::size_t>(c.node_tri[static_cast<std::size_t>(k)]);
      e.node_n1[i] += e.tri_n1[t];
      e.node_n0[i] += e.tri_n0[t];
    }
  });
}

// Whether any particle may come within reach of the sheet this step: the boxes of the nodes (now
// and a step back) and of the particles, the first grown by the reach, overlap.
bool overlaps(const Exchange& e) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t i = 0; i < e.x.size(); ++i) {
    const Vec3 back = e.x[i] - e.h * e.v[i];
    lo = lo.cwiseMin(e.x[i]).cwiseMin(back);
    hi = hi.cwiseMax(e.x[i]).cwiseMax(back);
  }
  lo -= Vec3::Constant(e.grow);
  hi += Vec3::Constant(e.grow);
  Vec3 plo = Vec3::Constant(1e300), phi = Vec3::Constant(-1e300);
  for (const Vec3& p : e.fl.x) {
    plo = plo.cwiseMin(p);
    phi = phi.cwiseMax(p);
  }
  return (plo.array() <= hi.array()).all() && (lo.array() <= phi.array()).all();
}

// Grid of the drawn triangles' boxes, over where each was a step back and is now, grown by the
// farthest reach.
void buildTriangleGrid(Exchange& e) {
  Cloth& c = e.c;
  e.alive.clear();
  for (std::size_t t = 0; t < c.tris.size(); ++t)
    if (c.tri_alive[t]) e.alive.push_back(static_cast<int>(t));
  c.lo.resize(e.alive.size());
  c.hi.resize(e.alive.size());
  e.edge.resize(e.alive.size());
  parallelFor(static_cast<std::ptrdiff_t>(e.alive.size()), [&](std::ptrdiff_t kk) {
    const auto k = static_cast<std::size_t>(kk);
    const auto& tri = c.tris[static_cast<std::size_t>(e.alive[k])];
    Vec3 lo = e.x[static_cast<std::size_t>(tri[0])], hi = lo;
    for (int q : tri) {
      const auto i = static_cast<std::size_t>(q);
      for (const Vec3& p : {e.x[i], Vec3(e.x[i] - e.h * e.v[i])}) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    e.edge[k] = (hi - lo).maxCoeff();
    c.lo[k] = lo - Vec3::Constant(e.grow);
    c.hi[k] = hi + Vec3::Constant(e.grow);
  });
  double edge = 0.0;
  e.lo = Vec3::Constant(1e300);
  e.hi = Vec3::Constant(-1e300);
  for (std::size_t k = 0; k < e.alive.size(); ++k) {
    edge = std::max(edge, e.edge[k]);
    e.lo = e.lo.cwiseMin(c.lo[k]);
    e.hi = e.hi.cwiseMax(c.hi[k]);
  }
  c.grid.build(c.lo, c.hi, edge + 2.0 * e.grow);
}

// The closest drawn triangle to particle i within its reach, on the side it came from.
SheetContact closest(const Exchange& e, std::size_t i) {
  const Vec3 p1 = e.fl.x[i], p0 = p1 - e.h * e.fl.v[i];
  const auto si = static_cast<std::size_t>(e.fl.s[i]);
  const double within = e.reach + e.range[si];
  SheetContact ct;
  if (!((p1.array() >= e.lo.array()).all() && (p1.array() <= e.hi.array()).all())) return ct;
  // The closest point of the sheet (the first triangle on a tie: the grid's order is fixed).
  int t = -1;
  Vec3 w = Vec3::Zero(), q = Vec3::Zero();
  double dist2 = within * within;
  e.c.grid.forEachAt(p1, [&](int k) {
    const int tk = e.alive[static_cast<std::size_t>(k)];
    const auto& tri = e.c.tris[static_cast<std::size_t>(tk)];
    const Vec3 &a = e.x[static_cast<std::size_t>(tri[0])], &b = e.x[static_cast<std::size_t>(tri[1])],
               &c = e.x[static_cast<std::size_t>(tri[2])];
    // Farther from the triangle's plane than the best so far: not closer (a cheap test first).
    const Vec3& nk = e.tri_n1[static_cast<std::size_t>(tk)];
    const double plane = nk.dot(p1 - a);
    if (plane * plane >= dist2 * nk.squaredNorm()) return;
    const Vec3 wk = closestOnTriangle(p1, a, b, c);
    const Vec3 qk = wk[0] * a + wk[1] * b + wk[2] * c;
    const double d2 = (p1 - qk).squaredNorm();
    if (d2 < dist2) dist2 = d2, t = tk, w = wk, q = qk;
  });
  if (t < 0) return ct;
  const auto& tri = e.c.tris[static_cast<std::size_t>(t)];
  // Which side: the pseudo-normal of the closest feature (Bærentzen & Aanæs 2005, "Signed distance
  // computation using the angle weighted pseudonormal"; here area-weighted): the face's normal,
  // the sum of the two faces' at an edge, of the faces' around a corner; now and a step back.
  Vec3 N1 = e.tri_n1[static_cast<std::size_t>(t)], N0 = e.tri_n0[static_cast<std::size_t>(t)];
  const int zeros = (w[0] == 0.0) + (w[1] == 0.0) + (w[2] == 0.0);
  if (zeros == 2) {
    const auto node = static_cast<std::size_t>(tri[w[0] == 1.0 ? 0 : w[1] == 1.0 ? 1 : 2]);
    N1 = e.node_n1[node];
    N0 = e.node_n0[node];
  } else if (zeros == 1) {
    const int edge = w[2] == 0.0 ? 0 : w[0] == 0.0 ? 1 : 2;  // edges 01, 12, 20
    const int u = e.c.tri_adj[static_cast<std::size_t>(t)][static_cast<std::size_t>(edge)];
    if (u >= 0 && e.c.tri_alive[static_cast<std::size_t>(u)]) {
      N1 += e.tri_n1[static_cast<std::size_t>(u)];
      N0 += e.tri_n0[static_cast<std::size_t>(u)];
    }
  }
  const double len = N1.norm();
  if (!(len > 0)) return ct;
  const Vec3 n = N1 / len;
  // The same material point of the sheet a step back, and the particle then.
  Vec3 q0 = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const auto node = static_cast<std::size_t>(tri[static_cast<std::size_t>(k)]);
    q0 += w[k] * (e.x[node] - e.h * e.v[node]);
  }
  const double s1 = n.dot(p1 - q), s0 = N0.dot(p0 - q0);
  const double side = s0 != 0.0 ? (s0 > 0 ? 1.0 : -1.0) : (s1 >= 0 ? 1.0 : -1.0);
  ct.tri = t;
  ct.w = w;
  if (zeros == 0 || side * s1 < 0) {  // over the face, or through the sheet since a step back
    ct.normal = side * n;
    ct.gap = side * s1;
  } else {  // beside an edge or a corner, on the particle's side: pushed away from it
    ct.gap = std::sqrt(dist2);
    ct.normal = ct.gap > 0 ? Vec3((p1 - q) / ct.gap) : Vec3(side * n);
  }
  return ct;
}

// One particle against its triangle: soaked up (returns true), or pushed apart and given the
// impulse of restitution, friction, adhesion or seepage.
bool resolve(Exchange& e, std::size_t i, const SheetContact& ct) {
  Fluid& fl = e.fl;
  Cloth& c = e.c;
  const auto& tri = c.tris[static_cast<std::size_t>(ct.tri)];
  const auto si = static_cast<std::size_t>(fl.s[i]);
  const Surface& sf = e.surface[si];
  const bool touching = ct.gap < e.reach;
  // Soaked up while the triangle's nodes hold less than their capacity: its mass and momentum
  // are shared among them by the weights of the closest point.
  if (touching && !c.capacity.empty()) {
    double wet = 0.0, cap = 0.0;
    for (int q : tri) wet += c.wet[static_cast<std::size_t>(q)], cap += c.capacity[static_cast<std::size_t>(q)];
    if (wet < cap) {
      for (int k = 0; k < 3; ++k) {
        const auto node = static_cast<std::size_t>(tri[static_cast<std::size_t>(k)]);
        const double share = ct.w[k] * fl.m[i];
        if (share == 0.0) continue;
        if (e.m.fixed[node]) c.pin_liquid_force += (share / e.h) * (fl.v[i] - e.v[node]);
        wetNode(c, e.m, e.v, node, share, fl.v[i]);
        c.wet_species[node] = fl.s[i];
      }
      c.wet_from = e.liquid;
      ++c.absorbed;
      return true;
    }
  }
  const double wp = 1.0 / fl.m[i];
  double weff = wp;
  Vec3 vc = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const auto node = static_cast<std::size_t>(tri[static_cast<std::size_t>(k)]);
    weff += ct.w[k] * ct.w[k] * e.m.inv_mass[node];
    vc += ct.w[k] * e.v[node];
  }
  const Vec3& nn = ct.normal;
  const double gap = ct.gap;  // the nodes do not move here (only their velocities change)
  const Vec3 vrel = fl.v[i] - vc;
  const double vn = nn.dot(vrel);
  Vec3 J = Vec3::Zero();
  // Adhesion: an acceleration of the particle towards the sheet, full in contact, fading to 0 one
  // range away; the sheet is pulled back as much.
  if (sf.adhesion > 0 && e.range[si] > 0)
    J -= (e.h * sf.adhesion * fl.m[i] * std::clamp(1.0 - (gap - e.reach) / e.range[si], 0.0, 1.0)) * nn;
  if (touching) {
    const double p = c.wetting.porosity;
    double jn = 0.0;
    if (p == 0.0) {
      // The particle goes back to the reach; the nodes move only by the impulse (moving them
      // would stretch stiff springs of light nodes: energy from nowhere).
      fl.x[i] += (e.reach - gap) * nn;
      if (vn < 0) jn = -(1.0 + sf.restitution) * vn / weff;
    } else if (p < 1.0) {
      // Seepage: v_n → v_n / (1 + h/τ), τ = kSeepTime·p/(1 − p).
      const double tau = kSeepTime * p / (1.0 - p);
      jn = -vn * (e.h / tau) / (1.0 + e.h / tau) / weff;
    }
    // Coulomb friction on the tangential relative velocity, bounded by μ·|J_n|.
    const Vec3 vt = vrel - vn * nn;
    const double st = vt.norm();
    J += jn * nn;
    if (st > 0) J -= std::min(st / weff, sf.friction * std::abs(jn)) * (vt / st);
  }
  if (J.isZero()) return false;
  fl.v[i] += wp * J;
  for (int k = 0; k < 3; ++k) {
    const auto node = static_cast<std::size_t>(tri[static_cast<std::size_t>(k)]);
    if (e.m.fixed[node])
      c.pin_liquid_force -= (ct.w[k] / e.h) * J;
    else
      e.v[node] -= (ct.w[k] * e.m.inv_mass[node]) * J;
  }
  return false;
}

// Nodes holding a drop's mass beyond their capacity release it below themselves, into the liquid
// the sheet soaked up last.
void drip(Exchange& e, const Vec3& gravity) {
  Cloth& c = e.c;
  const double g = gravity.norm();
  if (c.capacity.empty() || !(g > 0) || c.wet_from != e.liquid) return;
  const Vec3 down = gravity / g;
  for (std::size_t i = 0; i < c.wet.size(); ++i) {
    const int sp = c.wet_species[i];
    const double drop = e.fl.species_mass[static_cast<std::size_t>(sp)];
    if (!(c.wet[i] - c.capacity[i] >= drop)) continue;
    if (static_cast<long long>(e.fl.x.size()) >= e.fl.max_particles) return;
    addParticle(e.fl, e.x[i] + (1.2 * e.reach) * down, e.v[i], sp);
    wetNode(c, e.m, e.v, i, -drop, e.v[i]);
    ++c.dripped;
  }
}

}  // namespace

void exchangeClothLiquid(Body& liquid, Body& sheet, StepContext& ctx) {
  auto& fb = dynamic_cast<FluidBody&>(liquid);
  auto& cb = dynamic_cast<ClothBody&>(sheet);
  Exchange e(fb.fluid(), cb.cloth(), cb.network(), ctx.h);
  Fluid& fl = e.fl;
  e.c.pin_liquid_force.setZero();
  const auto S = static_cast<std::size_t>(fl.species_count);
  e.reach = e.c.thickness + fl.radius;
  double far = 0.0;
  for (std::size_t s = 0; s < S; ++s) {
    e.surface.push_back(surfaceFor(e.c.wetting.surface, e.c.wetting.species_surface, fl.species_names[s]));
    e.range.push_back(e.surface.back().adhesion > 0 ? fl.pairs[s * S + s].cutoff : 0.0);
    far = std::max(far, e.range.back());
  }
  e.grow = e.reach + far;
  {
    Hasher name;
    name.add(liquid.name().data(), liquid.name().size());
    e.liquid = name.h;
  }
  const auto n = static_cast<std::ptrdiff_t>(fl.x.size());
  if (n > 0 && overlaps(e)) {
    buildTriangleGrid(e);
    buildNormals(e);
    e.contact.resize(fl.x.size());
    parallelFor(n, [&](std::ptrdiff_t i) { e.contact[static_cast<std::size_t>(i)] = closest(e, static_cast<std::size_t>(i)); });
    std::vector<std::uint8_t> gone(fl.x.size(), 0);
    bool any_gone = false;
    for (std::size_t i = 0; i < fl.x.size(); ++i)
      if (e.contact[i].tri >= 0 && resolve(e, i, e.contact[i])) gone[i] = 1, any_gone = true;
    if (any_gone) removeParticles(fl, gone);
  }
  drip(e, ctx.gravity);
}

}  // namespace reel
