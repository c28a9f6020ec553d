#include "sim/rigid/rigid_body.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/math.h"
#include "sim/contact_layer.h"

namespace reel {

RigidBody::RigidBody(std::string name, std::vector<RigidModel> models, std::vector<RigidState> states, int iterations)
    : Body(std::move(name)), models_(std::move(models)), states_(std::move(states)), iterations_(iterations) {
  for (const RigidModel& m : models_) mass_view_.push_back(m.mass);
  refreshView();
}

void RigidBody::refreshView() {
  x_view_.resize(states_.size());
  v_view_.resize(states_.size());
  for (std::size_t i = 0; i < states_.size(); ++i) {
    x_view_[i] = states_[i].x;
    v_view_[i] = states_[i].v;
  }
}

void RigidBody::follow(const std::vector<Collider>& colliders) {
  for (std::size_t i = 0; i < models_.size(); ++i) {
    const RigidModel& m = models_[i];
    if (!m.kinematic) continue;
    const Collider& c = colliders[m.collider];
    RigidState& s = states_[i];
    const Mat3 R = c.pose.rot * m.axes0;
    s.q = Eigen::Quaterniond(R).normalized();
    s.x = c.fromAuthored(m.center0);
    s.v = c.velocityAt(s.x);
    s.w = c.angularVelocity();
  }
}

void RigidBody::pose(std::vector<Collider>& colliders, double h) {
  for (std::size_t i = 0; i < models_.size(); ++i) {
    const RigidModel& m = models_[i];
    if (m.kinematic) continue;
    Collider& c = colliders[m.collider];
    const RigidState& s = states_[i];
    const Mat3 R = s.q.toRotationMatrix();
    c.pose.rot_prev = c.pose.rot;
    c.pose.pos_prev = c.pose.pos;
    c.pose.dt = h;
    c.pose.rot = R * m.axes0.transpose();
    c.pose.pos = s.x + R * m.pivot;
    c.pose.inv_mass = m.inv_mass;
    c.pose.inv_inertia = inverseInertia(m, s);
    c.pose.centre = s.x;
  }
  refreshView();
}

void RigidBody::step(StepContext&) { REEL_CHECK(false, "rigid body '" + name() + "' stepped outside the rigid system"); }

void RigidSystem::adopt(std::vector<Body*> members) {
  for (Body* b : members) {
    auto* r = static_cast<RigidBody*>(b);  // the World hands a system only bodies of its kind
    r->joint_ = &stats_;
    r->reports_joint_ = entries_.empty();
    entries_.push_back(r);
  }
}

void RigidSystem::step(StepContext& ctx) { stepRigidBodies(entries_, ctx, cache_, stats_); }

void RigidSystem::snapshot(StateBlob& out) const {
  StateWriter w(out);
  w.put(cache_.impulses);
  w.put(cache_.manifolds);
}

bool RigidSystem::restore(const StateBlob& in) {
  StateReader r(in);
  std::vector<CachedImpulse> impulses;
  std::vector<CachedManifold> manifolds;
  r.get(impulses);
  r.get(manifolds);
  if (!r.done()) return false;
  // The warm-start cache: finite, sorted (it is searched).
  if (!std::is_sorted(impulses.begin(), impulses.end())) return false;
  for (const CachedImpulse& c : impulses)
    if (!std::isfinite(c.normal) || !std::isfinite(c.t1) || !std::isfinite(c.t2) || !std::isfinite(c.anchor[0]) ||
        !std::isfinite(c.anchor[1]) || !std::isfinite(c.anchor[2]))
      return false;
  // The manifold cache: sorted, finite, at most 4 points each.
  if (!std::is_sorted(manifolds.begin(), manifolds.end())) return false;
  for (const CachedManifold& m : manifolds) {
    if (m.count < 1 || m.count > 4 || !std::isfinite(m.margin) || m.margin < 0) return false;
    bool finite = true;
    double q2 = 0, n2 = 0;
    for (int k = 0; k < 4; ++k) finite = finite && std::isfinite(m.q[static_cast<std::size_t>(k)]), q2 += m.q[static_cast<std::size_t>(k)] * m.q[static_cast<std::size_t>(k)];
    for (std::size_t k = 0; k < 3; ++k) {
      finite = finite && std::isfinite(m.t[k]) && std::isfinite(m.normal[k]);
      n2 += m.normal[k] * m.normal[k];
      for (std::size_t i = 0; i < 4; ++i) finite = finite && std::isfinite(m.on_a[i][k]) && std::isfinite(m.on_b[i][k]);
    }
    // (A unit turn and a unit normal: the normal gives the contact's tangents.)
    if (!finite || std::abs(q2 - 1.0) > 1e-9 || std::abs(n2 - 1.0) > 1e-9) return false;
  }
  cache_.impulses = std::move(impulses);
  cache_.manifolds = std::move(manifolds);
  return true;
}

std::unique_ptr<BodySystem> makeRigidSystem() { return std::make_unique<RigidSystem>(); }

Status RigidBody::checkState(const StepContext& ctx) const {
  for (std::size_t i = 0; i < states_.size(); ++i) {
    const RigidState& s = states_[i];
    const char* what = nullptr;
    if (!s.x.allFinite() || !(s.x.norm() < kRunawayDistance)) what = "position";
    else if (!s.v.allFinite() || !(s.v.norm() < kRunawaySpeed)) what = "velocity";
    else if (!s.w.allFinite() || !(s.w.norm() * models_[i].extent < kRunawaySpeed)) what = "angular velocity";
    if (what)
      return Error(ErrorKind::Unstable, "frame " + std::to_string(ctx.frame) + ", t = " + std::to_string(ctx.t1) +
                                            " s: rigid body '" + models_[i].name + "' of '" + name() + "': " + what +
                                            " is not finite or ran away");
  }
  return {};
}

void RigidBody::exportConvex(ContactExport& out) const {
  for (std::size_t i = 0; i < models_.size(); ++i) {
    const RigidModel& m = models_[i];
    const RigidState& s = states_[i];
    out.convex(m.shape, Pose{s.q.toRotationMatrix(), s.x}, s.v, s.w, m.inv_mass, inverseInertia(m, s), m.collider);
  }
}

bool RigidBody::view(BodyView& out) const {
  out.name = name();
  out.type = "rigid";
  out.generator = "rigid";
  out.positions = x_view_;
  out.velocities = v_view_;
  out.masses = mass_view_;
  ViewField q{"orientation", 4, {}}, w{"angular_velocity", 3, {}}, I{"inertia", 9, {}};
  for (std::size_t i = 0; i < states_.size(); ++i) {
    const RigidState& s = states_[i];
    q.values.insert(q.values.end(), {s.q.w(), s.q.x(), s.q.y(), s.q.z()});
    w.values.insert(w.values.end(), {s.w.x(), s.w.y(), s.w.z()});
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) I.values.push_back(models_[i].inertia(r, c));
  }
  out.fields = {q, w, I};
  return true;
}

void RigidBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  w.put(states_.size());
  for (const RigidState& s : states_) {
    w.put(s.x);
    w.put(std::array<double, 4>{s.q.w(), s.q.x(), s.q.y(), s.q.z()});
    w.put(s.v);
    w.put(s.w);
    w.put(s.rest);
    w.put(static_cast<std::uint8_t>(s.asleep));
  }
}

bool RigidBody::restore(const StateBlob& in) {
  StateReader r(in);
  std::size_t n = 0;
  r.get(n);
  if (n != states_.size()) return false;
  std::vector<RigidState> states(n);
  for (RigidState& s : states) {
    std::array<double, 4> q{};
    std::uint8_t asleep = 0;
    r.get(s.x);
    r.get(q);
    r.get(s.v);
    r.get(s.w);
    r.get(s.rest);
    r.get(asleep);
    s.q = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    s.asleep = asleep != 0;
    if (!(std::abs(s.q.norm() - 1.0) < 1e-6)) return false;
  }
  if (!r.done()) return false;
  for (const RigidState& s : states)
    if (!allWithin({s.x}, kRunawayDistance) || !allWithin({s.v, s.w}, kRunawaySpeed) || !(s.rest >= 0 && s.rest < 1e300))
      return false;
  states_ = std::move(states);
  refreshView();
  return true;
}

void RigidBody::hash(Hasher& h) const {
  for (const RigidState& s : states_) {
    const Vec3 state[5] = {s.x, s.v, s.w, s.q.vec(), Vec3(s.q.w(), s.rest, s.asleep ? 1.0 : 0.0)};
    h.add(std::span<const Vec3>(state, 5));
  }
}

void RigidBody::statistics(std::vector<Statistic>& out) const {
  double energy = 0.0;
  for (std::size_t i = 0; i < states_.size(); ++i) energy += kineticEnergy(models_[i], states_[i]);
  out.push_back({"kinetic_energy", energy});
  if (reports_joint_) {  // the first entry: the joint step's, over every rigid entry
    out.push_back({"contacts", static_cast<double>(joint_->contacts)});
    out.push_back({"asleep", static_cast<double>(joint_->asleep)});
  }
}

namespace {

// A shape in the body frame from its object as placed at t = 0: x_body = R0ᵀ·(x − c0).
Result<ConvexShape> bodyShape(const ObjectDesc& o, const Mat3& R0, const Vec3& c0) {
  const Mat3 Rt = R0.transpose();
  auto local = [&](const Vec3& a) -> Vec3 { return Rt * (a - c0); };
  ConvexShape s;
  switch (o.kind()) {
    case ObjectKind::Sphere:
      s.kind = CoreKind::Point;
      s.a = local(o.as<SphereShape>().center);
      s.radius = o.as<SphereShape>().radius;
      return s;
    case ObjectKind::Capsule: {
      const auto& c = o.as<CapsuleShape>();
      s.kind = CoreKind::Segment;
      s.a = local(c.a);
      s.b = local(c.b);
      s.radius = c.radius;
      return s;
    }
    case ObjectKind::Box: {
      const auto& b = o.as<BoxShape>();
      s.kind = CoreKind::Polytope;
      s.poly = std::make_shared<ConvexPolytope>(
          transformedPolytope(boxPolytope(0.5 * b.size), Rt * rotationFromEulerDeg(b.rotation_deg), local(b.center)));
      return s;
    }
    case ObjectKind::Mesh:
    case ObjectKind::Container: {
      // A mesh touches as its convex hull; a container as the hull of its boxes.
      std::vector<Vec3> pts;
      if (o.kind() == ObjectKind::Mesh) {
        const auto& m = o.as<MeshObjectShape>();
        const TriMesh placed = placeMesh(*m.mesh, m.scale, rotationFromEulerDeg(m.rotation_deg), m.position);
        for (std::size_t i = 0; i < placed.vertexCount(); ++i)
          pts.push_back(local(Vec3(placed.positions[3 * i], placed.positions[3 * i + 1], placed.positions[3 * i + 2])));
      } else {
        const auto& c = o.as<ContainerShape>();
        const Mat3 R = rotationFromEulerDeg(c.rotation_deg);
        for (int k = 0; k < 8; ++k)
          pts.push_back(local(c.center + R * (0.5 * c.size).cwiseProduct(Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1))));
      }
      auto hull = convexHull(pts);
      if (!hull) return Error(ErrorKind::BadInput, o.path + ": the shape is flat (its convex hull has no volume)");
      s.kind = CoreKind::Polytope;
      s.poly = std::make_shared<ConvexPolytope>(std::move(*hull));
      return s;
    }
    case ObjectKind::Plane:
      break;
  }
  return Error(ErrorKind::BadInput, o.path + ": a plane cannot be a rigid body");
}

}  // namespace

Result<std::unique_ptr<Body>> buildRigidBody(const BodyDesc& desc, const BuildContext& ctx) {
  const auto& d = desc.as<RigidDesc>();
  std::vector<RigidModel> models;
  std::vector<RigidState> states;
  for (const RigidItem& it : d.items) {
    const ObjectDesc& o = d.scene_object ? ctx.scene->objects[it.object] : d.objects[it.object];
    RigidModel m;
    m.name = it.name;
    m.collider = d.scene_object ? it.object : ctx.first_object + it.object;
    m.kinematic = it.kinematic;
    m.mass = it.mass.mass;
    m.inv_mass = m.kinematic ? 0.0 : 1.0 / m.mass;
    m.axes0 = it.axes;
    m.center0 = it.mass.center_of_mass;
    m.inertia = it.axes.transpose() * it.mass.inertia * it.axes;
    m.inertia = 0.5 * (m.inertia + m.inertia.transpose());
    // Principal axes: a proper rotation of the body frame.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(m.inertia);
    m.moments = eig.eigenvalues();
    m.principal = eig.eigenvectors();
    if (m.principal.determinant() < 0) m.principal.col(2) *= -1.0;
    if (!(m.moments.minCoeff() > 0))
      return Error(ErrorKind::BadInput, o.path + ": rigid body '" + it.name + "' has no rotational inertia about an axis");
    const Collider& c = (*ctx.colliders)[m.collider];
    m.pivot = it.axes.transpose() * (c.shape->pivot - m.center0);
    m.surface = o.surface;
    m.sleep_time = d.sleep_time;
    m.force = it.force;
    m.torque = it.torque;
    m.linear_damping = it.linear_damping;
    m.angular_damping = it.angular_damping;
    auto shape = bodyShape(o, it.axes, m.center0);
    if (!shape.ok()) return shape.error();
    m.shape = shape.value();
    Vec3 lo, hi;
    shapeBounds(m.shape, Pose{}, lo, hi);
    m.extent = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).norm();  // (the box's farthest corner from the centre of mass)
    RigidState s;
    s.x = m.center0;
    s.q = Eigen::Quaterniond(it.axes).normalized();
    s.v = it.velocity;
    s.w = it.angular_velocity;
    models.push_back(std::move(m));
    states.push_back(s);
  }
  return std::unique_ptr<Body>(std::make_unique<RigidBody>(desc.name, std::move(models), std::move(states), d.iterations));
}

}  // namespace reel
