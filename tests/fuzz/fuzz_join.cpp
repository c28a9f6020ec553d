// libFuzzer target: `reel join` (app::join) of a good first chunk and a second one that is the
// input (the first byte picks MP4 or WebM): its comment and chunk tag, the order and coverage
// checks between tags, and the packet copy with its timestamp shifts and frame checks. Both good
// chunks are made at start with reel's own writer (frames 0-1 and 2-3 of a 4-frame film), and the
// second is the seed. A refusal (exit 2) is the expected answer; only a crash, sanitizer report,
// leak or hang is a finding. libav's own decoders are not the target: they run uninstrumented.
#include <sys/stat.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "app/commands.h"
#include "core/image.h"
#include "fuzz_files.h"
#include "io/video.h"

namespace {

const char* const kExt[] = {".mp4", ".webm"};

// frames first..last of a 4-frame film, into `path`.
void chunk(const std::string& path, int first, int last) {
  reel::io::ChunkTag tag{first, last, 4, "fuzz", "0123456789abcdef", ""};
  reel::io::VideoWriter w;
  if (!w.open(path, 64, 48, 30, 18, &tag)) std::abort();
  for (int f = first; f <= last; ++f) {
    reel::Image img(64, 48);
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        std::uint8_t* p = img.pixel(x, y);
        p[0] = static_cast<std::uint8_t>(4 * x + 20 * f);
        p[1] = static_cast<std::uint8_t>(5 * y);
        p[2] = static_cast<std::uint8_t>(60 * f);
      }
    if (!w.write(img)) std::abort();
  }
  if (!w.finish()) std::abort();
}

const std::string& firstChunk(int kind) {
  static const std::string paths[2] = {reel::fuzz::privateDir() + "/a" + kExt[0], reel::fuzz::privateDir() + "/a" + kExt[1]};
  static const bool made = [] {
    for (int k = 0; k < 2; ++k) chunk(paths[k], 0, 1);
    return true;
  }();
  (void)made;
  return paths[kind];
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (reel::fuzz::seedDir()) {
    for (int k = 0; k < 2; ++k) {
      const std::string b = reel::fuzz::privateDir() + "/b" + kExt[k];
      chunk(b, 2, 3);
      reel::fuzz::seed(std::string("second") + kExt[k], static_cast<std::uint8_t>(k), reel::fuzz::slurp(b));
    }
    std::exit(0);
  }
  (void)firstChunk(0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int kind = data[0] % 2;
  const std::string in = reel::fuzz::put(std::string("b") + kExt[kind], {reinterpret_cast<const char*>(data + 1), size - 1});
  const std::string out = reel::fuzz::privateDir() + "/joined" + kExt[kind];
  (void)reel::io::probeVideo(in);
  (void)reel::app::join({firstChunk(kind), in}, out, true);
  std::remove(out.c_str());
  return 0;
}
