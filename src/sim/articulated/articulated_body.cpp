#include "sim/articulated/articulated_body.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/figure.h"
#include "core/math.h"
#include "sim/contact_layer.h"
#include "sim/rigid/hull.h"
#include "sim/rigid/rigid.h"

namespace reel {
namespace {

std::vector<double> toVector(const VecX& v, int i, int n) { return std::vector<double>(v.data() + i, v.data() + i + n); }

}  // namespace

ArticulatedBody::ArticulatedBody(std::string name, ArticulatedModel model, ArticulatedState state)
    : Body(std::move(name)), model_(std::move(model)), state_(std::move(state)), roles_(humanRoles(model_)) {
  for (const ArtLink& l : model_.links) mass_view_.push_back(l.mass);
  // Per velocity: the servo's gains (0 where none or where its torque limit is 0) and damping.
  const int nv = model_.nv;
  gains_.kp = gains_.kd = gains_.damp = VecX::Zero(nv);
  gains_.cap = VecX::Constant(nv, 1e300);
  for (const ArtJoint& j : model_.joints) {
    if (j.type == JointType::Free) continue;
    for (int d = 0; d < j.nv; ++d) {
      gains_.damp[j.vi + d] = j.damping;
      if (j.servo.kp > 0 && j.servo.max_torque > 0 && !j.target.empty()) {
        gains_.kp[j.vi + d] = j.servo.kp;
        gains_.kd[j.vi + d] = j.servo.kd;
        gains_.cap[j.vi + d] = j.servo.max_torque;
      }
    }
  }
  refresh();
}

void ArticulatedBody::refresh() {
  forwardKinematics(model_, state_.q, view_k_);
  linkVelocities(model_, state_.v, view_k_);
  x_view_ = view_k_.x;
  v_view_.resize(x_view_.size());
  for (std::size_t i = 0; i < x_view_.size(); ++i) v_view_[i] = pointVelocity(view_k_.vel[i], x_view_[i]);
}

// The smooth dynamics with the servos: v* (and, for rk4, q moved).
void ArticulatedBody::smoothStep(StepContext& ctx, VecX& v_star, bool& moved) {
  const double h = ctx.h;
  ArtScratch& s = s_;
  const int nv = model_.nv;
  servoTargets(model_, ctx.t1, s.targets);
  ControlInput in;
  in.k = &view_k_;
  in.foot_points = &foot_points_;
  in.left_down = left_down_;
  in.right_down = right_down_;
  in.gravity = ctx.gravity;
  in.t = ctx.t1;
  if (model_.controllers.any()) centreOfMass(model_, view_k_, in.com, in.vcom);
  active_ = standUp(roles_, model_.controllers, in, stand_, s.targets)
                ? ControllerKind::StandUp
                : supervise(model_, roles_, model_.controllers, in, s.targets);
  // What the other bodies handed the links (coupling stage), as forces over the step.
  s.f_ext.assign(model_.links.size(), Vec6::Zero());
  for (std::size_t i = 0; i < model_.links.size(); ++i) {
    const std::size_t c = model_.links[i].collider;
    const Vec3 J = ctx.coupling->impulse[c];
    const Vec3 L = ctx.coupling->angular[c] + (*ctx.colliders)[c].pose.pos.cross(J);
    s.f_ext[i].head<3>() = L / h;
    s.f_ext[i].tail<3>() = J / h;
  }
  // Pushes whose time falls in this step, through their link's centre of mass (now: view_k_).
  for (const PushDesc& push : model_.pushes)
    if ((push.time > ctx.t0 || (ctx.t0 == 0.0 && push.time == 0.0)) && push.time <= ctx.t1) {
      const auto i = static_cast<std::size_t>(push.link);
      s.f_ext[i].head<3>() += view_k_.x[i].cross(push.impulse) / h;
      s.f_ext[i].tail<3>() += push.impulse / h;
    }
  const VecX &kp = gains_.kp, &kd = gains_.kd, &damp = gains_.damp, &cap = gains_.cap;
  auto dynamics = [&](const VecX& q, const VecX& v, MatX& M, VecX& C) {
    forwardKinematics(model_, q, s.k);
    linkVelocities(model_, v, s.k);
    biasForces(model_, s.k, ctx.gravity, s.f_ext, C);
    massMatrix(model_, s.k, M);
    servoErrors(model_, q, s.targets, s.e);
  };
  // Gravity compensation: the servos also give the torques that hold the figure still against
  // gravity (C at zero velocity and no outside force), so they need no error to carry its weight.
  auto gravityHold = [&](VecX& hold) {
    hold.setZero(nv);
    if (!model_.gravity_compensation) return;
    ArtKinematics still = s.k;
    linkVelocities(model_, VecX::Zero(nv), still);
    biasForces(model_, still, ctx.gravity, {}, hold);
    for (int d = 0; d < nv; ++d)
      if (kp[d] <= 0) hold[d] = 0.0;
  };
  if (ctx.integrator == IntegratorKind::Rk4) {
    // Classical Runge–Kutta on (q, v), the servos explicit and clamped.
    auto accel = [&](const VecX& q, const VecX& v, VecX& a) {
      dynamics(q, v, s.M, s.C);
      VecX tau;
      gravityHold(tau);
      tau += -kp.cwiseProduct(s.e) - (kd + damp).cwiseProduct(v);
      for (int d = 0; d < nv; ++d) {
        const double servo = -kp[d] * s.e[d] - kd[d] * v[d];
        tau[d] += std::clamp(servo, -cap[d], cap[d]) - servo;
      }
      Eigen::LLT<MatX> llt(s.M);
      if (llt.info() != Eigen::Success) singular_ = true;
      a = llt.solve(tau - s.C);
    };
    const VecX q0 = state_.q, v0 = state_.v;
    VecX a1, a2, a3, a4, q = q0;
    accel(q0, v0, a1);
    const VecX v2 = v0 + 0.5 * h * a1;
    integrateCoordinates(model_, q, v0, 0.5 * h);
    accel(q, v2, a2);
    const VecX v3 = v0 + 0.5 * h * a2;
    q = q0;
    integrateCoordinates(model_, q, v2, 0.5 * h);
    accel(q, v3, a3);
    const VecX v4 = v0 + h * a3;
    q = q0;
    integrateCoordinates(model_, q, v3, h);
    accel(q, v4, a4);
    q = q0;
    integrateCoordinates(model_, q, (v0 + 2.0 * v2 + 2.0 * v3 + v4) / 6.0, h);
    state_.q = q;
    v_star = v0 + (h / 6.0) * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    dynamics(state_.q, v_star, s.M, s.C);
    s.llt.compute(s.M);
    moved = true;
    return;
  }
  // Semi-implicit with stable PD: (M + h·(h·Kp + Kd + D))·a = −C − Kp·(e + h·v) − (Kd + D)·v; a servo
  // whose torque would pass its limit gives that limit instead (explicit), and the step is solved again.
  dynamics(state_.q, state_.v, s.M, s.C);
  const VecX& v = state_.v;
  VecX hold;
  gravityHold(hold);
  std::vector<char> clamped(static_cast<std::size_t>(nv), 0);
  VecX a;
  for (int pass = 0; pass < 3; ++pass) {
    s.diag = damp;
    s.rhs = -s.C - damp.cwiseProduct(v) + hold;
    for (int d = 0; d < nv; ++d) {
      if (kp[d] <= 0) continue;
      if (clamped[static_cast<std::size_t>(d)]) {
        const double servo = -kp[d] * (s.e[d] + h * v[d]) - kd[d] * v[d];
        s.rhs[d] += servo > 0 ? cap[d] : -cap[d];
        continue;
      }
      s.diag[d] += h * kp[d] + kd[d];
      s.rhs[d] += -kp[d] * (s.e[d] + h * v[d]) - kd[d] * v[d];
    }
    s.Mt = s.M;
    s.Mt.diagonal() += h * s.diag;
    s.llt.compute(s.Mt);
    if (s.llt.info() != Eigen::Success) singular_ = true;
    a = s.llt.solve(s.rhs);
    bool more = false;
    for (int d = 0; d < nv; ++d) {
      if (kp[d] <= 0 || clamped[static_cast<std::size_t>(d)]) continue;
      const double vp = v[d] + h * a[d];
      const double tau = -kp[d] * (s.e[d] + h * vp) - kd[d] * vp;
      if (std::abs(tau) > cap[d]) clamped[static_cast<std::size_t>(d)] = 1, more = true;
    }
    if (!more) break;
  }
  v_star = v + h * a;
  moved = false;
}

void ArticulatedBody::step(StepContext& ctx) {
  VecX v;
  bool moved = false;
  smoothStep(ctx, v, moved);
  if (moved) {
    const VecX v_free = v;
    constrain(ctx, v);
    integrateCoordinates(model_, state_.q, v - v_free, ctx.h);
  } else {
    constrain(ctx, v);
    integrateCoordinates(model_, state_.q, v, ctx.h);
  }
  state_.v = v;
  refresh();
}

void ArticulatedBody::publish(StepContext& ctx) {
  pose(*ctx.colliders, ctx.h);
  // Coupling::handBack gives the collider the opposite of what the figure took.
  for (const Handback& b : handbacks_) ctx.coupling->handBack(b.collider, b.at, (*ctx.colliders)[b.collider].pose.pos, b.impulse);
}

void ArticulatedBody::pose(std::vector<Collider>& colliders, double h) const {
  for (std::size_t i = 0; i < model_.links.size(); ++i) {
    const ArtLink& l = model_.links[i];
    Collider& c = colliders[l.collider];
    c.pose.rot_prev = c.pose.rot;
    c.pose.pos_prev = c.pose.pos;
    c.pose.dt = h;
    c.pose.rot = view_k_.R[i] * l.axes0.transpose();
    c.pose.pos = view_k_.x[i] + view_k_.R[i] * l.pivot;
    // Met by another figure as a free body of the link's mass (its joints not counted).
    c.pose.inv_mass = 1.0 / l.mass;
    c.pose.inv_inertia = view_k_.R[i] * l.inertia.inverse() * view_k_.R[i].transpose();
    c.pose.centre = view_k_.x[i];
  }
}

Status ArticulatedBody::checkState(const StepContext& ctx) const {
  if (singular_)
    return Error(ErrorKind::Unstable, "frame " + std::to_string(ctx.frame) + ", t = " + std::to_string(ctx.t1) +
                                          " s: articulated body '" + name() + "': its joint-space inertia is not positive definite");
  // The links' centres of mass as points; then their spin.
  if (Status st = checkPoints(ctx, name(), "link", x_view_, v_view_, {}); !st) return st;
  for (std::size_t i = 0; i < model_.links.size(); ++i)
    if (!view_k_.vel[i].allFinite() || !(view_k_.vel[i].head<3>().norm() * model_.links[i].extent < kRunawaySpeed))
      return Error(ErrorKind::Unstable, "frame " + std::to_string(ctx.frame) + ", t = " + std::to_string(ctx.t1) +
                                            " s: link '" + model_.links[i].name + "' of articulated body '" + name() +
                                            "': angular velocity is not finite or ran away");
  return {};
}

void ArticulatedBody::exportConvex(ContactExport& out) const {
  for (std::size_t i = 0; i < model_.links.size(); ++i) {
    const ArtLink& l = model_.links[i];
    const Mat3& R = view_k_.R[i];
    out.convex(l.shape, Pose{R, view_k_.x[i]}, pointVelocity(view_k_.vel[i], view_k_.x[i]), view_k_.vel[i].head<3>(),
               1.0 / l.mass, R * l.inertia.inverse() * R.transpose(), l.collider);
  }
}

bool ArticulatedBody::view(BodyView& out) const {
  out.name = name();
  out.type = "articulated";
  out.generator = "articulated";
  out.positions = x_view_;
  out.velocities = v_view_;
  out.masses = mass_view_;
  ViewField q{"orientation", 4, {}}, w{"angular_velocity", 3, {}};
  for (std::size_t i = 0; i < model_.links.size(); ++i) {
    const Eigen::Quaterniond r(view_k_.R[i]);
    q.values.insert(q.values.end(), {r.w(), r.x(), r.y(), r.z()});
    const Vec3 om = view_k_.vel[i].head<3>();
    w.values.insert(w.values.end(), {om.x(), om.y(), om.z()});
    out.link_names.push_back(model_.links[i].name);
    if (model_.joints[i].parent >= 0 && model_.joints[i].type != JointType::Fixed)
      out.joints.push_back({model_.links[i].name, jointAngles(model_, state_.q, static_cast<int>(i))});
  }
  out.fields = {q, w};
  return true;
}

void ArticulatedBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  w.put(toVector(state_.q, 0, model_.nq));
  w.put(toVector(state_.v, 0, model_.nv));
  w.put(foot_points_);
  w.put(static_cast<std::uint8_t>(left_down_ + 2 * right_down_));
  w.put(std::vector<double>{static_cast<double>(stand_.phase), stand_.since, stand_.still_since});
  w.put(std::vector<double>(std::begin(stand_.from), std::end(stand_.from)));
}

bool ArticulatedBody::restore(const StateBlob& in) {
  StateReader r(in);
  std::vector<double> q, v;
  std::vector<Vec3> feet;
  std::uint8_t down = 0;
  r.get(q);
  r.get(v);
  r.get(feet);
  r.get(down);
  std::vector<double> stand, from;
  r.get(stand);
  r.get(from);
  if (!allWithin(feet, kRunawayDistance) || down > 3) return false;
  if (stand.size() != 3 || from.size() != std::size(stand_.from) || !(stand[0] >= 0 && stand[0] <= kStandUpLastPhase) ||
      stand[0] != std::floor(stand[0]) || !std::isfinite(stand[1]) || !std::isfinite(stand[2]))
    return false;
  for (double x : from)
    if (!(std::abs(x) < 1e3)) return false;
  if (!r.done() || q.size() != static_cast<std::size_t>(model_.nq) || v.size() != static_cast<std::size_t>(model_.nv)) return false;
  for (double x : q)
    if (!(std::abs(x) < kRunawayDistance)) return false;
  for (double x : v)
    if (!(std::abs(x) < kRunawaySpeed * kRunawayDistance)) return false;
  for (const ArtJoint& j : model_.joints) {
    const int at = j.type == JointType::Free ? j.qi + 3 : j.type == JointType::Ball ? j.qi : -1;
    if (at < 0) continue;
    const double n2 = q[static_cast<std::size_t>(at)] * q[static_cast<std::size_t>(at)] + q[static_cast<std::size_t>(at + 1)] * q[static_cast<std::size_t>(at + 1)] +
                      q[static_cast<std::size_t>(at + 2)] * q[static_cast<std::size_t>(at + 2)] + q[static_cast<std::size_t>(at + 3)] * q[static_cast<std::size_t>(at + 3)];
    if (!(std::abs(n2 - 1.0) < 1e-6)) return false;
  }
  state_.q = Eigen::Map<const VecX>(q.data(), model_.nq);
  state_.v = Eigen::Map<const VecX>(v.data(), model_.nv);
  foot_points_ = std::move(feet);
  candidate_age_ = 0;  // the parts near it are listed afresh
  left_down_ = (down & 1) != 0;
  right_down_ = (down & 2) != 0;
  stand_.phase = static_cast<int>(stand[0]);
  stand_.since = stand[1];
  stand_.still_since = stand[2];
  std::copy(from.begin(), from.end(), stand_.from);
  refresh();
  return true;
}

void ArticulatedBody::hash(Hasher& h) const {
  h.add(std::span<const double>(state_.q.data(), static_cast<std::size_t>(state_.q.size())));
  h.add(std::span<const double>(state_.v.data(), static_cast<std::size_t>(state_.v.size())));
  h.add(std::span<const double>(stand_.from));
  const double stand[3] = {static_cast<double>(stand_.phase), stand_.since, stand_.still_since};
  h.add(std::span<const double>(stand, 3));
}

void ArticulatedBody::statistics(std::vector<Statistic>& out) const {
  out.push_back({"kinetic_energy", kineticEnergy(model_, view_k_)});
  out.push_back({"contacts", static_cast<double>(contacts_)});
  out.push_back({"controller", static_cast<double>(static_cast<int>(active_))});
  out.push_back({"stand_up_phase", static_cast<double>(stand_.phase)});
}

Result<std::unique_ptr<Body>> buildArticulatedBody(const BodyDesc& desc, const BuildContext& ctx) {
  const auto& d = desc.as<ArticulatedDesc>();
  ArticulatedModel m;
  m.iterations = d.iterations;
  m.poses = d.poses;
  m.pushes = d.pushes;
  m.gravity_compensation = d.gravity_compensation;
  m.controllers = d.controllers;
  std::vector<Mat3> R;
  std::vector<Vec3> x;
  startPoses(d, R, x);
  for (std::size_t i = 0; i < d.links.size(); ++i) {
    const ArticulatedLinkDesc& ld = d.links[i];
    ArtJoint j;
    j.type = ld.parent < 0 ? (d.fixed_base ? JointType::Fixed : JointType::Free) : ld.joint.type;
    j.parent = ld.parent;
    j.nv = jointDofs(j.type);
    j.nq = j.type == JointType::Free ? 7 : j.type == JointType::Ball ? 4 : j.nv;
    j.qi = m.nq;
    j.vi = m.nv;
    m.nq += j.nq;
    m.nv += j.nv;
    j.axis = ld.joint.axis;
    j.axis2 = ld.joint.axis2;
    j.anchor = ld.joint.anchor;
    j.parent_anchor = ld.joint.parent_anchor;
    j.lower = ld.joint.lower;
    j.upper = ld.joint.upper;
    j.cone = ld.joint.cone;
    j.damping = ld.joint.damping;
    j.armature = ld.joint.armature;
    j.servo = ld.joint.servo;
    j.target = ld.joint.target.empty() ? ld.joint.angles : ld.joint.target;
    j.R_fixed = R[i];
    j.x_fixed = x[i];
    m.joints.push_back(j);
    ArtLink l;
    l.name = ld.name;
    l.mass = ld.mass.mass;
    l.inertia = ld.mass.inertia;
    const Mat3& Rs = ld.shape.rotation;
    const Vec3& off = ld.shape.offset;
    switch (ld.shape.kind) {
      case LinkShape::Kind::Sphere:
        l.shape.kind = CoreKind::Point;
        l.shape.a = off;
        l.shape.radius = ld.shape.radius;
        break;
      case LinkShape::Kind::Capsule:
        l.shape.kind = CoreKind::Segment;
        l.shape.a = off + Rs * Vec3(0, -0.5 * ld.shape.length, 0);
        l.shape.b = off + Rs * Vec3(0, 0.5 * ld.shape.length, 0);
        l.shape.radius = ld.shape.radius;
        break;
      case LinkShape::Kind::Box:
        l.shape.kind = CoreKind::Polytope;
        l.shape.poly = std::make_shared<ConvexPolytope>(transformedPolytope(boxPolytope(0.5 * ld.shape.size), Rs, off));
        break;
      case LinkShape::Kind::Cylinder:
        l.shape.kind = CoreKind::Polytope;
        l.shape.poly = std::make_shared<ConvexPolytope>(
            transformedPolytope(prismPolytope(ld.shape.radius, 0.5 * ld.shape.length, 16), Rs, off));
        break;
      case LinkShape::Kind::Mesh: {
        // Met as its convex hull (a flat or degenerate mesh: a sphere around its vertices).
        std::vector<Vec3> pts;
        const std::vector<float>& xyz = ld.shape.mesh->positions;
        for (std::size_t v = 0; v + 2 < xyz.size(); v += 3)
          pts.push_back(Rs * Vec3(xyz[v], xyz[v + 1], xyz[v + 2]).cwiseProduct(ld.shape.scale) + off);
        if (auto hull = convexHull(pts)) {
          l.shape.kind = CoreKind::Polytope;
          l.shape.poly = std::make_shared<ConvexPolytope>(std::move(*hull));
        } else {
          double r = 0.005;
          for (const Vec3& p : pts) r = std::max(r, (p - off).norm());
          l.shape.kind = CoreKind::Point;
          l.shape.a = off;
          l.shape.radius = r;
        }
        break;
      }
    }
    Vec3 lo, hi;
    shapeBounds(l.shape, Pose{}, lo, hi);
    l.extent = std::max(lo.norm(), hi.norm());
    l.collider = ctx.first_object + i;
    l.surface = d.objects[i].surface;
    l.axes0 = R[i];
    l.pivot = R[i].transpose() * (d.objects[i].referencePoint() - x[i]);
    m.links.push_back(std::move(l));
  }
  ArticulatedState s;
  s.q = VecX::Zero(m.nq);
  s.v = VecX::Zero(m.nv);
  for (std::size_t i = 0; i < d.links.size(); ++i) {
    const ArtJoint& j = m.joints[i];
    const std::vector<double>& a = d.links[i].joint.angles;
    switch (j.type) {
      case JointType::Free: {
        s.q.segment<3>(j.qi) = x[i];
        const Eigen::Quaterniond r(R[i]);
        s.q.segment<4>(j.qi + 3) << r.w(), r.x(), r.y(), r.z();
        s.v.segment<3>(j.vi) = d.angular_velocity;
        s.v.segment<3>(j.vi + 3) = d.velocity - d.angular_velocity.cross(x[i]);  // at the origin
        break;
      }
      case JointType::Ball: {
        const Eigen::Quaterniond r(jointRotation(d.links[i].joint, a));
        s.q.segment<4>(j.qi) << r.w(), r.x(), r.y(), r.z();
        break;
      }
      case JointType::Hinge:
      case JointType::Universal:
        for (int k = 0; k < j.nq; ++k) s.q[j.qi + k] = a[static_cast<std::size_t>(k)];
        break;
      case JointType::Fixed: break;
    }
  }
  return std::unique_ptr<Body>(std::make_unique<ArticulatedBody>(desc.name, std::move(m), std::move(s)));
}

}  // namespace reel
