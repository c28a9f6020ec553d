#include "core/brdf.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace reel::brdf {

double ggxD(double n_dot_h, double alpha) {
  const double a2 = alpha * alpha;
  const double d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}

double smithV(double n_dot_l, double n_dot_v, double alpha) {
  const double a2 = alpha * alpha;
  const double gv = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
  const double gl = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
  return 0.5 / std::max(gv + gl, 1e-12);
}

double schlick(double f0, double f90, double cos_theta) {
  return f0 + (f90 - f0) * std::pow(1.0 - std::clamp(cos_theta, 0.0, 1.0), 5.0);
}

double roughnessOfShininess(double shininess) {
  return std::sqrt(std::sqrt(2.0 / (std::max(shininess, 0.0) + 2.0)));
}

Vec2 hammersley(unsigned k, unsigned n) {
  unsigned b = k;
  b = (b << 16u) | (b >> 16u);
  b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
  b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
  b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
  b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
  return {(k + 0.5) / n, b * 2.3283064365386963e-10};
}

Vec3 sampleGgx(const Vec2& u, double alpha) {
  const double phi = 2.0 * kPi * u.x();
  const double cos_t = std::sqrt((1.0 - u.y()) / (1.0 + (alpha * alpha - 1.0) * u.y()));
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
  return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

DfgTable integrateDfg(int size, int samples) {
  DfgTable t;
  t.size = size;
  t.ab.assign(static_cast<std::size_t>(2 * size * size), 0.0f);
  const unsigned n = static_cast<unsigned>(samples);
  for (int j = 0; j < size; ++j) {
    const double rough = (j + 0.5) / size;
    const double alpha = rough * rough;
    for (int i = 0; i < size; ++i) {
      const double nv = (i + 0.5) / size;
      const Vec3 v(std::sqrt(1.0 - nv * nv), 0.0, nv);
      double a = 0, b = 0;
      // ∫ f_s (n·l) dl with l drawn from the GGX half-vector density p(l) = D·(n·h)/(4 v·h):
      // each sample weighs V·(n·l)·4(v·h)/(n·h), split by Schlick into its F0 and F90 parts.
      for (unsigned k = 0; k < n; ++k) {
        const Vec3 h = sampleGgx(hammersley(k, n), alpha);
        const double vh = v.dot(h);
        const Vec3 l = 2.0 * vh * h - v;
        if (l.z() <= 0 || vh <= 0) continue;
        const double w = smithV(l.z(), nv, alpha) * l.z() * 4.0 * vh / h.z();
        const double fc = std::pow(1.0 - vh, 5.0);
        a += (1.0 - fc) * w;
        b += fc * w;
      }
      const std::size_t at = static_cast<std::size_t>(2 * (j * size + i));
      t.ab[at] = static_cast<float>(a / n);
      t.ab[at + 1] = static_cast<float>(b / n);
    }
  }
  return t;
}

namespace {

// d'Eon & Luebke 2007, table 14-1: variance (mm²), then the red, green and blue weights.
constexpr double kSkinGaussians[6][4] = {{0.0064, 0.233, 0.455, 0.649}, {0.0484, 0.100, 0.336, 0.344},
                                         {0.187, 0.118, 0.198, 0.0},     {0.567, 0.113, 0.007, 0.007},
                                         {1.99, 0.358, 0.004, 0.0},      {7.41, 0.078, 0.0, 0.0}};

double gaussian2d(double v, double r) { return std::exp(-r * r / (2.0 * v)) / (2.0 * kPi * v); }

// One Gaussian of the profile around a ring of radius r (mm): its samples x_k ∈ [−X, X] (X eight
// of its angular widths, at most π) by the midpoint rule, with the weights G(v, 2r·sin(|x|/2))·dx.
struct RingKernel {
  std::vector<double> cos_x, sin_x, weight;
  double total = 0.0;
};
RingKernel ringKernel(double v, double r) {
  constexpr int kSteps = 128;
  const double X = std::min(kPi, 8.0 * std::sqrt(v) / r), dx = 2.0 * X / kSteps;
  RingKernel k;
  for (int s = 0; s < kSteps; ++s) {
    const double x = -X + (s + 0.5) * dx;
    const double w = gaussian2d(v, 2.0 * r * std::sin(0.5 * std::abs(x))) * dx;
    k.cos_x.push_back(std::cos(x));
    k.sin_x.push_back(std::sin(x));
    k.weight.push_back(w);
    k.total += w;
  }
  return k;
}

// ∫ cos⁺(θ + x)·kernel over the kernel's samples: cos(θ + x) = cos θ cos x − sin θ sin x.
double ringIntegral(const RingKernel& k, double cos_t, double sin_t) {
  double sum = 0.0;
  for (std::size_t s = 0; s < k.weight.size(); ++s) sum += std::max(0.0, cos_t * k.cos_x[s] - sin_t * k.sin_x[s]) * k.weight[s];
  return sum;
}

// D for each column's cos θ at one curvature (the kernels are the same across a row).
void skinRow(double curvature, const std::vector<double>& cos_t, Vec3* out) {
  if (curvature <= 0.0) {
    for (std::size_t i = 0; i < cos_t.size(); ++i) out[i] = Vec3::Constant(std::max(0.0, cos_t[i]));
    return;
  }
  std::vector<RingKernel> kernels;
  for (const auto& g : kSkinGaussians) kernels.push_back(ringKernel(g[0], 1.0 / curvature));
  for (std::size_t i = 0; i < cos_t.size(); ++i) {
    const double ct = std::clamp(cos_t[i], -1.0, 1.0), st = std::sqrt(1.0 - ct * ct);
    Vec3 num = Vec3::Zero(), den = Vec3::Zero();
    for (std::size_t g = 0; g < kernels.size(); ++g) {
      const double j = ringIntegral(kernels[g], ct, st);
      for (int c = 0; c < 3; ++c) {
        num[c] += kSkinGaussians[g][1 + c] * j;
        den[c] += kSkinGaussians[g][1 + c] * kernels[g].total;
      }
    }
    out[i] = num.cwiseQuotient(den);
  }
}

}  // namespace

Vec3 skinProfile(double r_mm) {
  Vec3 R = Vec3::Zero();
  for (const auto& g : kSkinGaussians) R += gaussian2d(g[0], r_mm) * Vec3(g[1], g[2], g[3]);
  return R;
}

Vec3 preintegratedSkin(double n_dot_l, double curvature_per_mm) {
  Vec3 d;
  skinRow(curvature_per_mm, {n_dot_l}, &d);
  return d;
}

SkinTable integrateSkin(int size) {
  SkinTable t;
  t.size = size;
  t.rgb.assign(static_cast<std::size_t>(3 * size * size), 0.0f);
  std::vector<double> cos_t(static_cast<std::size_t>(size));
  for (int i = 0; i < size; ++i) cos_t[static_cast<std::size_t>(i)] = 2.0 * (i + 0.5) / size - 1.0;
  std::vector<Vec3> row(static_cast<std::size_t>(size));
  for (int j = 0; j < size; ++j) {
    const double f = (j + 0.5) / size;
    skinRow(kSkinMaxCurvature * f * f, cos_t, row.data());
    for (int i = 0; i < size; ++i)
      for (int c = 0; c < 3; ++c) t.rgb[static_cast<std::size_t>(3 * (j * size + i) + c)] = static_cast<float>(row[static_cast<std::size_t>(i)][c]);
  }
  return t;
}

namespace {

// A size × size table of N interleaved channels read bilinearly at (x, y) in [0, 1]², clamped to
// the texel centres, as the shader's texture is.
template <int N>
Eigen::Matrix<double, N, 1> bilinear(const std::vector<float>& data, int size, double x, double y) {
  auto coord = [&](double u, int& i0, double& f) {
    const double p = std::clamp(u * size - 0.5, 0.0, size - 1.0);
    i0 = std::min(static_cast<int>(p), size - 2);
    f = p - i0;
  };
  int i, j;
  double fi, fj;
  coord(x, i, fi);
  coord(y, j, fj);
  auto v = [&](int c, int r) {
    Eigen::Matrix<double, N, 1> out;
    for (int k = 0; k < N; ++k) out[k] = data[static_cast<std::size_t>(N * (r * size + c) + k)];
    return out;
  };
  return (1 - fj) * ((1 - fi) * v(i, j) + fi * v(i + 1, j)) + fj * ((1 - fi) * v(i, j + 1) + fi * v(i + 1, j + 1));
}

}  // namespace

Vec3 SkinTable::at(double n_dot_l, double curvature_per_mm) const {
  return bilinear<3>(rgb, size, 0.5 * n_dot_l + 0.5, std::sqrt(std::clamp(curvature_per_mm / kSkinMaxCurvature, 0.0, 1.0)));
}

Vec2 DfgTable::at(double n_dot_v, double roughness) const { return bilinear<2>(ab, size, n_dot_v, roughness); }

}  // namespace reel::brdf
