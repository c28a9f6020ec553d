// Chunk tags and joining chunks of one film without re-encoding (io/video.h).
#include "io/video.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/hash.h"
#include "io/files.h"
#include "io/libav_util.h"

namespace reel::io {

std::string ChunkTag::comment() const {
  return "reel frames " + std::to_string(first) + "-" + std::to_string(last) + " of " + std::to_string(total) +
         ", scene " + scene + ", film " + film + (check.empty() ? "" : ", check " + check);
}

std::string ChunkTag::checkOf(std::uint64_t frames_hash) const {
  ChunkTag t = *this;
  t.check.clear();
  Hasher h;
  const std::string fields = t.comment();
  h.add(fields.data(), fields.size());
  h.add(&frames_hash, sizeof frames_hash);
  return h.hex();
}

bool ChunkTag::parse(const std::string& comment, ChunkTag& out) {
  int a = -1, b = -1, n = -1, used = 0;
  if (std::sscanf(comment.c_str(), "reel frames %d-%d of %d, scene %n", &a, &b, &n, &used) != 3 || used == 0 || a < 0 ||
      b < a || n <= b)
    return false;
  std::string rest = comment.substr(static_cast<std::size_t>(used));
  std::string check;
  if (const std::size_t c = rest.rfind(", check "); c != std::string::npos && rest.size() - c == 8 + 16) {
    check = rest.substr(c + 8);
    rest.resize(c);
  }
  const std::size_t at = rest.rfind(", film ");
  if (at == std::string::npos) return false;
  out = ChunkTag{a, b, n, rest.substr(0, at), rest.substr(at + 7), check};
  return true;
}

namespace {

// One input of a join: its demuxer and its video stream.
struct JoinInput {
  std::string path;
  AVFormatContext* fmt = nullptr;
  AVStream* st = nullptr;
  ~JoinInput() { avformat_close_input(&fmt); }
};

Status openJoinInput(const std::string& path, JoinInput& in) {
  in.path = path;
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(st)) return Error(ErrorKind::BadInput, path + ": no such file");
  if (!std::filesystem::is_regular_file(st))
    return Error(ErrorKind::BadInput, path + ": is " + kindInWords(st) + ", not a video file (join reads MP4 or WebM files)");
  silenceLibav();
  clearLibavError();
  int r = openReelVideo(&in.fmt, path, false);
  if (r < 0) return Error(ErrorKind::BadInput, path + ": not a video file reel joins (" + kReelVideos + "): " + averr(r));
  if ((r = avformat_find_stream_info(in.fmt, nullptr)) < 0) return Error(ErrorKind::BadInput, path + ": " + averr(r));
  const int si = av_find_best_stream(in.fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (si < 0 || in.fmt->nb_streams != 1) return Error(ErrorKind::BadInput, path + ": not a video file of one video stream");
  in.st = in.fmt->streams[si];
  // A file cut short (a copy that stopped, a full disk) has no readable picture format.
  if (in.st->codecpar->format < 0 || in.st->codecpar->width <= 0 || in.st->codecpar->height <= 0)
    return Error(ErrorKind::BadInput, path + ": a damaged or truncated video (" +
                                          (lastLibavError().empty() ? std::string("its pictures cannot be read") : "libav: " + lastLibavError()) +
                                          "); render it again");
  return {};
}

// How `b` differs from `a` in what a join needs the same ("" when it does not).
std::string joinMismatch(const JoinInput& a, const JoinInput& b) {
  const AVCodecParameters *p = a.st->codecpar, *q = b.st->codecpar;
  auto size = [](const AVCodecParameters* c) { return std::to_string(c->width) + "x" + std::to_string(c->height); };
  if (p->codec_id != q->codec_id)
    return std::string("codec ") + avcodec_get_name(q->codec_id) + ", unlike " + avcodec_get_name(p->codec_id);
  if (p->width != q->width || p->height != q->height) return "size " + size(q) + ", unlike " + size(p);
  if (p->format != q->format) return "another pixel format";
  if (av_cmp_q(a.st->avg_frame_rate, b.st->avg_frame_rate) != 0 || av_cmp_q(a.st->time_base, b.st->time_base) != 0)
    return "frame rate " + std::to_string(av_q2d(b.st->avg_frame_rate)) + ", unlike " + std::to_string(av_q2d(a.st->avg_frame_rate));
  if (p->extradata_size != q->extradata_size ||
      (p->extradata_size > 0 && std::memcmp(p->extradata, q->extradata, static_cast<std::size_t>(p->extradata_size)) != 0))
    return "other encoder settings (its codec headers differ)";
  return "";
}

}  // namespace

Result<std::string> videoComment(const std::string& path) {
  JoinInput in;
  if (Status st = openJoinInput(path, in); !st) return st.error();
  const AVDictionaryEntry* c = av_dict_get(in.fmt->metadata, "comment", nullptr, 0);
  return std::string(c ? c->value : "");
}

Status joinVideos(const std::vector<std::string>& inputs, const std::string& output, const ChunkTag* tag,
                  const std::vector<ChunkTag>& tags) {
  if (inputs.empty()) return Error(ErrorKind::BadInput, "join: no input videos");
  if (!isVideoPath(output) || extensionOf(output) == ".gif")
    return Error(ErrorKind::BadInput, output + ": join writes .mp4 or .webm (a GIF's frames are joined as PNG chunks)");
  // Every input checked against the first before anything is written, each open only while it is
  // read (a film of a thousand chunks stays within the open-file limit).
  JoinInput first;
  if (Status st = openJoinInput(inputs.front(), first); !st) return st;
  for (const std::string& p : inputs) {
    if (extensionOf(p) != extensionOf(output))
      return Error(ErrorKind::BadInput, p + ": a " + extensionOf(p) + " file cannot be joined into " + output +
                                            " without re-encoding (use " + extensionOf(p) + ")");
    JoinInput in;
    if (Status st = openJoinInput(p, in); !st) return st;
    const std::string why = joinMismatch(first, in);
    if (!why.empty())
      return Error(ErrorKind::BadInput, p + ": cannot join: " + why + " in " + inputs.front() +
                                            " (chunks must be rendered with the same scene, --size and --samples)");
  }
  if (Status st = checkOutputTarget(output); !st) return st;
  if (Status st = createParentFolders(output); !st) return st;
  // The output, written as OUTPUT.part; removed unless complete.
  struct Out {
    std::string part;
    AVFormatContext* fmt = nullptr;
    AVPacket* pkt = av_packet_alloc();
    bool done = false;
    ~Out() {
      if (fmt && fmt->pb) avio_closep(&fmt->pb);
      if (fmt && !done) std::remove(part.c_str());
      avformat_free_context(fmt);
      av_packet_free(&pkt);
    }
  } out;
  const std::string target = writeThrough(output);
  out.part = target + ".part";
  const std::string ext = extensionOf(output);
  auto fail = [&](const std::string& what, int e) { return Error(ErrorKind::Output, output + ": " + what + ": " + averr(e)); };
  int r = avformat_alloc_output_context2(&out.fmt, nullptr, ext == ".mp4" ? "mp4" : "webm", out.part.c_str());
  if (r < 0 || !out.fmt || !out.pkt) return fail("cannot set up the muxer", r);
  AVStream* os = avformat_new_stream(out.fmt, nullptr);
  if (!os || (r = avcodec_parameters_copy(os->codecpar, first.st->codecpar)) < 0) return fail("codec parameters", r);
  os->codecpar->codec_tag = 0;
  os->time_base = first.st->time_base;
  os->avg_frame_rate = first.st->avg_frame_rate;
  const AVRational tb = first.st->time_base;
  // One frame's duration in the inputs' time base, for a packet that does not say.
  const std::int64_t period =
      first.st->avg_frame_rate.num > 0 ? std::max<std::int64_t>(1, av_rescale_q(1, av_inv_q(first.st->avg_frame_rate), tb)) : 1;
  if (tag) av_dict_set(&out.fmt->metadata, "comment", tag->comment().c_str(), 0);
  if ((r = avio_open(&out.fmt->pb, out.part.c_str(), AVIO_FLAG_WRITE)) < 0) return fail("cannot write " + out.part, r);
  AVDictionary* mux = nullptr;
  if (ext == ".mp4") av_dict_set(&mux, "movflags", "+faststart", 0);
  r = avformat_write_header(out.fmt, &mux);
  av_dict_free(&mux);
  if (r < 0) return fail("cannot write the header", r);
  // Each input's timestamps shifted by the end of those before it (in the inputs' time base).
  std::int64_t offset = 0, last_dts = AV_NOPTS_VALUE;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    JoinInput in;
    if (Status st = openJoinInput(inputs[k], in); !st) return st;
    const std::int64_t start = in.st->start_time != AV_NOPTS_VALUE ? in.st->start_time : 0;
    std::int64_t end = offset;
    long long packets = 0;
    Hasher frames;  // of its encoded frames, as the writer hashed them
    while ((r = av_read_frame(in.fmt, out.pkt)) >= 0) {
      if (out.pkt->stream_index != in.st->index) {
        av_packet_unref(out.pkt);
        continue;
      }
      ++packets;
      hashFrame(frames, out.pkt, in.st->codecpar->codec_id == AV_CODEC_ID_H264, /*annex_b=*/false);
      if (out.pkt->pts != AV_NOPTS_VALUE) {
        out.pkt->pts += offset - start;
        end = std::max(end, out.pkt->pts + (out.pkt->duration > 0 ? out.pkt->duration : period));
      }
      if (out.pkt->dts != AV_NOPTS_VALUE) {
        out.pkt->dts += offset - start;
        if (last_dts != AV_NOPTS_VALUE && out.pkt->dts <= last_dts)
          return Error(ErrorKind::BadInput, inputs[k] + ": its frames would go back in time after " + inputs[k - (k > 0)] +
                                                "'s (another encoder delay: not a chunk of the same render)");
        last_dts = out.pkt->dts;
      }
      out.pkt->stream_index = 0;
      out.pkt->pos = -1;
      av_packet_rescale_ts(out.pkt, tb, os->time_base);
      if ((r = av_interleaved_write_frame(out.fmt, out.pkt)) < 0) return fail("write failed (disk full?)", r);
    }
    if (r != AVERROR_EOF) return Error(ErrorKind::BadInput, inputs[k] + ": read error: " + averr(r));
    if (k < tags.size()) {
      const long long said = static_cast<long long>(tags[k].last) - tags[k].first + 1;
      if (said != packets)
        return Error(ErrorKind::BadInput, inputs[k] + ": holds " + std::to_string(packets) + " frames where its tag says " +
                                              std::to_string(said) + " (a render that stopped early?)");
      if (!tags[k].check.empty() && tags[k].checkOf(frames.h) != tags[k].check)
        return Error(ErrorKind::BadInput, inputs[k] + ": its frames are not the ones its tag was written for (frames " +
                                              std::to_string(tags[k].first) + "-" + std::to_string(tags[k].last) +
                                              "): an edited tag, or another chunk's frames; render the chunk again");
    }
    offset = end;
  }
  if ((r = av_write_trailer(out.fmt)) < 0) return fail("write failed (disk full?)", r);
  if ((r = avio_closep(&out.fmt->pb)) < 0) return fail("write failed (disk full?)", r);
  if (std::rename(out.part.c_str(), target.c_str()) != 0) return Error(ErrorKind::Output, output + ": cannot rename from .part");
  out.done = true;
  return {};
}

}  // namespace reel::io
