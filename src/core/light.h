// A light of the scene, as the scene describes it and the renderer draws it.
#pragma once

#include "core/types.h"

namespace reel {

enum class LightKind { Directional, Point, Ambient };
struct LightDesc {
  LightKind kind = LightKind::Directional;
  Vec3 direction{-1, -2, -1}, position{0, 5, 0}, color{1, 1, 1};
  double intensity = 1.0;
  bool shadows = false;
  // The light's size, which softens its shadows' edges with distance (percentage-closer soft
  // shadows): a directional light's angular diameter in degrees (the sun's is 0.53), a point
  // light's radius in m; 0: a fixed, narrow filter.
  double size = 0.0;
};

}  // namespace reel
