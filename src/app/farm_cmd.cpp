// The farm's commands besides simulate and render (docs/farm.md): reel join, reel info --video,
// and render's --chunk I/K.
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/commands.h"
#include "io/video.h"

namespace reel::app {

Result<std::string> chunkFrames(const std::string& chunk, int frames) {
  int i = -1, k = -1, used = 0;
  char slash = 0;
  if (std::sscanf(chunk.c_str(), "%d%c%d%n", &i, &slash, &k, &used) != 3 || slash != '/' ||
      used != static_cast<int>(chunk.size()) || k < 1 || i < 0 || i >= k)
    return Error(ErrorKind::BadInput, "--chunk must be I/K with 0 <= I < K, got \"" + chunk + "\"");
  if (k > frames)
    return Error(ErrorKind::BadInput, "--chunk " + chunk + ": the film has only " + std::to_string(frames) +
                                          " frames, fewer than " + std::to_string(k) + " chunks");
  // Chunk i holds frames [i N / K, (i + 1) N / K): sizes differ by at most one.
  const long long n = frames;
  const long long a = i * n / k, b = (i + 1) * n / k - 1;
  return std::to_string(a) + "-" + std::to_string(b);
}

int videoInfo(const std::string& file) {
  auto info = io::probeVideo(file);
  if (!info.ok()) return report(info.error());
  const io::VideoInfo& v = info.value();
  const nlohmann::json out = {{"file", file},     {"codec", v.codec},   {"pix_fmt", v.pix_fmt}, {"color", v.color},
                              {"width", v.width}, {"height", v.height}, {"fps", v.fps},
                              {"frames", v.frames}, {"duration_s", v.duration}, {"comment", v.comment}};
  std::printf("%s\n", out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
  return 0;
}

int join(const std::vector<std::string>& chunks, const std::string& output, bool quiet) {
  // reel's chunks say which frames of which film they hold: they go in film order, and must be of
  // one film, follow one another from its first frame to its last, and hold what they say. Other
  // videos are joined in the order given.
  struct Chunk {
    std::string path;
    io::ChunkTag tag;
  };
  std::vector<Chunk> tagged;
  std::string untagged;
  for (const std::string& c : chunks) {
    auto comment = io::videoComment(c);
    if (!comment.ok()) return report(comment.error());
    io::ChunkTag t;
    if (io::ChunkTag::parse(comment.value(), t)) tagged.push_back({c, t});
    else if (untagged.empty()) untagged = c;
  }
  if (!tagged.empty() && !untagged.empty())
    return report(Error(ErrorKind::BadInput, untagged + ": not a chunk reel rendered, unlike " + tagged.front().path +
                                                 " (join reel's chunks of one film, or other videos, not both)"));
  auto range = [](const Chunk& c) { return " (frames " + std::to_string(c.tag.first) + "-" + std::to_string(c.tag.last) + ")"; };
  auto missing = [](int a, int b, const std::string& where) {
    return Error(ErrorKind::BadInput, "frames " + std::to_string(a) + "-" + std::to_string(b) + " are in none of the chunks " + where);
  };
  std::vector<std::string> order = chunks;
  std::vector<io::ChunkTag> tags;
  std::optional<io::ChunkTag> whole;
  if (!tagged.empty()) {
    std::stable_sort(tagged.begin(), tagged.end(), [](const Chunk& a, const Chunk& b) { return a.tag.first < b.tag.first; });
    const Chunk& head = tagged.front();
    if (head.tag.first > 0) return report(missing(0, head.tag.first - 1, "(before " + head.path + range(head) + ")"));
    for (std::size_t i = 1; i < tagged.size(); ++i) {
      const Chunk &p = tagged[i - 1], &c = tagged[i];
      if (c.tag.film == p.tag.film && c.tag.total != p.tag.total)
        return report(Error(ErrorKind::BadInput, c.path + ": its tag says film " + c.tag.film + " has " + std::to_string(c.tag.total) +
                                                     " frames, " + p.path + "'s says " + std::to_string(p.tag.total) +
                                                     " (an edited or damaged tag: render the chunk again)"));
      if (c.tag.film != p.tag.film)
        return report(Error(ErrorKind::BadInput, c.path + ": a chunk of another film (\"" + c.tag.scene + "\", film " + c.tag.film +
                                                     ") than " + p.path + " (\"" + p.tag.scene + "\", film " + p.tag.film +
                                                     "): another scene, seed, --size or --samples"));
      if (c.tag.first <= p.tag.last) return report(Error(ErrorKind::BadInput, c.path + range(c) + " overlaps " + p.path + range(p)));
      if (c.tag.first > p.tag.last + 1)
        return report(missing(p.tag.last + 1, c.tag.first - 1, "(between " + p.path + " and " + c.path + ")"));
    }
    const Chunk& tail = tagged.back();
    if (tail.tag.last < tail.tag.total - 1)
      return report(missing(tail.tag.last + 1, tail.tag.total - 1, "(after " + tail.path + range(tail) + ")"));
    for (std::size_t i = 0; i < tagged.size(); ++i) {
      order[i] = tagged[i].path;
      tags.push_back(tagged[i].tag);
    }
    whole = io::ChunkTag{0, tail.tag.total - 1, tail.tag.total, head.tag.scene, head.tag.film, ""};
  }
  if (Status st = io::joinVideos(order, output, whole ? &*whole : nullptr, tags); !st) return report(st.error());
  if (!quiet) {
    if (whole)
      std::printf("%s: frames 0-%d of \"%s\" (%zu chunks)\n", output.c_str(), whole->last, whole->scene.c_str(), chunks.size());
    else
      std::printf("%s: %zu videos joined\n", output.c_str(), chunks.size());
  }
  return 0;
}

}  // namespace reel::app
