#include "sim/collide.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "core/keys.h"
#include "core/math.h"
#include "core/parallel.h"
#include "sim/geometry.h"

namespace reel {

std::shared_ptr<MeshShape> makeMeshShape(const TriMesh& mesh, double reach) {
  auto s = std::make_shared<MeshShape>();
  s->reach = reach;
  const std::size_t nv = mesh.vertexCount();
  s->vertices.resize(nv);
  for (std::size_t i = 0; i < nv; ++i)
    s->vertices[i] = Vec3(mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]);
  std::vector<Vec3> lo, hi;
  double edge = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const std::array<int, 3> tri = {static_cast<int>(mesh.indices[3 * t]), static_cast<int>(mesh.indices[3 * t + 1]),
                                    static_cast<int>(mesh.indices[3 * t + 2])};
    const Vec3 &a = s->vertices[tri[0]], &b = s->vertices[tri[1]], &c = s->vertices[tri[2]];
    const Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 1e-14)) continue;  // degenerate: no surface to touch
    s->triangles.push_back(tri);
    s->normals.push_back(n.normalized());
    const Vec3 centre = (a + b + c) / 3.0;
    s->centres.push_back(centre);
    s->radii.push_back(std::sqrt(std::max({(a - centre).squaredNorm(), (b - centre).squaredNorm(), (c - centre).squaredNorm()})));
    lo.push_back(a.cwiseMin(b).cwiseMin(c) - Vec3::Constant(reach));
    hi.push_back(a.cwiseMax(b).cwiseMax(c) + Vec3::Constant(reach));
    edge = std::max(edge, (hi.back() - lo.back()).maxCoeff());
  }
  s->lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  s->hi = -s->lo;
  for (std::size_t t = 0; t < lo.size(); ++t) {
    s->lo = s->lo.cwiseMin(lo[t]);
    s->hi = s->hi.cwiseMax(hi[t]);
  }
  // Cells a quarter of the mean grown triangle: a query lists the triangles of its cell only, and
  // a cell as large as a grown triangle (the reach of a liquid with adhesion makes it several
  // times the triangle) listed hundreds, three quarters of a liquid film's simulation time. Each
  // triangle then lies in about 5³ cells (capped below so that a few huge triangles do not make a
  // coarse grid for the rest).
  double mean = 0.0;
  for (std::size_t t = 0; t < lo.size(); ++t) mean += (hi[t] - lo[t]).maxCoeff();
  mean = lo.empty() ? 1.0 : mean / static_cast<double>(lo.size());
  double cell = std::max(mean / 4.0, 1e-6);
  // A box may span many cells when much larger than the mean: keep it under the grid's limit.
  while (edge / cell > 15.0) cell *= 2.0;
  s->grid.build(lo, hi, cell);
  return s;
}

Collider makeCollider(const ObjectDesc& o, double reach) {
  auto shape = std::make_shared<ColliderShape>();
  ColliderShape& c = *shape;
  c.kind = o.kind();
  c.thickness = o.thickness;
  c.surface = o.surface;
  c.species_surface = o.species_surface;
  c.free_body = o.free_body;
  c.keys = o.motion;
  c.pivot = o.referencePoint();
  struct Shape {
    ColliderShape& c;
    double reach;
    double thickness;
    void operator()(const PlaneShape& s) const {
      c.p0 = s.point;
      c.R = rotationFromUp(s.normal);
      if (s.extent) c.half = Vec3((*s.extent)[0] / 2, 0, (*s.extent)[1] / 2);
      c.bound_radius = std::numeric_limits<double>::infinity();
    }
    void operator()(const SphereShape& s) const {
      c.p0 = c.bound_center = s.center;
      c.bound_radius = c.radius = s.radius;
    }
    void operator()(const BoxShape& s) const {
      c.p0 = c.bound_center = s.center;
      c.half = s.size / 2;
      c.R = rotationFromEulerDeg(s.rotation_deg);
      c.bound_radius = c.half.norm();
    }
    void operator()(const ContainerShape& s) const {
      c.p0 = c.bound_center = s.center;
      c.half = s.size / 2;
      c.R = rotationFromEulerDeg(s.rotation_deg);
      c.wall = s.wall;
      c.bound_radius = c.half.norm();
    }
    void operator()(const CapsuleShape& s) const {
      c.p0 = s.a;
      c.p1 = s.b;
      c.radius = s.radius;
      c.bound_center = 0.5 * (s.a + s.b);
      c.bound_radius = 0.5 * (s.b - s.a).norm() + s.radius;
    }
    void operator()(const MeshObjectShape& s) const {
      c.mesh = makeMeshShape(placeMesh(*s.mesh, s.scale, rotationFromEulerDeg(s.rotation_deg), s.position),
                             thickness + reach);
      c.bound_center = 0.5 * (c.mesh->lo + c.mesh->hi);
      c.bound_radius = 0.5 * (c.mesh->hi - c.mesh->lo).norm();
    }
  };
  std::visit(Shape{c, reach, o.thickness}, o.shape);
  c.bound_radius += o.thickness;
  Collider out;
  out.pose.pos = out.pose.pos_prev = c.pivot;
  if (c.moving()) {
    c.poseAt(0.0, out.pose.rot, out.pose.pos);
    out.pose.rot_prev = out.pose.rot;
    out.pose.pos_prev = out.pose.pos;
  }
  out.shape = std::move(shape);
  return out;
}

void ColliderShape::poseAt(double t, Mat3& r, Vec3& p) const {
  if (keys.empty()) {
    r = Mat3::Identity();
    p = pivot;
    return;
  }
  auto quat = [](const MotionKey& k) { return Eigen::Quaterniond(rotationFromEulerDeg(k.rotation_deg)); };
  const auto [i, s] = keySpan(keys, t, [](const MotionKey& k) { return k.time; });
  if (s == 0.0) {  // at a key, or held before the first or after the last
    r = rotationFromEulerDeg(keys[i].rotation_deg);
    p = keys[i].position;
    return;
  }
  p = (1.0 - s) * keys[i].position + s * keys[i + 1].position;
  r = quat(keys[i]).slerp(s, quat(keys[i + 1])).toRotationMatrix();
}

void Collider::moveTo(double t, double dt_since) {
  if (!moving()) return;
  pose.rot_prev = pose.rot;
  pose.pos_prev = pose.pos;
  shape->poseAt(t, pose.rot, pose.pos);
  pose.dt = dt_since;
}

Vec3 Collider::angularVelocity() const {
  const Eigen::AngleAxisd turn(pose.rot * pose.rot_prev.transpose());
  return pose.dt > 0 ? Vec3(turn.axis() * (turn.angle() / pose.dt)) : Vec3::Zero();
}

Vec3 Collider::velocityAt(const Vec3& p) const {
  if (!moving() || !(pose.dt > 0)) return Vec3::Zero();
  // Where the material point now at p was one step ago: authored point, then the old pose.
  const Vec3 before = pose.rot_prev * (toAuthored(p) - shape->pivot) + pose.pos_prev;
  return (p - before) / pose.dt;
}

bool Collider::distance(const Vec3& p, double& d, Vec3& n) const {
  if (!moving()) return shape->distance(p, d, n);
  if (!shape->distance(toAuthored(p), d, n)) return false;
  n = pose.rot * n;
  return true;
}

int Collider::partDistances(const Vec3& p, double* d, Vec3* n) const {
  if (!moving()) return shape->partDistances(p, d, n);
  const int k = shape->partDistances(toAuthored(p), d, n);
  for (int i = 0; i < k; ++i) n[i] = pose.rot * n[i];
  return k;
}

namespace {

// Signed distance from q to the box of half extents `half` centred at the origin (axis-aligned),
// and the outward normal.
void boxDistance(const Vec3& q, const Vec3& half, double& d, Vec3& n) {
  const Vec3 out = q.cwiseAbs() - half;  // per-axis distance outside the faces
  if (out.maxCoeff() > 0) {
    const Vec3 o = out.cwiseMax(0.0);
    d = o.norm();
    n = Vec3(q.x() > 0 ? o.x() : -o.x(), q.y() > 0 ? o.y() : -o.y(), q.z() > 0 ? o.z() : -o.z()) / d;
  } else {  // inside: leave through the nearest face
    int axis = 0;
    out.maxCoeff(&axis);
    d = out[axis];
    n = Vec3::Zero();
    n[axis] = q[axis] >= 0 ? 1.0 : -1.0;
  }
}

}  // namespace

int ColliderShape::partDistances(const Vec3& p, double* d, Vec3* n) const {
  if (kind != ObjectKind::Container) return distance(p, d[0], n[0]) ? 1 : 0;
  const Vec3 q = R.transpose() * (p - p0);
  int k = 0;
  for (const auto& [centre, size] : containerBoxes(2 * half, wall)) {
    boxDistance(q - centre, size / 2, d[k], n[k]);
    n[k] = R * n[k];
    ++k;
  }
  return k;
}

bool ColliderShape::clearOfParts(const Vec3& p, double margin) const {
  if (kind != ObjectKind::Container) return false;
  // The cavity of containerBoxes(2·half, wall): inside its walls and above its floor by more
  // than the margin (and a hair, for the parts' own rounding), every part is farther than it.
  const Vec3 q = R.transpose() * (p - p0);
  const double w = std::min(wall, half.minCoeff()), m = margin + 1e-9;
  return half.x() - w - std::abs(q.x()) > m && half.z() - w - std::abs(q.z()) > m && q.y() + half.y() - w > m;
}

// One case per shape, each short; kept in one switch (past 80 lines) so that every shape's
// distance and normal read side by side.
bool ColliderShape::distance(const Vec3& p, double& d, Vec3& n) const {
  switch (kind) {
    case ObjectKind::Container: {
      // The union of the floor and four walls: the nearest of the five boxes.
      double dk[kMaxParts];
      Vec3 nk[kMaxParts];
      const int parts = partDistances(p, dk, nk);
      d = std::numeric_limits<double>::infinity();
      for (int k = 0; k < parts; ++k)
        if (dk[k] < d) d = dk[k], n = nk[k];
      return true;
    }
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
      Vec3 ln;
      boxDistance(R.transpose() * (p - p0), half, d, ln);
      n = R * ln;
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
    case ObjectKind::Mesh: {
      // The closest point over the triangles listed in p's cell; inside or outside by the face
      // normal of the closest triangle. When the closest point is an edge or a vertex, several
      // triangles tie: the one whose normal is most aligned with p − q decides (at a convex
      // edge the other face sees p almost in its plane, and rounding could flip its sign).
      if (!p.allFinite()) return false;
      if ((p - mesh->lo).minCoeff() < 0 || (mesh->hi - p).minCoeff() < 0) return false;  // beyond every triangle's reach
      double best = mesh->reach * mesh->reach, align = -1.0;
      double best_len = std::sqrt(best * (1.0 + 1e-9) + 1e-24);  // follows best
      int bt = -1;
      Vec3 bc;
      mesh->grid.forEachAt(p, [&](int t) {
        // The triangle lies inside its bounding sphere: skip it when even the sphere is farther
        // than the best so far (compared squared: no root per triangle).
        const double far = mesh->radii[static_cast<std::size_t>(t)] + best_len;
        if ((p - mesh->centres[static_cast<std::size_t>(t)]).squaredNorm() > far * far) return;
        const auto& tri = mesh->triangles[static_cast<std::size_t>(t)];
        const Vec3 &a = mesh->vertices[tri[0]], &b = mesh->vertices[tri[1]], &c = mesh->vertices[tri[2]];
        const Vec3 w = closestOnTriangle(p, a, b, c);
        const Vec3 q = w[0] * a + w[1] * b + w[2] * c;
        const double d2 = (p - q).squaredNorm();
        if (d2 > best * (1.0 + 1e-9) + 1e-24) return;
        const double al = d2 > 0 ? std::abs((p - q).dot(mesh->normals[static_cast<std::size_t>(t)])) / std::sqrt(d2) : 1.0;
        if (d2 < best * (1.0 - 1e-9) - 1e-24 || al > align) {
          if (d2 < best) best_len = std::sqrt(d2 * (1.0 + 1e-9) + 1e-24);
          best = std::min(best, d2);
          align = al;
          bt = t;
          bc = q;
        }
      });
      if (bt < 0) return false;
      const Vec3& fn = mesh->normals[static_cast<std::size_t>(bt)];
      const Vec3 r = p - bc;
      const double len = r.norm();
      const bool inside = r.dot(fn) < 0;
      d = inside ? -len : len;
      n = len > 1e-12 ? Vec3((inside ? -r : r) / len) : fn;
      return true;
    }
  }
  return false;
}

void contactNode(const Collider& c, const Surface& s, double reach, double d, const Vec3& n, double h, Vec3& x,
                 Vec3& v) {
  x += (reach - d) * n;  // project onto the surface
  // Velocity relative to the surface (exactly v for a static collider).
  const Vec3 vs = c.moving() ? c.velocityAt(x) : Vec3::Zero();
  const Vec3 vr = v - vs;
  const double vn = vr.dot(n);
  if (vn >= 0) return;  // already separating
  const Vec3 vt = vr - vn * n;
  const double e = s.restitution;
  const double vt_len = vt.norm();
  const double keep = vt_len > 0 ? std::max(0.0, vt_len - s.friction * (1.0 + e) * (-vn)) / vt_len : 0.0;
  v = keep * vt - e * vn * n;
  if (c.moving()) v += vs;
  x += (h * (keep - 1.0)) * vt;  // the step's tangential drift, redone at the new velocity
}

void resolveContacts(const std::vector<Collider>& colliders, double radius, double h, const std::uint8_t* fixed,
                     std::vector<Vec3>& x, std::vector<Vec3>& v) {
  if (std::none_of(colliders.begin(), colliders.end(), [](const Collider& c) { return !c.shape->free_body; })) return;
  parallelFor(static_cast<std::ptrdiff_t>(x.size()), [&](std::ptrdiff_t i) {
    if (fixed[i]) return;
    for (const Collider& c : colliders) {
      if (c.shape->free_body) continue;
      double d;
      Vec3 n;
      if (!c.distance(x[static_cast<std::size_t>(i)], d, n)) continue;
      const double reach = c.shape->thickness + radius;
      if (d < reach) contactNode(c, c.shape->surface, reach, d, n, h, x[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(i)]);
    }
  });
}

bool segmentBlocked(const std::vector<Collider>& colliders, const Vec3& a, const Vec3& b, double step) {
  const Vec3 d = b - a;
  const double len = d.norm();
  if (!(len > 1e-12)) return false;
  const Vec3 u = d / len;
  for (const Collider& c : colliders) {
    // Beyond a mesh's reach its distance is unknown but at least the reach.
    const double unknown = std::max(step, c.shape->mesh ? c.shape->mesh->reach : 0.0);
    for (double t = 0.0; t <= len;) {
      double dist;
      Vec3 n;
      if (!c.distance(a + t * u, dist, n)) {
        t += unknown;
        continue;
      }
      if (dist < 0.0) return true;
      t += std::max(dist, step);
    }
  }
  return false;
}

}  // namespace reel
