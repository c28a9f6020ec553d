// `reel simulate --stats`: per frame and body, the quantities bodies report (Body::statistics),
// as CSV: frame,time,body and one column per quantity (the union over the bodies, in order of
// first appearance at frame 0; a body without a quantity leaves its cell empty). Written
// atomically like the dump: the file appears complete or not at all.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/frame_view.h"
#include "io/files.h"

namespace reel::io {

class StatsWriter {
 public:
  Status open(const std::string& path);
  // One frame: each body's name with its quantities. The first call fixes the columns.
  Status write(int frame, double time, const std::vector<std::pair<std::string, std::vector<Statistic>>>& bodies);
  Status finish();

 private:
  AtomicFile file_;
  std::vector<std::string> columns_;
  bool started_ = false;
};

}  // namespace reel::io
