#include "sim/cloth/cloth_body.h"

#include <algorithm>

#include "core/profile.h"
#include "sim/contact_layer.h"

namespace reel {

void ClothBody::step(StepContext& ctx) {
  MassSpringState& s = net_.state;
  cloth_.pin_liquid_force.setZero();  // what liquids give the pins this step (the contact layer's hook)
  gripVelocities(cloth_, ctx.t0, *ctx.colliders, s.v);
  const AirDesc& air = cloth_.air;
  if (air.viscous != 0.0 || air.drag != 0.0 || air.lift != 0.0) {
    airForces(cloth_, *ctx.wind, ctx.t0, s.x, s.v);
    net_.system->setExternalForces(cloth_.f_air.data());
  }
  net_.integrate(ctx);
  net_.system->setExternalForces(nullptr);
  gripPositions(cloth_, ctx.t1, *ctx.colliders, s.x);
  {
    profile::Scope stage(profile::Stage::StrainLimit);
    limitStrain(cloth_, net_.model, ctx.h, s.x, s.v);
  }
  if (cloth_.self_collision) {
    profile::Scope stage(profile::Stage::SelfCollision);
    selfCollide(cloth_, net_.model, s.x, s.v);
  }
  net_.contacts(ctx);
  handBackGrips(cloth_, net_.model, s, ctx.h, *ctx.colliders, *ctx.coupling);
  spreadWetness(cloth_, net_.model, s.x, s.v, ctx.gravity, ctx.h);
  profile::Scope stage(profile::Stage::Tearing);
  tearSprings(cloth_, net_.model, s.x);
}

// The sheet meets other bodies with its intact triangles (a torn one opens the tear) and with its
// border as threads, so that two sheets whose rims cross between their nodes (a falling sheet's
// hem across a hanging one's top) catch there: the edge–edge handler.
void ClothBody::exportSurface(ContactExport& out) const {
  std::size_t alive = 0;
  for (std::size_t t = 0; t < cloth_.tris.size(); ++t)
    if (cloth_.tri_alive[t]) {
      out.triangle(cloth_.tris[t][0], cloth_.tris[t][1], cloth_.tris[t][2]);
      ++alive;
    }
  if (alive != border_at_) {
    if (edges_of_.empty()) {  // the sheet's edges and the one or two triangles of each, found once
      std::vector<std::array<int, 3>> e;  // (a < b, triangle)
      e.reserve(3 * cloth_.tris.size());
      for (std::size_t t = 0; t < cloth_.tris.size(); ++t)
        for (int k = 0; k < 3; ++k) {
          const int a = cloth_.tris[t][k], b = cloth_.tris[t][(k + 1) % 3];
          e.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t)});
        }
      std::sort(e.begin(), e.end());
      for (std::size_t i = 0; i < e.size(); ++i) {
        if (i > 0 && e[i][0] == e[i - 1][0] && e[i][1] == e[i - 1][1]) {
          tris_of_.back()[1] = e[i][2];
          continue;
        }
        edges_of_.push_back({e[i][0], e[i][1]});
        tris_of_.push_back({e[i][2], -1});
      }
    }
    border_.clear();
    for (std::size_t k = 0; k < edges_of_.size(); ++k) {
      const auto [s, t] = tris_of_[k];
      const bool a = cloth_.tri_alive[static_cast<std::size_t>(s)] != 0;
      const bool b = t >= 0 && cloth_.tri_alive[static_cast<std::size_t>(t)] != 0;
      if (a != b) border_.push_back(edges_of_[k]);
    }
    border_at_ = alive;
  }
  for (const auto& b : border_) out.edge(b[0], b[1]);
}

bool ClothBody::view(BodyView& out) const {
  SpringNetworkBody::view(out);
  out.masses = net_.model.mass;  // they grow as the sheet soaks liquid up
  return true;
}

void ClothBody::statistics(std::vector<Statistic>& out) const {
  const Vec3& g = net_.model.gravity;
  const Vec3 up = g.norm() > 0 ? Vec3(-g.normalized()) : Vec3::UnitY();
  out.push_back({"support_force", supportForce(cloth_, net_.model, net_.state).dot(up)});
  if (cloth_.capacity.empty()) return;
  double wet = 0.0;
  for (double w : cloth_.wet) wet += w;
  out.push_back({"wet_mass", wet});
  out.push_back({"absorbed", static_cast<double>(cloth_.absorbed)});
  out.push_back({"dripped", static_cast<double>(cloth_.dripped)});
}

// Besides the nodes: the springs left (tearing removes them) and the sheet's state, in one order
// for writing and reading.
template <class Self, class Archive>
void ClothBody::fields(Self& self, Archive& a) {
  auto& sp = self.net_.model.springs;
  auto& c = self.cloth_;
  a(sp.a)(sp.b)(sp.stiffness)(sp.damping)(sp.rest);
  a(c.spring_id)(c.intact)(c.limited)(c.tear_strain)(c.tri_alive)(c.x_prev)(c.self_passes)(c.springs_broken);
  a(c.wet)(c.wet_species)(c.wet_from)(c.absorbed)(c.dripped)(c.pin_liquid_force);
}

void ClothBody::snapshotMore(StateWriter& w) const { fields(*this, w); }

bool ClothBody::restoreMore(StateReader& r) {
  fields(*this, r);
  border_at_ = static_cast<std::size_t>(-1);  // found again from the restored triangles
  const Springs& sp = net_.model.springs;
  const ClothState& c = cloth_;
  const std::size_t n = net_.model.nodes(), ns = sp.a.size();
  // Sizes and indices as this sheet's (a blob of another sheet, or a damaged one, is refused).
  const std::size_t ids = cloth_.holds.size();
  for (std::size_t size : {sp.b.size(), sp.stiffness.size(), sp.damping.size(), sp.rest.size(), c.spring_id.size(),
                           c.limited.size()})
    if (size != ns) return false;
  if (!r.ok() || ns > ids || c.intact.size() != ids || c.tri_alive.size() != cloth_.tris.size() ||
      !(c.tear_strain.empty() || c.tear_strain.size() == ns) || !(c.x_prev.empty() || c.x_prev.size() == n))
    return false;
  if (c.wet.size() != cloth_.capacity.size() || c.wet_species.size() != c.wet.size()) return false;
  for (std::size_t i = 0; i < c.wet.size(); ++i)
    if (!(c.wet[i] >= 0 && c.wet[i] < 1e6) || c.wet_species[i] < 0) return false;
  for (std::size_t k = 0; k < ns; ++k)
    if (sp.a[k] < 0 || sp.b[k] < 0 || static_cast<std::size_t>(sp.a[k]) >= n || static_cast<std::size_t>(sp.b[k]) >= n ||
        c.spring_id[k] < 0 || static_cast<std::size_t>(c.spring_id[k]) >= ids)
      return false;
  net_.model.incidence.build(n, sp);
  // Node masses: dry plus the liquid held.
  for (std::size_t i = 0; i < n; ++i) setNodeMass(net_.model, i, cloth_.dry_mass[i] + (c.wet.empty() ? 0.0 : c.wet[i]));
  return true;
}

Result<std::unique_ptr<Body>> buildClothBody(const BodyDesc& desc, const BuildContext& ctx) {
  const auto& d = desc.as<ClothDesc>();
  auto b = std::make_unique<ClothBody>(desc.name, desc.type, desc.material);
  if (Status st = buildNetwork(*b, buildCloth(d, ctx.seed, b->cloth()), desc, ctx, d.thickness); !st) return st.error();
  // Grips held by objects: the scene's objects, then the bodies' own (a figure's links), by name.
  std::vector<std::string> names;
  for (const ObjectDesc& o : ctx.scene->objects) names.push_back(o.name);
  for (const BodyDesc& bd : ctx.scene->bodies)
    for (const ObjectDesc& o : bd.params->ownObjects()) names.push_back(o.name);
  auto& grip_collider = b->cloth().grip_collider;
  grip_collider.assign(d.grips.size(), -1);
  for (std::size_t g = 0; g < d.grips.size(); ++g) {
    if (d.grips[g].object.empty()) continue;
    const auto at = std::find(names.begin(), names.end(), d.grips[g].object);
    if (at == names.end())
      return Error(ErrorKind::BadInput, desc.path + "/grips/" + std::to_string(g) + "/object: no object '" + d.grips[g].object +
                                            "' (objects and figures' links, as figure/link)");
    grip_collider[g] = static_cast<int>(at - names.begin());
  }
  return std::unique_ptr<Body>(std::move(b));
}

}  // namespace reel
