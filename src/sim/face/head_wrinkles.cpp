// reel's head's wrinkles (head_shape.h, Wrinkles): where each kind of line forms on the face and
// the lines themselves, which the skin's wrinkle map holds and the muscles deepen.
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "sim/face/head_shape.h"
#include "sim/face/head_tone.h"

namespace reel::head {

Wrinkles wrinkleRegions(const Vec3& p) {
  const double X = p.x(), Y = p.y(), ax = std::abs(X);
  if (p.z() < 0.02) return {};
  const double forehead = smoothstep(0.03, 0.037, Y) * smoothstep(0.072, 0.062, Y) * smoothstep(0.052, 0.038, ax);
  const double glabella = smoothstep(0.0095, 0.0065, ax) * smoothstep(0.006, 0.012, Y) * smoothstep(0.032, 0.025, Y);
  const double cx = ax - 0.047, r = std::hypot(cx, Y - 0.001), fan = std::atan2(Y - 0.001, cx);
  const double crows = cx > -0.002 ? smoothstep(0.004, 0.008, r) * smoothstep(0.02, 0.012, r) * smoothstep(1.1, 0.7, std::abs(fan)) : 0.0;
  const double fold = std::exp(-0.5 * sq(segmentDistance(ax, Y, kFoldTop[0], kFoldTop[1], kFoldEnd[0], kFoldEnd[1]) / 0.004));
  const double nose = smoothstep(0.002, 0.0045, ax) * smoothstep(0.015, 0.01, ax) * smoothstep(-0.017, -0.012, Y) * smoothstep(0.004, 0.0, Y);
  return {forehead, glabella, crows, fold, nose};
}

Wrinkles wrinkleLines(const Vec3& p) {
  const double X = p.x(), Y = p.y(), ax = std::abs(X);
  if (p.z() < 0.02) return {};
  const Wrinkles region = wrinkleRegions(p);
  // The forehead: four or five furrows about 7.5 mm apart, wavering across it, each breaking and
  // fading along its length, some deeper than others (evenly spaced and deep all across, they
  // read as parallel stripes painted on, a viewer said).
  const double phase = 2 * kPi * (Y - 0.0335) / 0.0075 + 0.9 * std::sin(X * 45.0) + 1.2 * (valueNoise(Vec3(X * 40.0, 2.5, 8.5)) - 0.5);
  const double furrows = std::pow(0.5 + 0.5 * std::cos(phase), 4.0) *
                         std::clamp(-0.6 + 2.6 * valueNoise(Vec3(X * 90.0, std::floor(phase / (2 * kPi) + 0.5) * 3.7, 5.5)), 0.0, 1.0);
  // Between the brows: two short vertical lines.
  const double glabella = std::exp(-0.5 * sq((ax - 0.0045) / 0.0009)) * smoothstep(0.006, 0.012, Y) * smoothstep(0.032, 0.025, Y);
  // Crow's feet: four or five fine lines fanning out from the outer corner of each eye, fading
  // in and out along their length, wavering.
  const double cx = ax - 0.047, r = std::hypot(cx, Y - 0.001), fan = std::atan2(Y - 0.001, cx);
  // (A third as deep as the others and soft: at full depth their lit edges read as whiskers, at
  // half depth and sharper as scratches.)
  const double crows = 0.35 * region.crows * std::pow(0.5 + 0.5 * std::cos(fan * 12.0 + 0.25 * std::sin(r * 900.0)), 1.6);
  // The nasolabial fold, from the nose's wing to beside the mouth's corner: steep on the cheek's
  // side, which a smile bunches over it, shelving over 3.5 mm toward the lips (a line 1.2 mm
  // across each way drew a scratch, and the smile lifted no cheek).
  const double gap = segmentDistance(ax, Y, kFoldTop[0], kFoldTop[1], kFoldEnd[0], kFoldEnd[1]);
  const double cheekward = (kFoldEnd[0] - kFoldTop[0]) * (Y - kFoldTop[1]) - (kFoldEnd[1] - kFoldTop[1]) * (ax - kFoldTop[0]);
  const double fold = std::exp(-0.5 * sq(gap / (cheekward > 0 ? 0.0015 : 0.0035)));
  // The nose's wrinkles: three or four lines about 3.4 mm apart down the nose, across the sides of
  // its upper half, slanting down and out from its root (the "bunny lines"), each wavering and of
  // its own depth (six alike, evenly spaced, read as a ladder, a texture's glitch, viewers said).
  const double wander = Y + 0.55 * ax + 0.0006 * (valueNoise(Vec3(ax * 400.0, Y * 150.0, 2.5)) - 0.5);
  const double line = std::floor(wander / 0.0034 + 0.5);
  const double nose = (0.35 + 0.35 * valueNoise(Vec3(line * 1.7, 0.5, 6.5))) * region.nose *
                      std::pow(0.5 + 0.5 * std::cos(2 * kPi * wander / 0.0034), 3.0);
  return {region.forehead * furrows, glabella, crows, fold, nose};
}

}  // namespace reel::head
