#include "sim/wind.h"

#include <cmath>

#include "core/math.h"
#include "core/random.h"

namespace reel {

Wind::Wind(const WindDesc& d, std::uint64_t seed) : mean_(d.velocity) {
  const double speed = d.velocity.norm();
  const Vec3 along = speed > 0 ? Vec3(d.velocity / speed) : Vec3::UnitX();
  const double carry = std::max(speed, 1.0);  // m/s: how fast the gusts travel
  auto xi = [seed](int k) { return uniformAt(seed, 0x57494E44ull /* "WIND" */, static_cast<std::uint64_t>(k)); };
  for (int k = 0; k < 3; ++k) {
    // Mostly along the mean wind, turned a little by a random vector in [−½, ½]³.
    const Vec3 turn(xi(8 * k) - 0.5, xi(8 * k + 1) - 0.5, xi(8 * k + 2) - 0.5);
    dir_[k] = (along + turn).normalized();
    amp_[k] = d.gust * (0.7 + 0.6 * xi(8 * k + 3)) / 3.0;
    omega_[k] = 2.0 * kPi / (d.gust_period * (0.6 + 0.8 * xi(8 * k + 4)));
    phase_[k] = 2.0 * kPi * xi(8 * k + 5);
    k_[k] = (omega_[k] / carry) * along;
  }
}

Vec3 Wind::at(const Vec3& x, double t) const {
  Vec3 u = mean_;
  // Each gust wave is non-negative, ½(1 + sin), so gusts strengthen the wind; together they
  // reach about `gust` at their peaks.
  for (int k = 0; k < 3; ++k)
    if (amp_[k] != 0.0) u += amp_[k] * 0.5 * (1.0 + std::sin(omega_[k] * t - k_[k].dot(x) + phase_[k])) * dir_[k];
  return u;
}

}  // namespace reel
