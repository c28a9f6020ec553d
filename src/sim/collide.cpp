#include "sim/collide.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/parallel.h"

namespace reel {

Collider makeCollider(const ObjectDesc& o) {
  Collider c;
  c.kind = o.kind;
  c.thickness = o.thickness;
  c.surface = o.surface;
  switch (o.kind) {
    case ObjectKind::Plane:
      c.p0 = o.point;
      c.R = rotationFromUp(o.normal);
      if (o.extent) c.half = Vec3((*o.extent)[0] / 2, 0, (*o.extent)[1] / 2);
      break;
    case ObjectKind::Sphere:
      c.p0 = o.center;
      c.radius = o.radius;
      break;
    case ObjectKind::Box:
      c.p0 = o.center;
      c.half = o.size / 2;
      c.R = rotationFromEulerDeg(o.rotation_deg);
      break;
    case ObjectKind::Capsule:
      c.p0 = o.a;
      c.p1 = o.b;
      c.radius = o.radius;
      break;
    case ObjectKind::Mesh:
      break;  // drawn only: collisions with triangle meshes come with the cloth module
  }
  return c;
}

bool Collider::distance(const Vec3& p, double& d, Vec3& n) const {
  switch (kind) {
    case ObjectKind::Plane: {
      const Vec3 q = R.transpose() * (p - p0);  // local: y along the normal
      if (half.x() > 0) {
        // A finite plane is a sheet, not a slab: it catches nodes just below its surface (those
        // that crossed it this step), never ones that pass far beneath it.
        if (std::abs(q.x()) > half.x() || std::abs(q.z()) > half.z()) return false;
        if (q.y() < -(thickness + 0.05 * std::min(half.x(), half.z()))) return false;
      }
      d = q.y();
      n = R.col(1);
      return true;
    }
    case ObjectKind::Sphere: {
      const Vec3 r = p - p0;
      const double len = r.norm();
      d = len - radius;
      n = len > 0 ? Vec3(r / len) : Vec3::UnitY();
      return true;
    }
    case ObjectKind::Box: {
      const Vec3 q = R.transpose() * (p - p0);
      const Vec3 out = q.cwiseAbs() - half;  // per-axis distance outside the faces
      if (out.maxCoeff() > 0) {
        const Vec3 o = out.cwiseMax(0.0);
        d = o.norm();
        Vec3 ln(q.x() > 0 ? o.x() : -o.x(), q.y() > 0 ? o.y() : -o.y(), q.z() > 0 ? o.z() : -o.z());
        n = R * (ln / d);
      } else {  // inside: leave through the nearest face
        int axis = 0;
        out.maxCoeff(&axis);
        d = out[axis];
        Vec3 ln = Vec3::Zero();
        ln[axis] = q[axis] >= 0 ? 1.0 : -1.0;
        n = R * ln;
      }
      return true;
    }
    case ObjectKind::Capsule: {
      const Vec3 ab = p1 - p0;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - p0).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const Vec3 r = p - (p0 + t * ab);
      const double len = r.norm();
      d = len - radius;
      n = len > 0 ? Vec3(r / len) : Vec3::UnitY();
      return true;
    }
    case ObjectKind::Mesh: return false;
  }
  return false;
}

void resolveContacts(const std::vector<Collider>& colliders, double radius, double h,
                     const std::uint8_t* fixed, std::vector<Vec3>& x, std::vector<Vec3>& v) {
  if (colliders.empty()) return;
  parallelFor(static_cast<std::ptrdiff_t>(x.size()), [&](std::ptrdiff_t i) {
    if (fixed[i]) return;
    for (const Collider& c : colliders) {
      double d;
      Vec3 n;
      if (!c.distance(x[i], d, n)) continue;
      const double reach = c.thickness + radius;
      if (d >= reach) continue;
      x[i] += (reach - d) * n;  // project onto the surface
      const double vn = v[i].dot(n);
      if (vn >= 0) continue;  // already separating
      const Vec3 vt = v[i] - vn * n;
      const double e = c.surface.restitution;
      const double vt_len = vt.norm();
      const double keep =
          vt_len > 0 ? std::max(0.0, vt_len - c.surface.friction * (1.0 + e) * (-vn)) / vt_len : 0.0;
      v[i] = keep * vt - e * vn * n;
      x[i] += (h * (keep - 1.0)) * vt;  // the step's tangential drift, redone at the new velocity
    }
  });
}

}  // namespace reel
