#include "sim/spring_network.h"

#include <algorithm>
#include <cmath>

#include "core/profile.h"
#include "sim/contact_layer.h"

namespace reel {

void SpringNetwork::build(const MassSpringDesc& desc, const Vec3& gravity, IntegratorKind integrator,
                          double contact_radius) {
  buildMassSpring(desc, gravity, model, state);
  system = std::make_unique<MassSpringSystem>(model);
  bound = stableStep(model, integrator);
  radius = contact_radius;
}

void SpringNetwork::integrate(StepContext& ctx) {
  profile::Scope stage(profile::Stage::Integration);
  SolverStats& s = *ctx.solver;
  ImplicitSettings set = *ctx.implicit;
  if (!set.tolerance_given) set.cg_tolerance = tolerance;
  reel::integrate(ctx.integrator, *system, state.x, state.v, ctx.h, workspace, set, &s.last);
  if (implicitIntegrator(ctx.integrator) && s.last.cg_relative_residual > set.cg_tolerance) {
    ++s.unconverged;
    s.worst_residual = std::max(s.worst_residual, s.last.cg_relative_residual);
  }
}

void SpringNetwork::contacts(const StepContext& ctx) {
  profile::Scope stage(profile::Stage::Contacts);
  resolveContacts(*ctx.colliders, radius, ctx.h, model.fixed.data(), state.x, state.v);
}

std::string SpringNetwork::unstableMethod(const std::string& body, IntegratorKind integrator) const {
  if (bound.h_max > 0) return {};
  return "/integrator: " + std::string(integratorName(integrator)) + " is unstable for body '" + body +
         "': its springs are undamped (stable step bound 0); add spring or node damping, or use "
         "symplectic_euler, verlet, rk4 or implicit_euler";
}

StepLimit SpringNetwork::stepLimit(const std::string& body, IntegratorKind integrator) const {
  return {bound, "of " + std::string(integratorName(integrator)) + " for body '" + body + "' (node " + std::to_string(bound.node),
          "implicit_euler"};
}

void SpringNetwork::snapshot(StateWriter& w) const {
  w.put(state.x);
  w.put(state.v);
  w.put(workspace.dv);
  w.put(workspace.x_prev);
  w.put(workspace.v_prev);
  w.put(workspace.h_prev);
}

void SpringNetwork::restore(StateReader& r) {
  r.get(state.x);
  r.get(state.v);
  r.get(workspace.dv);
  r.get(workspace.x_prev);
  r.get(workspace.v_prev);
  r.get(workspace.h_prev);
}

Status SpringNetworkBody::checkState(const StepContext& ctx) const {
  return checkPoints(ctx, name(), "node", net_.state.x, net_.state.v, net_.bound);
}

bool SpringNetworkBody::view(BodyView& out) const {
  out.name = name();
  out.type = "mass_spring";
  out.generator = generator_;
  out.positions = net_.state.x;
  out.velocities = net_.state.v;
  out.spring_a = net_.model.springs.a;
  out.spring_b = net_.model.springs.b;
  return true;
}

void SpringNetworkBody::hash(Hasher& h) const {
  h.add(std::span<const Vec3>(net_.state.x));
  h.add(std::span<const Vec3>(net_.state.v));
}

void SpringNetworkBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  net_.snapshot(w);
  snapshotMore(w);
}

bool SpringNetworkBody::restore(const StateBlob& in) {
  StateReader r(in);
  net_.restore(r);
  const std::size_t n = net_.model.nodes();
  const IntegratorWorkspace& ws = net_.workspace;  // BDF2's step before: none, or one of n nodes
  const bool history = (ws.x_prev.empty() || ws.x_prev.size() == n) && ws.v_prev.size() == ws.x_prev.size() &&
                       allWithin(ws.x_prev, kRunawayDistance) && allWithin(ws.v_prev, kRunawaySpeed) &&
                       std::isfinite(ws.h_prev) && ws.h_prev >= 0.0;
  return restoreMore(r) && r.done() && net_.state.x.size() == n && net_.state.v.size() == n &&
         allWithin(net_.state.x, kRunawayDistance) && allWithin(net_.state.v, kRunawaySpeed) && history;
}

void SpringNetworkBody::exportContacts(ContactExport& out) const {
  out.points(net_.state.x, net_.state.v, net_.model.inv_mass, net_.radius, piece_);
  exportSurface(out);
}

void SpringNetworkBody::exportSurface(ContactExport& out) const {
  for (const auto& t : surface_) out.triangle(t[0], t[1], t[2]);
  for (const auto& e : edges_) out.edge(e[0], e[1]);
}

void SpringNetworkBody::importContacts(std::span<const Vec3> x, std::span<const Vec3> v) {
  std::copy(x.begin(), x.end(), net_.state.x.begin());
  std::copy(v.begin(), v.end(), net_.state.v.begin());
}

Status buildNetwork(SpringNetworkBody& body, const MassSpringDesc& nodes, const BodyDesc& desc, const BuildContext& ctx,
                    double contact_radius) {
  SpringNetwork& net = body.network();
  net.build(nodes, ctx.scene->gravity, ctx.scene->integrator, contact_radius);
  if (std::string e = net.unstableMethod(desc.name, ctx.scene->integrator); !e.empty())
    return Error(ErrorKind::BadInput, ctx.scene->file + ": " + e);
  return {};
}

}  // namespace reel
