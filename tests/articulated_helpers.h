// What the articulated-figure tests share: the world's figure, how far its joints have come apart.
#pragma once

#include <algorithm>
#include <stdexcept>

#include "sim/articulated/articulated_body.h"
#include "sim/world.h"

namespace reel::test {

inline ArticulatedBody& figure(World& w, std::size_t k = 0) {
  std::size_t seen = 0;
  for (const auto& b : w.bodies())
    if (auto* a = dynamic_cast<ArticulatedBody*>(b.get()))
      if (seen++ == k) return *a;
  throw std::runtime_error("no articulated body");
}

// The farthest a joint's point on the parent is from the same point on the child, m.
inline double jointGap(const ArticulatedBody& b) {
  const ArtKinematics& k = b.kinematics();
  double worst = 0;
  for (std::size_t i = 0; i < b.model().joints.size(); ++i) {
    const ArtJoint& j = b.model().joints[i];
    if (j.parent < 0) continue;
    const auto p = static_cast<std::size_t>(j.parent);
    const Vec3 on_parent = k.x[p] + k.R[p] * j.parent_anchor, on_child = k.x[i] + k.R[i] * j.anchor;
    worst = std::max(worst, (on_parent - on_child).norm());
  }
  return worst;
}

}  // namespace reel::test
