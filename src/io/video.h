// Video files encoded in-process with FFmpeg's libraries (no ffmpeg program):
//   .mp4  H.264 (libx264), yuv420p, CRF 18, +faststart
//   .webm VP9 (libvpx-vp9), yuv420p
//   .gif  8-bit palette (a fixed 6x7x6 colour cube with ordered dithering)
// Odd sizes are padded to even ones for the yuv420p codecs by repeating the last row/column.
// Written to NAME.part and renamed when complete.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace reel::io {

bool isVideoPath(const std::string& path);

class VideoWriter {
 public:
  VideoWriter();
  ~VideoWriter();  // an unfinished file is removed
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;
  Status open(const std::string& path, int width, int height, int fps, int crf = 18);
  Status write(const Image& frame);
  Status finish();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Encoders this build can use, by output type (for `reel info`).
std::vector<std::string> availableEncoders();

}  // namespace reel::io
