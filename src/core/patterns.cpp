#include "core/patterns.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace reel {
namespace {

using Rgb = std::array<double, 3>;  // sRGB, 0..1

constexpr Rgb kRed{0.55, 0.08, 0.07}, kDeepRed{0.40, 0.05, 0.06}, kNavy{0.07, 0.10, 0.28},
    kGold{0.86, 0.66, 0.24}, kCream{0.93, 0.88, 0.74}, kTeal{0.10, 0.38, 0.40};

// Distance from (u, v) to the nearest point of a repeating lattice of diamonds of period p.
double diamondLattice(double u, double v, double p) {
  const double a = std::fmod(u + v + 8.0, p) / p, b = std::fmod(u - v + 8.0, p) / p;
  return std::min(std::min(a, 1 - a), std::min(b, 1 - b));
}

Rgb rugAt(double u, double v) {
  const double e = std::min(std::min(u, 1 - u), std::min(v, 1 - v));  // distance to the edge
  // Fringe: cream threads.
  if (e < 0.018) return (static_cast<int>(std::floor((u + v) * 400)) % 2) ? kCream : Rgb{0.82, 0.77, 0.63};
  // Outer border: navy with gold diamonds along it.
  if (e < 0.075) {
    const double along = (std::abs(u - 0.5) > std::abs(v - 0.5)) ? v : u;  // coordinate along the side
    const double s = std::fmod(along * 18.0, 1.0) - 0.5, t = (e - 0.0465) / 0.022;
    if (std::abs(s) * 1.1 + std::abs(t) * 0.5 < 0.28) return kGold;
    if (std::abs(s) * 1.1 + std::abs(t) * 0.5 < 0.36) return kCream;
    return kNavy;
  }
  if (e < 0.085) return kGold;
  // Zigzag band.
  if (e < 0.135) {
    const double along = (std::abs(u - 0.5) > std::abs(v - 0.5)) ? v : u;
    const double zig = std::abs(std::fmod(along * 30.0, 2.0) - 1.0);  // 0..1 triangle wave
    const double t = (e - 0.085) / 0.05;
    return std::abs(t - (0.2 + 0.6 * zig)) < 0.14 ? kCream : kTeal;
  }
  if (e < 0.145) return kGold;
  // Field: central medallion, corner quarter medallions, a lattice elsewhere.
  const double du = u - 0.5, dv = v - 0.5;
  const double r = std::abs(du) + std::abs(dv);  // diamond distance from the centre
  if (r < 0.25) {
    const double band = r / 0.25;
    if (band < 0.18) return kGold;
    if (band < 0.28) return kNavy;
    if (band < 0.55) return (std::fmod(std::atan2(dv, du) * 8.0 / 3.14159265 + 16.0, 2.0) < 1.0) ? kCream : kGold;
    if (band < 0.66) return kNavy;
    if (band < 0.9) return kDeepRed;
    return kGold;
  }
  const double cu = std::min(u, 1 - u) - 0.145, cv = std::min(v, 1 - v) - 0.145;
  const double rc = cu + cv;  // corner medallion
  if (rc < 0.12) return rc < 0.06 ? kNavy : (rc < 0.08 ? kGold : kDeepRed);
  const double lat = diamondLattice(u, v, 0.1);
  if (lat < 0.05) return kNavy;
  if (lat > 0.42) return kGold;  // a small gold flower at each lattice cell's centre
  return kRed;
}

}  // namespace

Image makeRugTexture(int size) {
  Image img(size, size);
  // 2 x 2 supersampling keeps the pattern's edges clean at every mip level.
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      Rgb sum{0, 0, 0};
      for (int s = 0; s < 4; ++s) {
        const Rgb c = rugAt((x + 0.25 + 0.5 * (s & 1)) / size, (y + 0.25 + 0.5 * (s >> 1)) / size);
        for (int k = 0; k < 3; ++k) sum[k] += c[k] / 4;
      }
      std::uint8_t* p = img.pixel(x, y);
      for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(std::clamp(sum[k], 0.0, 1.0) * 255.0));
    }
  return img;
}

Image makePattern(std::string_view name, int size) {
  if (name == "rug") return makeRugTexture(size);
  return {};
}

}  // namespace reel
