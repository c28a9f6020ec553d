// Outgrowing one machine (docs/farm.md): the farm cache `reel simulate --cache` writes and
// `reel render --cache` reads, chunks of a film rendered from it, and `reel join`.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "app/sim_cache.h"
#include "body_scenes.h"
#include "helpers.h"
#include "io/frame_store.h"
#include "io/video.h"
#include "sim/world.h"

using namespace reel;
using reel::test::Run;
using reel::test::runReel;
namespace fs = std::filesystem;

namespace {

void writeBytes(const fs::path& p, const std::string& b) { std::ofstream(p, std::ios::binary | std::ios::trunc) << b; }

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

const std::string kTear = std::string(REEL_SOURCE_DIR) + "/tests/scenes/cloth_tear.json";      // 12 frames
const std::string kLiquid = std::string(REEL_SOURCE_DIR) + "/tests/scenes/fluid_surface.json";  // 10 frames

}  // namespace

TEST_CASE("farm cache: every body kind's frames go through the store and come back bit for bit") {
  for (const auto& [kind, text] : test::kScenes) {
    CAPTURE(kind);
    const fs::path d = test::freshDir("farm_kinds");
    World w = test::worldFromText(text, "kinds.json");
    const int frames = test::sceneFromText(text).frameCount();
    std::vector<std::uint64_t> hashes;
    {
      io::FrameStoreWriter store;
      REQUIRE(store.create(d.string()).ok());
      for (int f = 0; f < frames; ++f) {
        if (f > 0) REQUIRE(w.advanceFrame().ok());
        hashes.push_back(w.stateHash());
        REQUIRE(store.append(app::encodeSnapshot(w.snapshot())).ok());
      }
      REQUIRE(store.finish().ok());
    }
    auto store = io::FrameStoreReader::open(d.string());
    REQUIRE(store.ok());
    REQUIRE(store.value().frames() == frames);
    // Each frame restored into a fresh world of the scene is that frame, and runs on as it did.
    for (int k : {0, frames / 2, frames - 2}) {
      CAPTURE(k);
      auto b = store.value().read(k);
      REQUIRE(b.ok());
      WorldSnapshot snap;
      REQUIRE(app::decodeSnapshot(b.value().data(), b.value().size(), snap));
      World r = test::worldFromText(text, "kinds.json");
      REQUIRE(r.restore(snap).ok());
      CHECK(r.stateHash() == hashes[static_cast<std::size_t>(k)]);
      CHECK(app::encodeSnapshot(r.snapshot()) == b.value());
      REQUIRE(r.advanceFrame().ok());
      CHECK(r.stateHash() == hashes[static_cast<std::size_t>(k) + 1]);
    }
  }
}

TEST_CASE("farm cache: compression is lossless on awkward sizes") {
  for (std::size_t n : {0u, 1u, 7u, 8u, 9u, 4096u + 5u}) {
    CAPTURE(n);
    io::Bytes raw(n);
    for (std::size_t i = 0; i < n; ++i) raw[i] = static_cast<std::byte>((i * 37u) ^ (i >> 3));
    const io::Bytes packed = io::packFrame(raw);
    auto back = io::unpackFrame(packed.data(), packed.size(), n);
    REQUIRE(back.ok());
    CHECK(back.value() == raw);
  }
}

TEST_CASE("farm cache: one writer at a time; a reader sees the frames written so far") {
  const fs::path d = test::freshDir("farm_lock");
  io::FrameStoreWriter first;
  REQUIRE(first.create(d.string()).ok());
  REQUIRE(first.append(io::Bytes(100, std::byte{7})).ok());
  io::FrameStoreWriter second;
  auto r = second.resume(d.string());
  REQUIRE_FALSE(r.ok());
  CHECK(has(r.error().headline(), "another reel is writing this cache"));
  io::FrameStoreWriter third;
  CHECK_FALSE(third.create(d.string()).ok());
  // While the first writes on, a reader (a render job started early) reads what is complete.
  auto reader = io::FrameStoreReader::open(d.string());
  REQUIRE(reader.ok());
  CHECK(reader.value().frames() == 1);
  CHECK(reader.value().read(0).value() == io::Bytes(100, std::byte{7}));
  CHECK_FALSE(reader.value().read(1).ok());
  REQUIRE(first.append(io::Bytes(3, std::byte{1})).ok());
  REQUIRE(first.finish().ok());
  CHECK(io::FrameStoreReader::open(d.string()).value().frames() == 2);
}

TEST_CASE("render --cache: chunks of a film drawn from the cache are the whole render's frames, byte for byte") {
  for (const std::string& scene : {kTear, kLiquid}) {
    CAPTURE(scene);
    const fs::path d = test::freshDir("farm_chunks");
    const std::string cd = "cd " + d.string() + " && ";
    REQUIRE(runReel("render " + scene + " --no-cache -q -o whole/f_###.png", cd).code == 0);
    const Run sim = runReel("simulate " + scene + " --cache cache -q", cd);
    REQUIRE(sim.code == 0);
    CHECK(has(sim.out, "cache: cache ("));
    // Three chunks, rendered in another order than the film's.
    for (const char* c : {"2/3", "0/3", "1/3"}) REQUIRE(runReel("render " + scene + " --cache cache -q --chunk " + c + " -o chunks/f_###.png", cd).code == 0);
    int frames = 0;
    for (const auto& f : fs::directory_iterator(d / "whole")) {
      CAPTURE(f.path().filename().string());
      CHECK(test::fileBytes(f.path()) == test::fileBytes(d / "chunks" / f.path().filename()));
      ++frames;
    }
    CHECK(frames >= 10);
    CHECK(std::distance(fs::directory_iterator(d / "chunks"), fs::directory_iterator{}) == frames);
    // A still from the cache is that frame too.
    REQUIRE(runReel("still " + scene + " --cache cache --frame 7 -o still.png", cd).code == 0);
    CHECK(test::fileBytes(d / "still.png") == test::fileBytes(d / "whole" / "f_008.png"));
  }
}

TEST_CASE("join: MP4 chunks become one film of the right frames and duration, without re-encoding") {
  const fs::path d = test::freshDir("farm_join");
  const std::string cd = "cd " + d.string() + " && ";
  REQUIRE(runReel("simulate " + kTear + " --cache cache -q", cd).code == 0);
  for (int i = 0; i < 3; ++i)
    REQUIRE(runReel("render " + kTear + " --cache cache -q --chunk " + std::to_string(i) + "/3 -o c" + std::to_string(i) + ".mp4", cd).code == 0);
  auto c1 = io::probeVideo((d / "c1.mp4").string());
  REQUIRE(c1.ok());
  CHECK(c1.value().frames == 4);
  CHECK(c1.value().comment == "reel frames 4-7 of 12, scene cloth_tear");
  // Given out of order: reel's chunks say where they belong.
  const Run j = runReel("join c2.mp4 c0.mp4 c1.mp4 -o film.mp4", cd);
  REQUIRE(j.code == 0);
  CHECK(has(j.out, "frames 0-11 of 12 (3 chunks)"));
  auto film = io::probeVideo((d / "film.mp4").string());
  REQUIRE(film.ok());
  CHECK(film.value().frames == 12);
  CHECK(film.value().duration == doctest::Approx(1.2).epsilon(1e-3));
  CHECK(film.value().fps == doctest::Approx(10));
  CHECK(film.value().width == 160);
  // The packets are the chunks' own: the joined film is the sum of their sizes give or take headers.
  const auto sum = fs::file_size(d / "c0.mp4") + fs::file_size(d / "c1.mp4") + fs::file_size(d / "c2.mp4");
  CHECK(fs::file_size(d / "film.mp4") < sum);
  CHECK(fs::file_size(d / "film.mp4") + 3000 > sum);
  // Frames in film order: the joined film's frame 5 is the chunk's frame 1 (the same packets decode alike).
  auto joined = io::decodeVideo((d / "film.mp4").string(), 160, 120);
  auto middle = io::decodeVideo((d / "c1.mp4").string(), 160, 120);
  REQUIRE(joined.ok());
  REQUIRE(middle.ok());
  REQUIRE(joined.value().size() == 12);
  CHECK(joined.value()[5].rgb == middle.value()[1].rgb);
  CHECK(joined.value()[4].rgb == middle.value()[0].rgb);
  // info --video says the same, as JSON.
  const Run info = runReel("info --video film.mp4", cd);
  CHECK(info.code == 0);
  CHECK(has(info.out, "\"frames\":12"));

  SUBCASE("chunks that do not make one film are refused") {
    Run r = runReel("join c0.mp4 c2.mp4 -o gap.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "frames 4-7 are in none of the chunks"));
    r = runReel("join c0.mp4 c0.mp4 -o twice.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "overlaps"));
    REQUIRE(runReel("render " + kTear + " --cache cache -q --frames 4-7 --size 96x64 -o small.mp4", cd).code == 0);
    r = runReel("join c0.mp4 small.mp4 c2.mp4 -o sizes.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "size 96x64, unlike 160x120"));
    writeBytes(d / "not.mp4", "not a video");
    r = runReel("join c0.mp4 not.mp4 -o bad.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "not.mp4"));
    CHECK(runReel("join c0.mp4 missing.mp4 -o bad.mp4", cd).code == 2);
    for (const char* f : {"gap.mp4", "twice.mp4", "sizes.mp4", "bad.mp4"}) CHECK_FALSE(fs::exists(d / f));
  }
}

TEST_CASE("farm cache: a killed run resumes to the same bytes; damaged frames are reported, then rewritten") {
  const fs::path d = test::freshDir("farm_resume");
  const std::string cd = "cd " + d.string() + " && ";
  REQUIRE(runReel("simulate " + kTear + " --cache whole -q", cd).code == 0);
  const std::string bin = test::fileBytes(d / "whole" / "frames.bin"), idx = test::fileBytes(d / "whole" / "frames.idx");
  // Determinism: again, and on one thread, the same bytes.
  REQUIRE(runReel("simulate " + kTear + " --cache again -q --threads 1", cd).code == 0);
  CHECK(test::fileBytes(d / "again" / "frames.bin") == bin);
  CHECK(test::fileBytes(d / "again" / "frames.idx") == idx);
  fs::copy(d / "whole", d / "cut");
  // A run killed while writing frame 9: its record half there, its index entry not yet.
  auto entry = [&](int k) {
    std::uint64_t e[2];
    std::memcpy(e, idx.data() + 8 + 16 * k, 16);
    return std::pair{e[0], e[1]};
  };
  writeBytes(d / "cut" / "frames.bin", bin.substr(0, entry(9).first + entry(9).second / 2));
  writeBytes(d / "cut" / "frames.idx", idx.substr(0, 8 + 16 * 9));
  Run r = runReel("render " + kTear + " --cache cut -q --frames 8-11 -o x_#.png", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "frames 8-11 are not all in the cache (it holds frames 0-8 of 12"));
  CHECK(runReel("render " + kTear + " --cache cut -q --frames 0-8 -o x_#.png", cd).code == 0);
  // A truncated last frame and a corrupted checksum, each named with its frame.
  writeBytes(d / "cut" / "frames.idx", idx);
  r = runReel("render " + kTear + " --cache cut -q --frames 9-9 -o y_#.png", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "frame 9 is cut short"));
  std::string flipped = bin;
  const auto [off5, len5] = entry(5);
  flipped[off5 + len5 - 3] = static_cast<char>(flipped[off5 + len5 - 3] ^ 0x10);
  writeBytes(d / "cut" / "frames.bin", flipped);
  r = runReel("render " + kTear + " --cache cut -q -o z.mp4", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "frame 5: checksum mismatch"));
  CHECK_FALSE(fs::exists(d / "z.mp4"));
  // --resume keeps frames 0-4 and rewrites the rest: the bytes of the uninterrupted run.
  r = runReel("simulate " + kTear + " --cache cut --resume -q", cd);
  CHECK(r.code == 0);
  CHECK(has(r.out, "resumed after frame 4"));
  CHECK(test::fileBytes(d / "cut" / "frames.bin") == bin);
  CHECK(test::fileBytes(d / "cut" / "frames.idx") == idx);
  // A complete cache resumes to nothing; --resume of a missing cache starts one.
  r = runReel("simulate " + kTear + " --cache cut --resume -q", cd);
  CHECK(r.code == 0);
  CHECK(has(r.out, "complete (12 frames)"));
  REQUIRE(runReel("simulate " + kTear + " --cache fresh --resume -q", cd).code == 0);
  CHECK(test::fileBytes(d / "fresh" / "frames.bin") == bin);
}

TEST_CASE("farm cache: bad input") {
  const fs::path d = test::freshDir("farm_bad");
  const std::string cd = "cd " + d.string() + " && ";
  REQUIRE(runReel("simulate " + kTear + " --cache cache -q", cd).code == 0);
  // A folder holding something else, or a cache already there without --resume.
  fs::create_directories(d / "other");
  writeBytes(d / "other" / "notes.txt", "mine");
  Run r = runReel("simulate " + kTear + " --cache other -q", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "holds something else"));
  CHECK(test::fileBytes(d / "other" / "notes.txt") == "mine");
  r = runReel("simulate " + kTear + " --cache cache -q", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "add --resume"));
  CHECK(runReel("render " + kTear + " --cache other -q -o o.mp4", cd).code == 2);
  // Another scene, another seed: refused, saying which.
  const std::string drape = std::string(REEL_SOURCE_DIR) + "/tests/scenes/cloth_drape.json";
  r = runReel("render " + drape + " --cache cache -q -o o.mp4", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "another scene"));
  r = runReel("render " + kTear + " --cache cache --seed 9 -q -o o.mp4", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "seed 5, not 9"));
  // A cache of another reel version or build (its manifest says so).
  const std::string manifest = test::fileBytes(d / "cache" / "cache.json");
  std::string other = manifest;
  other.replace(other.find("\"reel\": \"") + 9, 1, "9");
  writeBytes(d / "cache" / "cache.json", other);
  r = runReel("render " + kTear + " --cache cache -q -o o.mp4", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "it was made by reel 9"));
  other = manifest;
  other.replace(other.find("\"build\": \"") + 10, 4, "0000");
  writeBytes(d / "cache" / "cache.json", other);
  r = runReel("render " + kTear + " --cache cache -q -o o.mp4", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "another build of reel"));
  writeBytes(d / "cache" / "cache.json", "{ not json");
  CHECK(runReel("render " + kTear + " --cache cache -q -o o.mp4", cd).code == 2);
  writeBytes(d / "cache" / "cache.json", manifest);
  r = runReel("simulate " + drape + " --cache cache --resume -q", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "cannot resume"));
  // Frames outside the film, chunks that do not divide it.
  CHECK(runReel("render " + kTear + " --cache cache -q --frames 5-12 -o o.mp4", cd).code == 2);
  for (const char* c : {"3/3", "-1/2", "1/0", "a/b", "0/13", "1/2/3"}) {
    CAPTURE(c);
    r = runReel("render " + kTear + " --cache cache -q --chunk " + std::string(c) + " -o o.mp4", cd);
    CHECK(r.code == 2);
  }
  CHECK(runReel("render " + kTear + " --cache cache -q --chunk 0/2 --frames 0-3 -o o.mp4", cd).code == 2);
  // --resume continues a cache only.
  CHECK(runReel("simulate " + kTear + " --resume -q", cd).code == 2);
  CHECK(runReel("simulate " + kTear + " --cache cache --resume --dump d.json -q", cd).code == 2);
  CHECK_FALSE(fs::exists(d / "o.mp4"));
  // A cache that cannot be written: exit 4, and nothing left behind.
  writeBytes(d / "file", "x");
  r = runReel("simulate " + kTear + " --cache file/cache -q", cd);
  CHECK(r.code == 4);
  CHECK(test::fileBytes(d / "file") == "x");
  const std::string long_name(300, 'n');
  r = runReel("simulate " + kTear + " --cache " + long_name + " -q", cd);
  CHECK(r.code == 4);
  CHECK_FALSE(fs::exists(d / long_name.substr(0, 200)));
}
