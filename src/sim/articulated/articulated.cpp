#include "sim/articulated/articulated.h"

#include <algorithm>
#include <cmath>

namespace reel {
namespace {

Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return s;
}

// Motion cross product v ×m u (Featherstone 2.9): [ω × u_ω; v_O × u_ω + ω × u_v].
Vec6 crossMotion(const Vec6& v, const Vec6& u) {
  Vec6 r;
  r.head<3>() = v.head<3>().cross(u.head<3>());
  r.tail<3>() = v.tail<3>().cross(u.head<3>()) + v.head<3>().cross(u.tail<3>());
  return r;
}

// Force cross product v ×* f: [ω × f_n + v_O × f_f; ω × f_f].
Vec6 crossForce(const Vec6& v, const Vec6& f) {
  Vec6 r;
  r.head<3>() = v.head<3>().cross(f.head<3>()) + v.tail<3>().cross(f.tail<3>());
  r.tail<3>() = v.head<3>().cross(f.tail<3>());
  return r;
}

// The spatial inertia about the origin of mass m with centre c and rotational inertia Ic about
// it (world): [[Ic + m·[c]×[c]×ᵀ, m·[c]×], [m·[c]×ᵀ, m·1]] (Featherstone 2.63).
Mat6 spatialInertia(double m, const Vec3& c, const Mat3& Ic) {
  const Mat3 cx = skew(c);
  Mat6 I;
  I.topLeftCorner<3, 3>() = Ic + m * cx * cx.transpose();
  I.topRightCorner<3, 3>() = m * cx;
  I.bottomLeftCorner<3, 3>() = m * cx.transpose();
  I.bottomRightCorner<3, 3>() = m * Mat3::Identity();
  return I;
}

Eigen::Quaterniond quat(const VecX& q, int i) { return {q[i], q[i + 1], q[i + 2], q[i + 3]}; }
void setQuat(VecX& q, int i, Eigen::Quaterniond r) {
  r.normalize();
  q[i] = r.w(), q[i + 1] = r.x(), q[i + 2] = r.y(), q[i + 3] = r.z();
}
Eigen::Quaterniond expMap(const Vec3& w) {
  const double a = w.norm();
  return a > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(a, w / a)) : Eigen::Quaterniond::Identity();
}
// The rotation vector of a unit quaternion (the shorter way round).
Vec3 logMap(Eigen::Quaterniond r) {
  if (r.w() < 0) r.coeffs() = -r.coeffs();
  const double s = r.vec().norm();
  if (s < 1e-12) return 2.0 * r.vec();
  return (2.0 * std::atan2(s, r.w()) / s) * r.vec();
}

}  // namespace

void forwardKinematics(const ArticulatedModel& m, const VecX& q, ArtKinematics& k) {
  const std::size_t n = m.links.size();
  k.R.resize(n);
  k.x.resize(n);
  k.p.resize(n);
  k.I.resize(n);
  k.S.setZero(6, m.nv);
  for (std::size_t i = 0; i < n; ++i) {
    const ArtJoint& j = m.joints[i];
    if (j.parent < 0) {
      if (j.type == JointType::Free) {
        k.x[i] = q.segment<3>(j.qi);
        k.R[i] = quat(q, j.qi + 3).toRotationMatrix();
        k.S.block<6, 6>(0, j.vi).setIdentity();
      } else {
        k.x[i] = j.x_fixed;
        k.R[i] = j.R_fixed;
      }
      k.p[i] = k.x[i];
    } else {
      const auto pa = static_cast<std::size_t>(j.parent);
      Mat3 rel = Mat3::Identity();
      switch (j.type) {
        case JointType::Hinge: rel = Eigen::AngleAxisd(q[j.qi], j.axis).toRotationMatrix(); break;
        case JointType::Universal:
          rel = Eigen::AngleAxisd(q[j.qi], j.axis).toRotationMatrix() * Eigen::AngleAxisd(q[j.qi + 1], j.axis2).toRotationMatrix();
          break;
        case JointType::Ball: rel = quat(q, j.qi).toRotationMatrix(); break;
        default: break;
      }
      k.R[i] = k.R[pa] * rel;
      k.p[i] = k.x[pa] + k.R[pa] * j.parent_anchor;
      k.x[i] = k.p[i] - k.R[i] * j.anchor;
      // Motion subspace: a rotation about unit a through p is [a; p × a].
      auto column = [&](int c, const Vec3& a) {
        k.S.block<3, 1>(0, c) = a;
        k.S.block<3, 1>(3, c) = k.p[i].cross(a);
      };
      switch (j.type) {
        case JointType::Hinge: column(j.vi, k.R[pa] * j.axis); break;
        case JointType::Universal:
          column(j.vi, k.R[pa] * j.axis);
          column(j.vi + 1, k.R[i] * j.axis2);
          break;
        case JointType::Ball:
          for (int c = 0; c < 3; ++c) column(j.vi + c, k.R[i].col(c));
          break;
        default: break;
      }
    }
    const ArtLink& l = m.links[i];
    k.I[i] = spatialInertia(l.mass, k.x[i], k.R[i] * l.inertia * k.R[i].transpose());
  }
}

void linkVelocities(const ArticulatedModel& m, const VecX& v, ArtKinematics& k) {
  const std::size_t n = m.links.size();
  k.vel.resize(n);
  k.bias.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ArtJoint& j = m.joints[i];
    const Vec6 vp = j.parent < 0 ? Vec6::Zero() : k.vel[static_cast<std::size_t>(j.parent)];
    const Vec6 vj = j.nv > 0 ? Vec6(k.S.middleCols(j.vi, j.nv) * v.segment(j.vi, j.nv)) : Vec6::Zero();
    k.vel[i] = vp + vj;
    // Ṡ·v: a hinge's axis turns with the parent, a ball's axes with the child (both give vp × vj);
    // a universal's first axis turns with the parent and its second with the child; the free
    // root's subspace is constant.
    k.bias[i] = j.type == JointType::Free || j.nv == 0 ? Vec6::Zero() : crossMotion(vp, vj);
    if (j.type == JointType::Universal)
      k.bias[i] += crossMotion(Vec6(k.S.col(j.vi) * v[j.vi]), Vec6(k.S.col(j.vi + 1) * v[j.vi + 1]));
  }
}

void massMatrix(const ArticulatedModel& m, const ArtKinematics& k, MatX& M) {
  const std::size_t n = m.links.size();
  M.setZero(m.nv, m.nv);
  thread_local std::vector<Mat6> Ic;
  Ic.assign(k.I.begin(), k.I.end());
  for (std::size_t i = n; i-- > 0;) {
    const ArtJoint& j = m.joints[i];
    if (j.parent >= 0) Ic[static_cast<std::size_t>(j.parent)] += Ic[i];
  }
  // Column by column: F = Ic_i·S_i, then M[j][i] = S_jᵀ·F for i's joint and every joint above it.
  for (std::size_t i = 0; i < n; ++i) {
    const ArtJoint& j = m.joints[i];
    for (int c = 0; c < j.nv; ++c) {
      const int col = j.vi + c;
      const Vec6 F = Ic[i] * k.S.col(col);
      for (int r = j.vi; r <= col; ++r) M(r, col) = M(col, r) = k.S.col(r).dot(F);
      for (int a = j.parent; a >= 0; a = m.joints[static_cast<std::size_t>(a)].parent) {
        const ArtJoint& ja = m.joints[static_cast<std::size_t>(a)];
        for (int r = ja.vi; r < ja.vi + ja.nv; ++r) M(r, col) = M(col, r) = k.S.col(r).dot(F);
      }
      // Armature: a rotor geared to the joint adds its reflected inertia to the joint's own
      // coordinate only (MuJoCo's `armature`; Featherstone 2008, §9.5 on gear-driven joints).
      M(col, col) += j.armature;
    }
  }
}

void biasForces(const ArticulatedModel& m, const ArtKinematics& k, const Vec3& gravity, const std::vector<Vec6>& f_ext,
                VecX& C) {
  const std::size_t n = m.links.size();
  std::vector<Vec6> a(n), f(n);
  Vec6 a0 = Vec6::Zero();
  a0.tail<3>() = -gravity;  // gravity as an upward acceleration of the base (Featherstone 5.3)
  for (std::size_t i = 0; i < n; ++i) {
    const ArtJoint& j = m.joints[i];
    a[i] = (j.parent < 0 ? a0 : a[static_cast<std::size_t>(j.parent)]) + k.bias[i];
    f[i] = k.I[i] * a[i] + crossForce(k.vel[i], Vec6(k.I[i] * k.vel[i]));
    if (!f_ext.empty()) f[i] -= f_ext[i];
  }
  C.setZero(m.nv);
  for (std::size_t i = n; i-- > 0;) {
    const ArtJoint& j = m.joints[i];
    if (j.nv > 0) C.segment(j.vi, j.nv) = k.S.middleCols(j.vi, j.nv).transpose() * f[i];
    if (j.parent >= 0) f[static_cast<std::size_t>(j.parent)] += f[i];
  }
}

void integrateCoordinates(const ArticulatedModel& m, VecX& q, const VecX& v, double h) {
  for (const ArtJoint& j : m.joints) {
    switch (j.type) {
      case JointType::Free: {
        const Vec3 w = v.segment<3>(j.vi), vO = v.segment<3>(j.vi + 3);
        const Vec3 c = q.segment<3>(j.qi);
        q.segment<3>(j.qi) = c + h * (vO + w.cross(c));  // the centre of mass's velocity
        setQuat(q, j.qi + 3, expMap(h * w) * quat(q, j.qi + 3));
        break;
      }
      case JointType::Ball: setQuat(q, j.qi, quat(q, j.qi) * expMap(h * Vec3(v.segment<3>(j.vi)))); break;
      case JointType::Hinge:
      case JointType::Universal: q.segment(j.qi, j.nq) += h * v.segment(j.vi, j.nv); break;
      case JointType::Fixed: break;
    }
  }
}

std::vector<double> jointAngles(const ArticulatedModel& m, const VecX& q, int link) {
  const ArtJoint& j = m.joints[static_cast<std::size_t>(link)];
  if (j.type == JointType::Ball) {
    const Vec3 r = logMap(quat(q, j.qi));
    return {r.x(), r.y(), r.z()};
  }
  if (j.type == JointType::Hinge || j.type == JointType::Universal)
    return std::vector<double>(q.data() + j.qi, q.data() + j.qi + j.nq);
  return {};
}

void servoErrors(const ArticulatedModel& m, const VecX& q, const std::vector<std::vector<double>>& targets, VecX& e) {
  e.setZero(m.nv);
  for (std::size_t i = 0; i < m.joints.size(); ++i) {
    const ArtJoint& j = m.joints[i];
    const std::vector<double>& t = targets[i];
    if (t.empty()) continue;
    if (j.type == JointType::Ball) {
      const Vec3 r(t[0], t[1], t[2]);
      e.segment<3>(j.vi) = logMap(expMap(r).conjugate() * quat(q, j.qi));
    } else if (j.type == JointType::Hinge || j.type == JointType::Universal) {
      for (int d = 0; d < j.nv; ++d) e[j.vi + d] = q[j.qi + d] - t[static_cast<std::size_t>(d)];
    }
  }
}

void servoTargets(const ArticulatedModel& m, double t, std::vector<std::vector<double>>& targets) {
  targets.resize(m.joints.size());
  for (std::size_t i = 0; i < m.joints.size(); ++i) targets[i] = m.joints[i].target;
  if (m.poses.empty()) return;
  // Per joint: the keys that name it, interpolated linearly; held before the first and after the last.
  for (std::size_t i = 0; i < m.joints.size(); ++i) {
    const PoseKey* before = nullptr;
    const PoseKey* after = nullptr;
    const std::vector<double>* vb = nullptr;
    const std::vector<double>* va = nullptr;
    for (const PoseKey& key : m.poses)
      for (const auto& [link, angles] : key.targets) {
        if (static_cast<std::size_t>(link) != i) continue;
        if (key.time <= t) before = &key, vb = &angles;
        else if (!after) after = &key, va = &angles;
      }
    if (!before && !after) continue;
    if (!before) targets[i] = *va;
    else if (!after) targets[i] = *vb;
    else {
      const double s = (t - before->time) / (after->time - before->time);
      targets[i].resize(vb->size());
      for (std::size_t d = 0; d < vb->size(); ++d) targets[i][d] = (1 - s) * (*vb)[d] + s * (*va)[d];
    }
  }
}

double kineticEnergy(const ArticulatedModel& m, const ArtKinematics& k) {
  double e = 0;
  for (std::size_t i = 0; i < m.links.size(); ++i) e += 0.5 * k.vel[i].dot(k.I[i] * k.vel[i]);
  return e;
}

double potentialEnergy(const ArticulatedModel& m, const ArtKinematics& k, const Vec3& gravity) {
  double e = 0;
  for (std::size_t i = 0; i < m.links.size(); ++i) e -= m.links[i].mass * gravity.dot(k.x[i]);
  return e;
}

}  // namespace reel
