// The skin's tone from side to side (head_tone.h): value noise, and the uneven patches of colour
// that make the two halves of a face differ.
#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "sim/face/head_tone.h"

namespace reel::head {

namespace {

// A hash of the lattice point (x, y, z) to 0..1.
double lattice(std::int64_t x, std::int64_t y, std::int64_t z) {
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
                    static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull;
  h ^= h >> 31;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 29;
  return static_cast<double>(h >> 11) / static_cast<double>(1ull << 53);
}

}  // namespace

double valueNoise(const Vec3& p) {
  const Vec3 f(std::floor(p.x()), std::floor(p.y()), std::floor(p.z()));
  Vec3 t = p - f;
  t = t.cwiseProduct(t).cwiseProduct(Vec3(3, 3, 3) - 2 * t);
  const auto X = static_cast<std::int64_t>(f.x()), Y = static_cast<std::int64_t>(f.y()), Z = static_cast<std::int64_t>(f.z());
  double v = 0.0;
  for (int c = 0; c < 8; ++c) {
    const int i = c & 1, j = (c >> 1) & 1, k = (c >> 2) & 1;
    v += (i ? t.x() : 1 - t.x()) * (j ? t.y() : 1 - t.y()) * (k ? t.z() : 1 - t.z()) * lattice(X + i, Y + j, Z + k);
  }
  return v;
}

Vec3 skinTint(const Vec3& p) {
  // Over the face and scalp, fading out down the neck (under the collar, and where the shoulders'
  // mesh meets it).
  const double face = smoothstep(-0.14, -0.115, p.y());
  // Redder patches 2-3 cm across (the capillaries' density varies: with only the flush's zones the
  // skin read as one waxy peach), and the skin paler or darker over 4-5 cm; as the texture's
  // patches were, mirrored, a viewer saw "a mirrored skin texture".
  const double red = face * (valueNoise(p * 45.0 + Vec3(3.7, 1.1, 5.3)) - 0.5), tone = face * (valueNoise(p * 24.0 + Vec3(8.2, 4.4, 0.6)) - 0.5);
  return Vec3(1.0, 1.0 - 0.16 * red, 1.0 - 0.06 * red) * (1.0 + 0.12 * tone);
}

}  // namespace reel::head
