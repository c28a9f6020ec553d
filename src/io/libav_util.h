// libav helpers shared inside io by the video writer and reader (video.cpp) and the join
// (video_join.cpp): libav's log kept off the terminal, its error codes in words, chunk checks.
#pragma once

#include <string>

#include "core/hash.h"

struct AVFormatContext;
struct AVPacket;

namespace reel::io {

// The lowercased extension of a path (".mp4").
std::string extensionOf(const std::string& path);
// libav's own log never reaches the user; its last error line (this thread's) is kept, to quote
// in reel's message when it explains one ("partial file").
void silenceLibav();
std::string lastLibavError();
void clearLibavError();
// A libav error code in words.
std::string averr(int e);
// Opens a video for reading (avformat_open_input) with only the demuxers and decoders of what
// reel writes (MP4 of H.264, WebM of VP9, and with `gif` GIF): libav's others never see a file a
// user hands reel (docs/fuzzing.md, fuzz_join's finding). Returns libav's code.
int openReelVideo(AVFormatContext** fmt, const std::string& path, bool gif);
inline constexpr const char* kReelVideos = "MP4 of H.264 or WebM of VP9";  // what join reads
inline constexpr const char* kReelVideosGif = "MP4 of H.264, WebM of VP9 or GIF";  // what info --video reads
// An encoded frame into a chunk's check (ChunkTag::check): H.264 by its NAL units' contents
// (`annex_b`: after start codes, as the encoder writes them; else after 4-byte lengths, as MP4
// stores them), other codecs' frames as they are.
void hashFrame(Hasher& h, const AVPacket* p, bool h264, bool annex_b);

}  // namespace reel::io
