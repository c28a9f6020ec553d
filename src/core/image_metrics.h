// Perceptual image differences for golden-image tests (`reel test`, docs/testing.md): SSIM, which
// asks whether the structure of the picture is the same, and FLIP, which asks what a viewer
// flipping between the two pictures would notice. Both are deterministic (fixed order of sums).
#pragma once

#include <vector>

#include "core/image.h"

namespace reel {

// Mean structural similarity (Wang, Bovik, Sheikh & Simoncelli 2004, "Image quality assessment:
// from error visibility to structural similarity", IEEE TIP 13(4)) of the luma (Rec. 601) of two
// images of one size: 11×11 Gaussian windows, σ = 1.5 px, K1 = 0.01, K2 = 0.03, L = 255, over
// every window that lies inside the image (images smaller than a window: one window the size of
// the image). 1 for identical images, lower for less alike.
double ssim(const Image& a, const Image& b);

// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström & Fairchild 2020, "FLIP: A
// Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2)):
// per pixel a difference 0..1 of a test image against a reference as seen at `ppd` pixels per
// degree of visual angle (the paper's default, kFlipPpd: a 0.7 m wide 3840-pixel monitor seen from
// 0.7 m), colour and features (edges,
// points) both. `map`, when given, receives the per-pixel values (row-major from the top-left).
inline constexpr double kFlipPpd = 0.7 * (3840.0 / 0.7) * 3.14159265358979323846 / 180.0;  // ≈ 67.02
struct FlipResult {
  double mean = 0.0;  // the mean over the pixels: the pooled value to set a limit on
  double max = 0.0;
};
FlipResult flip(const Image& reference, const Image& test, double ppd = kFlipPpd, std::vector<float>* map = nullptr);

// A picture of a per-pixel difference 0..1 (a FLIP map): black through purple and orange to pale
// yellow, so the eye finds the worst places first. With `under` (of the same size), the picture is
// shown dimmed in grey where the images agree and the colours lie over it where they differ.
Image heatmap(const std::vector<float>& values, int width, int height, const Image* under = nullptr);

}  // namespace reel
