#include "sim/water.h"

#include <cmath>

#include "core/math.h"

namespace reel {

Vec3 Water::at(const Vec3& x, double t, const std::vector<Collider>& colliders) const {
  Vec3 u{0, 0, 0};
  if (!(desc_.density > 0)) return u;  // no water, no flow
  for (const CurrentDesc& c : desc_.currents) {
    if (c.kind == CurrentDesc::Kind::Uniform) {
      u += c.velocity + std::sin(2 * kPi * t / c.period) * c.amplitude;
      continue;
    }
    // A point source of volume flow Q: u = ±Q/(4π r²) r̂ (continuity through any sphere around
    // it), falling linearly to zero inside the core so the flow stays finite.
    const Vec3 r = x - colliders[static_cast<std::size_t>(c.collider)].pose.pos;  // its reference point now
    const double d = r.norm();
    if (!(d > 1e-12)) continue;
    const double q = (c.kind == CurrentDesc::Kind::Source ? 1.0 : -1.0) * c.rate / (4 * kPi);
    const double speed = d > c.core ? q / (d * d) : q * d / (c.core * c.core * c.core);
    u += (speed / d) * r;
  }
  return u;
}

}  // namespace reel
