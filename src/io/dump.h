// The state dump (DESIGN 5): `reel-dump/1` JSON with every number written as the shortest text
// that reads back to the same double. Streamed frame by frame, written atomically.
#pragma once

#include <string>

#include "core/error.h"
#include "core/frame_view.h"
#include "io/files.h"

namespace reel::io {

class DumpWriter {
 public:
  Status open(const std::string& path, const std::string& scene, int fps, int substeps);
  Status write(const FrameView& frame);
  // Closes the JSON and renames the part file onto the final name.
  Status finish();

 private:
  AtomicFile file_;
  bool first_ = true;
  std::string buf_;
};

}  // namespace reel::io
