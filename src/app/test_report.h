// What `reel test` found, frame by frame, and the two ways it is written for people and for CI:
// a self-contained HTML report (expected, actual and difference of each failure, flicker and
// slider views, the metrics against their limits) and JUnit XML.
#pragma once

#include <string>
#include <vector>

#include "core/error.h"
#include "core/image_compare.h"
#include "core/test_suite.h"

namespace reel::app {

struct FrameOutcome {
  std::string test_case, scene, golden;  // golden: its file
  int frame = 0;
  double time = 0.0;  // s
  enum class Verdict { Pass, Fail, Missing, Error } verdict = Verdict::Pass;
  bool updated = false;  // --update wrote its golden
  ImageDiff diff;
  double ssim = 1.0, flip = 0.0, flip_max = 0.0;
  Tolerance tolerance;
  std::vector<std::string> broken;  // the limits not held, in words
  std::string message;              // why it is missing or failed to render
  double seconds = 0.0;             // the case's simulation and drawing, shared by its frames
  // The report's pictures, relative to its folder ("" when there is none).
  std::string expected, actual, difference, thumbnail;
  bool passed() const { return verdict == Verdict::Pass; }
};

// The metrics of an outcome against its limits, in one line ("mean 0.12 ≤ 1, …").
std::string metricsLine(const FrameOutcome& o);

// DIR/index.html: failures first, each with its three pictures, a flicker and a slider view and
// the metrics against the limits; passing frames folded away with thumbnails. No network, no
// external scripts; the pictures are files in DIR. `#selftest` in the page's address makes it
// check itself (every picture decodes, the slider moves) and say so in <body data-selftest>.
Status writeHtmlReport(const std::string& dir, const TestSuite& suite, const std::vector<FrameOutcome>& outcomes);

// JUnit XML: one testcase per case and frame, a failure element with the metrics.
Status writeJunit(const std::string& file, const TestSuite& suite, const std::vector<FrameOutcome>& outcomes, double seconds);

}  // namespace reel::app
