#include "sim/face/head_shape.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "core/math.h"
#include "sim/face/head_tone.h"

namespace reel::head {
namespace {


double gauss(double x, double y, double x0, double y0, double sx, double sy) {
  const double u = (x - x0) / sx, v = (y - y0) / sy;
  return std::exp(-0.5 * (u * u + v * v));
}

// A smooth curve through points (a, value), a increasing: monotone cubic Hermite interpolation
// (Fritsch & Carlson 1980), so it never overshoots between its points; held flat outside them.
class Curve {
 public:
  Curve(std::initializer_list<std::array<double, 2>> pts) : p_(pts), m_(p_.size(), 0.0) {
    const std::size_t n = p_.size();
    std::vector<double> d(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) d[i] = (p_[i + 1][1] - p_[i][1]) / (p_[i + 1][0] - p_[i][0]);
    m_[0] = d[0];
    m_[n - 1] = d[n - 2];
    for (std::size_t i = 1; i + 1 < n; ++i) m_[i] = d[i - 1] * d[i] <= 0 ? 0.0 : 0.5 * (d[i - 1] + d[i]);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      if (d[i] == 0) {
        m_[i] = m_[i + 1] = 0;
        continue;
      }
      const double a = m_[i] / d[i], b = m_[i + 1] / d[i], r = a * a + b * b;
      if (r > 9) m_[i] *= 3 / std::sqrt(r), m_[i + 1] *= 3 / std::sqrt(r);
    }
  }
  double operator()(double a) const {
    if (a <= p_.front()[0]) return p_.front()[1];
    if (a >= p_.back()[0]) return p_.back()[1];
    std::size_t i = 0;
    while (a > p_[i + 1][0]) ++i;
    const double h = p_[i + 1][0] - p_[i][0], t = (a - p_[i][0]) / h, t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * p_[i][1] + (t3 - 2 * t2 + t) * h * m_[i] + (-2 * t3 + 3 * t2) * p_[i + 1][1] +
           (t3 - t2) * h * m_[i + 1];
  }

 private:
  std::vector<std::array<double, 2>> p_;
  std::vector<double> m_;
};

// The sections' profiles against height y: half-width, the front's and the back's depth from the
// centre (the face's midline before its features). Below the chin they close; above y = 0.03 the
// crown is a dome.
const Curve kWidth{{-0.124, 0.0},  {-0.119, 0.0185}, {-0.112, 0.0325}, {-0.1, 0.048}, {-0.085, 0.0565},
                   {-0.07, 0.061},  {-0.05, 0.066},   {-0.02, 0.071}, {0.0, 0.0735}, {0.03, 0.075}};
const Curve kFront{{-0.124, 0.0},  {-0.119, 0.04},  {-0.114, 0.066}, {-0.108, 0.08}, {-0.1, 0.086},
                   {-0.088, 0.087}, {-0.07, 0.09},  {-0.046, 0.092}, {0.005, 0.092}, {0.018, 0.095},
                   {0.03, 0.095}};
const Curve kBack{{-0.124, 0.0},  {-0.118, 0.006}, {-0.105, 0.014}, {-0.09, 0.03}, {-0.07, 0.055},
                  {-0.05, 0.075}, {-0.03, 0.088},  {0.0, 0.098},    {0.03, 0.102}};
constexpr double kDomeFrom = 0.03, kDomeHeight = 0.083;
constexpr double kHeadBottom = -0.124;  // where the sections close

// The nose along the midline: how far it stands out (m) and its half-width (the Gaussian's σ)
// against height, from the root between the eyes to the tip and under it to the upper lip.
const Curve kNose{{-0.05, 0.0},     {-0.047, 0.002},  {-0.0445, 0.0095}, {-0.041, 0.0185}, {-0.037, 0.0215},
                  {-0.033, 0.021},  {-0.026, 0.0175}, {-0.01, 0.011},    {0.006, 0.0042},  {0.012, 0.0}};
const Curve kNoseWidth{{-0.05, 0.007}, {-0.038, 0.0076}, {-0.03, 0.0058}, {-0.01, 0.0034}, {0.014, 0.003}};

// The hairline's height against the angle around the vertical from the front (rad): a soft peak
// at the middle, receding at the temples, down to the sideburns just in front of the ears (whose
// fronts are 1.69 rad round), over the ears, to the nape.
const Curve kHairline{{0.0, 0.075},  {0.22, 0.0765}, {0.4, 0.079},  {0.55, 0.071},  {0.72, 0.057}, {0.9, 0.045},
                      {1.08, 0.037}, {1.22, 0.028}, {1.32, 0.012}, {1.4, -0.012}, {1.45, -0.02}, {1.6, -0.022},  {1.66, 0.01},
                      {1.72, 0.02},  {2.0, 0.02},   {2.12, -0.01},  {2.3, -0.045},  {2.75, -0.064}, {3.1416, -0.066}};

// How far past youth a look is: 0 at 20 years, 1 at 70, at most 1.4.
double agedness(const FaceLook& look) { return std::clamp((look.age - 20.0) / 50.0, 0.0, 1.4); }

// The hair's locks as they stand off the scalp (-0.5..0.5 in direction d): about 7 mm across and
// 3 cm long, combed down from the crown; mirrored about the midline, as the head is.
double hairLocks(const Vec3& d) {
  return valueNoise(Vec3(std::abs(std::atan2(d.x(), d.z())) * 14.0, std::acos(std::clamp(d.y(), -1.0, 1.0)) * 3.0, 11.5)) - 0.5;
}

// The hair's albedo at a strand's shade (0..1): dark brown, greying with age.
Vec3 hairTone(double strand, const FaceLook& look) {
  const Vec3 h = Vec3(0.05, 0.033, 0.022) * (0.6 + 0.8 * strand);
  return h + std::clamp(agedness(look) - 0.6, 0.0, 1.0) * (Vec3(0.35, 0.34, 0.33) * (0.7 + 0.5 * strand) - h);
}

// The lips' vermilion: its upper border (with Cupid's bow) and lower border at x, against the
// parting's height ym; the corners at |x| = 0.026, which the borders turn into over their last few
// millimetres (tapering from the middle, as powers 2.2 and 1.8, the lips read as a pointed leaf
// and the corners as spikes).
double vermilionTop(double x, double ym) {
  const double a = std::abs(x);
  return ym + 0.0078 + 0.0013 * std::exp(-0.5 * sq((a - 0.0052) / 0.0028)) - 0.0007 * std::exp(-0.5 * sq(a / 0.0018)) -
         0.0078 * std::pow(std::min(a / 0.026, 1.0), 3.5);
}
double vermilionBottom(double x, double ym) { return ym - 0.0095 + 0.0093 * std::pow(std::min(std::abs(x) / 0.026, 1.0), 3.0); }

// The middle of the nose's left wing (x, y) (its nostril: head_shape.h).
constexpr double kWing[2] = {0.013, -0.0412};

// How much of the alar crease runs at (u, v) from the wing's middle (u outward, v up): the
// alar-facial groove round its back and top, and over toward the tip as the shallower crease
// between the wing and the lobule, fading before the tip (a ring all round read as a disc stuck
// on the cheek).
double alarCrease(double u, double v) {
  const double a = std::atan2(v, u);
  return smoothstep(-1.4, -0.6, a) * (0.45 + 0.55 * smoothstep(2.5, 1.6, a)) * smoothstep(2.9, 2.5, a);
}


// The vermilion's cover at (x, y) (0..1, with a sharp border), on the face's front.
double vermilion(double x, double y, double ym) {
  return smoothstep(-0.0004, 0.0004, vermilionTop(x, ym) - y) * smoothstep(-0.0004, 0.0004, y - vermilionBottom(x, ym)) *
         smoothstep(0.0275, 0.0255, std::abs(x));
}

// Brows at (|x|, y) on the face's front: arched bands of hairs, thick inside, thinning to their
// tails; the hairs' density there (0..1).
double browHairs(double ax, double y) {
  const Brow b = browAt(ax, y);
  if (b.density <= 0) return 0.0;
  // Hairs: streaks along the brow (upward at its head, sideways along it).
  const double slant = b.along < kBrowHead ? 0.3 : 1.0;  // hairs upright at the brow's head, lying along it after
  const double hairs = valueNoise(Vec3((ax - slant * 0.6 * y) * 4000.0, (y + slant * 0.25 * ax) * 1200.0, 3.0));
  return b.density * std::clamp(0.62 + 0.45 * hairs, 0.0, 1.0);
}

// The hair over the skin at p, direction d: its cover (0..1; the edge a band about 7 mm wide where
// single strands thin out over the skin: a hard edge reads as a helmet) and the strand there (0..1,
// streaks running down from the crown).
struct HairAt {
  double cover = 0, strand = 0;
  double around = 0, down = 0;  // the direction's angle round the vertical from the front, and from the crown (rad)
};
HairAt hairAt(const Vec3& p, const Vec3& d) {
  const double cover = hairCover(p, d, 0.0045 + 0.002 * valueNoise(p * 1500.0));
  const double around = std::atan2(d.x(), d.z()), down = std::acos(std::clamp(d.y(), -1.0, 1.0));
  const double wisps = valueNoise(Vec3(around * 260.0, down * 30.0, 2.5));
  // The strand's shade: fine streaks over locks about 4 mm across and 3 cm long (streaks alone,
  // under a pixel at a portrait's distance, left the cap one smooth shell).
  const double locks = valueNoise(Vec3(around * 28.0, down * 3.5, 6.5));
  // (Dark partings between the locks standing off the scalp, in their grooves, where the scalp's
  // shadow shows: locks of one shade read as a painted shell.)
  const double parting = smoothstep(-0.2, -0.32, hairLocks(d));
  // (The cover's ramp steepened 1.3 times, its streaks across it: steepened twice, the hairline
  // read as a swim cap's edge.)
  return {std::clamp(0.5 + 1.3 * (cover - 0.5) + 1.1 * (wisps - 0.5) * (1.0 - std::abs(2.0 * cover - 1.0)), 0.0, 1.0),
          std::clamp(0.55 * valueNoise(Vec3(around * 160.0, down * 14.0, 0.5)) + 1.1 * (locks - 0.5) + 0.22 - 0.25 * parting, 0.0, 1.0), around,
          down};
}

// Pores (under a millimetre) and mottling (a few mm), value noise over the surface; none on the
// neck, whose few rows of the mesh would stretch them into streaks.
double poreAt(const Vec3& p) { return valueNoise(p * 2400.0 + Vec3(7.1, 3.3, 1.7)); }
double skinDetail(double y) { return smoothstep(-0.14, -0.115, y); }

}  // namespace

Brow browAt(double ax, double y) {
  const double t = (ax - 0.012) / 0.042;
  if (t <= -0.1 || t >= 1.1) return {0.0, t};
  // The brow's head rounded, its tail tapering to a point; its edges soft (the hairs thin out),
  // softer above than below. Cut square at both ends, they read as painted bands.
  const double tc = std::clamp(t, 0.0, 1.0);
  const double mid = 0.0195 + 0.0065 * t * (1.6 - t) - 0.0008 * tc * tc;
  const double half = 0.0041 * (1 - 0.8 * std::pow(tc, 1.6)) * std::sqrt(smoothstep(-0.1, 0.14, t));
  // (At 1.1 and 0.6 mm they read as painted decals: hairs thin out over 2 mm above, 1 below.)
  const double soft = y > mid ? 0.002 : 0.001;
  const double band = smoothstep(half + soft, half - 0.5 * soft, std::abs(y - mid)) * smoothstep(-0.1, 0.0, t) * smoothstep(1.08, 0.95, t) *
                      (0.8 + 0.2 * smoothstep(0.0, 0.2, t));
  return {band, t};
}

double baseShape(const Vec3& p, const FaceLook& look) {
  const double x = p.x(), y = p.y(), z = p.z();
  const double yc = std::min(y, kDomeFrom);
  // A heavier build and a man's jaw are wider below the cheekbones.
  const double jaw = 1.0 + (0.03 * (look.build - 0.5) + 0.03 * (look.sex - 0.5)) * smoothstep(-0.03, -0.08, y);
  const double a = std::max(kWidth(yc) * jaw, 1e-4);
  const double depth = std::max(z > 0 ? kFront(yc) : kBack(yc), 1e-4);
  const double dome = y > kDomeFrom ? std::sqrt(std::max(0.0, 1.0 - sq((y - kDomeFrom) / kDomeHeight))) : 1.0;
  // Sections: a superellipse, a little squarer at the front (a face is broad across the cheeks;
  // at n = 2.4 all down the face its front was a flat mask, the cheeks one plane with the jaw).
  const double n = z > 0 ? 2.1 + 0.35 * smoothstep(-0.07, -0.1, y) : 2.0;  // squarer at the jaw: a round one read as a narrow chin
  const double q = std::pow(std::pow(std::abs(x) / a, n) + std::pow(std::abs(z) / depth, n), 1.0 / n);
  // (Below its closing section the head is outside everywhere, its axis too, where the
  // superellipse of zero size would leave q = 0.)
  double head = std::max((q - dome) * 0.085, kHeadBottom - y);
  // The mandible's angle (gonion), flaring out over the neck below and in front of the ear, and
  // the hollow behind the jaw's ramus under the ear: without them the cheek ran down into the neck
  // as one plane, with no jaw.
  const double side = smoothstep(0.02, 0.045, std::abs(x));
  head -= side * (0.0045 + 0.002 * look.sex) * std::exp(-0.5 * (sq((y + 0.084) / 0.011) + sq((z + 0.004) / 0.013)));
  head += side * 0.003 * std::exp(-0.5 * (sq((y + 0.062) / 0.01) + sq((z + 0.032) / 0.008)));
  // The neck: an elliptic cylinder, thicker with the build, from under the skull to the shoulders.
  const auto [nx, nz] = neckRadii(look);
  const double cyl = (std::sqrt(sq(x / nx) + sq((z - kNeckAxisZ) / nz)) - 1.0) * 0.055;
  const double neck = std::max({cyl, y + 0.04, kNeckCut - y});
  // Smooth minimum: the union with a fillet where the jaw meets the neck.
  // (Tighter under the jaw, from its angles to the chin, than at the nape: with a 24 mm fillet all
  // round the jaw ran into the neck without an edge, and the head read as a mannequin's.)
  const double k = 0.024 - 0.014 * smoothstep(-0.045, 0.0, z);
  const double h = std::clamp(0.5 + 0.5 * (neck - head) / k, 0.0, 1.0);
  return neck * (1 - h) + head * h - k * h * (1 - h);
}

double baseDistance(const Vec3& o, const Vec3& d, const FaceLook& look) {
  double lo = 1e-3, hi = 0.6;
  for (int it = 0; it < 44; ++it) {
    const double mid = 0.5 * (lo + hi);
    (baseShape(o + mid * d, look) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double baseRadius(const Vec3& d, const FaceLook& look) { return baseDistance(Vec3::Zero(), d, look); }

Vec3 baseNormal(const Vec3& p, const FaceLook& look) {
  constexpr double e = 1e-4;  // m: central differences
  Vec3 g;
  for (int c = 0; c < 3; ++c) {
    Vec3 a = p, b = p;
    a[c] += e, b[c] -= e;
    g[c] = baseShape(a, look) - baseShape(b, look);
  }
  return g.normalized();
}

Vec3 eyeCentre(int e, const FaceLook& look) {
  // (Cached for the last look: features() asks for it at every point of the skin.)
  thread_local FaceLook last{-1.0, -1.0, -1.0};
  thread_local double front = 0.0;
  if (!(last == look)) {
    Vec3 d = Vec3(kEyeX, kEyeY, 0.09).normalized();
    for (int it = 0; it < 4; ++it) {
      const Vec3 p = baseRadius(d, look) * d;
      d = Vec3(kEyeX, kEyeY, p.z()).normalized();
    }
    front = baseRadius(d, look) * d.z();
    last = look;
  }
  // (At 2.5 mm behind, the lids stood out like caps, a shut eye as a dome; at 4, level with the brow.)
  return Vec3(e == 0 ? kEyeX : -kEyeX, kEyeY, front - 0.0065 - kEyeRadius);
}

double hairCover(const Vec3& p, const Vec3& d, double soft) {
  const double around = std::abs(std::atan2(d.x(), d.z()));
  // The hairline uneven, in tufts a centimetre or so across, mostly within 3 mm either way and at
  // most 4.5 (a smooth curve read as drawn with a compass, the hair as a helmet).
  const double tufts = 0.006 * (valueNoise(Vec3(around * 9.0, 1.5, 4.5)) - 0.5) + 0.003 * (valueNoise(Vec3(around * 23.0, 7.5, 2.5)) - 0.5);
  return smoothstep(-soft, soft, p.y() - kHairline(around) - tufts);
}

Features features(const Vec3& p, const Vec3& d, double ym, const FaceLook& look) {
  const double X = p.x(), Y = p.y();
  const double front = smoothstep(0.15, 0.6, d.z());
  const double male = std::clamp(look.sex, 0.0, 1.0), heavy = std::clamp(look.build, 0.0, 1.0);
  const double aged = agedness(look);
  Features f;
  for (double s : {-1.0, 1.0}) {
    f.bone += (0.0015 + 0.004 * male) * gauss(X, Y, s * 0.028, 0.02, 0.018, 0.006);  // brow ridge
    // The eye's socket, shallower toward the temple (the eye shows less from the side).
    const double outer = s * (X - s * kEyeX) > 0 ? 0.0095 : 0.011;
    f.bone -= 0.0105 * gauss(X, Y, s * kEyeX, kEyeY + 0.0005, outer, 0.0065);
    f.bone += 0.004 * gauss(X, Y, s * 0.05, -0.016, 0.014, 0.009);                     // cheekbone
    // The orbit's upper rim over the eye's middle and outer half, overhanging the lid's crease
    // (without it the eyes lay level with the forehead, "stuck on", with no fold over the lid).
    const double u = (X - s * kEyeX) / 0.016, arc = kEyeY + 0.0135 - 0.004 * u * u;
    f.bone += 0.0045 * smoothstep(-1.0, -0.35, s * u) * std::exp(-0.5 * sq(u / 0.9)) * std::exp(-0.5 * sq((Y - arc) / 0.0042));
    // The inner corner's recess (the medial canthus lies 7 to 8 mm behind the cornea, under the
    // nose's side): without it the skin stood as a wall in front of the lids' inner tips.
    f.bone -= 0.0065 * gauss(X, Y, s * (kEyeX - 0.0138), kEyeY - 0.001, 0.0027, 0.0052);
    // Either side of the bridge, between it and the inner corners, the skin falls away to the
    // orbits' inner walls (without it the bridge spread flat from eye to eye, viewers said).
    f.bone -= 0.0028 * gauss(X, Y, s * 0.0125, kEyeY - 0.001, 0.0045, 0.011);
    // The nose's wing (ala): a lobe beside the tip's base, ringed above and behind by the alar
    // groove where it meets the cheek (not below it, where it sits on the lip).
    const double wing = std::hypot((X - s * kWing[0]) / 0.0052, (Y - kWing[1]) / 0.0047);  // 1 at its rim
    // (Sloping gently out to the cheek: a lobe as steep outside as in reads as a ball stuck on,
    // its far side dark.)
    const double outside = s * (X - s * kWing[0]) > 0 ? 0.006 : 0.0058;
    f.soft += 0.0046 * std::exp(-0.5 * (sq((X - s * kWing[0]) / outside) + sq((Y - kWing[1]) / 0.0047)));
    f.soft -= 0.0019 * std::exp(-0.5 * sq((wing - 1.4) / 0.22)) * alarCrease(s * (X - s * kWing[0]), Y - kWing[1]);
    f.soft -= 0.0028 * gauss(X, Y, s * kNostril[0], kNostril[1], kNostril[2], kNostril[3]);  // nostril
    f.soft += 0.0013 * gauss(X, Y, s * 0.0045, -0.056, 0.0015, 0.0055);                // philtrum's ridge
    // The fold from the nose's wing to beside the mouth's corner (deeper with age), and the
    // cheek's fat beside it (fuller with the build).
    const double fold = segmentDistance(X, Y, s * kFoldTop[0], kFoldTop[1], s * kFoldEnd[0], kFoldEnd[1]);
    f.soft -= (0.0004 + 0.0012 * aged) * std::exp(-0.5 * sq(fold / 0.0022));
    f.soft += (0.001 + 0.0022 * heavy) * gauss(X, Y, s * 0.036, -0.046, 0.01, 0.011);
    f.soft -= 0.0009 * (1 - heavy) * gauss(X, Y, s * 0.052, -0.056, 0.014, 0.016);    // under the cheekbone
    f.soft += 0.001 * (0.4 + aged) * gauss(X, Y, s * kEyeX, -0.0135, 0.009, 0.0028);  // below the lower lid
  }
  // The glabella, over the nose's root: the profile dips from it into the nasion at the eyes'
  // level (a nose running straight up into the brow read as a statue's).
  f.bone += (0.0025 + 0.003 * male) * gauss(X, Y, 0, 0.022, 0.012, 0.007);
  // The nasion itself sunk between the glabella and the bridge (with the glabella alone the
  // profile still ran nearly straight from the forehead down the nose: a viewer's "plank").
  f.bone -= 0.0016 * gauss(X, Y, 0, 0.007, 0.01, 0.0045);
  f.bone += (0.0065 + 0.002 * male) * gauss(X, Y, 0, -0.103, 0.013, 0.0075);  // chin
  f.bone += 0.004 * gauss(X, Y, 0, ym, 0.028, 0.014);                        // the teeth's arch under the lips
  // Nose: the ridge from the root to the tip and under it, the tip's lobule.
  const double nose = 0.92 + 0.16 * male;
  // (Across it, flatter on top and steeper at the sides than a Gaussian, most so up the bridge:
  // a Gaussian's soft shoulders read as a wide, flat bridge; at an exponent of 3.2 up the bridge
  // its side turned from the key along a hard line from the brow to the wing, a nose of folded
  // card, two viewers said: 2.5.)
  const double sides = 2.0 + 0.4 * smoothstep(-0.034, -0.018, Y);
  // Up the bridge, 45% of its height as a base 2.2 times as wide, over which the sidewalls flatten
  // into the cheeks (with the ridge alone its sidewall turned from the key as one dark band from the
  // brow to the wing, "a cardboard fin").
  const double broad = 0.32 * smoothstep(-0.036, -0.026, Y);
  f.soft += nose * kNose(Y) * ((1 - broad) * std::exp(-0.5 * std::pow(std::abs(X) / kNoseWidth(Y), sides)) + broad * std::exp(-0.5 * sq(X / (1.9 * kNoseWidth(Y)))));
  // The tip's lobule: two domes either side of the midline (the lower lateral cartilages'
  // domes), which give a tip its highlight and its notch; one round ball read as a blob. Above
  // them the supratip break, where the ridge dips a little before the lobule.
  for (double s : {-1.0, 1.0}) f.soft += 0.0026 * gauss(X, Y, s * 0.0036, -0.0366, 0.0037, 0.0038);
  f.soft -= 0.0008 * gauss(X, Y, 0.0, -0.029, 0.005, 0.0028);
  // Lips: the upper lip's skin slopes out from under the nose to the vermilion; the vermilion
  // of each lip rolls out (fuller for a woman), as full nearly to the corners as in the middle;
  // the parting and the fold under the lower lip.
  const double full = 1.08 - 0.16 * male;
  f.soft += 0.004 * smoothstep(-0.047, -0.06, Y) * smoothstep(ym - 0.002, ym + 0.003, Y) * std::exp(-0.5 * sq(X / 0.02));
  const double wu = std::pow(std::max(0.0, 1 - std::pow(std::abs(X) / 0.028, 3.5)), 0.7), wl = std::pow(std::max(0.0, 1 - std::pow(std::abs(X) / 0.026, 3.5)), 0.7);
  // Each lip's section leans: the upper lip stands out most near its border and slopes back down
  // to the parting, so it faces down and lies in its own shade; the lower lip stands out most
  // above its middle and curves long down to the fold under it, facing up into the light. (As
  // symmetric Gaussians, two even tubes, viewers said.) The upper lip's tubercle swells its
  // middle over the parting.
  auto lean = [](double y, double c, double below, double above) { return std::exp(-0.5 * sq((y - c) / (y < c ? below : above))); };
  f.soft += full * 0.0048 * wu * lean(Y, ym + 0.0058, 0.005, 0.0024);
  f.soft += full * 0.0013 * gauss(X, Y, 0.0, ym + 0.0018, 0.0045, 0.0017);
  f.soft += full * 0.0068 * wl * lean(Y, ym - 0.004, 0.006, 0.0032);
  // The corners tuck in, and the modiolus beside them bulges (lips that ran on full to blunt ends
  // read as a tube laid across the face).
  for (double s : {-1.0, 1.0}) {
    f.soft -= 0.0009 * gauss(X, Y, s * 0.0262, ym, 0.0022, 0.0022);
    f.soft += 0.0007 * gauss(X, Y, s * 0.0315, ym + 0.001, 0.0035, 0.005);
  }
  f.soft -= 0.0018 * gauss(X, Y, 0, ym, 0.026, 0.0013) * smoothstep(0.03, 0.022, std::abs(X));  // the parting, the mouth's width
  f.soft -= 0.0022 * gauss(X, Y, 0, ym - 0.0165, 0.015, 0.004);
  f.bone *= front;
  f.soft *= front;
  // The lids are skin lying on the eyeball: over the eye's opening and a band around it (up to
  // the upper lid's crease, down past the lower lid, round the corners), the skin sinks behind the
  // lids' shell, so the lids and the opening between them show out to the corners, 26.4 mm apart
  // (Farkas 1994: the palpebral fissure 28-30 mm). Over the flat socket alone, only the middle
  // 16 mm of the almond cleared the skin, and the eyes looked small. Where the eye can show (the
  // almond opened as wide as the lids go) it sinks to just behind the eyeball; elsewhere only to
  // just behind the shell: sunk to the eyeball all over the band, the skin left a pit past the
  // lids' inner ends that read as a bruise, and its ramp up out of the pit hid the lids' inner
  // tips, so the opening ended cut off square.
  {
    const Vec3 e = featureDirection(d);
    const double shell = kLidShell * kEyeRadius, eye = kEyeRadius / 0.012;
    for (int k = 0; k < 2; ++k) {
      const Vec3 c = eyeCentre(k, look);
      // The displacements along e that take the base point to just behind the lids' shell and to
      // just inside the eyeball, met from outside (a ray past the eyeball's edge that meets the
      // shell goes behind the shell alone: skipped, it left a wall at the eye's inner corner).
      const Vec3 m = p - c;
      const double under = shell - 0.0003, ball_in = kEyeRadius - 0.0004;  // the two spheres' radii
      const double along = m.dot(e), disc = along * along - m.squaredNorm() + sq(under);
      if (disc <= 0 || e.z() < 0.3) continue;
      const double behind = -along + std::sqrt(disc), ball = disc - sq(under) + sq(ball_in);
      const double inside = -along + std::sqrt(std::max(ball, 0.0));
      const Vec3 h = p + behind * e - c;
      // The almond as drawn at rest (FaceBody::Eye), on the lids' shell: its corners 13.2 mm to
      // either side, the outer 1 mm above the middle's line, the inner as far below; the band
      // above reaching the lid's crease (43° above the eye's centre: 10.5 mm above that line), the
      // one below about 4 mm past the margin, both narrowing to 2 mm round the corners (the sizes
      // of a 12 mm eye's, scaled to the eye), fading out from 76° round the shell to the lids' ends
      // at 80° (t as h's across the shell, h being just inside it).
      const double t = (k == 0 ? h.x() : -h.x()) / (shell * std::sin(kEyeCorner)), v = h.y();
      const double across = under / (shell * std::sin(kEyeCorner));
      const double fade = across * std::sin(kLidAzimuth - 4.0 * kPi / 180.0), end = across * std::sin(kLidAzimuth);
      if (std::abs(t) >= end) continue;
      const double tc = std::clamp(t, -1.0, 1.0);
      const double lobe = std::pow(std::cos(0.5 * kPi * tc), 0.65), mid = shell * std::sin(kEyeCorners + 0.5 * kCanthalTilt * tc);
      const double crease = shell * (std::sin(43.0 * kPi / 180.0) - std::sin(kEyeCorners));  // above the middle's line
      // (The crease's curve fuller than the margin's: following the margin's lobe, the band
      // ended just above the inner half's margin, and the skin over it hid the lid there as if hooded.)
      // (Toward the outer corner it hugs the margin closer, the crease's curve as full as the
      // margin's: as full as on the inner side, it bared a triangle of the lid's shell above the
      // outer corner that viewers saw as a pink notch, a seam through to the socket.)
      const double top = mid + eye * 0.002 + (crease - eye * 0.002) * std::pow(lobe, t > 0 ? 0.8 : 0.4);
      const double bottom = mid - eye * (0.002 + 0.0058 * lobe);
      // (Its lower edge over 4 mm: over 2.5 the skin rose as a wall that the fine mesh cut into steps.)
      const double w = smoothstep(top, top - 0.003, v) * smoothstep(bottom, bottom + 0.004, v) * smoothstep(end, fade, std::abs(t));
      // The widest the opening gets: the upper margin 46° up (raised, looking up), the lower 34°
      // down (looking down), with a millimetre to spare.
      const double up = mid + (shell * std::sin(46.0 * kPi / 180.0) - mid) * lobe, down = mid + (shell * std::sin(-34.0 * kPi / 180.0) - mid) * lobe;
      const double open = smoothstep(up + 0.001, up, v) * smoothstep(down - 0.001, down, v);
      const double most = behind + open * (inside - std::max(behind, inside));
      const double over = f.bone + f.soft - most;
      if (over > 0) f.bone -= over * w;
    }
  }
  // Hair stands off the scalp, thin at its edges and fuller behind them and over the top (short
  // hair, a millimetre or two at the hairline, rising over 3 cm behind it to 9.5 mm at the sides
  // and 17.5 mm over the top: at 4 mm all over it read as a painted helmet, at 9 over the crown as
  // a helmet still, and with the fullness from the height alone the forehead ran up to a bare
  // dome; 3.5 mm at the hairline stood as the helmet's rim).
  const double above = Y - kHairline(std::abs(std::atan2(d.x(), d.z())));
  // Over it, its locks (hairLocks) stand up to 1.2 mm proud of each other (a smooth shell, however
  // its colour was streaked, read as a helmet).
  f.soft += (0.0012 + smoothstep(-0.004, 0.016, above) * (0.0083 + 0.013 * smoothstep(0.02, 0.09, Y) + 0.0024 * hairLocks(d))) *
            hairCover(p, d, 0.012);
  return f;
}

Vec3 featureDirection(const Vec3& d) {
  const double front = smoothstep(0.15, 0.6, d.z()) * smoothstep(-0.8, -0.62, d.y()) * smoothstep(0.15, 0.0, d.y());
  if (front <= 0) return d;
  const Vec3 level = Vec3(d.x(), 0.0, d.z()).normalized();
  Vec3 out = (d + front * (level - d)).normalized();
  // Straight back over the eyes (the levelled ray leans out 20° there, and the skin along it
  // could not reach behind the eye's inner corner: a wall there cut the opening off square).
  for (double s : {-1.0, 1.0}) {
    const double from = std::acos(std::clamp(d.dot(Vec3(s * kEyeX, kEyeY, 0.085).normalized()), -1.0, 1.0));
    out += front * std::exp(-0.5 * sq(from / 0.16)) * (Vec3::UnitZ() - out);
  }
  return out.normalized();
}

double skinGloss(const Vec3& p, const Vec3& d, double ym) {
  const double X = p.x(), Y = p.y(), ax = std::abs(X);
  const double front = smoothstep(0.2, 0.5, d.z());
  const double tzone = std::max({gauss(X, Y, 0, 0.035, 0.03, 0.02), gauss(X, Y, 0, -0.03, 0.008, 0.02), gauss(X, Y, 0, -0.1, 0.012, 0.008)});
  const double lips = front * vermilion(X, Y, ym);
  const double brows = front * gauss(ax, Y, 0.034, 0.022, 0.02, 0.005);
  const double g = 0.15 + 0.15 * front * tzone + 0.15 * lips;
  // Hair dulled (−1): its sheen in its own colour, none white at grazing (a grey band round the
  // crown, lit from behind, read as a headband).
  const double hair = hairCover(p, d, 0.004);
  // The inner corners' pits, where the skin sinks behind the lids: dulled (their walls face across
  // the face, and at grazing on the far side of the nose their sheen flashed as a white streak
  // beside the eye).
  const double canthus = gauss(ax, Y, kEyeX - 0.0135, kEyeY - 0.002, 0.004, 0.004);
  // The nose's sides, where disgust's lines fold, less wet than its ridge: with the ridge's sheen
  // the lines' edges caught the rim at grazing as white stripes. And down to the wings: seen at
  // grazing on the far side of a turned head, their sheen under the rim light read as a white
  // patch on the nose (happiness and disgust in the docs' row).
  const double lower = smoothstep(0.003, 0.006, ax) * smoothstep(0.021, 0.016, ax) * smoothstep(-0.047, -0.041, Y) * smoothstep(-0.008, -0.015, Y);
  const double sides = std::max(wrinkleRegions(p).nose, front * lower);
  return std::clamp(g * (1.0 - hair) * (1.0 - 0.8 * brows) * (1.0 - canthus) * (1.0 - 0.8 * sides) - hair - 0.7 * canthus - 0.3 * sides, -1.0, 1.0);
}

Vec3 skinColor(const Vec3& p, const Vec3& d, double ym, const FaceLook& look) {
  const double X = p.x(), Y = p.y(), ax = std::abs(X);
  const bool front = d.z() > 0.2;
  const double male = std::clamp(look.sex, 0.0, 1.0);
  const double aged = agedness(look);
  Vec3 c(0.6, 0.34, 0.25);
  // Mottling and pores.
  const double mottle = valueNoise(p * 320.0);
  c *= 1.0 + skinDetail(Y) * (0.12 * (mottle - 0.5) - 0.04 * smoothstep(0.7, 0.9, poreAt(p)));
  // Blood under thin skin: cheeks, the nose's tip, the chin; shadow under the eyes.
  const double flush = 0.55 * gauss(ax, Y, 0.045, -0.028, 0.016, 0.013) + 0.45 * gauss(X, Y, 0, -0.036, 0.01, 0.008) +
                       0.2 * gauss(X, Y, 0, -0.1, 0.015, 0.01);
  // (Its patches, uneven from side to side: skinTint.)
  c = c + 0.45 * flush * (Vec3(0.6, 0.27, 0.24) - c);
  // The forehead a shade more yellow, the temples and the sides of the face a shade paler: the
  // face's colour zones (a face in one tone read as wax).
  c = c.cwiseProduct(Vec3::Ones() + 0.06 * smoothstep(0.02, 0.05, Y) * Vec3(0.3, 0.2, -0.6));
  c = c.cwiseProduct(Vec3::Ones() + 0.08 * smoothstep(0.03, 0.06, ax) * smoothstep(0.02, -0.02, Y) * smoothstep(-0.09, -0.06, Y) * Vec3(0.6, -0.3, -0.4));
  c = c.cwiseProduct(Vec3::Ones() - (0.1 + 0.08 * aged) * gauss(ax, Y, kEyeX, -0.0125, 0.012, 0.004) * Vec3(0.7, 1.0, 0.8));
  // And over the upper lid's fold, under the brow, where the skin is thin and darker (an orbit in
  // the face's tone read as flat, the eyes as glued onto it, a viewer said).
  c = c.cwiseProduct(Vec3::Ones() - 0.16 * gauss(ax, Y, kEyeX - 0.001, kEyeY + 0.0115, 0.014, 0.0045) * Vec3(0.75, 1.0, 0.9));
  // A man's shaved beard: a faint grey-blue over the chin, jaw and upper lip.
  if (male > 0.5) {
    const double beard = smoothstep(-0.048, -0.058, Y) * smoothstep(0.3, 0.6, d.z()) * (1 - 0.8 * smoothstep(-0.13, -0.15, Y));
    // As stubble: the cut hairs' dark dots, half a millimetre or so apart, over the grey (an even grey read as
    // a smudge of make-up).
    const double stubble = smoothstep(0.55, 0.8, valueNoise(p * 2500.0 + Vec3(2.9, 8.3, 4.1)));
    c = c + 0.35 * (male - 0.5) * beard * (Vec3(0.3, 0.27, 0.27) - c);
    c = c + 0.5 * (male - 0.5) * beard * stubble * (Vec3(0.06, 0.05, 0.045) - c);
  }
  if (front) {
    // The vermilion, with a sharp border.
    const double lips = vermilion(X, Y, ym);
    // (A muted rose, not a painted one: lips are skin with blood showing through; a shade deeper
    // than the cheek's flush, the upper lip darker than the lower, which faces the light: at
    // (0.46, 0.21, 0.18) and (0.42, 0.19, 0.17), then at (0.48, 0.19, 0.17) and (0.42, 0.16, 0.145), viewers
    // found them nearly skin-coloured and flat, and the upper lip long and bare.)
    const Vec3 lip = Y < ym ? Vec3(0.36, 0.1, 0.095) : Vec3(0.28, 0.075, 0.07);
    // Darker where the vermilion turns in to the parting and into the corners, where it lies in
    // the lips' own shade (in one colour to its border, a viewer saw lips pasted on).
    const double inward = std::exp(-0.5 * sq((Y - ym) / 0.0016)), corner = smoothstep(0.012, 0.026, ax);
    // And darkest along the line where they meet, as closed lips shade each other there: a line
    // continuous along the parting (without it the gap of lips not quite closed, a fraction of a
    // pixel, showed the mouth's dark inside as broken dark fragments).
    const double meet = std::exp(-0.5 * sq((Y - ym) / 0.0006));
    const double deep = (1.0 - 0.3 * inward - 0.3 * corner * (1.0 - 0.5 * inward)) * (1.0 - 0.4 * meet);
    c = c + lips * (0.9 - 0.1 * male) * (lip * (0.95 + 0.1 * mottle) * deep - c);
    // Just outside the border the white roll's skin is paler, a fine light line that draws the
    // lips' outline (without it the vermilion's edge was only a change of colour, and at a film's
    // distance the lips read as two even tubes with no border, viewers said).
    const double top = vermilionTop(X, ym), bottom = vermilionBottom(X, ym);
    const double pale = (smoothstep(top - 0.0002, top + 0.0003, Y) * std::exp(-0.5 * sq((Y - top - 0.0006) / 0.0005)) +
                         0.6 * smoothstep(bottom + 0.0002, bottom - 0.0003, Y) * std::exp(-0.5 * sq((Y - bottom + 0.0006) / 0.0005))) *
                        smoothstep(0.027, 0.021, ax);
    c = c + 0.22 * pale * (Vec3(0.72, 0.52, 0.42) - c);
    // Nostrils, under the nose.
    // (Edged and dark at their core, the openings under the nose's tip; with a soft edge and a
    // mid-brown core they read as one smudge, viewers said.)
    const double nostril = smoothstep(0.4, 0.8, gauss(ax, Y, kNostril[0], kNostril[1], kNostril[2], kNostril[3]));
    c = c + 0.95 * nostril * (Vec3(0.08, 0.033, 0.03) - c);
    // The alar groove's shade, and the wing a touch redder than the cheek.
    const double wing = std::hypot((ax - kWing[0]) / 0.0052, (Y - kWing[1]) / 0.0047);
    c = c.cwiseProduct(Vec3::Ones() - 0.12 * std::exp(-0.5 * sq((wing - 1.5) / 0.3)) * alarCrease(ax - kWing[0], Y - kWing[1]) * Vec3(0.8, 1.0, 1.0));
    c = c + 0.12 * std::exp(-0.5 * sq(wing)) * (Vec3(0.58, 0.3, 0.25) - c);
    // Brows.
    c = c + 0.95 * browHairs(ax, Y) * (Vec3(0.035, 0.024, 0.018) - c);
  }
  // Hair.
  const HairAt hair = hairAt(p, d);
  if (hair.cover > 0) c = c + hair.cover * (hairTone(hair.strand, look) - c);
  return c.cwiseMax(Vec3::Zero()).cwiseMin(Vec3::Ones());
}

Vec3 hairColor(const Vec3& p, const Vec3& d, const FaceLook& look) { return hairTone(hairAt(p, d).strand, look); }

// The skin's relief: what a bump map over the skin can show that the mesh, 1.4 mm at its finest,
// cannot (skin without it reads as plastic at close range). Skin's surface has a fine grain of
// furrows a fraction of a millimetre deep between plateaus, pores sunk into it, and on the lips
// vertical furrows across the vermilion and a ridge along its border (Igarashi et al. 2007, "The
// appearance of human skin: a survey", for the scales); brows and hair stand off it in strands.
double skinRelief(const Vec3& p, const Vec3& d, double ym, const FaceLook& look) {
  const double X = p.x(), Y = p.y(), ax = std::abs(X);
  const double aged = agedness(look);
  // The grain: two octaves of noise, about 1.2 mm and 0.5 mm; coarser and deeper with age.
  const double grain = 0.65 * valueNoise(p * (800.0 - 150.0 * aged) + Vec3(1.3, 5.1, 2.2)) + 0.35 * valueNoise(p * 2000.0 + Vec3(4.4, 0.7, 9.2));
  // Pores deepest over the nose and the cheeks beside it, where they are largest, shallow elsewhere
  // (pits 0.12 mm deep all over, a texel or two wide, read as stucco in a close-up, viewers said).
  const double porous = 0.07 + 0.07 * std::max(gauss(X, Y, 0, -0.03, 0.012, 0.014), gauss(ax, Y, 0.03, -0.03, 0.016, 0.012));
  double h = 0.5 + skinDetail(Y) * ((0.13 + 0.08 * aged) * (grain - 0.5) - porous * smoothstep(0.7, 0.9, poreAt(p)));
  if (d.z() > 0.2) {
    // The lips' furrows, about 1.1 mm apart, wavering, deepest at the vermilion's middle.
    const double lips = vermilion(X, Y, ym);
    if (lips > 0) {
      const double wave = 2 * kPi * (X + 0.0004 * std::sin(Y * 900.0)) / 0.0011 + 3.0 * valueNoise(Vec3(X * 600.0, Y * 150.0, 7.0));
      const double across = std::abs(Y - ym) / std::max(Y > ym ? vermilionTop(X, ym) - ym : ym - vermilionBottom(X, ym), 1e-4);
      // (Each furrow its own depth: all alike and 0.35 deep they read as corduroy.)
      const double depth = 0.08 + 0.22 * valueNoise(Vec3(X * 900.0, 5.0, Y > ym ? 1.0 : 9.0));
      h -= depth * lips * std::pow(0.5 + 0.5 * std::cos(wave), 3.0) * smoothstep(0.05, 0.3, across) * smoothstep(1.0, 0.7, across);
    }
    // The vermilion's border, the "white roll": a ridge about a millimetre wide where lip meets
    // skin (without it the vermilion's edge is only colour, and the lips read as pasted on).
    const double roll = std::exp(-0.5 * sq((Y - vermilionTop(X, ym)) / 0.0006)) + std::exp(-0.5 * sq((Y - vermilionBottom(X, ym)) / 0.0007));
    h += 0.3 * roll * smoothstep(0.0265, 0.022, ax);
    h += 0.3 * browHairs(ax, Y);
  }
  const HairAt hair = hairAt(p, d);
  if (hair.cover > 0) {
    const double fine = valueNoise(Vec3(hair.around * 700.0, hair.down * 25.0, 4.0));
    h += hair.cover * (0.25 + 0.35 * (hair.strand - 0.5) + 0.25 * (fine - 0.5));
  }
  return std::clamp(h, 0.0, 1.0);
}

}  // namespace reel::head
