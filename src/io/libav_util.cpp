// libav helpers shared by the video writer and reader (video.cpp) and the join (video_join.cpp).
#include "io/libav_util.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/log.h>
}

#include <cctype>
#include <cstdarg>
#include <filesystem>
#include <mutex>

namespace reel::io {

namespace {
// libav's own log never reaches the user: its last error line is kept (per thread) and quoted in
// reel's message when it explains one ("partial file").
thread_local std::string g_libav_last;
void quietLog(void* avcl, int level, const char* fmt, va_list vl) {
  if (level > AV_LOG_ERROR) return;
  char line[512];
  int prefix = 1;
  av_log_format_line2(avcl, level, fmt, vl, line, sizeof line, &prefix);
  std::string m = line;
  while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
  // Without the "[h264 @ 0x...] " context.
  if (const std::size_t at = m.find("] "); !m.empty() && m[0] == '[' && at != std::string::npos) m = m.substr(at + 2);
  if (!m.empty()) g_libav_last = m;
}
}  // namespace

void silenceLibav() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_callback(quietLog); });
}

std::string averr(int e) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(e, buf, sizeof buf);
  return buf;
}

// The demuxers of MP4 (libav names the family mov,mp4,…), WebM (matroska,webm) and GIF; the
// decoders of the encoders video.cpp chooses (libx264 writes h264, libvpx-vp9 vp9, gif gif): a
// writer that gains a codec adds its decoder here.
int openReelVideo(AVFormatContext** fmt, const std::string& path, bool gif) {
  AVDictionary* opts = nullptr;
  av_dict_set(&opts, "format_whitelist", gif ? "mov,mp4,m4a,3gp,3g2,mj2,matroska,webm,gif" : "mov,mp4,m4a,3gp,3g2,mj2,matroska,webm", 0);
  av_dict_set(&opts, "codec_whitelist", gif ? "h264,vp9,libvpx-vp9,gif" : "h264,vp9,libvpx-vp9", 0);
  const int r = avformat_open_input(fmt, path.c_str(), nullptr, &opts);
  av_dict_free(&opts);
  return r;
}

std::string lastLibavError() { return g_libav_last; }
void clearLibavError() { g_libav_last.clear(); }

std::string extensionOf(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// An encoded frame into a chunk's check, by its NAL units' contents when it is H.264: the encoder
// writes them after start codes (Annex B) and MP4 stores them after their lengths, so only the
// units themselves are the same on both sides. Other codecs' frames are hashed as they are.
void hashFrame(Hasher& h, const AVPacket* p, bool h264, bool annex_b) {
  const std::uint8_t* d = p->data;
  const std::size_t n = static_cast<std::size_t>(p->size);
  auto unit = [&](std::size_t a, std::size_t b) {
    while (b > a && d[b - 1] == 0) --b;  // trailing zeros belong to no unit
    const std::uint64_t len = b - a;
    h.add(&len, sizeof len);
    h.add(d + a, b - a);
  };
  if (!h264) {
    h.add(d, n);
  } else if (annex_b) {
    std::size_t start = n;  // of the current unit
    for (std::size_t i = 0; i + 2 < n;) {
      if (d[i] == 0 && d[i + 1] == 0 && d[i + 2] == 1) {
        if (start < n) unit(start, i);
        i += 3;
        start = i;
      } else {
        ++i;
      }
    }
    if (start < n) unit(start, n);
  } else {
    for (std::size_t i = 0; i + 4 <= n;) {
      const std::size_t len = (std::size_t{d[i]} << 24) | (std::size_t{d[i + 1]} << 16) | (std::size_t{d[i + 2]} << 8) | d[i + 3];
      if (len > n - i - 4) break;
      unit(i + 4, i + 4 + len);
      i += 4 + len;
    }
  }
}

}  // namespace reel::io
