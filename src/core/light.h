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
};

}  // namespace reel
