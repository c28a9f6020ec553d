// The camera at a time: the scene's camera, or its keyframes interpolated smoothly
// (Catmull–Rom through the keys, held at the first and last key), and the rig that moves it to
// follow or frame a body.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/drawlist.h"
#include "core/keys.h"
#include "core/math.h"
#include "core/scene.h"

namespace reel {

inline DrawCamera cameraAt(const CameraDesc& c, double t) {
  DrawCamera out;
  out.position = c.position;
  out.target = c.target;
  out.up = c.up;
  out.fov_deg = c.fov_deg;
  out.aperture = c.aperture;
  out.focus_distance = c.focus_distance;
  out.lens_samples = c.lens_samples;
  const auto& k = c.keys;
  if (k.empty()) return out;
  const auto [i, s] = keySpan(k, t, [](const CameraKey& key) { return key.time; });
  if (s == 0.0) {  // at a key, or held before the first or after the last
    out.position = k[i].position;
    out.target = k[i].target;
    out.fov_deg = k[i].fov_deg;
    return out;
  }
  // Two keys closer than kCameraCut make a cut: the path on either side does not reach across it
  // for its tangent (a shot's last second had swung toward the next shot's camera).
  constexpr double kCameraCut = 0.01;  // s
  const std::size_t i0 = i == 0 || k[i].time - k[i - 1].time < kCameraCut ? i : i - 1;
  const std::size_t i3 = i + 2 >= k.size() || k[i + 2].time - k[i + 1].time < kCameraCut ? i + 1 : i + 2;
  // Uniform Catmull–Rom (core/math.h).
  out.position = catmullRom(k[i0].position, k[i].position, k[i + 1].position, k[i3].position, s);
  out.target = catmullRom(k[i0].target, k[i].target, k[i + 1].target, k[i3].target, s);
  out.fov_deg = std::clamp(catmullRom(k[i0].fov_deg, k[i].fov_deg, k[i + 1].fov_deg, k[i3].fov_deg, s), 1.0, 179.0);
  return out;
}

// What a camera that follows or frames a body aims at: the body's centre and radius, smoothed.
// The World advances it each frame and its snapshot carries it, so a render from the farm cache
// sees the same camera as one that simulated.
struct CameraRig {
  bool active = false;
  Vec3 centre0{0, 0, 0};  // m: the smoothed centre at frame 0, where the authored camera looks
  Vec3 centre{0, 0, 0}, velocity{0, 0, 0};  // m, m/s
  double radius = 0.0, radius_rate = 0.0;   // m, m/s
};

// The rig at rest on a body whose centre and radius are these.
inline CameraRig startRig(const Vec3& centre, double radius) {
  CameraRig r;
  r.active = true;
  r.centre0 = r.centre = centre;
  r.radius = radius;
  return r;
}

// Advances the rig h seconds toward the body's centre and radius by a critically damped spring,
// x'' = −ω²(x − c) − 2ωx' with ω = 2/lag (a body moving at a steady speed is trailed by `lag`
// seconds, without oscillating), solved exactly for c held over the step: with e = x − c and
// b = x' + ωe, e(h) = (e + b·h)·exp(−ωh) and x'(h) = (x' − ω·b·h)·exp(−ωh). Stable at any step.
inline void advanceRig(CameraRig& r, const Vec3& centre, double radius, double h, double lag) {
  const double w = lag > 0.0 ? 2.0 / lag : 0.0;
  if (lag <= 0.0 || w * h > 700.0) {  // rigid (exp(−ωh) is 0 to double precision beyond)
    r.velocity = (centre - r.centre) / h;
    r.radius_rate = (radius - r.radius) / h;
    r.centre = centre;
    r.radius = radius;
    return;
  }
  const double decay = std::exp(-w * h);
  const Vec3 e = r.centre - centre, b = r.velocity + w * e;
  r.centre = centre + (e + b * h) * decay;
  r.velocity = (r.velocity - w * h * b) * decay;
  const double er = r.radius - radius, br = r.radius_rate + w * er;
  r.radius = radius + (er + br * h) * decay;
  r.radius_rate = (r.radius_rate - w * h * br) * decay;
}

// The camera at time t moved by its rig: `track` carries the authored camera (or its keys) with
// the smoothed centre's travel since frame 0, `pan` turns it to keep the same aim, `frame` looks
// at the smoothed centre along the authored direction from the distance at which a sphere of
// margin × radius just fits the narrower of the picture's two fields of view (aspect: width/height).
inline DrawCamera rigCamera(const CameraDesc& c, const CameraRig& rig, double t, double aspect) {
  DrawCamera out = cameraAt(c, t);
  const Vec3 travel = rig.centre - rig.centre0;
  switch (c.rig.mode) {
    case CameraRigDesc::Mode::None:
      break;
    case CameraRigDesc::Mode::Track:
      out.position += travel;
      out.target += travel;
      break;
    case CameraRigDesc::Mode::Pan:
      out.target += travel;
      break;
    case CameraRigDesc::Mode::Frame: {
      const double half_v = 0.5 * out.fov_deg * kPi / 180.0;
      const double half = std::min(half_v, std::atan(aspect * std::tan(half_v)));
      const Vec3 dir = (out.target - out.position).normalized();
      const double distance = c.rig.margin * std::max(rig.radius, 0.25) / std::sin(half);  // (the spring may dip)
      out.target = rig.centre;
      out.position = rig.centre - distance * dir;
      break;
    }
  }
  return out;
}

}  // namespace reel
