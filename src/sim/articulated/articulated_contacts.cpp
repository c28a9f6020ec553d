// An articulated body's constraints: contacts with the objects and with free bodies (rigid bodies,
// other figures' links) with Coulomb friction, and joint limits, as velocity constraints solved by
// projected Gauss–Seidel with impulses through the step's factorised matrix (see articulated.h).
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "sim/articulated/articulated_body.h"

namespace reel {
namespace {

constexpr double kSlop = 0.002;        // m of overlap left alone
constexpr double kPushRate = 0.2;      // share of an overlap (or limit overshoot) taken back per step
constexpr double kMaxPush = 2.0;       // m/s, the fastest push out
constexpr double kLimitMargin = 0.02;  // rad: a limit this close enters the solve

// The least velocity a constraint at `gap` (negative: overshoot) allows along its row: a gap may
// close within the step (speculative); an overshoot beyond `slop` is taken back at kPushRate a step.
double closingTarget(double gap, double slop, double h) {
  return gap > 0 ? -gap / h : std::min(kPushRate * std::max(0.0, -gap - slop) / h, kMaxPush);
}

}  // namespace

// Contacts with the objects and joint limits as velocity constraints on v (projected Gauss–Seidel
// over the rows, impulses through the factorised matrix of the step).
void ArticulatedBody::constrain(StepContext& ctx, VecX& v) {
  const double h = ctx.h;
  const std::vector<Collider>& colliders = *ctx.colliders;
  if (!parts_.built) {
    const std::size_t first = model_.links.front().collider;
    buildParts(colliders, parts_, true, first, first + model_.links.size());
  }
  ArtScratch& s = s_;
  const ArtKinematics& k = s.k;  // at the configuration the rows are built for
  // Free bodies met (rigid bodies, other figures' links): their velocities as the solve changes
  // them, and the impulses they take (handed back when the figure publishes its step).
  struct Partner {
    std::size_t collider = 0;
    double inv_mass = 0;
    Mat3 inv_inertia = Mat3::Zero();
    Vec3 centre{0, 0, 0}, v{0, 0, 0}, w{0, 0, 0};
  };
  std::vector<Partner> partners;
  handbacks_.clear();
  const int nv = model_.nv;
  struct Row {
    double b0 = 0, target = 0, mu = 0;
    int kind = 0;  // 0: unilateral (normal, limit); 1, 2: a contact's two tangents (normal: row − kind)
    int partner = -1;  // a free body's, whose point's velocity b0 follows
    Vec3 dir{0, 0, 0}, at{0, 0, 0};  // the impulse's direction on the partner, and where
  };
  std::vector<Row> rows;
  std::vector<double> jac;  // the rows' Jacobians, nv numbers each
  auto addJacobian = [&](const VecX& J) { jac.insert(jac.end(), J.data(), J.data() + nv); };
  linkVelocities(model_, v, s.k);
  foot_points_.clear();
  left_down_ = right_down_ = false;
  // A link point's velocity as a row: Σ over the joints up to the root of S_v + S_ω × at.
  auto pointJacobian = [&](std::size_t link, const Vec3& at, Eigen::Matrix<double, 3, Eigen::Dynamic>& Jp) {
    Jp.setZero(3, nv);
    for (int a = static_cast<int>(link); a >= 0; a = model_.joints[static_cast<std::size_t>(a)].parent) {
      const ArtJoint& j = model_.joints[static_cast<std::size_t>(a)];
      for (int c = 0; c < j.nv; ++c) {
        const Vec6 col = k.S.col(j.vi + c);
        Jp.col(j.vi + c) = col.tail<3>() + col.head<3>().cross(at);
      }
    }
  };
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jp;
  // The parts near the whole figure once; each link then tries those near its own box.
  std::vector<Vec3> link_lo(model_.links.size()), link_hi(model_.links.size());
  std::vector<double> link_margin(model_.links.size(), -1.0);  // −1: a link whose state is not usable
  Vec3 fig_lo = Vec3::Constant(1e300), fig_hi = Vec3::Constant(-1e300);
  for (std::size_t i = 0; i < model_.links.size(); ++i) {
    if (!k.x[i].allFinite() || !k.vel[i].allFinite() || !(k.x[i].norm() < kRunawayDistance)) {
      singular_ = singular_ || !k.x[i].allFinite();  // (the state check stops the run)
      continue;
    }
    const ArtLink& l = model_.links[i];
    const double speed = k.vel[i].head<3>().norm() * l.extent + pointVelocity(k.vel[i], k.x[i]).norm();
    link_margin[i] = 0.004 + h * speed;
    shapeBounds(l.shape, Pose{k.R[i], k.x[i]}, link_lo[i], link_hi[i]);
    link_lo[i] -= Vec3::Constant(link_margin[i]);
    link_hi[i] += Vec3::Constant(link_margin[i]);
    fig_lo = fig_lo.cwiseMin(link_lo[i]);
    fig_hi = fig_hi.cwiseMax(link_hi[i]);
  }
  // Refreshed every 8 steps from a box grown by what 8 steps can close at up to 20 m/s (a list that
  // holds every part in reach, so the contacts do not depend on when it was made: a resumed run
  // makes it afresh and finds the same).
  std::vector<std::uint32_t>& candidates = candidates_;
  if (candidate_age_ <= 0 || candidate_age_ >= 8) {
    double fastest = 0.0;
    for (std::size_t i = 0; i < model_.links.size(); ++i)
      if (k.vel[i].allFinite()) fastest = std::max(fastest, pointVelocity(k.vel[i], k.x[i]).norm() + k.vel[i].head<3>().norm() * model_.links[i].extent);
    const double grow = 8.0 * h * (fastest + 20.0) + 0.05;
    candidates.clear();
    if ((fig_lo.array() <= fig_hi.array()).all())
      partsNear(parts_, colliders, fig_lo - Vec3::Constant(grow), fig_hi + Vec3::Constant(grow), candidates);
    candidate_age_ = 0;
  }
  ++candidate_age_;
  for (std::size_t i = 0; i < model_.links.size(); ++i) {
    const ArtLink& l = model_.links[i];
    const Pose pose{k.R[i], k.x[i]};
    const double margin = link_margin[i];
    if (margin < 0) continue;
    for (std::uint32_t pi : candidates) {
      const ObjectPart& part = parts_.parts[pi];
      // A figure that stepped before this one met this link itself and handed it the opposite.
      if (ctx.solved && (*ctx.solved)[part.collider]) continue;
      const Collider& c = colliders[part.collider];
      if (c.shape->bound_radius < 1e300) {  // the link's box against the part's collider's sphere first
        const Vec3 centre = c.fromAuthored(c.shape->bound_center);
        if ((centre.cwiseMax(link_lo[i]).cwiseMin(link_hi[i]) - centre).squaredNorm() > c.shape->bound_radius * c.shape->bound_radius) continue;
      }
      Manifold mf;
      if (!collidePart(l.shape, pose, part, c, margin, mf)) continue;
      const double mu = std::sqrt(l.surface.friction * c.shape->surface.friction);
      int partner = -1;
      if (c.shape->free_body && c.pose.inv_mass > 0) {
        for (std::size_t q = 0; q < partners.size(); ++q)
          if (partners[q].collider == part.collider) partner = static_cast<int>(q);
        if (partner < 0) {
          Partner pt;
          pt.collider = part.collider;
          pt.inv_mass = c.pose.inv_mass;
          pt.inv_inertia = c.pose.inv_inertia;
          pt.centre = c.pose.centre;
          pt.v = c.velocityAt(c.pose.centre);
          pt.w = c.angularVelocity();
          partner = static_cast<int>(partners.size());
          partners.push_back(pt);
        }
      }
      for (int pt = 0; pt < mf.count; ++pt) {
        const ContactPoint& cp = mf.points[static_cast<std::size_t>(pt)];
        pointJacobian(i, cp.position, Jp);
        const Vec3 vs = c.moving() ? c.velocityAt(cp.position) : Vec3::Zero();
        const Vec3 n = mf.normal, t1 = perpendicular(n), t2 = n.cross(t1);
        const double sep = -cp.depth;
        if (sep < 0.005 && (static_cast<int>(i) == roles_.foot_l || static_cast<int>(i) == roles_.foot_r)) {
          foot_points_.push_back(cp.position);
          (static_cast<int>(i) == roles_.foot_l ? left_down_ : right_down_) = true;
        }
        Row r;
        r.partner = partner;
        r.dir = n;
        r.at = cp.position;
        r.b0 = n.dot(vs);
        r.target = closingTarget(sep, kSlop, h);
        r.mu = mu;
        rows.push_back(r);
        addJacobian(-(Jp.transpose() * n));
        for (int t = 1; t <= 2; ++t) {
          const Vec3& dir = t == 1 ? t1 : t2;
          Row f;
          f.kind = t;
          f.partner = partner;
          f.dir = dir;
          f.at = cp.position;
          f.b0 = dir.dot(vs);
          f.mu = mu;
          rows.push_back(f);
          addJacobian(-(Jp.transpose() * dir));
        }
      }
    }
  }
  contacts_ = static_cast<int>(rows.size() / 3);
  // Joint limits: a coordinate near its bound, or a ball near its cone.
  auto limitRow = [&](int dof, double sign, double gap) {
    VecX J = VecX::Zero(nv);
    J[dof] = sign;
    Row r;
    r.target = closingTarget(gap, 0.0, h);
    rows.push_back(r);
    addJacobian(J);
  };
  for (std::size_t i = 0; i < model_.joints.size(); ++i) {
    const ArtJoint& j = model_.joints[i];
    if (j.type == JointType::Hinge || j.type == JointType::Universal) {
      for (int d = 0; d < j.nv && d < static_cast<int>(j.lower.size()); ++d) {
        const double th = state_.q[j.qi + d], rate = std::abs(v[j.vi + d]) * h + kLimitMargin;
        const double lo_gap = th - j.lower[static_cast<std::size_t>(d)], hi_gap = j.upper[static_cast<std::size_t>(d)] - th;
        if (lo_gap < rate) limitRow(j.vi + d, 1.0, lo_gap);
        if (hi_gap < rate) limitRow(j.vi + d, -1.0, hi_gap);
      }
    } else if (j.type == JointType::Ball && j.cone > 0) {
      const std::vector<double> r = jointAngles(model_, state_.q, static_cast<int>(i));
      const Vec3 rv(r[0], r[1], r[2]);
      const double angle = rv.norm(), gap = j.cone - angle;
      if (angle > 1e-9 && gap < v.segment<3>(j.vi).norm() * h + kLimitMargin) {
        VecX J = VecX::Zero(nv);
        J.segment<3>(j.vi) = -rv / angle;  // d(cone − angle)/dt = −u·ω
        Row row;
        row.target = closingTarget(gap, 0.0, h);
        rows.push_back(row);
        addJacobian(J);
      }
    }
  }
  if (rows.empty()) return;
  const int m = static_cast<int>(rows.size());
  s.J = Eigen::Map<const MatX>(jac.data(), nv, m);  // column r: row r's Jacobian
  s.W = s.llt.solve(s.J);  // nv × m: the velocity change of a unit impulse on each row
  VecX diag(m), lambda = VecX::Zero(m);
  for (int r = 0; r < m; ++r) {
    diag[r] = s.J.col(r).dot(s.W.col(r));
    const Row& row = rows[static_cast<std::size_t>(r)];
    if (row.partner < 0) continue;
    const Partner& pt = partners[static_cast<std::size_t>(row.partner)];
    const Vec3 rc = (row.at - pt.centre).cross(row.dir);
    diag[r] += pt.inv_mass + rc.dot(pt.inv_inertia * rc);
  }
  // A row's relative velocity: the figure's side, and the partner's point as the solve moves it.
  auto relative = [&](int r) {
    const Row& row = rows[static_cast<std::size_t>(r)];
    double u = s.J.col(r).dot(v);
    if (row.partner < 0) return u + row.b0;
    const Partner& pt = partners[static_cast<std::size_t>(row.partner)];
    return u + row.dir.dot(pt.v + pt.w.cross(row.at - pt.centre));
  };
  // An impulse λ on row r: the figure through W, the partner the opposite way.
  auto apply = [&](int r, double dl) {
    v += s.W.col(r) * dl;
    const Row& row = rows[static_cast<std::size_t>(r)];
    if (row.partner < 0) return;
    Partner& pt = partners[static_cast<std::size_t>(row.partner)];
    pt.v += pt.inv_mass * dl * row.dir;
    pt.w += pt.inv_inertia * ((row.at - pt.centre).cross(row.dir) * dl);
  };
  // Passes until no row's velocity changes by more than 1e-6 m/s (or rad/s), at most `iterations`.
  for (int it = 0; it < model_.iterations; ++it) {
    double change = 0.0;
    for (int r = 0; r < m; ++r) {
      const Row& row = rows[static_cast<std::size_t>(r)];
      if (row.kind != 0) continue;
      if (!(diag[r] > 0)) continue;
      const double l = std::max(0.0, lambda[r] + (row.target - relative(r)) / diag[r]);
      apply(r, l - lambda[r]);
      change = std::max(change, std::abs(l - lambda[r]) * diag[r]);
      lambda[r] = l;
      // The contact's friction (its tangents follow), in the circle of radius μ·λ_n.
      if (r + 2 < m && rows[static_cast<std::size_t>(r + 1)].kind == 1) {
        const int a = r + 1, b = r + 2;
        double la = diag[a] > 0 ? lambda[a] - relative(a) / diag[a] : 0.0;
        double lb = diag[b] > 0 ? lambda[b] - relative(b) / diag[b] : 0.0;
        const double lim = row.mu * lambda[r], len = std::sqrt(la * la + lb * lb);
        if (len > lim && len > 0) la *= lim / len, lb *= lim / len;
        apply(a, la - lambda[a]);
        apply(b, lb - lambda[b]);
        change = std::max({change, std::abs(la - lambda[a]) * diag[a], std::abs(lb - lambda[b]) * diag[b]});
        lambda[a] = la;
        lambda[b] = lb;
      }
    }
    if (change < 1e-6) break;
  }
  // What the partners took, to hand back (the figure's point was pushed along −dir by λ).
  for (int r = 0; r < m; ++r) {
    const Row& row = rows[static_cast<std::size_t>(r)];
    if (row.partner >= 0 && lambda[r] != 0.0)
      handbacks_.push_back({partners[static_cast<std::size_t>(row.partner)].collider, row.at, -lambda[r] * row.dir});
  }
}

}  // namespace reel
