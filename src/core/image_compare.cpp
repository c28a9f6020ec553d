#include "core/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/error.h"

namespace reel {

ImageDiff compareImages(const Image& a, const Image& b, int threshold, Image* diff) {
  REEL_CHECK(a.width == b.width && a.height == b.height, "images differ in size");
  ImageDiff d;
  double sum = 0.0, sq = 0.0;
  if (diff) *diff = Image(a.width, a.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::uint8_t* p = a.pixel(x, y);
      const std::uint8_t* q = b.pixel(x, y);
      int m = 0;
      for (int c = 0; c < 3; ++c) {
        const int e = std::abs(int(p[c]) - int(q[c]));
        m = std::max(m, e);
        sum += e;
        sq += double(e) * e;
      }
      d.max_abs = std::max(d.max_abs, m);
      if (m > threshold) ++d.over;
      if (diff) {
        std::uint8_t* o = diff->pixel(x, y);
        const auto grey = static_cast<std::uint8_t>((p[0] + p[1] + p[2]) / 12 + 32);
        if (m == 0) {
          o[0] = o[1] = o[2] = grey;
        } else {
          o[0] = static_cast<std::uint8_t>(std::min(255, 96 + 4 * m));
          o[1] = o[2] = 0;
        }
      }
    }
  const double n = 3.0 * a.width * a.height;
  d.mean_abs = n > 0 ? sum / n : 0.0;
  const double mse = n > 0 ? sq / n : 0.0;
  d.psnr_db = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  d.over_fraction = a.width * a.height > 0 ? double(d.over) / (double(a.width) * a.height) : 0.0;
  return d;
}

}  // namespace reel
