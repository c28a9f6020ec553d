// What a school gives the renderer: one instanced fish mesh (reel's own, or the scene's `mesh`),
// each agent placed along its heading, tinted, its tail beating at its own phase.
#include <cmath>

#include "sim/draw_material.h"
#include "sim/school/school_body.h"

namespace reel {
namespace {

// reel's fish, near and far (core/mesh.h), made once and shared by every school and frame.
const std::shared_ptr<const TriMesh>& fishMesh(int detail) {
  static const std::shared_ptr<const TriMesh> near = std::make_shared<const TriMesh>(makeFishMesh(1)),
                                              far = std::make_shared<const TriMesh>(makeFishMesh(0));
  return detail > 0 ? near : far;
}

// The z extent of a mesh's vertices (an imported fish: head at the top, tail at the bottom).
std::pair<double, double> zRange(const TriMesh& m) {
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t k = 2; k < m.positions.size(); k += 3) lo = std::min<double>(lo, m.positions[k]), hi = std::max<double>(hi, m.positions[k]);
  return {lo, hi};
}

}  // namespace

// Each agent: its local z along its heading, x level (perpendicular to the heading and world up),
// scaled to the fish's length and centred on the agent. The body wave of a carangiform swimmer:
// about one wavelength per body length, growing from a third of the way back to a tenth of the
// length at the tail tip (Videler, "Fish Swimming", 1993, ch. 6).
void SchoolBody::draw(DrawList& out) const {
  const School& s = school_;
  const SchoolDesc& d = s.desc;
  DrawInstances di;
  di.material = drawMaterial(material_);
  double z_lo = -1.0, z_hi = 0.0;
  if (d.mesh) {
    di.mesh = d.mesh;
    std::tie(z_lo, z_hi) = zRange(*d.mesh);
    if (!(z_hi > z_lo)) z_lo = z_hi - 1.0;
  } else {
    di.mesh = fishMesh(1);
    di.far_mesh = fishMesh(0);
    di.far_distance = 15.0 * d.length;  // beyond, a fish is under about 60 pixels long at 720p
  }
  const double span = z_hi - z_lo, scale = d.length / span;
  di.wave_start = static_cast<float>(z_hi - span / 3);
  di.wave_end = static_cast<float>(z_lo);
  di.wave_amplitude = static_cast<float>(0.1 * span);
  di.wave_number = static_cast<float>(2 * 3.14159265358979 / span);
  const std::size_t n = s.size();
  di.transforms.resize(12 * n);
  di.phases.resize(n);
  di.colors = s.tint;
  const Vec3 up(0, 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 z = s.v[i].normalized();
    Vec3 x = up.cross(z);
    x = x.norm() > 1e-6 ? Vec3(x.normalized()) : Vec3(1, 0, 0);
    const Vec3 y = z.cross(x);
    // Mesh point p lands at origin + scale·(p.x X + p.y Y + p.z Z); the middle of the body sits
    // on the agent.
    const Vec3 origin = s.x[i] - scale * 0.5 * (z_lo + z_hi) * z;
    float* t = &di.transforms[12 * i];
    for (int k = 0; k < 3; ++k) {
      t[k] = static_cast<float>(scale * x[k]);
      t[3 + k] = static_cast<float>(scale * y[k]);
      t[6 + k] = static_cast<float>(scale * z[k]);
      t[9 + k] = static_cast<float>(origin[k]);
    }
    di.phases[i] = static_cast<float>(s.phase[i]);
  }
  out.instances.push_back(std::move(di));
}

}  // namespace reel
