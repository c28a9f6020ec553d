#include "sim/articulated/controllers.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace reel {
namespace {

using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain: the convex hull, counter-clockwise.
std::vector<Vec2> hull2(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) { return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y(); });
  if (p.size() < 3) return p;
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross2(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Signed distance of q inside the convex polygon (positive inside; a polygon of fewer than three
// corners has no inside).
double insideBy(const std::vector<Vec2>& poly, const Vec2& q) {
  if (poly.size() < 3) return -1e300;
  double d = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    const Vec2 e = b - a;
    const double len = e.norm();
    if (len <= 0) continue;
    d = std::min(d, (e.x() * (q.y() - a.y()) - e.y() * (q.x() - a.x())) / len);
  }
  return d;
}

void addTo(std::vector<double>& target, int at, double amount) {
  if (static_cast<int>(target.size()) > at) target[static_cast<std::size_t>(at)] += amount;
}

}  // namespace

HumanRoles humanRoles(const ArticulatedModel& m) {
  HumanRoles r;
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const std::string& n = m.links[i].name;
    const int k = static_cast<int>(i);
    if (n == "pelvis") r.pelvis = k;
    else if (n == "abdomen") r.abdomen = k;
    else if (n == "chest") r.chest = k;
    else if (n == "head") r.head = k;
    else if (n == "thigh_l") r.thigh_l = k;
    else if (n == "thigh_r") r.thigh_r = k;
    else if (n == "shin_l") r.shin_l = k;
    else if (n == "shin_r") r.shin_r = k;
    else if (n == "foot_l") r.foot_l = k;
    else if (n == "foot_r") r.foot_r = k;
    else if (n == "upper_arm_l") r.upper_arm_l = k;
    else if (n == "upper_arm_r") r.upper_arm_r = k;
    else if (n == "forearm_l") r.forearm_l = k;
    else if (n == "forearm_r") r.forearm_r = k;
  }
  return r;
}

Vec3 heading(const Mat3& R, const Vec3& up) {
  Vec3 forward = R.col(2) - R.col(2).dot(up) * up;
  if (forward.norm() < 0.2) forward = -(R.col(1) - R.col(1).dot(up) * up);
  if (forward.norm() < 1e-6) forward = perpendicular(up);
  return forward.normalized();
}

void centreOfMass(const ArticulatedModel& m, const ArtKinematics& k, Vec3& c, Vec3& v) {
  double mass = 0;
  c = v = Vec3::Zero();
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    mass += m.links[i].mass;
    c += m.links[i].mass * k.x[i];
    v += m.links[i].mass * pointVelocity(k.vel[i], k.x[i]);
  }
  c /= mass;
  v /= mass;
}

ControllerKind supervise(const ArticulatedModel& m, const HumanRoles& roles, const ControllersDesc& c,
                         const ControlInput& in, std::vector<std::vector<double>>& targets) {
  if (!roles.valid() || !(c.balance || c.protect)) return ControllerKind::None;
  const ArtKinematics& k = *in.k;
  const Vec3 up = in.up();
  // The pelvis's heading frame on the ground: forward (its z) and side (its x), horizontal.
  const auto pelvis = static_cast<std::size_t>(roles.pelvis);
  const Vec3 forward = heading(k.R[pelvis], up);
  const Vec3 side = up.cross(forward);  // the figure's +x when upright (its left)
  const Vec3 &com = in.com, &vcom = in.vcom;
  auto flat = [&](const Vec3& p) { return Vec2(p.dot(side), p.dot(forward)); };
  std::vector<Vec2> pts;
  Vec2 centre(0, 0);
  for (const Vec3& p : *in.foot_points) {
    pts.push_back(flat(p));
    centre += pts.back();
  }
  const std::vector<Vec2> support = hull2(pts);
  const double inside = insideBy(support, flat(com));
  const bool standing = in.left_down && in.right_down;
  // Balance: both feet down, the centre of mass over the support.
  if (c.balance && standing && inside >= c.margin) {
    centre /= static_cast<double>(pts.size());
    const Vec2 d = flat(com) - centre, dv = flat(vcom);
    const double pitch = c.position_gain * d.y() + c.velocity_gain * dv.y();
    const double roll = -(c.position_gain * d.x() + c.velocity_gain * dv.x());
    for (int foot : {roles.foot_l, roles.foot_r}) {
      const ArtJoint& j = m.joints[static_cast<std::size_t>(foot)];
      if (j.type != JointType::Universal) continue;
      auto& t = targets[static_cast<std::size_t>(foot)];
      addTo(t, 0, pitch);
      addTo(t, 1, roll);
    }
    return ControllerKind::Balance;
  }
  // Protect: falling while the chest is still well above the feet.
  const auto chest = static_cast<std::size_t>(roles.chest);
  double ground = 1e300;
  for (int foot : {roles.foot_l, roles.foot_r}) ground = std::min(ground, k.x[static_cast<std::size_t>(foot)].dot(up));
  const bool high = k.x[chest].dot(up) - ground > 0.35;
  const Vec3 hv = vcom - vcom.dot(up) * up;
  if (c.protect && high && (!standing || inside < c.margin) && hv.norm() > 0.05) {
    // The fall's direction in the chest's frame; each arm swings from hanging toward it.
    const Vec3 dir = k.R[chest].transpose() * (hv.normalized() - 0.3 * up).normalized();
    const Vec3 hang(0, -1, 0);
    Vec3 axis = hang.cross(dir);
    if (axis.norm() < 1e-6) axis = Vec3::UnitX();
    const Vec3 r = (c.reach_deg * kPi / 180.0) * axis.normalized();
    for (int arm : {roles.upper_arm_l, roles.upper_arm_r})
      if (arm >= 0 && m.joints[static_cast<std::size_t>(arm)].type == JointType::Ball) targets[static_cast<std::size_t>(arm)] = {r.x(), r.y(), r.z()};
    for (int fore : {roles.forearm_l, roles.forearm_r})
      if (fore >= 0 && m.joints[static_cast<std::size_t>(fore)].type == JointType::Hinge) targets[static_cast<std::size_t>(fore)] = {-0.35};
    return ControllerKind::Protect;
  }
  return ControllerKind::None;
}

}  // namespace reel
