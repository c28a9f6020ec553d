#include "io/video.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>

#include "core/hash.h"
#include "io/files.h"
#include "io/libav_util.h"

namespace reel::io {

namespace {

// 4x4 Bayer matrix, thresholds in (0, 1).
constexpr int kBayer[4][4] = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};

}  // namespace

bool isVideoPath(const std::string& path) {
  const std::string e = extensionOf(path);
  return e == ".mp4" || e == ".webm" || e == ".gif";
}

struct VideoWriter::Impl {
  std::string path, part;
  AVFormatContext* fmt = nullptr;
  AVCodecContext* enc = nullptr;
  AVStream* stream = nullptr;
  SwsContext* sws = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* pkt = nullptr;
  bool gif = false, header = false, done = false;
  int width = 0, height = 0;  // of the input images
  std::optional<ChunkTag> tag;  // a chunk's tag: its check is written when the file is finished
  Hasher frames;                // of the encoded frames, in order
  std::int64_t next_pts = 0;

  ~Impl() {
    if (fmt && !done) {
      if (fmt->pb) avio_closep(&fmt->pb);
      std::remove(part.c_str());
    }
    if (fmt) avformat_free_context(fmt);
    avcodec_free_context(&enc);
    sws_freeContext(sws);
    av_frame_free(&frame);
    av_packet_free(&pkt);
  }

  Status fail(const std::string& what, int e) {
    return Error(ErrorKind::Output, path + ": " + what + (e < 0 ? ": " + averr(e) : ""));
  }

  Status drain() {
    for (;;) {
      int r = avcodec_receive_packet(enc, pkt);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return {};
      if (r < 0) return fail("encoding failed", r);
      av_packet_rescale_ts(pkt, enc->time_base, stream->time_base);
      pkt->stream_index = stream->index;
      hashFrame(frames, pkt, enc->codec_id == AV_CODEC_ID_H264, /*annex_b=*/true);
      r = av_interleaved_write_frame(fmt, pkt);
      if (r < 0) return fail("write failed (disk full?)", r);
    }
  }
};

VideoWriter::VideoWriter() : impl_(std::make_unique<Impl>()) {}
VideoWriter::~VideoWriter() = default;

Status VideoWriter::open(const std::string& path, int width, int height, int fps, int crf, const ChunkTag* tag) {
  Impl& v = *impl_;
  v.path = writeThrough(path);
  v.part = v.path + ".part";
  v.width = width;
  v.height = height;
  const std::string ext = extensionOf(path);
  const char* muxer = ext == ".mp4" ? "mp4" : ext == ".webm" ? "webm" : ext == ".gif" ? "gif" : nullptr;
  if (!muxer) return Error(ErrorKind::BadInput, path + ": unsupported video type (mp4, webm, gif)");
  v.gif = ext == ".gif";
  if (Status st = checkOutputTarget(path); !st) return st;
  silenceLibav();
  int r = avformat_alloc_output_context2(&v.fmt, nullptr, muxer, v.part.c_str());
  if (r < 0 || !v.fmt) return v.fail("cannot set up the " + std::string(muxer) + " muxer", r);
  const AVCodec* codec = ext == ".mp4"  ? avcodec_find_encoder_by_name("libx264")
                         : ext == ".webm" ? avcodec_find_encoder_by_name("libvpx-vp9")
                                          : avcodec_find_encoder(AV_CODEC_ID_GIF);
  if (!codec) return Error(ErrorKind::Internal, path + ": this FFmpeg has no encoder for " + ext);
  v.enc = avcodec_alloc_context3(codec);
  v.stream = avformat_new_stream(v.fmt, nullptr);
  v.frame = av_frame_alloc();
  v.pkt = av_packet_alloc();
  if (!v.enc || !v.stream || !v.frame || !v.pkt) return Error(ErrorKind::Internal, "out of memory for FFmpeg");
  // yuv420p halves the chroma resolution: even sizes only, so odd ones are padded.
  v.enc->width = v.gif ? width : (width + 1) & ~1;
  v.enc->height = v.gif ? height : (height + 1) & ~1;
  v.enc->pix_fmt = v.gif ? AV_PIX_FMT_PAL8 : AV_PIX_FMT_YUV420P;
  v.enc->time_base = AVRational{1, fps};
  v.enc->framerate = AVRational{fps, 1};
  v.enc->gop_size = 2 * fps;
  // A chunk of a film (a tag naming part of it) is made to be joined: without B-frames, its
  // decoding order is its display order, so chunks follow one another whatever their length
  // (B-frames delay the decoding timestamps by an amount that depends on the chunk).
  if (tag && (tag->first > 0 || tag->last < tag->total - 1)) v.enc->max_b_frames = 0;
  if (!v.gif) {
    // sRGB pixels through the BT.709 matrix into limited-range YUV, tagged as such throughout
    // (matrix, primaries: sRGB's are BT.709's; transfer: sRGB), so players invert what was done.
    v.enc->colorspace = AVCOL_SPC_BT709;
    v.enc->color_primaries = AVCOL_PRI_BT709;
    v.enc->color_trc = AVCOL_TRC_IEC61966_2_1;
    v.enc->color_range = AVCOL_RANGE_MPEG;
  }
  if (v.fmt->oformat->flags & AVFMT_GLOBALHEADER) v.enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  AVDictionary* opts = nullptr;
  if (ext == ".mp4") {
    av_dict_set(&opts, "crf", std::to_string(crf).c_str(), 0);
    av_dict_set(&opts, "preset", "fast", 0);
    v.enc->color_range = AVCOL_RANGE_MPEG;
  } else if (ext == ".webm") {
    av_dict_set(&opts, "crf", std::to_string(crf + 12).c_str(), 0);
    av_dict_set(&opts, "b", "0", 0);
    av_dict_set(&opts, "deadline", "realtime", 0);
    av_dict_set(&opts, "cpu-used", "8", 0);
    av_dict_set(&opts, "row-mt", "1", 0);
  }
  v.enc->thread_count = 2;
  r = avcodec_open2(v.enc, codec, &opts);
  av_dict_free(&opts);
  if (r < 0) return v.fail("cannot open the encoder", r);
  r = avcodec_parameters_from_context(v.stream->codecpar, v.enc);
  if (r < 0) return v.fail("codec parameters", r);
  v.stream->time_base = v.enc->time_base;
  v.stream->avg_frame_rate = v.enc->framerate;
  if (Status st = createParentFolders(path); !st) return st;
  r = avio_open(&v.fmt->pb, v.part.c_str(), AVIO_FLAG_WRITE);
  if (r < 0) return v.fail("cannot write " + v.part, r);
  if (tag && !v.gif) {
    v.tag = *tag;
    v.tag->check.clear();
    av_dict_set(&v.fmt->metadata, "comment", v.tag->comment().c_str(), 0);
  }
  AVDictionary* mux = nullptr;
  if (ext == ".mp4") av_dict_set(&mux, "movflags", "+faststart", 0);
  r = avformat_write_header(v.fmt, &mux);
  av_dict_free(&mux);
  if (r < 0) return v.fail("cannot write the header", r);
  v.header = true;
  v.frame->format = v.enc->pix_fmt;
  v.frame->width = v.enc->width;
  v.frame->height = v.enc->height;
  r = av_frame_get_buffer(v.frame, 0);
  if (r < 0) return v.fail("frame buffer", r);
  if (!v.gif) {
    v.sws = sws_getContext(v.enc->width, v.enc->height, AV_PIX_FMT_RGB24, v.enc->width, v.enc->height,
                           AV_PIX_FMT_YUV420P, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr, nullptr);
    if (!v.sws) return Error(ErrorKind::Internal, "swscale cannot convert RGB to YUV 4:2:0");
    // Full-range RGB in, limited-range BT.709 YUV out (swscale's default matrix is BT.601's).
    const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(v.sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);
  }
  return {};
}

Status VideoWriter::write(const Image& img) {
  Impl& v = *impl_;
  if (img.width != v.width || img.height != v.height)
    return Error(ErrorKind::Internal, "video frame size changed");
  int r = av_frame_make_writable(v.frame);
  if (r < 0) return v.fail("frame buffer", r);
  const int W = v.enc->width, H = v.enc->height;
  if (v.gif) {
    // Fixed palette: 6 levels of red, 7 of green, 6 of blue; 4x4 ordered dithering.
    auto* pal = reinterpret_cast<std::uint32_t*>(v.frame->data[1]);
    for (int i = 0; i < 256; ++i) {
      const int rr = (i / 42) % 6, gg = (i / 6) % 7, bb = i % 6;
      pal[i] = i < 252 ? (0xFFu << 24) | (static_cast<std::uint32_t>(rr * 51) << 16) |
                             (static_cast<std::uint32_t>(gg * 255 / 6) << 8) | static_cast<std::uint32_t>(bb * 51)
                       : 0xFF000000u;
    }
    for (int y = 0; y < H; ++y) {
      std::uint8_t* dst = v.frame->data[0] + static_cast<std::ptrdiff_t>(y) * v.frame->linesize[0];
      for (int x = 0; x < W; ++x) {
        const std::uint8_t* p = img.pixel(x, y);
        const double t = (kBayer[y & 3][x & 3] + 0.5) / 16.0;
        auto q = [t](int c, int levels) { return std::min(levels - 1, static_cast<int>(c * (levels - 1) / 255.0 + t)); };
        dst[x] = static_cast<std::uint8_t>(q(p[0], 6) * 42 + q(p[1], 7) * 6 + q(p[2], 6));
      }
    }
  } else {
    // Pad to the even size by repeating the last column and row, then RGB → YUV 4:2:0.
    std::vector<std::uint8_t> rgb;
    const std::uint8_t* src = img.rgb.data();
    int stride = img.width * 3;
    if (W != img.width || H != img.height) {
      rgb.resize(static_cast<std::size_t>(W) * H * 3);
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const std::uint8_t* p = img.pixel(std::min(x, img.width - 1), std::min(y, img.height - 1));
          std::copy(p, p + 3, &rgb[(static_cast<std::size_t>(y) * W + x) * 3]);
        }
      src = rgb.data();
      stride = W * 3;
    }
    const std::uint8_t* planes[1] = {src};
    const int strides[1] = {stride};
    sws_scale(v.sws, planes, strides, 0, H, v.frame->data, v.frame->linesize);
  }
  v.frame->pts = v.next_pts++;
  r = avcodec_send_frame(v.enc, v.frame);
  if (r < 0) return v.fail("encoding failed", r);
  return v.drain();
}

Status VideoWriter::finish() {
  Impl& v = *impl_;
  int r = avcodec_send_frame(v.enc, nullptr);
  if (r < 0) return v.fail("encoding failed", r);
  if (Status st = v.drain(); !st) return st;
  // The tag with its check over the frames, for the index the muxer writes last (MP4's moov).
  if (v.tag) {
    v.tag->check = v.tag->checkOf(v.frames.h);
    av_dict_set(&v.fmt->metadata, "comment", v.tag->comment().c_str(), 0);
  }
  r = av_write_trailer(v.fmt);
  if (r < 0) return v.fail("write failed (disk full?)", r);
  r = avio_closep(&v.fmt->pb);
  if (r < 0) return v.fail("write failed (disk full?)", r);
  if (std::rename(v.part.c_str(), v.path.c_str()) != 0) {
    std::remove(v.part.c_str());
    return Error(ErrorKind::Output, v.path + ": cannot rename from .part");
  }
  v.done = true;
  return {};
}

namespace {

// Opens, decodes every frame, and hands each to `sink` as RGB24.
template <class Sink>
Status decodeAll(const std::string& path, VideoInfo& info, Sink&& sink) {
  silenceLibav();
  AVFormatContext* fmt = nullptr;
  int r = openReelVideo(&fmt, path, true);
  if (r < 0) return Error(ErrorKind::BadInput, path + ": not a video file reel reads (" + kReelVideosGif + "): " + averr(r));
  struct Guard {
    AVFormatContext** f;
    AVCodecContext* c = nullptr;
    AVFrame* fr = nullptr;
    AVFrame* rgb = nullptr;
    AVPacket* p = nullptr;
    SwsContext* sws = nullptr;
    ~Guard() {
      avcodec_free_context(&c);
      av_frame_free(&fr);
      av_frame_free(&rgb);
      av_packet_free(&p);
      sws_freeContext(sws);
      avformat_close_input(f);
    }
  } g{&fmt};
  if ((r = avformat_find_stream_info(fmt, nullptr)) < 0) return Error(ErrorKind::BadInput, path + ": " + averr(r));
  const AVCodec* codec = nullptr;
  const int si = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
  if (si < 0 || !codec) return Error(ErrorKind::BadInput, path + ": no video stream");
  AVStream* st = fmt->streams[si];
  g.c = avcodec_alloc_context3(codec);
  avcodec_parameters_to_context(g.c, st->codecpar);
  if ((r = avcodec_open2(g.c, codec, nullptr)) < 0) return Error(ErrorKind::BadInput, path + ": " + averr(r));
  info.codec = codec->name;
  info.width = st->codecpar->width;
  info.height = st->codecpar->height;
  const char* pf = av_get_pix_fmt_name(static_cast<AVPixelFormat>(st->codecpar->format));
  info.pix_fmt = pf ? pf : "?";
  info.fps = st->avg_frame_rate.den ? av_q2d(st->avg_frame_rate) : av_q2d(st->r_frame_rate);
  const char* cs = av_color_space_name(st->codecpar->color_space);
  const char* cp = av_color_primaries_name(st->codecpar->color_primaries);
  info.color = std::string(cs ? cs : "?") + "/" + (cp ? cp : "?");
  info.duration = fmt->duration > 0 ? static_cast<double>(fmt->duration) / AV_TIME_BASE : 0.0;
  if (const AVDictionaryEntry* c = av_dict_get(fmt->metadata, "comment", nullptr, 0)) info.comment = c->value;
  g.fr = av_frame_alloc();
  g.p = av_packet_alloc();
  auto take = [&]() -> Status {
    for (;;) {
      int e = avcodec_receive_frame(g.c, g.fr);
      if (e == AVERROR(EAGAIN) || e == AVERROR_EOF) return {};
      if (e < 0) return Error(ErrorKind::BadInput, path + ": decoding failed: " + averr(e));
      ++info.frames;
      if (!g.sws) {
        g.sws = sws_getContext(g.fr->width, g.fr->height, static_cast<AVPixelFormat>(g.fr->format), g.fr->width,
                               g.fr->height, AV_PIX_FMT_RGB24, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT,
                               nullptr, nullptr, nullptr);
        // Back through the matrix the file says it was made with (BT.601's when it does not say).
        const int* m = sws_getCoefficients(g.fr->colorspace == AVCOL_SPC_BT709 ? SWS_CS_ITU709 : SWS_CS_ITU601);
        if (g.sws) sws_setColorspaceDetails(g.sws, m, g.fr->color_range == AVCOL_RANGE_JPEG, m, 1, 0, 1 << 16, 1 << 16);
      }
      Image img(g.fr->width, g.fr->height);
      std::uint8_t* dst[1] = {img.rgb.data()};
      const int ds[1] = {3 * img.width};
      sws_scale(g.sws, g.fr->data, g.fr->linesize, 0, g.fr->height, dst, ds);
      sink(std::move(img));
    }
  };
  while (av_read_frame(fmt, g.p) >= 0) {
    if (g.p->stream_index == si) avcodec_send_packet(g.c, g.p);
    av_packet_unref(g.p);
    if (Status s2 = take(); !s2) return s2;
  }
  avcodec_send_packet(g.c, nullptr);
  return take();
}

}  // namespace

Result<VideoInfo> probeVideo(const std::string& path) {
  VideoInfo info;
  if (Status st = decodeAll(path, info, [](Image&&) {}); !st) return st.error();
  return info;
}

Result<std::vector<Image>> decodeVideo(const std::string& path, int width, int height) {
  VideoInfo info;
  std::vector<Image> out;
  Status st = decodeAll(path, info, [&](Image&& img) {
    if (width > 0 && (img.width < width || img.height < height)) return;  // not ours to crop
    if (width > 0 && (img.width != width || img.height != height)) {
      Image c(width, height);
      for (int y = 0; y < height; ++y)
        std::copy(img.pixel(0, y), img.pixel(0, y) + 3 * width, c.pixel(0, y));
      img = std::move(c);
    }
    out.push_back(std::move(img));
  });
  if (!st) return st.error();
  return out;
}

std::vector<std::string> availableEncoders() {
  std::vector<std::string> out;
  if (avcodec_find_encoder_by_name("libx264")) out.push_back("mp4: libx264");
  if (avcodec_find_encoder_by_name("libvpx-vp9")) out.push_back("webm: libvpx-vp9");
  if (avcodec_find_encoder(AV_CODEC_ID_GIF)) out.push_back("gif: gif");
  return out;
}

}  // namespace reel::io
