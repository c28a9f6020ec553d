#include "core/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/parallel.h"

namespace reel {
namespace {

// A plane of floats, row-major.
struct Plane {
  int w = 0, h = 0;
  std::vector<double> v;
  Plane() = default;
  Plane(int w_, int h_) : w(w_), h(h_), v(static_cast<std::size_t>(w_) * h_, 0.0) {}
  double& at(int x, int y) { return v[static_cast<std::size_t>(y) * w + x]; }
  double at(int x, int y) const { return v[static_cast<std::size_t>(y) * w + x]; }
};

// body(y) for every row of a plane's size, rows in parallel (each writes its own row).
template <class F>
void rows(const Plane& p, F&& body) {
  parallelBlocks(
      p.h, 8, [&](std::ptrdiff_t y0, std::ptrdiff_t y1) {
        for (auto y = y0; y < y1; ++y) body(static_cast<int>(y));
      },
      static_cast<std::ptrdiff_t>(p.w) * p.h);
}

// Separable convolution with a symmetric or antisymmetric kernel along x, then another along y;
// borders repeat the edge pixel.
Plane convolve(const Plane& in, const std::vector<double>& kx, const std::vector<double>& ky) {
  const int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
  Plane tmp(in.w, in.h), out(in.w, in.h);
  rows(in, [&](int y) {
    for (int x = 0; x < in.w; ++x) {
      double s = 0.0;
      for (int i = -rx; i <= rx; ++i) s += kx[static_cast<std::size_t>(i + rx)] * in.at(std::clamp(x + i, 0, in.w - 1), y);
      tmp.at(x, y) = s;
    }
  });
  rows(in, [&](int y) {
    for (int x = 0; x < in.w; ++x) {
      double s = 0.0;
      for (int j = -ry; j <= ry; ++j) s += ky[static_cast<std::size_t>(j + ry)] * tmp.at(x, std::clamp(y + j, 0, in.h - 1));
      out.at(x, y) = s;
    }
  });
  return out;
}

// --- SSIM ---

Plane luma(const Image& im) {
  Plane p(im.width, im.height);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const std::uint8_t* c = im.pixel(x, y);
      p.at(x, y) = 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
    }
  return p;
}

// --- FLIP ---

// Linear sRGB (D65) to CIE XYZ and back, as FLIP's reference implementation takes them (the
// forward matrix in exact fractions).
constexpr double kRgbToXyz[3][3] = {{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                                    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                                    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
constexpr double kXyzToRgb[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                                    {-0.969224334, 1.875930071, 0.041554224},
                                    {0.055639423, -0.204011202, 1.057148933}};
using V3 = std::array<double, 3>;
V3 mul(const double (&m)[3][3], const V3& a) {
  return {m[0][0] * a[0] + m[0][1] * a[1] + m[0][2] * a[2], m[1][0] * a[0] + m[1][1] * a[1] + m[1][2] * a[2],
          m[2][0] * a[0] + m[2][1] * a[1] + m[2][2] * a[2]};
}
// The reference white: the XYZ of linear RGB (1, 1, 1).
V3 white() { return mul(kRgbToXyz, {1.0, 1.0, 1.0}); }

// XYZ to the opponent space YCxCz (Zhang & Wandell's linearised CIELAB) and back.
V3 xyzToYcxcz(const V3& c, const V3& w) {
  const double y = c[1] / w[1];
  return {116.0 * y - 16.0, 500.0 * (c[0] / w[0] - y), 200.0 * (y - c[2] / w[2])};
}
V3 ycxczToXyz(const V3& c, const V3& w) {
  const double y = (c[0] + 16.0) / 116.0;
  return {w[0] * (y + c[1] / 500.0), w[1] * y, w[2] * (y - c[2] / 200.0)};
}
V3 xyzToLab(const V3& c, const V3& w) {
  auto f = [](double t) {
    constexpr double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(c[0] / w[0]), fy = f(c[1] / w[1]), fz = f(c[2] / w[2]);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}
// Lab with the Hunt effect (chroma fades with lightness), from clamped linear RGB.
V3 huntLab(const V3& rgb, const V3& w) {
  const V3 lab = xyzToLab(mul(kRgbToXyz, rgb), w);
  return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]};
}
// HyAB (Abasi, Tehran & Fairchild 2020): city-block in lightness, Euclidean in chroma.
double hyab(const V3& a, const V3& b) { return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]); }

// The contrast sensitivity of one opponent channel as a sum of two Gaussians in the spatial
// domain (the paper's Table 1), sampled at the pixels: a1·√(π/b1)·exp(−π²x²/b1) + the same with
// (a2, b2), x in degrees. Each term is separable; the kernel of the sum is Σ terms, normalised to
// sum 1 over the 2D support.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsf[3] = {{1.0, 0.0047, 0.0, 1e-5}, {1.0, 0.0053, 0.0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};

Plane csfFilter(const Plane& in, const Csf& c, int radius, double ppd) {
  const double pi2 = std::numbers::pi * std::numbers::pi;
  Plane out(in.w, in.h);
  double total = 0.0;
  std::array<std::vector<double>, 2> g;
  std::array<double, 2> amp{};
  for (int k = 0; k < 2; ++k) {
    const double a = k == 0 ? c.a1 : c.a2, b = k == 0 ? c.b1 : c.b2;
    amp[static_cast<std::size_t>(k)] = a * std::sqrt(std::numbers::pi / b);
    auto& gk = g[static_cast<std::size_t>(k)];
    for (int i = -radius; i <= radius; ++i) {
      const double x = i / ppd;
      gk.push_back(std::exp(-pi2 * x * x / b));
    }
    double s = 0.0;
    for (double v : gk) s += v;
    total += amp[static_cast<std::size_t>(k)] * s * s;
  }
  for (int k = 0; k < 2; ++k) {
    if (amp[static_cast<std::size_t>(k)] == 0.0) continue;
    const Plane part = convolve(in, g[static_cast<std::size_t>(k)], g[static_cast<std::size_t>(k)]);
    const double scale = amp[static_cast<std::size_t>(k)] / total;
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] += scale * part.v[i];
  }
  return out;
}

// The edge and point detectors: the first and second derivatives of a Gaussian of σ = ½·w·ppd,
// w = 0.082° (the paper's feature width), over ±3σ. The first derivative is scaled so its
// positive taps sum to 1; the second so its positive taps sum to 1 and its negative taps to −1.
struct FeatureKernels {
  std::vector<double> gauss, d1, d2;
};
FeatureKernels featureKernels(double ppd) {
  const double sigma = 0.5 * 0.082 * ppd;
  const int r = static_cast<int>(std::ceil(3.0 * sigma));
  FeatureKernels k;
  double gsum = 0.0, d1pos = 0.0, d2pos = 0.0, d2neg = 0.0;
  for (int i = -r; i <= r; ++i) {
    const double g = std::exp(-(i * i) / (2.0 * sigma * sigma));
    k.gauss.push_back(g);
    k.d1.push_back(-i * g);
    k.d2.push_back((i * i / (sigma * sigma) - 1.0) * g);
    gsum += g;
  }
  for (double& v : k.gauss) v /= gsum;
  double d1neg = 0.0;
  for (double v : k.d1) (v > 0 ? d1pos : d1neg) += v;
  for (double& v : k.d1) v = v > 0 ? v / d1pos : v / -d1neg;
  for (double v : k.d2) (v > 0 ? d2pos : d2neg) += v;
  for (double& v : k.d2) v = v > 0 ? v / d2pos : v / -d2neg;
  return k;
}

// The colour of an image after the eye's spatial filtering, as Hunt-adjusted Lab per pixel; and
// its luminance for the feature detectors.
void prepare(const Image& im, double ppd, int radius, std::vector<V3>& lab, Plane& lum) {
  const V3 w = white();
  std::array<Plane, 3> ch{Plane(im.width, im.height), Plane(im.width, im.height), Plane(im.width, im.height)};
  lum = Plane(im.width, im.height);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const std::uint8_t* p = im.pixel(x, y);
      const V3 rgb{srgbToLinear(p[0] / 255.0), srgbToLinear(p[1] / 255.0), srgbToLinear(p[2] / 255.0)};
      const V3 o = xyzToYcxcz(mul(kRgbToXyz, rgb), w);
      for (int c = 0; c < 3; ++c) ch[static_cast<std::size_t>(c)].at(x, y) = o[static_cast<std::size_t>(c)];
      lum.at(x, y) = (o[0] + 16.0) / 116.0;  // Y/Yn, 0..1
    }
  for (int c = 0; c < 3; ++c) ch[static_cast<std::size_t>(c)] = csfFilter(ch[static_cast<std::size_t>(c)], kCsf[c], radius, ppd);
  lab.resize(ch[0].v.size());
  rows(lum, [&](int y) {
    for (std::size_t i = static_cast<std::size_t>(y) * lum.w; i < static_cast<std::size_t>(y + 1) * lum.w; ++i) {
      V3 rgb = mul(kXyzToRgb, ycxczToXyz({ch[0].v[i], ch[1].v[i], ch[2].v[i]}, w));
      for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);
      lab[i] = huntLab(rgb, w);
    }
  });
}

}  // namespace

double ssim(const Image& a, const Image& b) {
  REEL_CHECK(a.width == b.width && a.height == b.height, "images differ in size");
  if (a.width == 0 || a.height == 0) return 1.0;
  const Plane x = luma(a), y = luma(b);
  Plane xx(x.w, x.h), yy(x.w, x.h), xy(x.w, x.h);
  for (std::size_t i = 0; i < x.v.size(); ++i) {
    xx.v[i] = x.v[i] * x.v[i];
    yy.v[i] = y.v[i] * y.v[i];
    xy.v[i] = x.v[i] * y.v[i];
  }
  // Windows of 11 taps, or the image's size when smaller (then one window, centred).
  auto window = [](int n) {
    const int r = std::min(5, (n - 1) / 2);
    std::vector<double> g;
    double s = 0.0;
    for (int i = -r; i <= r; ++i) g.push_back(std::exp(-(i * i) / (2.0 * 1.5 * 1.5))), s += g.back();
    for (double& v : g) v /= s;
    return g;
  };
  const std::vector<double> gx = window(x.w), gy = window(x.h);
  const Plane mx = convolve(x, gx, gy), my = convolve(y, gx, gy), sxx = convolve(xx, gx, gy), syy = convolve(yy, gx, gy),
              sxy = convolve(xy, gx, gy);
  const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  const int rx = static_cast<int>(gx.size() / 2), ry = static_cast<int>(gy.size() / 2);
  double sum = 0.0;
  long long n = 0;
  for (int j = ry; j < x.h - ry; ++j)
    for (int i = rx; i < x.w - rx; ++i) {
      const double ux = mx.at(i, j), uy = my.at(i, j);
      const double vx = sxx.at(i, j) - ux * ux, vy = syy.at(i, j) - uy * uy, cxy = sxy.at(i, j) - ux * uy;
      sum += ((2 * ux * uy + c1) * (2 * cxy + c2)) / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
      ++n;
    }
  return n > 0 ? sum / static_cast<double>(n) : 1.0;
}

FlipResult flip(const Image& reference, const Image& test, double ppd, std::vector<float>* map) {
  REEL_CHECK(reference.width == test.width && reference.height == test.height, "images differ in size");
  REEL_CHECK(ppd > 0 && std::isfinite(ppd), "pixels per degree must be positive");
  FlipResult r;
  const std::size_t n = static_cast<std::size_t>(reference.width) * reference.height;
  if (map) map->assign(n, 0.0f);
  if (n == 0) return r;
  // One support for the three channels: three standard deviations of the widest Gaussian.
  double bmax = 0.0;
  for (const Csf& c : kCsf) bmax = std::max({bmax, c.b1, c.b2});
  const int radius = static_cast<int>(std::ceil(3.0 * std::sqrt(bmax / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
  std::vector<V3> lab_r, lab_t;
  Plane lum_r, lum_t;
  prepare(reference, ppd, radius, lab_r, lum_r);
  prepare(test, ppd, radius, lab_t, lum_t);
  // Colour: HyAB^qc, compressed so that differences up to pc·cmax take most of the range.
  constexpr double qc = 0.7, pc = 0.4, pt = 0.95, qf = 0.5;
  const V3 w = white();
  const double cmax = std::pow(hyab(huntLab({0.0, 1.0, 0.0}, w), huntLab({0.0, 0.0, 1.0}, w)), qc);
  // Features of the luminance: edges (first derivatives) and points (second).
  const FeatureKernels k = featureKernels(ppd);
  auto features = [&](const Plane& l, Plane& edge, Plane& point) {
    const Plane ex = convolve(l, k.d1, k.gauss), ey = convolve(l, k.gauss, k.d1);
    const Plane px = convolve(l, k.d2, k.gauss), py = convolve(l, k.gauss, k.d2);
    edge = point = Plane(l.w, l.h);
    for (std::size_t i = 0; i < l.v.size(); ++i) {
      edge.v[i] = std::hypot(ex.v[i], ey.v[i]);
      point.v[i] = std::hypot(px.v[i], py.v[i]);
    }
  };
  Plane edge_r, point_r, edge_t, point_t;
  features(lum_r, edge_r, point_r);
  features(lum_t, edge_t, point_t);
  std::vector<double> value(n);
  rows(lum_r, [&](int y) {
    for (std::size_t i = static_cast<std::size_t>(y) * lum_r.w; i < static_cast<std::size_t>(y + 1) * lum_r.w; ++i) {
      const double e = std::pow(hyab(lab_r[i], lab_t[i]), qc);
      const double ec = e < pc * cmax ? pt / (pc * cmax) * e : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
      const double ef = std::pow(std::max(std::abs(edge_r.v[i] - edge_t.v[i]), std::abs(point_r.v[i] - point_t.v[i])) /
                                     std::numbers::sqrt2,
                                 qf);
      value[i] = std::pow(ec, 1.0 - ef);
    }
  });
  double sum = 0.0;  // (in pixel order: the same bits for any thread count)
  for (std::size_t i = 0; i < n; ++i) {
    sum += value[i];
    r.max = std::max(r.max, value[i]);
    if (map) (*map)[i] = static_cast<float>(value[i]);
  }
  r.mean = sum / static_cast<double>(n);
  return r;
}

Image heatmap(const std::vector<float>& values, int width, int height, const Image* under) {
  // Control points of the ramp (sRGB), evenly spaced over 0..1.
  static constexpr std::array<std::array<double, 3>, 6> ramp{{{0, 0, 4},
                                                              {40, 11, 84},
                                                              {101, 21, 110},
                                                              {183, 55, 121},
                                                              {252, 137, 97},
                                                              {252, 253, 191}}};
  Image out(width, height);
  const bool over = under && under->width == width && under->height == height;
  for (std::size_t i = 0; i < values.size() && i < static_cast<std::size_t>(width) * height; ++i) {
    const double v = std::clamp(static_cast<double>(values[i]), 0.0, 1.0);
    // Over a picture, even a small difference shows in the ramp's purple, fully from 0.2 on.
    const double alpha = over ? std::min(1.0, 5.0 * v) : 1.0;
    const double t = (over ? std::max(v, 0.35) : v) * (ramp.size() - 1);
    const auto j = std::min(static_cast<std::size_t>(t), ramp.size() - 2);
    const double f = t - static_cast<double>(j);
    const double grey = over ? 0.4 * (under->rgb[i * 3] + under->rgb[i * 3 + 1] + under->rgb[i * 3 + 2]) / 3.0 : 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double hot = ramp[j][c] + f * (ramp[j + 1][c] - ramp[j][c]);
      out.rgb[i * 3 + c] = static_cast<std::uint8_t>(std::lround((1.0 - alpha) * grey + alpha * hot));
    }
  }
  return out;
}

}  // namespace reel
