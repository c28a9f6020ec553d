#include "sim/free_object.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace reel {

FreeObject makeFreeObject(const ObjectDesc& o, std::size_t collider) {
  FreeObject b;
  b.collider = collider;
  b.mass = o.mass;
  const double m = o.mass;
  auto boxInertia = [&](const Vec3& size) {
    Mat3 I = Mat3::Zero();
    I(0, 0) = size.y() * size.y() + size.z() * size.z();
    I(1, 1) = size.x() * size.x() + size.z() * size.z();
    I(2, 2) = size.x() * size.x() + size.y() * size.y();
    return Mat3(I * (m / 12.0));
  };
  // A box's (or a container's, as its solid box: an approximation) inertia and samples at its
  // corners, edge midpoints and face centres.
  auto solidBox = [&](const Vec3& center, const Vec3& size, const Vec3& rotation_deg) {
    const Mat3 R = rotationFromEulerDeg(rotation_deg);
    b.inertia = R * boxInertia(size) * R.transpose();
    for (int c = 0; c < 27; ++c) {
      const Vec3 l(c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1);
      if (l.isZero()) continue;
      b.samples.push_back(center + R * (0.5 * size.cwiseProduct(l)));
    }
  };
  switch (o.kind()) {
    case ObjectKind::Sphere: {
      const auto& s = o.as<SphereShape>();
      b.inertia = Mat3::Identity() * (0.4 * m * s.radius * s.radius);
      b.samples.push_back(s.center);
      b.sample_radius = s.radius;
      break;
    }
    case ObjectKind::Box: {
      const auto& s = o.as<BoxShape>();
      solidBox(s.center, s.size, s.rotation_deg);
      break;
    }
    case ObjectKind::Container: {
      const auto& s = o.as<ContainerShape>();
      solidBox(s.center, s.size, s.rotation_deg);
      break;
    }
    case ObjectKind::Capsule: {
      // A solid cylinder of the segment's length plus the two hemispheres' volume-equivalent.
      const auto& s = o.as<CapsuleShape>();
      const Vec3 ab = s.b - s.a;
      const double L = ab.norm() + 4.0 * s.radius / 3.0, r = s.radius;
      const double ia = 0.5 * m * r * r, ip = m * (3 * r * r + L * L) / 12.0;
      const Vec3 u = ab.norm() > 0 ? Vec3(ab.normalized()) : Vec3::UnitY();
      b.inertia = ip * Mat3::Identity() + (ia - ip) * u * u.transpose();
      for (int k = 0; k <= 4; ++k) b.samples.push_back(s.a + (k / 4.0) * ab);
      b.sample_radius = r;
      break;
    }
    case ObjectKind::Mesh: {
      const auto& s = o.as<MeshObjectShape>();
      const TriMesh placed = placeMesh(*s.mesh, s.scale, rotationFromEulerDeg(s.rotation_deg), s.position);
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      const std::size_t nv = placed.vertexCount(), stride = std::max<std::size_t>(1, nv / 400);
      for (std::size_t i = 0; i < nv; ++i) {
        const Vec3 p(placed.positions[3 * i], placed.positions[3 * i + 1], placed.positions[3 * i + 2]);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
        if (i % stride == 0) b.samples.push_back(p);
      }
      b.inertia = boxInertia(hi - lo);
      break;
    }
    case ObjectKind::Plane:
      break;  // the loader refuses free planes
  }
  return b;
}

void stepFreeObject(FreeObject& b, std::vector<Collider>& colliders, const Vec3& impulse, const Vec3& angular,
                    const Vec3& gravity, double h) {
  Collider& self = colliders[b.collider];
  const Mat3 I = self.rot * b.inertia * self.rot.transpose();  // world frame
  const Mat3 Iinv = I.inverse();
  b.v += impulse / b.mass + h * gravity;
  b.w += Iinv * angular;
  self.rot_prev = self.rot;
  self.pos_prev = self.pos;
  self.dt = h;
  self.pos += h * b.v;
  const double angle = b.w.norm() * h;
  if (angle > 0) self.rot = Eigen::AngleAxisd(angle, b.w.normalized()).toRotationMatrix() * self.rot;
  const Mat3 Iwinv = (self.rot * b.inertia * self.rot.transpose()).inverse();  // at the new pose
  // Contacts with the other objects at the sample points.
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    const Collider& c = colliders[k];
    if (k == b.collider || c.free_body) continue;
    double deepest = 0.0;
    Vec3 push = Vec3::Zero();
    for (const Vec3& s : b.samples) {
      const Vec3 p = self.rot * (s - self.pivot) + self.pos;
      double d;
      Vec3 n;
      if (!c.distance(p, d, n)) continue;
      const double reach = c.thickness + b.sample_radius;
      if (d >= reach) continue;
      if (reach - d > deepest) {
        deepest = reach - d;
        push = n;
      }
      // The contact point on the surface, and the velocity of the object's point there relative
      // to the surface.
      const Vec3 q = p - b.sample_radius * n;
      const Vec3 r = q - self.pos;
      const Vec3 vr = b.v + b.w.cross(r) - (c.moving() ? c.velocityAt(q) : Vec3::Zero());
      const double vn = vr.dot(n);
      if (vn >= 0) continue;
      auto effMass = [&](const Vec3& dir) { return 1.0 / b.mass + dir.dot((Iwinv * r.cross(dir)).cross(r)); };
      const double jn = -(1.0 + c.surface.restitution) * vn / effMass(n);
      Vec3 J = jn * n;
      const Vec3 vt = vr - vn * n;
      const double vtl = vt.norm();
      if (vtl > 1e-12) {
        const Vec3 t = vt / vtl;
        const double jt = std::min(vtl / effMass(t), c.surface.friction * jn);
        J -= jt * t;
      }
      b.v += J / b.mass;
      b.w += Iwinv * r.cross(J);
    }
    if (deepest > 0) self.pos += deepest * push;
  }
}

void FreeObjectBody::step(StepContext& ctx) {
  const std::size_t c = object_.collider;
  stepFreeObject(object_, *ctx.colliders, ctx.coupling->impulse[c], ctx.coupling->angular[c], ctx.gravity, ctx.h);
  pos_ = (*ctx.colliders)[c].pos;
  rot_ = (*ctx.colliders)[c].rot;
}

void FreeObjectBody::snapshot(StateBlob& out) const {
  StateWriter w(out);
  w.put(object_.v);
  w.put(object_.w);
  w.put(pos_);
  w.put(rot_);
}

bool FreeObjectBody::restore(const StateBlob& in) {
  StateReader r(in);
  r.get(object_.v);
  r.get(object_.w);
  r.get(pos_);
  r.get(rot_);
  return r.done() && allWithin({pos_, object_.v, object_.w, rot_.col(0), rot_.col(1), rot_.col(2)}, kRunawayDistance);
}

void FreeObjectBody::hash(Hasher& h) const {
  const Vec3 state[4] = {pos_, object_.v, object_.w, rot_.col(0) + 2.0 * rot_.col(1)};
  h.add(std::span<const Vec3>(state, 4));
}

}  // namespace reel
