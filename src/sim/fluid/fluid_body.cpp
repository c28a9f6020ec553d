#include "sim/fluid/fluid_body.h"

#include <cmath>

#include "core/format.h"
#include "sim/contact_layer.h"
#include "sim/fluid/fluid_diffuse.h"

namespace reel {

StepLimit FluidBody::stepLimit(IntegratorKind) const {
  // The liquid always steps by symplectic Euler; its bound names the pair of species that sets it.
  const auto S = static_cast<std::size_t>(fluid_.species_count);
  const auto pair = static_cast<std::size_t>(std::max(bound_.node, 0));
  return {bound_,
          "of fluid '" + name() + "' (species '" + fluid_.species_names[pair / S] + "' with '" +
              fluid_.species_names[pair % S] + "'",
          fluid_.model == LiquidModel::Dfsph ? "a lower viscosity (docs/fluids.md)" : "softer alpha and beta (docs/fluids.md)"};
}

void FluidBody::step(StepContext& ctx) {
  stepFluid(fluid_, *ctx.colliders, ctx.gravity, ctx.h, ctx.t0, ctx.t1);
}

void FluidBody::exportContacts(ContactExport& out) const {
  inv_mass_.resize(fluid_.m.size());
  for (std::size_t i = 0; i < inv_mass_.size(); ++i) inv_mass_[i] = 1.0 / fluid_.m[i];
  out.points(fluid_.x, fluid_.v, inv_mass_, fluid_.radius);
  if (fluid_.x_start.size() == fluid_.x.size()) out.starts(fluid_.x_start);
  out.surfaces(fluid_.surfaces, fluid_.species_count, fluid_.adhesion_range, fluid_.s);
}

void FluidBody::importContacts(std::span<const Vec3> x, std::span<const Vec3> v) {
  std::copy(x.begin(), x.end(), fluid_.x.begin());
  std::copy(v.begin(), v.end(), fluid_.v.begin());
}

void FluidBody::dropPoints(std::span<const std::uint8_t> gone) {
  removeParticles(fluid_, std::vector<std::uint8_t>(gone.begin(), gone.end()));
}

Status FluidBody::checkState(const StepContext& ctx) const {
  return checkPoints(ctx, name(), "particle", fluid_.x, fluid_.v, bound_);
}

const Fluid& FluidBody::byId() const {
  fluidById(fluid_);
  return fluid_;
}

bool FluidBody::view(BodyView& out) const {
  const Fluid& fl = byId();  // particles in order of creation, whatever slots they sit in
  out.name = name();
  out.type = "particles";
  out.generator = generator_;
  out.positions = fl.x_by_id;
  out.velocities = fl.v_by_id;
  out.species = fl.s_by_id;
  out.species_names = fl.species_names;
  return true;
}

// The particles, nozzles' progress, the neighbour list and its build positions, the random
// stream's position and the statistics, in one order for writing and reading.
template <class State, class Archive>
void FluidBody::fields(State& s, Archive& a) {
  a(s.x)(s.v)(s.s)(s.m)(s.id)(s.layers)(s.x_built)(s.nbr_start)(s.nbr)(s.list_skin)(s.list_age);
  a(s.thermal_draws)(s.rebuilds)(s.pair_tests)(s.split_steps)(s.skipped);
  a(s.diffuse_x)(s.diffuse_v)(s.diffuse_life)(s.diffuse_kind)(s.diffuse_id)(s.diffuse_time)(s.diffuse_ticks)(s.diffuse_made);
}

void FluidBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  fields(static_cast<const FluidState&>(fluid_), w);
}

bool FluidBody::restore(const StateBlob& in) {
  StateReader r(in);
  FluidState& s = fluid_;
  fields(s, r);
  const std::size_t n = s.x.size();
  if (!r.done() || s.v.size() != n || s.s.size() != n || s.m.size() != n || s.id.size() != n ||
      s.layers.size() != fluid_.emitters.size() || s.x_built.size() > n ||
      (!s.x_built.empty() && s.nbr_start.size() != s.x_built.size() + 1) ||
      (!s.nbr_start.empty() && s.nbr.size() != s.nbr_start.back()) ||
      !(s.list_skin == 0 || (s.list_skin > 0 && s.list_skin <= fluid_.skin)) || (!s.x_built.empty() && s.list_skin == 0) ||
      s.list_age < 0)
    return false;
  const std::size_t d = s.diffuse_x.size();
  if (s.diffuse_v.size() != d || s.diffuse_life.size() != d || s.diffuse_kind.size() != d || s.diffuse_id.size() != d ||
      d > kMaxDiffuse || !allWithin(s.diffuse_x, kRunawayDistance) || !allWithin(s.diffuse_v, kRunawaySpeed) ||
      !(s.diffuse_time >= 0 && s.diffuse_time < 1e9) || s.diffuse_ticks < 0 || s.diffuse_made < 0)
    return false;
  for (std::size_t k = 0; k < d; ++k)
    if (s.diffuse_kind[k] > static_cast<std::uint8_t>(DiffuseKind::Bubble) || !(s.diffuse_life[k] > 0 && s.diffuse_life[k] < 1e9) ||
        s.diffuse_id[k] < 0 || s.diffuse_id[k] >= s.diffuse_made)
      return false;
  if (!allWithin(s.x, kRunawayDistance) || !allWithin(s.v, kRunawaySpeed) || !allWithin(s.x_built, kRunawayDistance))
    return false;
  // Species and ids in range, each id once; the list's rows in order and its entries in range.
  std::vector<std::uint8_t> seen(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (s.s[i] < 0 || s.s[i] >= fluid_.species_count || s.id[i] < 0 || static_cast<std::size_t>(s.id[i]) >= n ||
        seen[static_cast<std::size_t>(s.id[i])]++)
      return false;
  }
  if (!s.nbr_start.empty() && s.nbr_start[0] != 0) return false;
  for (std::size_t i = 1; i < s.nbr_start.size(); ++i)
    if (s.nbr_start[i] < s.nbr_start[i - 1]) return false;
  for (std::int32_t j : s.nbr)
    if (j < 0 || static_cast<std::size_t>(j) >= n) return false;
  rebuildGrid(fluid_);
  return true;
}

void FluidBody::hash(Hasher& h) const {
  const Fluid& fl = byId();
  h.add(std::span<const Vec3>(fl.x_by_id));
  h.add(std::span<const Vec3>(fl.v_by_id));
  h.add(std::span<const Vec3>(fl.diffuse_x));
  h.add(std::span<const Vec3>(fl.diffuse_v));
  h.add(std::span<const double>(fl.diffuse_life));
  h.add(std::span<const long long>(fl.diffuse_id));
}

std::vector<std::string> FluidBody::notes(double h) const {
  const Fluid& fl = fluid_;
  auto num = [](double x, int d) { return formatNumber(x, d); };
  std::vector<std::string> out;
  out.push_back("fluid '" + name() + "': " + std::to_string(fl.size()) + " particles at the start, stable step " +
                num(bound_.h_max, 3) + " s (this scene steps " + num(h, 3) + " s)");
  if (fl.model == LiquidModel::Dfsph) {
    out.push_back("  divergence-free SPH: particles " + num(0.5 * fl.kernel_support, 4) + " m apart at rest, kernel reach " +
                  num(fl.kernel_support, 4) + " m");
    for (int k = 0; k < fl.species_count; ++k)
      out.push_back("  species '" + fl.species_names[static_cast<std::size_t>(k)] + "': rest density " +
                    num(fl.species_mass[static_cast<std::size_t>(k)] / fl.species_volume[static_cast<std::size_t>(k)], 4) +
                    " kg/m³, spacing " + num(std::cbrt(fl.species_volume[static_cast<std::size_t>(k)]), 4) + " m");
  }
  for (int k = 0; k < fl.species_count && fl.model == LiquidModel::Pairs; ++k) {
    const PairParams& p = fl.pairs[static_cast<std::size_t>(k * fl.species_count + k)];
    out.push_back("  species '" + fl.species_names[static_cast<std::size_t>(k)] + "': rest distance " +
                  num(restDistance(p), 4) + " m, bulk spacing " + num(bulkSpacing(p), 4) + " m, cutoff " +
                  num(p.cutoff, 4) + " m");
  }
  // A nozzle whose layers leave farther apart than its species' cutoff pours separate discs (no
  // pair force joins them): say so, with the rate that would pack them at the layer's spacing.
  for (std::size_t k = 0; k < fl.emitters.size(); ++k) {
    const FluidEmitter& e = fl.emitters[k];
    const PairParams& p = fl.pairs[static_cast<std::size_t>(e.desc.species * (fl.species_count + 1))];
    const double gap = e.desc.speed * e.layer_dt;
    if (!(gap > p.cutoff)) continue;
    out.push_back("  emitter " + std::to_string(k) + ": its layers leave " + num(gap, 3) + " m apart, farther than the cutoff " +
                  num(p.cutoff, 4) + " m: it pours separate discs; \"rate\": " +
                  num(std::ceil(e.desc.rate * gap / e.desc.spacing), 4) + " (layers " + num(e.desc.spacing, 3) +
                  " m apart) pours one stream");
  }
  return out;
}

Result<std::unique_ptr<Body>> buildFluidBody(const BodyDesc& desc, const BuildContext& ctx) {
  const auto& d = desc.as<FluidDesc>();
  Fluid fl = buildFluid(d, desc.name, *ctx.colliders, ctx.seed);
  for (const SpeciesDesc& sp : d.species) fl.species_transmission.push_back(sp.transmission.value_or(desc.material.transmission));
  return std::unique_ptr<Body>(std::make_unique<FluidBody>(std::move(fl), desc.type, desc.material));
}

}  // namespace reel
