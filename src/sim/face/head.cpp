#include "sim/face/head.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>

#include "core/math.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "sim/face/head_shape.h"
#include "sim/face/head_tone.h"
#include "sim/geometry.h"

namespace reel {
namespace {

using head::atIndex;
using head::direction;

// Rings of the neck below the rays' last, and the polar angle of that last ring (rad).
constexpr int kNeckRings = 4;
constexpr double kRayEnd = 2.875;

// The skin texture's padding: the share of its width beyond the midline, of its height at each end.
constexpr double kSkinPadU = 0.08, kSkinPadV = 0.02;


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

// The polar angle at azimuth ph whose base point lies as high as the midline's does at th0: the
// face's rows made level. (A ring of one polar angle rises toward the face's sides, where the
// head narrows: it would curve the lips' parting into a smile and tilt the eyes' rows.) Full over
// the face's front and its rows, fading out toward the sides, the crown and the neck.
double levelled(double th0, double ph, const FaceLook& look) {
  const double w = smoothstep(0.9, 1.2, th0) * smoothstep(2.5, 2.3, th0) * smoothstep(1.35, 0.8, std::abs(ph));
  if (w <= 0.0) return th0;
  const double target = head::baseRadius(direction(th0, 0.0), look) * std::cos(th0);
  auto height = [&](double th) { return head::baseRadius(direction(th, ph), look) * std::cos(th) - target; };
  // Secant steps from th0 (the height falls as the angle grows).
  double a = th0, b = th0 - 0.02, ga = height(a), gb = height(b);
  for (int it = 0; it < 6 && std::abs(gb - ga) > 1e-12; ++it) {
    const double c = std::clamp(b - gb * (b - a) / (gb - ga), th0 - 0.4, th0 + 0.4);
    a = b, ga = gb, b = c, gb = height(b);
  }
  return th0 + w * (b - th0);
}

}  // namespace

FaceSurface makeHead(double height, std::array<int, 2> resolution, double thickness, const FaceLook& look) {
  using head::baseRadius;
  using head::features;
  const int C = resolution[0] + resolution[0] % 2;  // even: the midline is a column, the face symmetric
  const int R = resolution[1];
  const double s = height / 0.24;
  FaceSurface out;
  out.generated = true;
  out.scale = s;
  out.look = look;
  // Rows (polar angle from the crown) and columns (azimuth from the front), denser on the face.
  // The rays' rows end at kRayEnd, where they meet the neck under the chin at the front and
  // 0.24 m down at the back; the neck's own rings go on below (at any row count: rows nearer
  // straight down would land on the neck's cut and fold the rings below them). theta[R] is the
  // bottom's angle, for the texture.
  out.theta = warped(R - 1, 0.0, kRayEnd, [](double a) {
    // (The neck under the jaw, seen at grazing rays from the centre, takes rows of its own.)
    return 1.0 + 2.4 * bump(a, 1.8, 0.95) + 1.2 * bump(a, 2.72, 0.16) - 0.6 * smoothstep(2.85, 3.0, a);
  });
  out.theta.push_back(kPi);
  out.phi = warped(C, -kPi, kPi, [](double a) { return 1.0 + 2.2 * bump(a, 0.0, 1.45); });
  const std::vector<double>&theta = out.theta, &phi = out.phi;
  // Each ring's levelled polar angle per column, kept in order down each column: at least a
  // third of the unlevelled spacing after the ring above (where the surface turns under the jaw,
  // levelling two rings could land them on one point, and their triangles would have no area).
  std::vector<double> polar(static_cast<std::size_t>((R + 1) * C));
  for (int i = 0; i < C; ++i)
    for (int j = 1; j < R; ++j) {
      const auto at = static_cast<std::size_t>(j * C + i);
      polar[at] = levelled(theta[static_cast<std::size_t>(j)], phi[static_cast<std::size_t>(i)], look);
      if (j > 1)
        polar[at] = std::max(polar[at], polar[at - static_cast<std::size_t>(C)] +
                                            (theta[static_cast<std::size_t>(j)] - theta[static_cast<std::size_t>(j) - 1]) / 3);
    }
  auto dir = [&](int j, int i) {
    return direction(polar[static_cast<std::size_t>(j * C + i)], phi[static_cast<std::size_t>(i)]);
  };
  // The mouth's row: the ring whose front is nearest the mouth's height.
  auto frontY = [&](int j) { return baseRadius(dir(j, C / 2), look) * dir(j, C / 2).y(); };
  int jm = 1;
  for (int j = 1; j < R; ++j)
    if (std::abs(frontY(j) - head::kMouthY) < std::abs(frontY(jm) - head::kMouthY)) jm = j;
  const double ym = frontY(jm);
  out.parting_y = ym;
  std::vector<Vec3> base;  // base points, for colours and weights
  // A vertex at base point p (its direction from the centre d).
  auto addAt = [&](const Vec3& p, const Vec3& d, float u, float v) {
    const head::Features f = features(p, d, ym, look);
    // The skin takes every feature; the skull its own, the tissue's thickness below (thicker
    // under the nose and lips, which are soft tissue only; never above the skin). Over the face
    // they stand out level (head::featureDirection), so its rows stay level and the lips'
    // parting straight.
    const Vec3 e = head::featureDirection(d);
    out.skin.push_back(s * (p + (f.bone + f.soft) * e));
    // The tissue's thickness is measured along the head's normal (a column along the ray from
    // the centre leans over where the surface meets the ray at a slant, under the chin by 45°:
    // a muscle's pull along the skin then drives the fascia into the bone).
    out.bone.push_back(s * (p + std::min(f.bone, f.bone + f.soft) * e) - thickness * head::baseNormal(p, look));
    out.uv.push_back({u, v});
    base.push_back(p);
  };
  auto add = [&](const Vec3& d, float u, float v) { addAt(baseRadius(d, look) * d, d, u, v); };
  // Texture coordinates: u from the midline (0) to the back (1), the same on both sides, so the
  // texture has no seam; v from the crown (0) to the neck (1), both along the grid's indices.
  // The texture's edges are padded (u: past the midline and past the back, mirrored; v: the
  // crown's and the neck's rows held), so its filtering, which wraps around, never mixes the back
  // of the head into the midline.
  auto tex = [](double a, double pad) { return static_cast<float>(pad + (1 - 2 * pad) * a); };
  auto texU = [&](double a) { return tex(a, kSkinPadU); };
  auto uOf = [&](int i) { return texU(static_cast<double>(std::abs(i - C / 2)) / (C / 2)); };
  add(Vec3(0, 1, 0), texU(0), tex(0, kSkinPadV));
  for (int j = 1; j < R; ++j)
    for (int i = 0; i < C; ++i) add(dir(j, i), uOf(i), tex(static_cast<double>(j) / R, kSkinPadV));
  // The neck: the last ring of rays runs under the chin at the front and down the nape at the
  // back; below it, kNeckRings rings of horizontal rays from the neck's axis, closer together
  // near the top, down to where the neck is cut (inside the shoulders), and a cap at its end.
  // (Rays from the head's centre meet the neck edge-on: they left it one fan of triangles from
  // the chin to the cut.) Their texture is the last ring's to the bottom's.
  for (int r = 1; r <= kNeckRings; ++r) {
    const double t = static_cast<double>(r) / kNeckRings;
    for (int i = 0; i < C; ++i) {
      const Vec3& top = base[static_cast<std::size_t>(1 + (R - 2) * C + i)];
      const double y = top.y() + (head::kNeckCut + 0.02 - top.y()) * t * t;
      // (Straight down from the last ring: the azimuth about the neck's axis, not the centre's.)
      const Vec3 axis(0.0, y, head::kNeckAxisZ), out_dir = Vec3(top.x(), 0.0, top.z() - head::kNeckAxisZ).normalized();
      const Vec3 p = axis + head::baseDistance(axis, out_dir, look) * out_dir;
      addAt(p, p.normalized(), uOf(i), tex((R - 1 + t) / R, kSkinPadV));
    }
  }
  addAt(Vec3(0.0, head::kNeckCut, head::kNeckAxisZ), Vec3(0, -1, 0), texU(0), tex(1, kSkinPadV));
  const int rings = R + kNeckRings;  // rows of the grid, the poles' included
  const auto bottom = static_cast<std::uint32_t>(out.skin.size() - 1);
  auto ring = [&](int j, int i) { return static_cast<std::uint32_t>(1 + (j - 1) * C + ((i % C) + C) % C); };
  // The lips' parting: the mouth row's vertices between the corners get a copy for the lower lip.
  std::map<std::uint32_t, std::uint32_t> lower;
  out.lower_lip = out.skin.size();
  for (int i = 0; i < C; ++i) {
    const Vec3& p = base[ring(jm, i)];
    if (p.z() > 0 && std::abs(p.x()) < head::kMouthHalf) {
      // The corners (the first column outside on each side) stay shared.
      lower[ring(jm, i)] = static_cast<std::uint32_t>(out.skin.size());
      out.skin.push_back(out.skin[ring(jm, i)]);
      out.bone.push_back(out.bone[ring(jm, i)]);
      out.uv.push_back(out.uv[ring(jm, i)]);
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
  for (int j = 1; j + 1 < rings; ++j)
    for (int i = 0; i < C; ++i) {
      std::uint32_t a = ring(j, i), b = ring(j, i + 1), c = ring(j + 1, i), d = ring(j + 1, i + 1);
      if (j == jm) a = low(a), b = low(b);  // the band below the parting takes the lower lip
      // Diagonals in a checkerboard, so the mesh (and every spring) is symmetric about the
      // midline (its mirror turns each diagonal into the other, as the next column's is) with no
      // line along which the diagonals meet. (Mirrored about the midline, the diagonals met there
      // in a chevron whose spine folded when the lips and the chin were drawn together: a seam of
      // light and shade down the chin in speech, viewers saw.)
      if ((i + j) % 2 == 0) {
        tri(a, d, b);
        tri(a, c, d);
      } else {
        tri(a, c, b);
        tri(b, c, d);
      }
    }
  for (int i = 0; i < C; ++i) tri(bottom, ring(rings - 1, i + 1), ring(rings - 1, i));
  // Colours (drawn as the skin's texture; these stand for it in a plain draw) and the jaw's share
  // of each bone point.
  const std::size_t n = out.skin.size();
  out.color.resize(n);
  out.gloss.resize(n);
  out.jaw.resize(n);
  // The neck's cut end (its last ring and the cap) goes on into the body: held.
  out.held.assign(n, 0);
  for (std::size_t k = static_cast<std::size_t>(ring(rings - 1, 0)); k <= bottom; ++k) out.held[k] = 1;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& p = base[k];
    const Vec3 d = p.normalized();
    const double X = p.x(), Y = p.y();
    out.color[k] = head::skinColor(p, d, ym, look);
    out.gloss[k] = head::skinGloss(p, d, ym);
    // The jaw (the mandible): everything below the parting at the front, fading into the cheeks
    // over 12 mm below the parting's level and toward the jaw's angles at the sides; under the
    // chin, from the mandible's lower border across the floor of the mouth to none where the
    // throat begins (an ellipse in plan through the chin and the jaw's angles), so the bone under
    // the floor of the mouth bends with the jaw over the whole span and the throat stays.
    // Beside the mouth the fade widens, from 12 mm at the lips to 40 mm over the cheeks (starting
    // 15 mm above the parting's level there): an opening jaw stretches the whole cheek, not a band
    // a node or two high that folds into a hard crease from the mouth's corner to the ear.
    const bool lower_lip = k >= bottom + 1;
    const double beside = smoothstep(head::kMouthHalf - 0.004, head::kMouthHalf + 0.025, std::abs(X));
    double w = smoothstep(ym + 0.015 * beside, ym - 0.012 - 0.013 * beside, Y);
    // The parting's own row (by index): its upper lip stays with the skull, its lower copy goes
    // with the jaw.
    const bool parting = lower_lip || (k >= ring(jm, 0) && k < ring(jm, 0) + static_cast<std::size_t>(C));
    // (Toward the corners the lower lip goes less far, half as far as the middle at the corner
    // itself: with all of it going with the jaw, an open mouth's sides stood as upright walls 4 to
    // 7 mm tall from the corner to the next column, a hexagon, where a mouth's opening tapers to
    // its corners, held by the modiolus.)
    if (parting && std::abs(X) < head::kMouthHalf && p.z() > 0)
      w = lower_lip ? 0.5 + 0.5 * smoothstep(head::kMouthHalf + 0.002, head::kMouthHalf - 0.013, std::abs(X)) : 0.0;
    // The corners of the mouth (where the parting ends) go half as far as the lower lip: the
    // stretch of an opening mouth is shared by the triangles above and below them. (Only near
    // the corner: a parting row that goes further than the rows below it folds into a crease.)
    else if (parting && p.z() > 0) w += (0.5 - w) * (1 - smoothstep(head::kMouthHalf, head::kMouthHalf + 0.01, std::abs(X)));
    w *= smoothstep(-0.05, 0.35, d.z());
    const double plan = std::hypot(X / 0.055, (p.z() + 0.01) / 0.095);  // 1 on the mandible's border
    w *= std::max(smoothstep(-0.125, -0.1, Y), smoothstep(0.45, 0.95, plan) * (1 - smoothstep(-0.12, -0.135, Y)));
    out.jaw[k] = w;
  }
  // Eyes: in the sockets (head::eyeCentre).
  out.eye_radius = head::kEyeRadius * s;
  for (int e = 0; e < 2; ++e) out.eye[static_cast<std::size_t>(e)] = s * head::eyeCentre(e, look);
  out.columns = C;
  out.rays = R;
  out.rows = rings;
  out.parting_row = jm;
  out.polar = std::move(polar);
  out.lower_copy.resize(n);
  for (std::size_t k = 0; k < n; ++k) out.lower_copy[k] = low(static_cast<std::uint32_t>(k));
  out.mouth = out.skin[ring(jm, C / 2)];  // the midline: column C/2 faces +z
  out.mouth_width = 2 * head::kMouthHalf * s;
  out.jaw_hinge = s * Vec3(0, -0.02, -0.015);
  // The ears in the skin's colour below the sideburn, in front of the ear (at the ear's own root the
  // sideburn's hair covers the skin, and its brown made the ears leather).
  const Vec3 cheek = Vec3(0.6, -0.35, 0.2).normalized();
  {
    // (And the skin's tint where each ear is, which differs from side to side as the skin's does:
    // the skin beside an ear's root is tinted.)
    auto ears = std::make_shared<TriMesh>(*makeEars(s, head::skinColor(head::baseRadius(cheek, look) * cheek, cheek, ym, look)));
    for (std::size_t v = 0; v < ears->vertexCount(); ++v) {
      const Vec3 tint = head::skinTint(Vec3(ears->positions[3 * v], ears->positions[3 * v + 1], ears->positions[3 * v + 2]) / s);
      for (int k = 0; k < 3; ++k) ears->colors[3 * v + static_cast<std::size_t>(k)] *= static_cast<float>(tint[k]);
    }
    out.ears = std::move(ears);
  }
  out.bust = makeBust(s, look);
  // The teeth behind the lips' parting: the upper 8.5 mm behind, their edges 4.5 mm below it (as
  // lips part, a few mm of the upper incisors show: with their edges 1.5 mm below it, the upper
  // lip rising as the jaw opened hid them), the lower 2.5 mm further back with their edges 0.8 mm below it
  // (the upper incisors stand ahead of and over them: overjet and overbite).
  for (int row = 0; row < 2; ++row)
    out.teeth[static_cast<std::size_t>(row)] = makeTeeth(s, out.mouth.z() - (row == 0 ? 0.0085 : 0.011) * s,
                                                         out.mouth.y() + (row == 0 ? -0.0045 : -0.0008) * s, row == 0);
  out.hair = makeHair(out);
  return out;
}

namespace {

// A texture over reel's head's uv, kSkinTexels a side: `texel(p, d, rgb)` writes the pixel of the
// skin's base point p in direction d (an empty image for a user's mesh).
template <class F>
std::shared_ptr<const Image> paintSkin(const FaceSurface& s, F&& texel) {
  const int size = kSkinTexels;
  auto img = std::make_shared<Image>(size, size);
  if (!s.generated || s.theta.size() < 2 || s.phi.size() < 3) return img;
  const int C = static_cast<int>(s.phi.size()) - 1, R = static_cast<int>(s.theta.size()) - 1;
  // The levelled polar angle and the base radius on a coarse grid over (u, v), interpolated
  // between (both are smooth).
  constexpr int kCoarse = 96;
  std::vector<double> radius(static_cast<std::size_t>((kCoarse + 1) * (kCoarse + 1))), polar(radius.size());
  auto azimuth = [&](double u) { return atIndex(s.phi, 0.5 * C + u * 0.5 * C); };
  for (int j = 0; j <= kCoarse; ++j)
    for (int i = 0; i <= kCoarse; ++i) {
      const std::size_t k = static_cast<std::size_t>(j * (kCoarse + 1) + i);
      const double ph = azimuth(static_cast<double>(i) / kCoarse);
      polar[k] = levelled(atIndex(s.theta, static_cast<double>(j) / kCoarse * R), ph, s.look);
      radius[k] = head::baseRadius(direction(polar[k], ph), s.look);
    }
  // Each texel on its own: the same bits at any number of threads.
  parallelFor(size, [&](std::ptrdiff_t row) {
    const int y = static_cast<int>(row);
    const double v = std::clamp(((y + 0.5) / size - kSkinPadV) / (1 - 2 * kSkinPadV), 0.0, 1.0);
    for (int x = 0; x < size; ++x) {
      const double t = ((x + 0.5) / size - kSkinPadU) / (1 - 2 * kSkinPadU);
      const double u = std::clamp(t < 0 ? -t : t > 1 ? 2 - t : t, 0.0, 1.0);  // mirrored past both ends
      const double fu = u * kCoarse, fv = v * kCoarse;
      const int i = std::min(static_cast<int>(fu), kCoarse - 1), j = std::min(static_cast<int>(fv), kCoarse - 1);
      const double a = fu - i, b = fv - j;
      auto lerp = [&](const std::vector<double>& g) {
        auto G = [&](int jj, int ii) { return g[static_cast<std::size_t>(jj * (kCoarse + 1) + ii)]; };
        return (1 - b) * ((1 - a) * G(j, i) + a * G(j, i + 1)) + b * ((1 - a) * G(j + 1, i) + a * G(j + 1, i + 1));
      };
      const double rb = lerp(radius);
      const Vec3 d = direction(lerp(polar), azimuth(u));
      texel(rb * d, d, img->pixel(x, y));
    }
  });
  return img;
}

}  // namespace

std::shared_ptr<const Image> skinTexture(const FaceSurface& s) {
  return paintSkin(s, [&](const Vec3& p, const Vec3& d, std::uint8_t* px) {
    const Vec3 c = head::skinColor(p, d, s.parting_y, s.look);
    for (int k = 0; k < 3; ++k) px[k] = linearToSrgb8(c[k]);
  });
}

std::shared_ptr<const Image> skinRelief(const FaceSurface& s) {
  return paintSkin(s, [&](const Vec3& p, const Vec3& d, std::uint8_t* px) {
    const auto h = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(head::skinRelief(p, d, s.parting_y, s.look), 0.0, 1.0)));
    px[0] = px[1] = px[2] = h;
  });
}

std::shared_ptr<const Image> skinWrinkles(const FaceSurface& s) {
  return paintSkin(s, [&](const Vec3& p, const Vec3&, std::uint8_t* px) {
    const auto h = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - std::clamp(head::wrinkleLines(p).most(), 0.0, 1.0))));
    px[0] = px[1] = px[2] = h;
  });
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
  std::vector<Vec3> normal = areaNormals(out.skin, out.tris);
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
    const double d = head::sq(p.x() - x) + head::sq(p.y() - y);
    if (d < bd - 1e-15) bd = d, best = k;
  }
  return best;
}

}  // namespace reel
