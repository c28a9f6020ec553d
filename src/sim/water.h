// The water of the fish kinds (core/scene.h: WaterDesc): its density and its flow u(x, t), the
// sum of the currents: uniform flows varying sinusoidally in time, and sources and sinks at
// objects (wherever the object is at that moment). Read by fish, food and seaweed.
#pragma once

#include <vector>

#include "core/scene.h"
#include "core/types.h"
#include "sim/collide.h"

namespace reel {

class Water {
 public:
  Water() = default;
  explicit Water(const WaterDesc& d) : desc_(d) {}
  double density() const { return desc_.density; }
  // The flow at x at time t, m/s; `colliders` at their pose at t (sources move with their object).
  // Without water (density 0) there is no flow.
  Vec3 at(const Vec3& x, double t, const std::vector<Collider>& colliders) const;
  bool still() const { return desc_.currents.empty(); }

 private:
  WaterDesc desc_;
};

}  // namespace reel
