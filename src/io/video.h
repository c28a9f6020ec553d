// Video files encoded in-process with FFmpeg's libraries (no ffmpeg program):
//   .mp4  H.264 (libx264), yuv420p (BT.709 matrix, limited range, tagged so), CRF 18, +faststart
//   .webm VP9 (libvpx-vp9), yuv420p
//   .gif  8-bit palette (a fixed 6x7x6 colour cube with ordered dithering)
// Odd sizes are padded to even ones for the yuv420p codecs by repeating the last row/column.
// Written to NAME.part (its missing folders created first) and renamed when complete.
#pragma once

#include <memory>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace reel::io {

bool isVideoPath(const std::string& path);

// Which frames of a film a video file holds: `first`..`last` of `total`, of the scene named
// `scene`; `film` tells films apart (a hash of what makes the pictures: the scene file's bytes, the
// seed, the size and samples). reel writes it into every video's comment ("reel frames A-B of N,
// scene NAME, film ID"), so that `reel join` puts chunks in film order and sees a gap, an overlap,
// a chunk that stopped early or one of another film.
struct ChunkTag {
  int first = 0, last = -1, total = 0;
  std::string scene, film;
  // FNV-1a of the tag's other fields and of every encoded frame, written when the file is finished
  // ("" in a tag not yet finished, or from a reel before the check): `join` recomputes it from the
  // frames it copies, so a tag edited onto another chunk's frames is refused.
  std::string check;
  std::string comment() const;  // the fields, then ", check C" when there is one
  std::string checkOf(std::uint64_t frames_hash) const;
  static bool parse(const std::string& comment, ChunkTag& out);
};

class VideoWriter {
 public:
  VideoWriter();
  ~VideoWriter();  // an unfinished file is removed
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;
  // `tag`: which frames of which film the file holds, stored in its comment (see ChunkTag); a
  // chunk of a film (part of it) is encoded without B-frames, so that chunks join.
  Status open(const std::string& path, int width, int height, int fps, int crf = 18, const ChunkTag* tag = nullptr);
  Status write(const Image& frame);
  Status finish();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Joins MP4 or WebM files of one codec, size and encoder settings into `output` without decoding
// them: their packets are copied in the order given, each file's timestamps shifted to follow the
// previous file's end. Written to OUTPUT.part, renamed when complete. A file that is not a video,
// one whose codec, size, pixel format, frame rate or codec headers differ from the first's, or
// whose timestamps would go back in time, is refused (exit-2 kind), naming both and the
// difference. `tag`: the joined file's comment; `tags`: when given, each input's own tag: it must
// hold the number of frames its tag says, and its frames must match the tag's check.
Status joinVideos(const std::vector<std::string>& inputs, const std::string& output, const ChunkTag* tag = nullptr,
                  const std::vector<ChunkTag>& tags = {});
// The comment a video file carries ("" when none); an unreadable file is an exit-2 kind of error.
Result<std::string> videoComment(const std::string& path);

// What a video file holds, read back with libavformat/libavcodec (tests and tools).
struct VideoInfo {
  std::string codec;    // e.g. "h264", "vp9", "gif"
  std::string pix_fmt;  // e.g. "yuv420p"
  int width = 0, height = 0;
  double fps = 0.0;
  long long frames = 0;  // decoded frames
  double duration = 0;   // s, as the container states it
  std::string color;     // the matrix and primaries the file is tagged with, e.g. "bt709/bt709"
  std::string comment;
};
Result<VideoInfo> probeVideo(const std::string& path);
// Every frame decoded to RGB, cropped to width x height when given (undoing padding).
Result<std::vector<Image>> decodeVideo(const std::string& path, int width = 0, int height = 0);

// Encoders this build can use, by output type (for `reel info`).
std::vector<std::string> availableEncoders();

}  // namespace reel::io
