#include "core/patterns.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "core/random.h"

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

// Value noise on a lattice of `period` cells across the texture, wrapped so that it tiles: the
// hashed values at the cell's corners blended by a smoothstep. u, v in [0, 1).
double tiledValueNoise(double u, double v, int period, std::uint64_t seed) {
  const double x = u * period, y = v * period;
  const double fx = std::floor(x), fy = std::floor(y);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  auto corner = [&](int i, int j) {
    const auto ci = static_cast<std::uint64_t>(((i % period) + period) % period);
    const auto cj = static_cast<std::uint64_t>(((j % period) + period) % period);
    return unitFromBits(splitmix64(splitmix64(seed ^ (ci << 32)) + cj));
  };
  auto smooth = [](double t) { return t * t * (3 - 2 * t); };
  const double sx = smooth(x - fx), sy = smooth(y - fy);
  const double a = corner(ix, iy) + sx * (corner(ix + 1, iy) - corner(ix, iy));
  const double b = corner(ix, iy + 1) + sx * (corner(ix + 1, iy + 1) - corner(ix, iy + 1));
  return a + sy * (b - a);
}

// Sand at (u, v) in [0, 1)² and pixel (x, y) (the grain is per pixel).
Rgb sandAt(double u, double v, int x, int y) {
  constexpr Rgb kSand{0.84, 0.76, 0.60};
  // Broad patches of lighter and darker sand (three octaves).
  const double patches = 0.5 * tiledValueNoise(u, v, 4, 11) + 0.3 * tiledValueNoise(u, v, 8, 12) +
                         0.2 * tiledValueNoise(u, v, 16, 13);
  // Ripples: 10 bands across the tile, wavering with the noise, with sharper crests than troughs.
  const double warp = 1.6 * tiledValueNoise(u, v, 3, 21) + 0.5 * tiledValueNoise(u, v, 6, 22);
  const double wave = 0.5 + 0.5 * std::sin(2 * kPi * (10 * v + 2 * u + warp));
  const double ripple = wave * wave * wave;
  // Fine grain, and a few dark (shell, mineral) and bright (quartz) grains.
  const std::uint64_t h = splitmix64((static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y) ^ 0x5a4dULL);
  const double grain = unitFromBits(h), speck = unitFromBits(splitmix64(h));
  double shade = 0.93 + 0.10 * (patches - 0.5) + 0.09 * ripple + 0.07 * (grain - 0.5);
  if (speck > 0.985) shade *= 0.7;
  else if (speck < 0.01) shade *= 1.12;
  return {kSand[0] * shade, kSand[1] * shade, kSand[2] * shade * (0.97 + 0.06 * patches)};
}

// Floorboards at (u, v): 20 planks across the tile (0.2 m each on a 4 m tile), running along u,
// each with its own tint and its end joints at its own offset, grain wavering along the plank.
Rgb woodAt(double u, double v, int x, int y) {
  constexpr Rgb kWood{0.60, 0.43, 0.29};
  const double pv = v * 20;
  const int plank = static_cast<int>(std::floor(pv));
  const double t = pv - plank;  // across the plank, 0..1
  const std::uint64_t ph = splitmix64(0x600dULL + static_cast<std::uint64_t>(plank));
  const double tint = 0.82 + 0.3 * unitFromBits(ph), shift = unitFromBits(splitmix64(ph));
  const double along = u * 3 + shift;  // three boards end to end per tile
  const double joint = along - std::floor(along);
  const int board = static_cast<int>(std::floor(along)) % 3;  // boards 0, 1, 2 (so the tile wraps)
  const double board_tint = 0.94 + 0.12 * unitFromBits(splitmix64(ph ^ static_cast<std::uint64_t>(board + 7)));
  // Grain: bands along the board, bent by noise, darker late wood.
  const double warp = 2.5 * tiledValueNoise(u, v, 6, 31 + static_cast<std::uint64_t>(plank)) + 0.8 * tiledValueNoise(u, v, 24, 32);
  const double g = 0.5 + 0.5 * std::sin(2 * kPi * (t * 5 + warp + shift * 3));
  const std::uint64_t h = splitmix64((static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y) ^ 0x3005ULL);
  double shade = tint * board_tint * (0.86 + 0.14 * (1 - g * g * g)) * (0.97 + 0.06 * unitFromBits(h));
  if (t < 0.025 || t > 0.985 || joint < 0.003) shade *= 0.45;  // the gaps between boards
  return {kWood[0] * shade, kWood[1] * shade, kWood[2] * shade};
}

// Smooth studio concrete at (u, v): broad soft patches, fine grain and a few pores.
Rgb concreteAt(double u, double v, int x, int y) {
  constexpr Rgb kGrey{0.63, 0.62, 0.60};
  const double patches = 0.5 * tiledValueNoise(u, v, 3, 41) + 0.3 * tiledValueNoise(u, v, 9, 42) +
                         0.2 * tiledValueNoise(u, v, 27, 43);
  const std::uint64_t h = splitmix64((static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y) ^ 0xc0cULL);
  const double grain = unitFromBits(h), pore = unitFromBits(splitmix64(h));
  double shade = 0.94 + 0.14 * (patches - 0.5) + 0.05 * (grain - 0.5);
  if (pore > 0.996) shade *= 0.75;
  return {kGrey[0] * shade, kGrey[1] * shade, kGrey[2] * shade * (0.98 + 0.04 * patches)};
}

template <class F>
Image tile(int size, F&& at) {
  Image img(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Rgb c = at((x + 0.5) / size, (y + 0.5) / size, x, y);
      std::uint8_t* p = img.pixel(x, y);
      for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(std::clamp(c[k], 0.0, 1.0) * 255.0));
    }
  return img;
}

}  // namespace

Image makeWoodTexture(int size) { return tile(size, woodAt); }
Image makeConcreteTexture(int size) { return tile(size, concreteAt); }

Image makeSandTexture(int size) { return tile(size, sandAt); }

Image makeFishSkin(std::string_view pattern, const Vec3& base, const Vec3& mark, int width) {
  const int height = width / 2;
  Image img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double u = (x + 0.5) / width, v = (y + 0.5) / height;
      const double belly = 0.5 - 0.5 * std::cos(2 * kPi * v);  // 0 on the back, 1 underneath
      Vec3 c = base;
      double m = 0.0;  // how much of the mark
      if (pattern == "stripes") {
        // Dark bands across the flanks, narrowing to the tail, fading toward the belly.
        const double band = std::sin(2 * kPi * (5.0 * u + 0.15 * std::sin(6 * v)));
        m = std::clamp((band - 0.35) * 4.0, 0.0, 1.0) * std::clamp(1.6 - 2.2 * belly, 0.0, 1.0) * ((u > 0.12 && u < 0.9) ? 1.0 : 0.0);
      } else if (pattern == "spots") {
        // Round spots on a jittered grid.
        const double gu = u * 14.0, gv = v * 10.0;
        const double cu = std::floor(gu), cv = std::floor(gv);
        const std::uint64_t h = static_cast<std::uint64_t>(cu) * 73856093u ^ static_cast<std::uint64_t>(cv) * 19349663u;
        const double ju = 0.3 + 0.4 * static_cast<double>(h % 97) / 97.0, jv = 0.3 + 0.4 * static_cast<double>((h / 97) % 89) / 89.0;
        const double du = gu - cu - ju, dv = (gv - cv - jv) * 0.7;
        m = std::clamp((0.28 - std::sqrt(du * du + dv * dv)) * 12.0, 0.0, 1.0) * std::clamp(1.5 - 2.0 * belly, 0.0, 1.0);
      } else if (pattern == "gradient") {
        m = std::clamp(1.2 * u - 0.1, 0.0, 1.0) * (1.0 - 0.6 * belly);
      }
      c = (1 - m) * c + m * mark;
      // Countershading: the back a little darker, the belly pale.
      c *= 0.75 + 0.25 * belly;
      c = (1 - 0.55 * belly * belly) * c + 0.55 * belly * belly * Vec3(0.9, 0.9, 0.85);
      std::uint8_t* p = img.pixel(x, y);
      for (int k = 0; k < 3; ++k)
        p[k] = static_cast<std::uint8_t>(std::lround(255.0 * std::pow(std::clamp(c[k], 0.0, 1.0), 1.0 / 2.2)));
    }
  return img;
}

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
  if (name == "sand") return makeSandTexture(size);
  if (name == "wood") return makeWoodTexture(size);
  if (name == "concrete") return makeConcreteTexture(size);
  return {};
}

}  // namespace reel
