#include "core/environment.h"

#include <algorithm>
#include <cmath>

#include "core/brdf.h"
#include "core/math.h"

namespace reel {

Vec3 RadianceMap::texel(int x, int y) const {
  x = ((x % width) + width) % width;
  y = std::clamp(y, 0, height - 1);
  const float* p = &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
  return {p[0], p[1], p[2]};
}

Vec3 RadianceMap::directionOf(double u, double v) const {
  const double phi = 2.0 * kPi * u / width - kPi, theta = kPi * v / height;
  return {std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
}

void RadianceMap::coordsOf(const Vec3& d, double& u, double& v) const {
  const Vec3 n = d.normalized();
  u = (std::atan2(n.x(), -n.z()) + kPi) / (2.0 * kPi) * width;
  v = std::acos(std::clamp(n.y(), -1.0, 1.0)) / kPi * height;
}

Vec3 RadianceMap::at(const Vec3& dir) const {
  double u, v;
  coordsOf(dir, u, v);
  const double fx = u - 0.5, fy = v - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const double tx = fx - x0, ty = fy - y0;
  return (1 - ty) * ((1 - tx) * texel(x0, y0) + tx * texel(x0 + 1, y0)) +
         ty * ((1 - tx) * texel(x0, y0 + 1) + tx * texel(x0 + 1, y0 + 1));
}

RadianceMap proceduralSky(const Vec3& zenith, const Vec3& horizon, const Vec3& ground, int width) {
  width = std::max(width, 4);
  RadianceMap m;
  m.width = width;
  m.height = width / 2;
  m.rgb.resize(static_cast<std::size_t>(3 * m.width * m.height));
  for (int y = 0; y < m.height; ++y) {
    const double elevation = kPi / 2 - kPi * (y + 0.5) / m.height;  // radians above the horizon
    const double up = std::clamp(elevation / (kPi / 2), 0.0, 1.0);
    const Vec3 sky = zenith + (horizon - zenith) * std::pow(1.0 - up, 3.0);
    const double s = std::clamp(1.0 + elevation / (12.0 * kPi / 180), 0.0, 1.0);  // 0 below −12°, 1 from the horizon up
    const Vec3 c = ground + (sky - ground) * (s * s * (3 - 2 * s));
    for (int x = 0; x < m.width; ++x)
      for (int k = 0; k < 3; ++k) m.rgb[3 * (static_cast<std::size_t>(y) * m.width + x) + k] = static_cast<float>(c[k]);
  }
  return m;
}

std::array<double, 9> shBasis(const Vec3& n) {
  const double x = n.x(), y = n.y(), z = n.z();
  return {0.282095,           0.488603 * y,       0.488603 * z, 0.488603 * x, 1.092548 * x * y,
          1.092548 * y * z,   0.315392 * (3 * z * z - 1),     1.092548 * x * z, 0.546274 * (x * x - y * y)};
}

Vec3 Environment::diffuse(const Vec3& n) const {
  const auto y = shBasis(n.normalized());
  Vec3 c = Vec3::Zero();
  for (std::size_t i = 0; i < 9; ++i) c += sh[i] * y[i];
  return c;
}

Vec3 Environment::specular(const Vec3& r, double roughness) const {
  const double lod = std::clamp(roughness, 0.0, 1.0) * (static_cast<double>(levels.size()) - 1);
  const std::size_t l0 = std::min(static_cast<std::size_t>(lod), levels.size() - 1);
  const std::size_t l1 = std::min(l0 + 1, levels.size() - 1);
  const double t = lod - static_cast<double>(l0);
  return (1 - t) * levels[l0].at(r) + t * levels[l1].at(r);
}

namespace {

// Half the size by 2x2 box averages (energy kept).
RadianceMap halve(const RadianceMap& m) {
  RadianceMap h;
  h.width = std::max(m.width / 2, 1);
  h.height = std::max(m.height / 2, 1);
  h.rgb.resize(static_cast<std::size_t>(3 * h.width * h.height));
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x) {
      const Vec3 c = 0.25 * (m.texel(2 * x, 2 * y) + m.texel(2 * x + 1, 2 * y) + m.texel(2 * x, 2 * y + 1) +
                             m.texel(2 * x + 1, 2 * y + 1));
      for (int k = 0; k < 3; ++k) h.rgb[3 * (static_cast<std::size_t>(y) * h.width + x) + k] = static_cast<float>(c[k]);
    }
  return h;
}

// The map scaled and turned, resampled to 256x128: level 0 of the environment (box-halved
// while it is twice that or more, so no texel's light is skipped, then bilinear).
RadianceMap base(const RadianceMap& src, double intensity, double rotation_deg) {
  RadianceMap m = src;
  while (m.width >= 512 && m.height >= 256) m = halve(m);
  RadianceMap out;
  out.width = 256;
  out.height = 128;
  out.rgb.resize(static_cast<std::size_t>(3 * out.width * out.height));
  const double turn = rotation_deg * kPi / 180;
  const double c = std::cos(turn), s = std::sin(turn);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const Vec3 d = out.directionOf(x + 0.5, y + 0.5);
      // turned by +rotation about +y: look the other way round in the source
      const Vec3 r(c * d.x() - s * d.z(), d.y(), s * d.x() + c * d.z());
      const Vec3 v = m.at(r) * intensity;
      for (int k = 0; k < 3; ++k) out.rgb[3 * (static_cast<std::size_t>(y) * out.width + x) + k] = static_cast<float>(v[k]);
    }
  return out;
}

}  // namespace

// Specular levels: Karis 2013's prefiltered radiance with n = v = r, each GGX sample weighed by
// n·l, read from a box-filtered pyramid of the map at the level whose texels cover the sample's
// solid angle (Křivánek & Colbert 2008, "Real-time Shading with Filtered Importance Sampling"),
// so a few dozen samples give a smooth result.
std::shared_ptr<Environment> prefilterEnvironment(const RadianceMap& src, double intensity, double rotation_deg,
                                                        int levels, int samples) {
  levels = std::clamp(levels, 1, 6);
  auto env = std::make_shared<Environment>();
  std::vector<RadianceMap> pyramid{base(src, intensity, rotation_deg)};
  while (pyramid.back().width > 4 && pyramid.back().height > 2) pyramid.push_back(halve(pyramid.back()));
  const RadianceMap& m0 = pyramid[0];
  // Irradiance harmonics: Σ L(ω)·Y_i(ω)·dΩ over the texels, then the cosine lobe's band factors
  // π, 2π/3, π/4 (Ramamoorthi & Hanrahan 2001, eq. 8) and 1/π.
  std::array<Vec3, 9> L{};
  L.fill(Vec3::Zero());
  for (int y = 0; y < m0.height; ++y) {
    const double theta = kPi * (y + 0.5) / m0.height;
    const double d_omega = (2 * kPi / m0.width) * (kPi / m0.height) * std::sin(theta);
    for (int x = 0; x < m0.width; ++x) {
      const auto Y = shBasis(m0.directionOf(x + 0.5, y + 0.5));
      const Vec3 c = m0.texel(x, y) * d_omega;
      for (std::size_t i = 0; i < 9; ++i) L[i] += c * Y[i];
    }
  }
  const double band[9] = {1.0, 2.0 / 3, 2.0 / 3, 2.0 / 3, 0.25, 0.25, 0.25, 0.25, 0.25};
  for (std::size_t i = 0; i < 9; ++i) env->sh[i] = L[i] * band[i];

  const double texel_omega = 4 * kPi / (static_cast<double>(m0.width) * m0.height);
  env->levels.push_back(m0);
  for (int k = 1; k < levels; ++k) {
    const double rough = static_cast<double>(k) / (levels - 1), alpha = rough * rough;
    RadianceMap lv;
    lv.width = m0.width >> k;  // a complete mipmap chain of 256x128 down to 8x4
    lv.height = m0.height >> k;
    lv.rgb.resize(static_cast<std::size_t>(3 * lv.width * lv.height));
    for (int y = 0; y < lv.height; ++y)
      for (int x = 0; x < lv.width; ++x) {
        const Vec3 n = lv.directionOf(x + 0.5, y + 0.5);
        const Vec3 t = (std::abs(n.y()) < 0.999 ? Vec3::UnitY().cross(n) : Vec3::UnitX().cross(n)).normalized();
        const Vec3 b = n.cross(t);
        Vec3 sum = Vec3::Zero();
        double wsum = 0;
        for (int s = 0; s < samples; ++s) {
          const Vec3 hl = brdf::sampleGgx(brdf::hammersley(static_cast<unsigned>(s), static_cast<unsigned>(samples)), alpha);
          const Vec3 h = hl.x() * t + hl.y() * b + hl.z() * n;
          const double nh = hl.z();
          const Vec3 l = 2.0 * nh * h - n;
          const double nl = n.dot(l);
          if (nl <= 0) continue;
          const double pdf = brdf::ggxD(nh, alpha) / 4.0;  // n = v: n·h = v·h
          const double omega = 1.0 / (samples * std::max(pdf, 1e-8));
          const double top = static_cast<double>(pyramid.size() - 1);
          const double lod = std::clamp(0.5 * std::log2(omega / texel_omega) + 1.0, 0.0, top);
          const std::size_t p0 = static_cast<std::size_t>(lod);
          const std::size_t p1 = std::min(p0 + 1, pyramid.size() - 1);
          const double f = lod - static_cast<double>(p0);
          sum += ((1 - f) * pyramid[p0].at(l) + f * pyramid[p1].at(l)) * nl;
          wsum += nl;
        }
        const Vec3 c = wsum > 0 ? Vec3(sum / wsum) : Vec3(m0.at(n));
        for (int q = 0; q < 3; ++q) lv.rgb[3 * (static_cast<std::size_t>(y) * lv.width + x) + q] = static_cast<float>(c[q]);
      }
    env->levels.push_back(std::move(lv));
  }
  return env;
}

}  // namespace reel
