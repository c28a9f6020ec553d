// libFuzzer target: a golden-image test suite (`reel test SUITE.json`, docs/testing.md) through
// io::loadTestSuite: its keys, cases, sizes, frames and times, tolerances, names and the scenes
// it names (a small scene lies beside it; no other file may be read). A refusal is the expected
// answer.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_files.h"
#include "io/test_suite.h"

namespace {

const char* const kSuite = R"({
  "format": "reel-test/1",
  "size": "64x48",
  "samples": 2,
  "tolerance": {"threshold": 3, "max_fraction": 0.002, "max_mean": 1, "min_ssim": 0.98, "max_flip": 0.05},
  "goldens": "goldens",
  "cases": [
    {"name": "drop", "scene": "s.json", "frames": [0, 5, 10]},
    {"name": "late", "scene": "s.json", "times": [0.25, 0.5], "size": "32x32", "samples": 1, "seed": 7,
     "tolerance": {"threshold": 8}}
  ]
}
)";

const std::string& suitePath() {
  static const std::string path = [] {
    reel::fuzz::put("s.json", R"({"format": "reel/1", "duration": 1, "fps": 24,
      "objects": [{"type": "plane"}], "bodies": [{"type": "rope", "start": [0, 1, 0], "end": [1, 1, 0]}]})");
    return reel::fuzz::privateDir() + "/suite.json";
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (reel::fuzz::seedDir()) {
    // The input is the suite's text: the kind byte is not used here, the seed has none.
    reel::fuzz::writeBytes(std::string(reel::fuzz::seedDir()) + "/suite.json", kSuite, std::char_traits<char>::length(kSuite));
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  reel::fuzz::writeBytes(suitePath(), data, size);
  (void)reel::io::loadTestSuite(suitePath());
  return 0;
}
