// Image difference metrics (pbrt's imgtool diff): max and mean absolute error over all channels,
// PSNR, and the pixels whose largest channel difference passes a threshold.
#pragma once

#include "core/image.h"

namespace reel {

struct ImageDiff {
  int max_abs = 0;           // 0..255
  double mean_abs = 0.0;     // over all channels
  double psnr_db = 0.0;      // infinite for identical images
  long long over = 0;        // pixels with a channel difference > threshold
  double over_fraction = 0.0;
};

// a and b must have the same size. When diff is given it receives a picture of the difference:
// a dimmed grey copy of a with differing pixels in red, brighter for larger differences.
ImageDiff compareImages(const Image& a, const Image& b, int threshold, Image* diff = nullptr);

}  // namespace reel
