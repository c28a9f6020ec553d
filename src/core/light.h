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

// A pool of light on the backdrop behind the subject, as a portrait's background light throws
// (added to the background's gradient where nothing covers the picture): a Gaussian of linear
// colour `color` about (x, y), fractions of the frame's width and height from its bottom left,
// `radius` (its σ) a fraction of the frame's height. Black: none.
struct BackgroundGlow {
  Vec3 color{0, 0, 0};
  double x = 0.5, y = 0.5, radius = 0.3;
};

}  // namespace reel
