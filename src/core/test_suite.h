// A golden-image test suite (`reel test`, docs/testing.md): cases of scenes and frames, each
// frame rendered and compared with its golden image within a tolerance.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace reel {

// When a rendered frame matches its golden: every limit holds.
struct Tolerance {
  // The defaults pass a render on another machine with the same Mesa (bit-identical) and a change
  // of one level in one channel, and fail an object's colour changed by 0.1, a frame off by one and
  // a camera moved by 1 cm in every test scene (docs/testing.md, "What the defaults catch").
  int threshold = 2;            // a pixel differs when a channel differs by more than this (0..255)
  double max_mean = 1.0;        // largest mean absolute error over all channels (0..255)
  double max_fraction = 0.001;  // largest fraction of differing pixels
  double min_ssim = 0.99;       // smallest mean SSIM (core/image_metrics.h)
  double max_flip = 0.05;       // largest mean FLIP (core/image_metrics.h)
};

struct TestCase {
  std::string name;   // unique in the suite; names its golden files
  std::string scene;  // the scene file, relative to the working folder
  std::string where;  // the case's JSON path (/cases/3), for messages
  std::vector<int> frames;     // as listed, or
  std::vector<double> times;   // s, each the nearest frame
  int width = 0, height = 0;   // 0: the scene's
  int samples = 0;             // 0: the scene's
  std::optional<std::uint64_t> seed;
  Tolerance tolerance;
};

struct TestSuite {
  std::string file;     // the suite file
  std::string name;     // default: the file's stem
  std::string goldens;  // the golden images' folder, relative to the working folder
  std::vector<TestCase> cases;
};

// A golden's file name: the case's name and the frame, "<case>_f0010.png".
inline std::string goldenName(const std::string& test_case, int frame) {
  std::string k = std::to_string(frame);
  if (k.size() < 4) k.insert(0, 4 - k.size(), '0');
  return test_case + "_f" + k + ".png";
}

}  // namespace reel
