// The camera at a time: the scene's camera, or its keyframes interpolated smoothly
// (Catmull–Rom through the keys, held at the first and last key).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/drawlist.h"
#include "core/keys.h"
#include "core/scene.h"

namespace reel {

inline DrawCamera cameraAt(const CameraDesc& c, double t) {
  DrawCamera out;
  out.position = c.position;
  out.target = c.target;
  out.up = c.up;
  out.fov_deg = c.fov_deg;
  const auto& k = c.keys;
  if (k.empty()) return out;
  const auto [i, s] = keySpan(k, t, [](const CameraKey& key) { return key.time; });
  if (s == 0.0) {  // at a key, or held before the first or after the last
    out.position = k[i].position;
    out.target = k[i].target;
    out.fov_deg = k[i].fov_deg;
    return out;
  }
  const std::size_t i0 = i == 0 ? 0 : i - 1, i3 = std::min(i + 2, k.size() - 1);
  // Uniform Catmull–Rom: p(s) = ½[2p1 + (p2 − p0)s + (2p0 − 5p1 + 4p2 − p3)s² + (3p1 − p0 − 3p2 + p3)s³].
  auto cr = [s = s](const auto& p0, const auto& p1, const auto& p2, const auto& p3) {
    return 0.5 * (2.0 * p1 + (p2 - p0) * s + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * (s * s) +
                  (3.0 * p1 - p0 - 3.0 * p2 + p3) * (s * s * s));
  };
  out.position = cr(k[i0].position, k[i].position, k[i + 1].position, k[i3].position);
  out.target = cr(k[i0].target, k[i].target, k[i + 1].target, k[i3].target);
  out.fov_deg = std::clamp(cr(k[i0].fov_deg, k[i].fov_deg, k[i + 1].fov_deg, k[i3].fov_deg), 1.0, 179.0);
  return out;
}

}  // namespace reel
