#pragma once

#include <cstdint>

#include "core/scene.h"
#include "core/types.h"

namespace reel {

// The wind field u(x, t) of WindDesc: the mean wind plus three travelling gust waves drawn from
// the scene seed (frozen turbulence carried along the mean wind, Taylor's hypothesis).
class Wind {
 public:
  Wind() = default;
  Wind(const WindDesc& d, std::uint64_t seed);
  Vec3 at(const Vec3& x, double t) const;

 private:
  Vec3 mean_{0, 0, 0};
  Vec3 dir_[3];       // gust directions, unit
  double amp_[3]{};   // m/s
  double omega_[3]{}; // rad/s
  double phase_[3]{};
  Vec3 k_[3];         // spatial wave vectors, rad/m
};

}  // namespace reel
