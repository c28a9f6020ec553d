#include "sim/rigid/rigid.h"

namespace reel {

ConvexPolytope transformedPolytope(const ConvexPolytope& p, const Mat3& R, const Vec3& t) {
  ConvexPolytope q = p;
  for (Vec3& v : q.vertices) v = R * v + t;
  for (ConvexPolytope::Face& f : q.faces) {
    f.normal = R * f.normal;
    f.offset = f.normal.dot(q.vertices[static_cast<std::size_t>(f.loop.front())]);
  }
  return q;
}

void rotateFree(const RigidModel& m, RigidState& s, double h) {
  if (m.kinematic) return;
  // Equal moments (a sphere, a cube): ω is constant and the rotation is exactly exp(h·ω).
  if (m.moments.maxCoeff() - m.moments.minCoeff() <= 1e-12 * m.moments.maxCoeff()) {
    const double angle = s.w.norm() * h;
    if (angle > 0) s.q = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, s.w / s.w.norm())) * s.q).normalized();
    return;
  }
  // The principal frame's orientation and the angular momentum in it.
  const Eigen::Quaterniond qP(m.principal);
  Eigen::Quaterniond qp = s.q * qP;
  Vec3 L = m.moments.cwiseProduct(qp.conjugate() * s.w);
  // Strang splitting 1-2-3-2-1: each a rotation about a principal axis by τ·L_i / I_i.
  auto sub = [&](int i, double tau) {
    const double angle = tau * L[i] / m.moments[i];
    const Eigen::AngleAxisd turn(angle, Vec3::Unit(i));
    qp = qp * Eigen::Quaterniond(turn);
    L = turn.inverse() * L;
  };
  sub(0, 0.5 * h);
  sub(1, 0.5 * h);
  sub(2, h);
  sub(1, 0.5 * h);
  sub(0, 0.5 * h);
  qp.normalize();
  s.q = (qp * qP.conjugate()).normalized();
  s.w = qp * L.cwiseQuotient(m.moments);
}

double kineticEnergy(const RigidModel& m, const RigidState& s) {
  const Vec3 wb = s.q.conjugate() * s.w;
  return 0.5 * m.mass * s.v.squaredNorm() + 0.5 * wb.dot(m.inertia * wb);
}

Vec3 angularMomentum(const RigidModel& m, const RigidState& s) { return s.q * (m.inertia * (s.q.conjugate() * s.w)); }

}  // namespace reel
