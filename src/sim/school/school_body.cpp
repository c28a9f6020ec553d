#include "sim/school/school_body.h"

#include <algorithm>

#include "core/format.h"

namespace reel {

StepLimit SchoolBody::stepLimit(IntegratorKind) const {
  // Agents are moved kinematically: no step is unstable (Couzin's model decides every τ anyway).
  return {StepBound{}, "of school '" + name() + "'", ""};
}

SchoolView SchoolBody::sees(const StepContext& ctx) const {
  SchoolView pv;
  if (ctx.shown) pv.bodies = ctx.shown->points;
  const auto& p = school_.desc.predator;
  if (!p) return pv;
  if (predator_object_ >= 0) {
    pv.object = &(*ctx.colliders)[static_cast<std::size_t>(predator_object_)];
  } else if (ctx.shown) {
    for (const SharedView::Agents& a : ctx.shown->agents)
      if (a.body == p->name) pv.points = a.x, pv.velocities = a.v;
  }
  return pv;
}

void SchoolBody::show(SharedView& out, int) { out.agents.push_back({name(), &school_.x, &school_.v}); }

void SchoolBody::step(StepContext& ctx) { stepSchool(school_, *ctx.colliders, sees(ctx), ctx.t0, ctx.h); }

Status SchoolBody::checkState(const StepContext& ctx) const {
  return checkPoints(ctx, name(), "agent", school_.x, school_.v, StepBound{});
}

bool SchoolBody::view(BodyView& out) const {
  out.name = name();
  out.type = "agents";
  out.generator = "school";
  out.positions = school_.x;
  out.velocities = school_.v;
  return true;
}

// Positions, velocities, the decisions in force and their count, the tail beats.
template <class State, class Archive>
void SchoolBody::fields(State& s, Archive& a) {
  a(s.x)(s.v)(s.desired)(s.turn)(s.phase)(s.decisions);
}

void SchoolBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  fields(static_cast<const SchoolState&>(school_), w);
}

bool SchoolBody::restore(const StateBlob& in) {
  StateReader r(in);
  SchoolState s;
  fields(s, r);
  const std::size_t n = school_.size();
  if (!r.done() || s.x.size() != n || s.v.size() != n || s.desired.size() != n || s.turn.size() != n ||
      s.phase.size() != n || s.decisions < 0)
    return false;
  if (!allWithin(s.x, kRunawayDistance) || !allWithin(s.v, kRunawaySpeed)) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (!(s.v[i].norm() > 0) || !(std::abs(s.desired[i].norm() - 1) < 1e-6) || !(s.turn[i] >= 1 && s.turn[i] <= 4) ||
        !std::isfinite(s.phase[i]))
      return false;
  static_cast<SchoolState&>(school_) = std::move(s);
  return true;
}

void SchoolBody::hash(Hasher& h) const {
  h.add(std::span<const Vec3>(school_.x));
  h.add(std::span<const Vec3>(school_.v));
}

void SchoolBody::statistics(std::vector<Statistic>& out) const {
  const SchoolOrder o = schoolOrder(school_.x, school_.v);
  out.push_back({"polarization", o.polarization});
  out.push_back({"milling", o.milling});
  out.push_back({"centroid_x", o.centroid.x()});
  out.push_back({"centroid_y", o.centroid.y()});
  out.push_back({"centroid_z", o.centroid.z()});
  out.push_back({"nearest_neighbour", o.nearest});
}

std::vector<std::string> SchoolBody::notes(double h) const {
  const SchoolDesc& d = school_.desc;
  auto num = [](double x) { return formatNumber(x, 3); };
  std::string line = "school '" + name() + "': " + std::to_string(school_.size()) + " agents, ";
  if (d.model == SchoolModel::Couzin) {
    const CouzinDesc& c = d.couzin;
    line += "Couzin's zones " + num(c.r_repulsion) + " / " + num(c.r_orientation) + " / " + num(c.r_attraction) +
            " m, speed " + num(d.speed) + " m/s, deciding every " + num(c.reaction_time) + " s (the scene steps " +
            num(h) + " s" + (h > c.reaction_time ? ": every step, turns capped at θh" : "") + ")";
  } else {
    line += "boids, speed " + num(d.boids.min_speed) + " to " + num(d.boids.max_speed) + " m/s, acceleration up to " +
            num(d.boids.max_accel) + " m/s²";
  }
  return {line};
}

Result<std::unique_ptr<Body>> buildSchoolBody(const BodyDesc& desc, const BuildContext& ctx) {
  const auto& d = desc.as<SchoolDesc>();
  int object = -1;
  if (d.predator) {
    // The loader checked that the name is an object or a school of the scene.
    if (!d.predator->is_school) object = objectIndex(*ctx.scene, d.predator->name);
  }
  School s = makeSchool(d, desc.name, ctx.seed);
  return std::unique_ptr<Body>(std::make_unique<SchoolBody>(std::move(s), desc.material, object));
}

}  // namespace reel
