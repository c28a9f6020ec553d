#include "sim/coupling/cloth_liquid.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/hash.h"
#include "sim/cloth/cloth_body.h"
#include "sim/fluid/fluid_body.h"
#include "sim/contact_layer.h"
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

class ClothLiquidHook final : public ContactHook {
 public:
  ClothLiquidHook(FluidBody& liquid, ClothBody& sheet) : fl_(liquid.fluid()), c_(sheet.cloth()), m_(sheet.network().model) {
    const auto S = static_cast<std::size_t>(fl_.species_count);
    reach_ = c_.thickness + fl_.radius;
    for (std::size_t s = 0; s < S; ++s) {
      surface_.push_back(surfaceFor(c_.wetting.surface, c_.wetting.species_surface, fl_.species_names[s]));
      range_.push_back(surface_.back().adhesion > 0 ? fl_.pairs[s * S + s].cutoff : 0.0);
      margin_ = std::max(margin_, range_.back());
    }
    Hasher name;
    name.add(liquid.name().data(), liquid.name().size());
    liquid_ = name.h;
    sheet_ = &sheet.network();
  }

  double margin() const override { return margin_; }
  void begin(const ContactProxies& p, std::uint32_t points, std::uint32_t surface, double h) override;
  bool point(ContactProxies& p, std::uint32_t i, std::span<const std::uint32_t> tris, double h) override;
  void end(const StepContext& ctx) override;

 private:
  SheetContact closest(const ContactProxies& p, std::uint32_t i, std::span<const std::uint32_t> tris) const;
  const Vec3& x(const ContactProxies& p, int node) const { return p.x[first_ + static_cast<std::size_t>(node)]; }
  const Vec3& x0(const ContactProxies& p, int node) const { return p.x0[first_ + static_cast<std::size_t>(node)]; }
  // Area-weighted normals of triangle t (of the sheet) now and at the start of the step; zero for
  // a torn one.
  Vec3 normal(const ContactProxies& p, std::size_t t) const {
    if (!c_.tri_alive[t]) return Vec3::Zero();
    const auto& T = c_.tris[t];
    return (x(p, T[1]) - x(p, T[0])).cross(x(p, T[2]) - x(p, T[0]));
  }
  Vec3 normal0(const ContactProxies& p, std::size_t t) const {
    if (!c_.tri_alive[t]) return Vec3::Zero();
    const auto& T = c_.tris[t];
    return (x0(p, T[1]) - x0(p, T[0])).cross(x0(p, T[2]) - x0(p, T[0]));
  }

  Fluid& fl_;
  Cloth& c_;
  MassSpringModel& m_;
  SpringNetwork* sheet_ = nullptr;
  std::uint64_t liquid_ = 0;       // FNV hash of the liquid's name
  std::vector<Surface> surface_;   // per species
  std::vector<double> range_;      // adhesion range per species (0: not sticky), m
  double reach_ = 0.0;             // contact distance: thickness plus particle radius, m
  double margin_ = 0.0;            // the farthest adhesion range, m
  // The step's: the first particle's and the first node's ids in the proxies, the sheet's first
  // triangle there; the drawn triangles (the proxies' order), found again when a tear changes them.
  std::size_t particles_ = 0, first_ = 0, tri_first_ = 0;
  std::vector<int> alive_;
};

// Where the two bodies are in the proxies (the normals are found as a particle needs them).
void ClothLiquidHook::begin(const ContactProxies& p, std::uint32_t points, std::uint32_t surface, double /*h*/) {
  particles_ = p.first[points];
  first_ = p.first[surface];
  tri_first_ = p.tri_first[surface];
  // A sheet only loses triangles (tears): the same count is the same triangles.
  if (alive_.size() != p.tri_first[surface + 1] - tri_first_) {
    alive_.clear();
    for (std::size_t t = 0; t < c_.tris.size(); ++t)
      if (c_.tri_alive[t]) alive_.push_back(static_cast<int>(t));
  }
  REEL_CHECK(alive_.size() == p.tri_first[surface + 1] - tri_first_, "cloth and liquid: the sheet's triangles changed");
}

// The closest of the candidate triangles to particle i within its reach, on the side it came from.
SheetContact ClothLiquidHook::closest(const ContactProxies& p, std::uint32_t i, std::span<const std::uint32_t> tris) const {
  const Vec3 &p1 = p.x[i], &p0 = p.x0[i];
  const auto si = static_cast<std::size_t>(fl_.s[i - particles_]);
  const double within = reach_ + range_[si];
  SheetContact ct;
  // The closest point of the sheet (the first triangle on a tie: the candidates are in id order).
  int t = -1;
  Vec3 w = Vec3::Zero(), q = Vec3::Zero();
  double dist2 = within * within;
  for (std::uint32_t id : tris) {
    const int tk = alive_[id - tri_first_];
    const auto& tri = c_.tris[static_cast<std::size_t>(tk)];
    const Vec3 &a = x(p, tri[0]), &b = x(p, tri[1]), &c = x(p, tri[2]);
    // Farther from the triangle's plane than the best so far: not closer (a cheap test first).
    const Vec3 nk = (b - a).cross(c - a);
    const double plane = nk.dot(p1 - a);
    if (plane * plane >= dist2 * nk.squaredNorm()) continue;
    const Vec3 wk = closestOnTriangle(p1, a, b, c);
    const Vec3 qk = wk[0] * a + wk[1] * b + wk[2] * c;
    const double d2 = (p1 - qk).squaredNorm();
    if (d2 < dist2) dist2 = d2, t = tk, w = wk, q = qk;
  }
  if (t < 0) return ct;
  const auto& tri = c_.tris[static_cast<std::size_t>(t)];
  // Which side: the pseudo-normal of the closest feature (Bærentzen & Aanæs 2005, "Signed distance
  // computation using the angle weighted pseudonormal"; here area-weighted): the face's normal,
  // the sum of the two faces' at an edge, of the faces' around a corner; now and a step back.
  const auto tu = static_cast<std::size_t>(t);
  Vec3 N1 = normal(p, tu), N0 = normal0(p, tu);
  const int zeros = (w[0] == 0.0) + (w[1] == 0.0) + (w[2] == 0.0);
  if (zeros == 2) {
    const auto node = static_cast<std::size_t>(tri[w[0] == 1.0 ? 0 : w[1] == 1.0 ? 1 : 2]);
    N1 = N0 = Vec3::Zero();
    for (int k = c_.node_tri_start[node]; k < c_.node_tri_start[node + 1]; ++k) {
      const auto around = static_cast<std::size_t>(c_.node_tri[static_cast<std::size_t>(k)]);
      N1 += normal(p, around);
      N0 += normal0(p, around);
    }
  } else if (zeros == 1) {
    const int edge = w[2] == 0.0 ? 0 : w[0] == 0.0 ? 1 : 2;  // edges 01, 12, 20
    const int u = c_.tri_adj[tu][static_cast<std::size_t>(edge)];
    if (u >= 0) {
      N1 += normal(p, static_cast<std::size_t>(u));
      N0 += normal0(p, static_cast<std::size_t>(u));
    }
  }
  const double len = N1.norm();
  if (!(len > 0)) return ct;
  const Vec3 n = N1 / len;
  // The same material point of the sheet at the start of the step, and the particle then.
  Vec3 q0 = Vec3::Zero();
  for (int k = 0; k < 3; ++k) q0 += w[k] * x0(p, tri[static_cast<std::size_t>(k)]);
  const double s1 = n.dot(p1 - q), s0 = N0.dot(p0 - q0);
  const double side = s0 != 0.0 ? (s0 > 0 ? 1.0 : -1.0) : (s1 >= 0 ? 1.0 : -1.0);
  ct.tri = t;
  ct.w = w;
  if (zeros == 0 || side * s1 < 0) {  // over the face, or through the sheet since the step began
    ct.normal = side * n;
    ct.gap = side * s1;
  } else {  // beside an edge or a corner, on the particle's side: pushed away from it
    ct.gap = std::sqrt(dist2);
    ct.normal = ct.gap > 0 ? Vec3((p1 - q) / ct.gap) : Vec3(side * n);
  }
  return ct;
}

// Particle i against its closest triangle: soaked up (marked gone), or pushed apart and given the
// impulse of restitution, friction, adhesion or seepage.
bool ClothLiquidHook::point(ContactProxies& p, std::uint32_t i, std::span<const std::uint32_t> tris, double h) {
  const SheetContact ct = closest(p, i, tris);
  if (ct.tri < 0) return false;
  const auto& tri = c_.tris[static_cast<std::size_t>(ct.tri)];
  const std::size_t li = i - particles_;
  const auto si = static_cast<std::size_t>(fl_.s[li]);
  const Surface& sf = surface_[si];
  const bool touching = ct.gap < reach_;
  auto node = [&](int k) { return static_cast<std::size_t>(tri[static_cast<std::size_t>(k)]); };
  auto vnode = [&](int k) -> Vec3& { return p.v[first_ + node(k)]; };
  // Soaked up while the triangle's nodes hold less than their capacity: its mass and momentum
  // are shared among them by the weights of the closest point.
  if (touching && !c_.capacity.empty()) {
    double wet = 0.0, cap = 0.0;
    for (int k = 0; k < 3; ++k) wet += c_.wet[node(k)], cap += c_.capacity[node(k)];
    if (wet < cap) {
      for (int k = 0; k < 3; ++k) {
        const double share = ct.w[k] * fl_.m[li];
        if (share == 0.0) continue;
        if (m_.fixed[node(k)]) c_.pin_liquid_force += (share / h) * (p.v[i] - vnode(k));
        wetNode(c_, m_, vnode(k), node(k), share, p.v[i]);
        p.w[first_ + node(k)] = m_.inv_mass[node(k)];
        c_.wet_species[node(k)] = fl_.s[li];
      }
      c_.wet_from = liquid_;
      ++c_.absorbed;
      p.gone[i] = 1;
      return true;
    }
  }
  const double wp = 1.0 / fl_.m[li];
  double weff = wp;
  Vec3 vc = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    weff += ct.w[k] * ct.w[k] * m_.inv_mass[node(k)];
    vc += ct.w[k] * vnode(k);
  }
  const Vec3& nn = ct.normal;
  const double gap = ct.gap;  // the nodes do not move here (only their velocities change)
  const Vec3 vrel = p.v[i] - vc;
  const double vn = nn.dot(vrel);
  Vec3 J = Vec3::Zero();
  bool moved = false;
  // Adhesion: an acceleration of the particle towards the sheet, full in contact, fading to 0 one
  // range away; the sheet is pulled back as much.
  if (sf.adhesion > 0 && range_[si] > 0)
    J -= (h * sf.adhesion * fl_.m[li] * std::clamp(1.0 - (gap - reach_) / range_[si], 0.0, 1.0)) * nn;
  if (touching) {
    const double por = c_.wetting.porosity;
    double jn = 0.0;
    if (por == 0.0) {
      // The particle goes back to the reach; the nodes move only by the impulse (moving them
      // would stretch stiff springs of light nodes: energy from nowhere).
      p.x[i] += (reach_ - gap) * nn;
      moved = true;
      if (vn < 0) jn = -(1.0 + sf.restitution) * vn / weff;
    } else if (por < 1.0) {
      // Seepage: v_n → v_n / (1 + h/τ), τ = kSeepTime·p/(1 − p).
      const double tau = kSeepTime * por / (1.0 - por);
      jn = -vn * (h / tau) / (1.0 + h / tau) / weff;
    }
    // Coulomb friction on the tangential relative velocity, bounded by μ·|J_n|.
    const Vec3 vt = vrel - vn * nn;
    const double st = vt.norm();
    J += jn * nn;
    if (st > 0) J -= std::min(st / weff, sf.friction * std::abs(jn)) * (vt / st);
  }
  if (J.isZero()) return moved;
  p.v[i] += wp * J;
  for (int k = 0; k < 3; ++k) {
    if (m_.fixed[node(k)])
      c_.pin_liquid_force -= (ct.w[k] / h) * J;
    else
      vnode(k) -= (ct.w[k] * m_.inv_mass[node(k)]) * J;
  }
  return true;
}

// Nodes holding a drop's mass beyond their capacity release it below themselves, into the liquid
// the sheet soaked up last.
void ClothLiquidHook::end(const StepContext& ctx) {
  const double g = ctx.gravity.norm();
  if (c_.capacity.empty() || !(g > 0) || c_.wet_from != liquid_) return;
  const Vec3 down = ctx.gravity / g;
  std::vector<Vec3>& x = sheet_->state.x;
  std::vector<Vec3>& v = sheet_->state.v;
  for (std::size_t i = 0; i < c_.wet.size(); ++i) {
    const int sp = c_.wet_species[i];
    const double drop = fl_.species_mass[static_cast<std::size_t>(sp)];
    if (!(c_.wet[i] - c_.capacity[i] >= drop)) continue;
    if (static_cast<long long>(fl_.x.size()) >= fl_.max_particles) return;
    addParticle(fl_, x[i] + (1.2 * reach_) * down, v[i], sp);
    wetNode(c_, m_, v[i], i, -drop, v[i]);
    ++c_.dripped;
  }
}

}  // namespace

std::unique_ptr<ContactHook> clothLiquidHook(Body& liquid, Body& sheet) {
  return std::make_unique<ClothLiquidHook>(dynamic_cast<FluidBody&>(liquid), dynamic_cast<ClothBody&>(sheet));
}

}  // namespace reel
