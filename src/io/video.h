// Video files encoded in-process with FFmpeg's libraries (no ffmpeg program):
//   .mp4  H.264 (libx264), yuv420p, CRF 18, +faststart
//   .webm VP9 (libvpx-vp9), yuv420p
//   .gif  8-bit palette (a fixed 6x7x6 colour cube with ordered dithering)
// Odd sizes are padded to even ones for the yuv420p codecs by repeating the last row/column.
// Written to NAME.part (its missing folders created first) and renamed when complete.
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

// What a video file holds, read back with libavformat/libavcodec (tests and tools).
struct VideoInfo {
  std::string codec;    // e.g. "h264", "vp9", "gif"
  std::string pix_fmt;  // e.g. "yuv420p"
  int width = 0, height = 0;
  double fps = 0.0;
  long long frames = 0;  // decoded frames
};
Result<VideoInfo> probeVideo(const std::string& path);
// Every frame decoded to RGB, cropped to width x height when given (undoing padding).
Result<std::vector<Image>> decodeVideo(const std::string& path, int width = 0, int height = 0);

// Encoders this build can use, by output type (for `reel info`).
std::vector<std::string> availableEncoders();

}  // namespace reel::io
