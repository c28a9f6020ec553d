#include "sim/face/head.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>

#include "core/math.h"
#include "sim/geometry.h"

namespace reel {
namespace {

double sq(double x) { return x * x; }

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

double gauss(double x, double y, double x0, double y0, double sx, double sy) {
  const double u = (x - x0) / sx, v = (y - y0) / sy;
  return std::exp(-0.5 * (u * u + v * v));
}

// n + 1 angles from a0 to a1 whose spacing follows 1 / density: equal steps of the density's
// integral (so a region of density 3 gets three times the samples).
std::vector<double> warped(int n, double a0, double a1, const std::function<double(double)>& density) {
  constexpr int kFine = 4096;
  std::vector<double> cum(kFine + 1, 0.0);
  for (int k = 0; k < kFine; ++k) {
    const double a = a0 + (a1 - a0) * (k + 0.5) / kFine;
    cum[static_cast<std::size_t>(k) + 1] = cum[static_cast<std::size_t>(k)] + density(a);
  }
  std::vector<double> out(static_cast<std::size_t>(n) + 1);
  std::size_t k = 0;
  for (int i = 0; i <= n; ++i) {
    const double target = cum[kFine] * i / n;
    while (k + 1 < static_cast<std::size_t>(kFine) && cum[k + 1] < target) ++k;
    const double frac = std::clamp((target - cum[k]) / (cum[k + 1] - cum[k]), 0.0, 1.0);
    out[static_cast<std::size_t>(i)] = a0 + (a1 - a0) * (static_cast<double>(k) + frac) / kFine;
  }
  out.front() = a0;
  out.back() = a1;
  return out;
}

// A smooth bump of height 1 at c, falling to 0 at c ± w (a raised cosine).
double bump(double a, double c, double w) {
  const double d = std::abs(a - c) / w;
  return d >= 1 ? 0.0 : 0.5 * (1 + std::cos(kPi * d));
}

// The head at height 0.24 m before its features: an ellipsoid narrowing toward the jaw, joined
// smoothly to a neck (a capped elliptic cylinder). Negative inside.
double baseShape(const Vec3& p) {
  const double x = p.x(), y = p.y(), z = p.z();
  const double narrow = 1.0 - 0.16 * smoothstep(0.0, -0.1, y) - 0.03 * smoothstep(0.04, 0.11, y);
  const double az = z > 0 ? 0.094 : 0.102;
  const double head = std::sqrt(sq(x / (0.074 * narrow)) + sq(y / 0.112) + sq(z / az)) - 1.0;
  const double cyl = std::sqrt(sq(x / 0.044) + sq((z + 0.018) / 0.048)) - 1.0;
  const double neck = std::max({cyl, (y + 0.03) / 0.05, (-y - 0.24) / 0.05});  // capped at y = −0.03 and −0.24
  // Smooth minimum: the union with a fillet under the jaw.
  const double k = 0.08;
  const double h = std::clamp(0.5 + 0.5 * (neck - head) / k, 0.0, 1.0);
  return neck * (1 - h) + head * h - k * h * (1 - h);
}

// Where the ray from the centre along unit d leaves the base shape, m (bisection).
double baseRadius(const Vec3& d) {
  double lo = 1e-3, hi = 0.6;
  for (int it = 0; it < 48; ++it) {
    const double mid = 0.5 * (lo + hi);
    (baseShape(mid * d) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

constexpr double kMouthY = -0.058, kMouthHalf = 0.022, kEyeX = 0.032, kEyeY = 0.012;

// The features as displacements along the ray, m, from the base point p (height 0.24), its
// direction d and the mouth's height ym: the skull's (brow ridge, eye sockets, cheekbones, chin,
// ears) and the soft tissue's (nose, lips and the grooves between them), which only the skin has.
struct Features {
  double bone = 0.0, soft = 0.0;
};

Features features(const Vec3& p, const Vec3& d, double ym) {
  const double X = p.x(), Y = p.y();
  const double front = smoothstep(0.15, 0.7, d.z());
  Features f;
  for (double s : {-1.0, 1.0}) {
    f.bone += 0.007 * gauss(X, Y, s * 0.03, 0.033, 0.022, 0.008);      // brow ridge
    f.bone -= 0.017 * gauss(X, Y, s * kEyeX, kEyeY, 0.015, 0.009);    // eye socket
    f.bone += 0.006 * gauss(X, Y, s * 0.046, -0.008, 0.015, 0.012);   // cheekbone
    f.soft += 0.006 * gauss(X, Y, s * 0.012, -0.029, 0.006, 0.006);   // nostril wing
  }
  // Nose: the bridge down from the brows to the tip.
  const double along = smoothstep(0.026, 0.0, Y) * smoothstep(-0.042, -0.022, Y);
  f.soft += (0.004 + 0.012 * smoothstep(0.02, -0.02, Y)) * std::exp(-0.5 * sq(X / 0.0075)) * along;
  f.soft += 0.008 * gauss(X, Y, 0, -0.023, 0.009, 0.008);
  // Lips, the parting between them, the dip below; the chin.
  f.soft += 0.0065 * gauss(X, Y, 0, ym + 0.0065, 0.018, 0.0048);
  f.soft += 0.0065 * gauss(X, Y, 0, ym - 0.0075, 0.016, 0.0052);
  f.soft -= 0.0025 * gauss(X, Y, 0, ym, 0.024, 0.0016);
  f.soft -= 0.003 * gauss(X, Y, 0, ym - 0.019, 0.016, 0.004);
  f.bone += 0.009 * gauss(X, Y, 0, -0.098, 0.02, 0.013);
  f.bone += 0.011 * gauss(X, Y, 0, ym + 0.004, 0.028, 0.022);  // the teeth's arch under the lips
  f.bone *= front;
  f.soft *= front;
  // Ears, on the sides.
  const double side = std::pow(std::abs(d.x()), 6.0);
  f.bone += 0.013 * side * std::exp(-0.5 * sq((Y - 0.004) / 0.02)) * std::exp(-0.5 * sq((p.z() + 0.01) / 0.02));
  return f;
}

}  // namespace

FaceSurface makeHead(double height, std::array<int, 2> resolution, double thickness) {
  const int C = resolution[0] + resolution[0] % 2;  // even: the midline is a column, the face symmetric
  const int R = resolution[1];
  const double s = height / 0.24;
  FaceSurface out;
  out.generated = true;
  out.scale = s;
  // Rows (polar angle from the crown) and columns (azimuth from the front), denser on the face.
  const std::vector<double> theta = warped(R, 0.0, kPi, [](double a) {
    return 1.0 + 2.2 * bump(a, 1.72, 0.95) - 0.6 * smoothstep(2.6, 2.9, a);
  });
  const std::vector<double> phi = warped(C, -kPi, kPi, [](double a) { return 1.0 + 2.2 * bump(a, 0.0, 1.45); });
  auto dir = [](double th, double ph) { return Vec3(std::sin(th) * std::sin(ph), std::cos(th), std::sin(th) * std::cos(ph)); };
  // The mouth's row: the ring whose front is nearest the mouth's height.
  int jm = 1;
  for (int j = 1; j < R; ++j) {
    const double y = baseRadius(dir(theta[static_cast<std::size_t>(j)], 0.0)) * std::cos(theta[static_cast<std::size_t>(j)]);
    const double yb = baseRadius(dir(theta[static_cast<std::size_t>(jm)], 0.0)) * std::cos(theta[static_cast<std::size_t>(jm)]);
    if (std::abs(y - kMouthY) < std::abs(yb - kMouthY)) jm = j;
  }
  const double ym = baseRadius(dir(theta[static_cast<std::size_t>(jm)], 0.0)) * std::cos(theta[static_cast<std::size_t>(jm)]);
  const Vec3 skin_tone(0.62, 0.36, 0.27);
  std::vector<Vec3> base;  // base points, for colours and weights
  auto add = [&](const Vec3& d) {
    const double rb = baseRadius(d);
    const Vec3 p = rb * d;
    const Features f = features(p, d, ym);
    // The skin takes every feature; the skull its own, the tissue's thickness below (thicker
    // under the nose and lips, which are soft tissue only; never above the skin).
    const double r = rb + f.bone + f.soft;
    out.skin.push_back(s * r * d);
    out.bone.push_back(s * (std::min(rb + f.bone, r) - thickness / s) * d);
    base.push_back(p);
  };
  add(Vec3(0, 1, 0));
  for (int j = 1; j < R; ++j)
    for (int i = 0; i < C; ++i) add(dir(theta[static_cast<std::size_t>(j)], phi[static_cast<std::size_t>(i)]));
  add(Vec3(0, -1, 0));
  const auto bottom = static_cast<std::uint32_t>(out.skin.size() - 1);
  auto ring = [&](int j, int i) { return static_cast<std::uint32_t>(1 + (j - 1) * C + ((i % C) + C) % C); };
  // The lips' parting: the mouth row's vertices between the corners get a copy for the lower lip.
  std::map<std::uint32_t, std::uint32_t> lower;
  out.lower_lip = out.skin.size();
  for (int i = 0; i < C; ++i) {
    const Vec3& p = base[ring(jm, i)];
    if (p.z() > 0 && std::abs(p.x()) < kMouthHalf) {
      // The corners (the first column outside on each side) stay shared.
      lower[ring(jm, i)] = static_cast<std::uint32_t>(out.skin.size());
      out.skin.push_back(out.skin[ring(jm, i)]);
      out.bone.push_back(out.bone[ring(jm, i)]);
      base.push_back(p);
    }
  }
  auto low = [&](std::uint32_t v) {
    auto it = lower.find(v);
    return it == lower.end() ? v : it->second;
  };
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { out.tris.insert(out.tris.end(), {a, b, c}); };
  // Counter-clockwise from outside: columns run toward +x at the front, rows downward.
  for (int i = 0; i < C; ++i) tri(0, ring(1, i), ring(1, i + 1));
  for (int j = 1; j + 1 < R; ++j)
    for (int i = 0; i < C; ++i) {
      std::uint32_t a = ring(j, i), b = ring(j, i + 1), c = ring(j + 1, i), d = ring(j + 1, i + 1);
      if (j == jm) a = low(a), b = low(b);  // the band below the parting takes the lower lip
      // Diagonals mirrored about the midline, so the mesh (and every spring) is symmetric.
      if (i < C / 2) {
        tri(a, d, b);
        tri(a, c, d);
      } else {
        tri(a, c, b);
        tri(b, c, d);
      }
    }
  for (int i = 0; i < C; ++i) tri(bottom, ring(R - 1, i + 1), ring(R - 1, i));
  // Colours: skin, lips, brows, hair; the jaw's share of each bone point.
  const std::size_t n = out.skin.size();
  out.color.resize(n);
  out.jaw.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& p = base[k];
    const Vec3 d = p.normalized();
    const double X = p.x(), Y = p.y();
    const double front = smoothstep(0.15, 0.7, d.z());
    const double lips = front * std::max(gauss(X, Y, 0, ym + 0.005, 0.019, 0.005), gauss(X, Y, 0, ym - 0.007, 0.017, 0.006));
    double brows = 0.0;
    for (double sx : {-1.0, 1.0}) brows = std::max(brows, front * gauss(X, Y, sx * 0.03, 0.037, 0.014, 0.0035));
    const double hairline = 0.072 * smoothstep(-0.3, 0.5, d.z()) + (-0.03) * (1 - smoothstep(-0.3, 0.5, d.z()));
    const double ears = std::pow(std::abs(d.x()), 6.0) * std::exp(-0.5 * sq((Y - 0.004) / 0.03));
    const double hair = smoothstep(hairline - 0.012, hairline + 0.012, Y) * (1 - ears);
    Vec3 c = skin_tone + 0.05 * front * gauss(std::abs(X), Y, 0.045, -0.02, 0.015, 0.012) * Vec3(1, -0.2, -0.2);
    c = (1 - 0.85 * lips) * c + 0.85 * lips * Vec3(0.5, 0.15, 0.13);
    c = (1 - 0.8 * brows) * c + 0.8 * brows * Vec3(0.08, 0.05, 0.035);
    c = (1 - hair) * c + hair * Vec3(0.05, 0.035, 0.025);
    out.color[k] = c;
    // The jaw: everything below the parting at the front, fading to the sides and into the throat.
    const bool lower_lip = k >= bottom + 1;
    double w = std::clamp((ym + 0.012 - Y) / 0.024, 0.0, 1.0);
    if (std::abs(Y - ym) < 1e-12 && std::abs(X) < kMouthHalf && p.z() > 0) w = lower_lip ? 1.0 : 0.0;
    w *= smoothstep(-0.05, 0.35, d.z());
    w *= 1 - smoothstep(-0.105, -0.14, Y);
    out.jaw[k] = w;
  }
  // Eyes: in the sockets, their fronts 7.5 mm out of the skin at the socket's deepest.
  out.eye_radius = 0.012 * s;
  for (int e = 0; e < 2; ++e) {
    const double x = (e == 0 ? 1 : -1) * kEyeX;
    const double z = 0.094 * std::sqrt(std::max(0.0, 1 - sq(x / 0.074) - sq(kEyeY / 0.112)));
    const Vec3 d = Vec3(x, kEyeY, z).normalized();
    const double rb = baseRadius(d);
    const Features f = features(rb * d, d, ym);
    const Vec3 skin = s * (rb + f.bone + f.soft) * d;
    out.eye[static_cast<std::size_t>(e)] = skin - Vec3(0, 0, out.eye_radius - 0.0075 * s);
  }
  out.mouth = out.skin[ring(jm, C / 2)];  // the midline: column C/2 faces +z
  out.mouth_width = 2 * kMouthHalf * s;
  out.jaw_hinge = s * Vec3(0, -0.008, -0.018);
  return out;
}

Result<FaceSurface> userHead(const TriMesh& mesh, const TriMesh* skull, double inset, const std::string& path) {
  FaceSurface out;
  // Weld vertices at the same position, to a millionth of the mesh's size (files split them at
  // seams of normals and UVs, and a pole's copies differ by rounding).
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], static_cast<double>(mesh.positions[3 * v + static_cast<std::size_t>(c)]));
      hi[c] = std::max(hi[c], static_cast<double>(mesh.positions[3 * v + static_cast<std::size_t>(c)]));
    }
  const double tol = 1e-6 * std::max((hi - lo).norm(), 1e-9);
  std::map<std::array<long long, 3>, std::uint32_t> index;
  std::vector<std::uint32_t> remap(mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3 p(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    const std::array<long long, 3> key{std::llround(p.x() / tol), std::llround(p.y() / tol), std::llround(p.z() / tol)};
    auto [it, fresh] = index.emplace(key, static_cast<std::uint32_t>(out.skin.size()));
    if (fresh) out.skin.push_back(p);
    remap[v] = it->second;
  }
  // Triangles that welding collapsed (a pole's slivers) are dropped.
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t a = remap[mesh.indices[t]], b = remap[mesh.indices[t + 1]], c = remap[mesh.indices[t + 2]];
    if (a != b && b != c && a != c) out.tris.insert(out.tris.end(), {a, b, c});
  }
  // Closed: every edge in exactly two triangles, once each way.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t t = 0; t + 2 < out.tris.size(); t += 3)
    for (int e = 0; e < 3; ++e) ++edges[{out.tris[t + static_cast<std::size_t>(e)], out.tris[t + static_cast<std::size_t>((e + 1) % 3)]}];
  for (const auto& [e, count] : edges)
    if (count != 1 || !edges.count({e.second, e.first}))
      return Error(ErrorKind::BadInput, path + ": the face mesh must be closed (every edge shared by two triangles); edge " +
                                            std::to_string(e.first) + "–" + std::to_string(e.second) + " is not");
  const std::size_t n = out.skin.size();
  std::vector<Vec3> normal(n, Vec3::Zero());
  for (std::size_t t = 0; t + 2 < out.tris.size(); t += 3) {
    const Vec3 &a = out.skin[out.tris[t]], &b = out.skin[out.tris[t + 1]], &c = out.skin[out.tris[t + 2]];
    const Vec3 an = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) normal[out.tris[t + static_cast<std::size_t>(k)]] += an;
  }
  for (Vec3& v : normal) v = unitOr(v, Vec3::UnitZ());
  out.bone.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (skull) {
      double best = 1e300;
      for (std::size_t t = 0; t + 2 < skull->indices.size(); t += 3) {
        auto P = [&](std::size_t i) {
          const std::size_t v = skull->indices[t + i];
          return Vec3(skull->positions[3 * v], skull->positions[3 * v + 1], skull->positions[3 * v + 2]);
        };
        const Vec3 q = closestOnTriangle(out.skin[k], P(0), P(1), P(2));
        if ((q - out.skin[k]).squaredNorm() < best) best = (q - out.skin[k]).squaredNorm(), out.bone[k] = q;
      }
    } else {
      out.bone[k] = out.skin[k] - inset * normal[k];
    }
    if ((out.skin[k] - out.bone[k]).dot(normal[k]) <= 1e-5)
      return Error(ErrorKind::BadInput, path + ": the tissue crosses the skull at vertex " + std::to_string(k) +
                                            " (the skull is not below the skin there)");
  }
  // An inset deeper than the body is thick comes out near the other side.
  for (std::size_t k = 0; k < n && !skull; ++k)
    for (std::size_t j = 0; j < n; ++j)
      if ((out.bone[k] - out.skin[j]).norm() < 0.5 * inset)
        return Error(ErrorKind::BadInput, path + ": the layers cross the skull at vertex " + std::to_string(k) +
                                              " (an inset of " + std::to_string(inset) + " m is deeper than the head is thick there)");
  // An inset that folds (a surface curved tighter than the inset) turns bone triangles over.
  for (std::size_t t = 0; t + 2 < out.tris.size(); t += 3) {
    const Vec3 &a = out.skin[out.tris[t]], &b = out.skin[out.tris[t + 1]], &c = out.skin[out.tris[t + 2]];
    const Vec3 &A = out.bone[out.tris[t]], &B = out.bone[out.tris[t + 1]], &Cc = out.bone[out.tris[t + 2]];
    if ((b - a).cross(c - a).dot((B - A).cross(Cc - A)) <= 0)
      return Error(ErrorKind::BadInput, path + ": the layers cross the skull near vertex " + std::to_string(out.tris[t]) +
                                            " (the surface curves tighter than the tissue is thick)");
  }
  out.color.assign(n, Vec3(0.62, 0.36, 0.27));
  out.jaw.assign(n, 0.0);
  return out;
}

std::size_t frontVertex(const FaceSurface& s, double x, double y) {
  std::size_t best = 0;
  double bd = 1e300;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3& p = s.skin[k];
    if (p.z() <= 0) continue;
    const double d = sq(p.x() - x) + sq(p.y() - y);
    if (d < bd - 1e-15) bd = d, best = k;
  }
  return best;
}

}  // namespace reel
