#include "render/projection.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace reel {

Mat4f lookAt(const Vec3& eye, const Vec3& target, const Vec3& up_hint) {
  const Vec3 f = (target - eye).normalized();
  Vec3 s = f.cross(up_hint);
  if (s.norm() < 1e-9) s = f.cross(std::abs(f.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitZ());
  s.normalize();
  const Vec3 u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m.cast<float>();
}

Mat4f perspective(double fovy_deg, double aspect, double n, double f) {
  const double t = 1.0 / std::tan(fovy_deg * kPi / 360.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2 * f * n / (n - f);
  m(3, 2) = -1;
  return m.cast<float>();
}

Mat4f ortho(double r, double n, double f) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 1 / r;
  m(1, 1) = 1 / r;
  m(2, 2) = -2 / (f - n);
  m(2, 3) = -(f + n) / (f - n);
  return m.cast<float>();
}

namespace {

// The largest distance of a mesh's vertices from its local origin.
double meshRadius(const TriMesh* m) {
  double r2 = 0;
  if (m)
    for (std::size_t i = 0; i + 2 < m->positions.size(); i += 3)
      r2 = std::max(r2, double(Vec3f(m->positions[i], m->positions[i + 1], m->positions[i + 2]).squaredNorm()));
  return std::sqrt(r2);
}

// Grows [lo, hi] by each copy's origin and a margin: the mesh's radius (plus the wave's sideways
// reach) times the copy's largest axis length.
void addInstances(const DrawInstances& d, Vec3& lo, Vec3& hi) {
  if (!d.mesh || d.count() == 0) return;
  const double r = std::max(meshRadius(d.mesh.get()), meshRadius(d.far_mesh.get())) + std::abs(d.wave_amplitude);
  for (std::size_t i = 0; i < d.count(); ++i) {
    const float* t = &d.transforms[12 * i];
    double scale = 0;
    for (int a = 0; a < 3; ++a) scale = std::max(scale, double(Vec3f(t[3 * a], t[3 * a + 1], t[3 * a + 2]).norm()));
    const Vec3 o(t[9], t[10], t[11]);
    lo = lo.cwiseMin(o - Vec3::Constant(r * scale));
    hi = hi.cwiseMax(o + Vec3::Constant(r * scale));
  }
}

}  // namespace

void sceneBounds(const DrawList& list, Vec3& center, double& radius) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  auto add = [&](const float* p) {
    const Vec3 q(p[0], p[1], p[2]);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  };
  for (const auto& m : list.meshes) {
    if (!m.mesh || m.mesh->vertexCount() == 0) continue;
    const auto& pos = m.mesh->positions;
    Vec3 mlo = Vec3::Constant(1e300), mhi = Vec3::Constant(-1e300);
    for (std::size_t i = 0; i + 2 < pos.size(); i += 3) {
      const Vec3 q(pos[i], pos[i + 1], pos[i + 2]);
      mlo = mlo.cwiseMin(q);
      mhi = mhi.cwiseMax(q);
    }
    if ((mhi - mlo).norm() > kGroundExtent) continue;  // a ground: it receives, it does not bound
    lo = lo.cwiseMin(mlo);
    hi = hi.cwiseMax(mhi);
  }
  for (const auto& s : list.spheres)
    for (std::size_t i = 0; i + 2 < s.centers.size(); i += 3) add(&s.centers[i]);
  for (const auto& t : list.tubes)
    for (std::size_t i = 0; i + 2 < t.ends.size(); i += 3) add(&t.ends[i]);
  for (const auto& d : list.instances) addInstances(d, lo, hi);
  if (lo.x() > hi.x()) {
    center = list.camera.target;
    radius = 5.0;
    return;
  }
  center = (lo + hi) / 2;
  radius = std::max(0.5 * (hi - lo).norm(), 0.1) * 1.05;
}

GroundPlane groundPlane(const TriMesh& m) {
  GroundPlane g;
  const std::size_t nv = m.vertexCount();
  if (nv < 3 || m.indices.size() < 3) return g;
  // No wider than kGroundExtent on the diagonal, none of its sides is (a sheet, a liquid's
  // surface, uploaded every frame, stop here).
  Vec3 lo = m.position(0), hi = lo;
  for (std::size_t k = 1; k < nv; ++k) lo = lo.cwiseMin(m.position(k)), hi = hi.cwiseMax(m.position(k));
  if (!((hi - lo).norm() > kGroundExtent)) return g;
  // The plane and its axes from the largest triangle: its normal, and its shortest edge as the
  // first axis (a side of a rectangle split along its diagonal).
  double best = 0;
  Vec3 u{0, 0, 0};
  double area = 0;  // all the triangles', m²
  for (std::size_t k = 0; k + 2 < m.indices.size(); k += 3) {
    const Vec3 a = m.position(m.indices[k]), b = m.position(m.indices[k + 1]), c = m.position(m.indices[k + 2]);
    const Vec3 n = (b - a).cross(c - a);
    const double twice = n.norm();
    area += 0.5 * twice;
    if (twice <= best) continue;
    best = twice, g.point = a, g.normal = n;
    u = (b - a).squaredNorm() <= (c - b).squaredNorm() && (b - a).squaredNorm() <= (a - c).squaredNorm() ? Vec3(b - a)
        : (c - b).squaredNorm() <= (a - c).squaredNorm()                                               ? Vec3(c - b)
                                                                                                       : Vec3(a - c);
  }
  if (!(best > 0)) return g;
  g.normal /= best;
  u.normalize();
  const Vec3 v = g.normal.cross(u);
  // Every vertex on the plane, the mesh at least kGroundExtent along both axes, and its triangles
  // covering the rectangle that bounds it on the plane (no holes, no strip, no scattered tiles):
  // only such a ground hides everything beyond it from a camera on its other side.
  double ulo = INFINITY, uhi = -INFINITY, vlo = INFINITY, vhi = -INFINITY, off = 0;
  for (std::size_t k = 0; k < nv; ++k) {
    const Vec3 r = m.position(k) - g.point;
    off = std::max(off, std::abs(r.dot(g.normal)));
    ulo = std::min(ulo, r.dot(u)), uhi = std::max(uhi, r.dot(u));
    vlo = std::min(vlo, r.dot(v)), vhi = std::max(vhi, r.dot(v));
  }
  const double eu = uhi - ulo, ev = vhi - vlo;
  if (!(eu > kGroundExtent && ev > kGroundExtent) || off > 1e-6 * std::hypot(eu, ev)) return g;
  g.flat = std::abs(area - eu * ev) <= 1e-4 * eu * ev;
  return g;
}

}  // namespace reel
