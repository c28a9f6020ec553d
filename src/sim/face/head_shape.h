// reel's procedural head, its anatomy (internal to the face kind): the head as a shape of
// horizontal sections whose half-width, front and back follow measured profiles, a neck joined to
// it, the features of the skull and of the soft tissue as displacements, and the skin's colours.
// Everything is at a height of 0.24 m (chin to crown) in the head's own frame (origin at its
// centre, +y up, +z out of the face, +x its left), in metres. Proportions are adult averages
// (Farkas 1994, "Anthropometry of the head and face"): the eyes at half the head's height, 62 mm
// apart; the nose's base a third of the way from the brows to the chin, the lips' parting a third
// of the way from the nose's base to the chin; mouth 50 mm wide, nose 35 mm.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/math.h"
#include "core/scene/face.h"
#include "core/types.h"

namespace reel::head {

inline constexpr double sq(double x) { return x * x; }

// The unit direction at polar angle th from the crown (+y) and azimuth ph from the front (+z).
inline Vec3 direction(double th, double ph) { return Vec3(std::sin(th) * std::sin(ph), std::cos(th), std::sin(th) * std::cos(ph)); }

// The value of `a` (sampled at integer indices) at fractional index f.
inline double atIndex(const std::vector<double>& a, double f) {
  const double c = std::clamp(f, 0.0, static_cast<double>(a.size() - 1));
  const auto i = std::min(static_cast<std::size_t>(c), a.size() - 2);
  return a[i] + (c - static_cast<double>(i)) * (a[i + 1] - a[i]);
}

// The distance from (x, y) to the segment a–b in the plane.
inline double segmentDistance(double x, double y, double ax, double ay, double bx, double by) {
  const double vx = bx - ax, vy = by - ay;
  const double t = std::clamp(((x - ax) * vx + (y - ay) * vy) / (vx * vx + vy * vy), 0.0, 1.0);
  return std::hypot(x - ax - t * vx, y - ay - t * vy);
}

// Landmarks at height 0.24 m.
inline constexpr double kEyeX = 0.031, kEyeY = 0.0, kEyeRadius = 0.013;
// The lids' shell about each eye (its radius over the eye's): the lids are drawn on it. Their
// almond's corners lie kEyeCorner to either side of the eye's middle on it (rad), at a mean
// elevation kEyeCorners, the outer kCanthalTilt higher than the inner (FaceBody::Eye).
inline constexpr double kLidShell = 1.07;
// How far round the lids' shell they reach to either side of the eye's middle (rad).
inline constexpr double kLidAzimuth = 80.0 * kPi / 180.0;
inline constexpr double kEyeCorner = 72.0 * kPi / 180.0, kEyeCorners = -4.0 * kPi / 180.0, kCanthalTilt = 8.0 * kPi / 180.0;
inline constexpr double kMouthY = -0.070, kMouthHalf = 0.025;
// The left nostril: its middle (x, y) and half-sizes across and up (the skin's dip and dark there).
inline constexpr double kNostril[4] = {0.0062, -0.0448, 0.0031, 0.0015};
// The nasolabial fold, from beside the nose's wing to beside the mouth's corner (the left side's,
// x > 0): its ends (x, y).
inline constexpr double kFoldTop[2] = {0.0195, -0.041}, kFoldEnd[2] = {0.031, -0.073};

// The neck: its axis (vertical, at this z) and where it is cut (inside the shoulders).
inline constexpr double kNeckAxisZ = -0.016, kNeckCut = -0.32;
inline constexpr double kCollarY = -0.142;  // the shoulders' collar: its rim's height
// The neck's half-width and half-depth (m): an elliptic cylinder about kNeckAxisZ, thicker with the build.
inline std::array<double, 2> neckRadii(const FaceLook& look) { return {0.046 + 0.008 * look.build, 0.047 + 0.006 * look.build}; }

// The head without its features, negative inside; where the ray from the centre along unit d
// leaves it, m; and where the ray from o (inside) along d does.
double baseShape(const Vec3& p, const FaceLook& look);
double baseRadius(const Vec3& d, const FaceLook& look);
double baseDistance(const Vec3& o, const Vec3& d, const FaceLook& look);
// The head's outward normal at a point of its base surface (the shape's gradient, unit).
Vec3 baseNormal(const Vec3& p, const FaceLook& look);
// The centre of eye e (0: left, +x; 1: right) in the socket: its front 6.5 mm behind where the
// face would be without the features.
Vec3 eyeCentre(int e, const FaceLook& look);

// The features as displacements along the ray at the base point p (direction d) with the lips'
// parting at height ym: the skull's (brow ridge, eye sockets, cheekbones, chin), which the skin
// over them takes too, and the soft tissue's (nose, lips, folds, cheeks, hair), the skin's alone.
struct Features {
  double bone = 0.0, soft = 0.0;
};
Features features(const Vec3& p, const Vec3& d, double ym, const FaceLook& look);
// The direction the features stand out along at a base point whose ray is d: the ray, but made
// level over the face from the eyes to the chin (a nose or lips pushed out along a ray that
// points down would sink, and the face's rows would not stay level). Not under the jaw or over
// the brow, where the surface turns down or up and level columns of tissue would lean over.
Vec3 featureDirection(const Vec3& d);
// The skin at base point p (ray d) with every feature, m at height 0.24 m.
inline Vec3 skinPoint(const Vec3& p, const Vec3& d, double ym, const FaceLook& look) {
  const Features f = features(p, d, ym, look);
  return p + (f.bone + f.soft) * featureDirection(d);
}

// The brows at (|x|, y) on the face's front (at 0.24 m): how densely their hairs grow there (0..1)
// and where along the brow that is (0 at its head by the nose, 1 at its tail).
struct Brow {
  double density = 0, along = 0;
};
Brow browAt(double ax, double y);
// Up to this far along the brow (`Brow::along`), its head, the hairs stand upright; past it they lie
// along the brow.
inline constexpr double kBrowHead = 0.25;

// The skin's albedo (linear rgb) at the base point p, direction d: skin with its redness, pores
// and mottling, the lips' vermilion, brows, hair, nostrils.
Vec3 skinColor(const Vec3& p, const Vec3& d, double ym, const FaceLook& look);

// The hair's own albedo at the base point p, direction d (whatever its cover there): the strands'
// colour (coloured as the skin under a thinning hairline, they read as pale stray hairs).
Vec3 hairColor(const Vec3& p, const Vec3& d, const FaceLook& look);

// The skin's sheen at the base point p (−1..1, the drawn skin's per-vertex gloss): the skin's own,
// more over the forehead, the nose and the chin (the oily T-zone) and on the moist lips, little on
// the brows, and −1 (dulled, its sheen in its own colour) on the hair.
double skinGloss(const Vec3& p, const Vec3& d, double ym);

// The skin's relief at the base point p, direction d (0..1, about 0.5 on bare skin; a bump map's
// height): a fine grain, pores, the lips' furrows, the brows' and the hair's strands.
double skinRelief(const Vec3& p, const Vec3& d, double ym, const FaceLook& look);

// Where the skin folds into lines when it is squeezed (0..1 at the rest point p): the forehead's
// horizontal furrows (the frontalis raising the brows), the two vertical lines between the brows
// (the corrugator), crow's feet fanning from each eye's outer corner (the orbicularis oculi, a
// smile's raised cheeks), the nasolabial fold, and the nose's wrinkles, slanting down its sides
// from its root (the levator labii's nose wrinkler, disgust's AU9). A wrinkle map (Oat 2007, "Animated wrinkle
// maps"): the drawn skin shows each as the muscle that makes it pulls, or where its area has
// shrunk.
struct Wrinkles {
  double forehead = 0, glabella = 0, crows = 0, fold = 0, nose = 0;
  double most() const { return std::max({forehead, glabella, crows, fold, nose}); }
};
Wrinkles wrinkleLines(const Vec3& p);
// The regions those lines lie in (0..1 at the rest point p, smooth over millimetres): how deep
// the wrinkle map may sink there as each region's muscle pulls.
Wrinkles wrinkleRegions(const Vec3& p);

// How much hair covers the point (0..1), with a soft edge `soft` m wide.
double hairCover(const Vec3& p, const Vec3& d, double soft);

}  // namespace reel::head
