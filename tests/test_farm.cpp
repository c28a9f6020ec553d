// Outgrowing one machine (docs/farm.md): the farm cache `reel simulate --cache` writes and
// `reel render --cache` reads, chunks of a film rendered from it, and `reel join`.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "capture.h"
#include "app/farm_cache.h"
#include "app/sim_cache.h"
#include "body_scenes.h"
#include "helpers.h"
#include "sanitizers.h"
#include "io/frame_store.h"
#include "io/png.h"
#include "io/video.h"
#include "core/image.h"
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
    CAPTURE_BINDING(kind);
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
  first.close();
  // A second simulate of the same new cache (two submissions) stops at the lock, touching nothing.
  const fs::path c = test::freshDir("farm_lock_cache");
  auto scene = app::loadScene(kTear);
  REQUIRE(scene.ok());
  auto want = app::CacheManifest::of(kTear, scene.value());
  REQUIRE(want.ok());
  app::CacheWriter a;
  REQUIRE(a.open((c / "cache").string(), want.value(), false).ok());
  app::CacheWriter b;
  const Status st = b.open((c / "cache").string(), want.value(), true);
  REQUIRE_FALSE(st.ok());
  CHECK(st.error().kind == ErrorKind::BadInput);
  CHECK(has(st.error().headline(), "another reel is writing this cache"));
  for (const char* f : {"cache.json", "scene.json", "frames.bin", "frames.idx"}) CHECK(fs::exists(c / "cache" / f));
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

TEST_CASE("farm cache: every body kind draws the same picture from the cache as from its simulation") {
  const fs::path d = test::freshDir("farm_draw");
  const std::string cd = "cd " + d.string() + " && ";
  for (const auto& [kind, text] : test::kScenes) {
    CAPTURE_BINDING(kind);
    std::string name = kind;
    std::replace(name.begin(), name.end(), '+', '_');
    writeBytes(d / (name + ".json"), text);
    const int k = test::sceneFromText(text).frameCount() / 2;
    const std::string frame = " --frame " + std::to_string(k) + " --size 64x48 --samples 1 -q ";
    REQUIRE(runReel("simulate " + name + ".json --cache " + name + " -q", cd).code == 0);
    REQUIRE(runReel("still " + name + ".json --no-cache" + frame + "-o " + name + "_sim.png", cd).code == 0);
    REQUIRE(runReel("still " + name + ".json --cache " + name + frame + "-o " + name + "_cache.png", cd).code == 0);
    CHECK(test::fileBytes(d / (name + "_sim.png")) == test::fileBytes(d / (name + "_cache.png")));
    CHECK(test::fileBytes(d / (name + "_sim.png")).size() > 100);
  }
}

TEST_CASE("join: MP4 chunks become one film of the right frames and duration, without re-encoding") {
  const fs::path d = test::freshDir("farm_join");
  const std::string cd = "cd " + d.string() + " && ";
  REQUIRE(runReel("simulate " + kTear + " --cache cache -q", cd).code == 0);
  // Five chunks of 12 frames: 2, 2, 3, 2 and 3 frames.
  for (int i = 0; i < 5; ++i)
    REQUIRE(runReel("render " + kTear + " --cache cache -q --chunk " + std::to_string(i) + "/5 -o c" + std::to_string(i) + ".mp4", cd).code == 0);
  auto c2 = io::probeVideo((d / "c2.mp4").string());
  REQUIRE(c2.ok());
  CHECK(c2.value().frames == 3);
  io::ChunkTag tag;
  REQUIRE(io::ChunkTag::parse(c2.value().comment, tag));
  CHECK(tag.first == 4);
  CHECK(tag.last == 6);
  CHECK(tag.total == 12);
  CHECK(tag.scene == "cloth_tear");
  CHECK(tag.film.size() == 16);
  // Given out of order: reel's chunks say where they belong.
  const Run j = runReel("join c3.mp4 c2.mp4 c0.mp4 c4.mp4 c1.mp4 -o film.mp4", cd);
  REQUIRE(j.code == 0);
  CHECK(has(j.out, "frames 0-11 of \"cloth_tear\" (5 chunks)"));
  auto film = io::probeVideo((d / "film.mp4").string());
  REQUIRE(film.ok());
  CHECK(film.value().frames == 12);
  CHECK(film.value().duration == doctest::Approx(1.2).epsilon(1e-3));
  CHECK(film.value().fps == doctest::Approx(10));
  CHECK(film.value().width == 160);
  CHECK(has(film.value().comment, "reel frames 0-11 of 12, scene cloth_tear, film "));
  CHECK(has(film.value().comment, tag.film));
  // The packets are the chunks' own: the joined film is the sum of their sizes give or take headers.
  std::uintmax_t sum = 0;
  for (const char* c : {"c0.mp4", "c1.mp4", "c2.mp4", "c3.mp4", "c4.mp4"}) sum += fs::file_size(d / c);
  CHECK(fs::file_size(d / "film.mp4") < sum);
  CHECK(fs::file_size(d / "film.mp4") + 5000 > sum);
  // Frames in film order: the joined film's frames 4-6 are the third chunk's (the same packets decode alike).
  auto joined = io::decodeVideo((d / "film.mp4").string(), 160, 120);
  auto middle = io::decodeVideo((d / "c2.mp4").string(), 160, 120);
  REQUIRE(joined.ok());
  REQUIRE(middle.ok());
  REQUIRE(joined.value().size() == 12);
  for (int k = 0; k < 3; ++k) CHECK(joined.value()[static_cast<std::size_t>(4 + k)].rgb == middle.value()[static_cast<std::size_t>(k)].rgb);
  // info --video says the same, as JSON.
  const Run info = runReel("info --video film.mp4", cd);
  CHECK(info.code == 0);
  CHECK(has(info.out, "\"frames\":12"));
  // It opens only what reel writes: a PNG named .mp4 (which libav's image demuxer would read as a
  // one-frame video) is refused before any other demuxer or decoder sees it.
  REQUIRE(io::writePng((d / "picture.mp4").string(), Image(32, 24)).ok());
  const Run pic = runReel("info --video picture.mp4", cd);
  CHECK(pic.code == 2);
  CHECK(has(pic.out, "not a video file reel reads (MP4 of H.264, WebM of VP9 or GIF)"));

  SUBCASE("WebM chunks join the same way") {
    for (int i = 0; i < 2; ++i)
      REQUIRE(runReel("render " + kTear + " --cache cache -q --chunk " + std::to_string(i) + "/2 -o w" + std::to_string(i) + ".webm", cd).code == 0);
    REQUIRE(runReel("join w1.webm w0.webm -o film.webm", cd).code == 0);
    auto w = io::probeVideo((d / "film.webm").string());
    REQUIRE(w.ok());
    CHECK(w.value().codec == "vp9");
    CHECK(w.value().frames == 12);
    CHECK(w.value().duration == doctest::Approx(1.2).epsilon(1e-2));
  }
  SUBCASE("chunks that do not make one film are refused, writing nothing") {
    Run r = runReel("join c0.mp4 c2.mp4 c3.mp4 c4.mp4 -o gap.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "frames 2-3 are in none of the chunks (between c0.mp4 and c2.mp4)"));
    r = runReel("join c1.mp4 c2.mp4 c3.mp4 c4.mp4 -o head.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "frames 0-1 are in none of the chunks (before c1.mp4"));
    r = runReel("join c0.mp4 c1.mp4 c2.mp4 c3.mp4 -o tail.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "frames 9-11 are in none of the chunks (after c3.mp4"));
    r = runReel("join c0.mp4 c0.mp4 c1.mp4 c2.mp4 c3.mp4 c4.mp4 -o twice.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "overlaps"));
    // Another size, other samples or another seed: another film.
    for (const std::string& other : {std::string("--size 96x64"), std::string("--samples 1")}) {
      CAPTURE(other);
      REQUIRE(runReel("render " + kTear + " --cache cache -q --chunk 1/5 " + other + " -o other.mp4", cd).code == 0);
      r = runReel("join c0.mp4 other.mp4 c2.mp4 c3.mp4 c4.mp4 -o sizes.mp4", cd);
      CHECK(r.code == 2);
      CHECK(has(r.out, "other.mp4: a chunk of another film"));
    }
    // Below the tags, the files themselves: another size is refused, named.
    REQUIRE(runReel("render " + kTear + " --cache cache -q --chunk 1/5 --size 96x64 -o small.mp4", cd).code == 0);
    Status st = io::joinVideos({(d / "c0.mp4").string(), (d / "small.mp4").string()}, (d / "raw.mp4").string());
    REQUIRE_FALSE(st.ok());
    CHECK(st.error().kind == ErrorKind::BadInput);
    CHECK(has(st.error().headline(), "size 96x64, unlike 160x120"));
    // A video of one black 160x120 frame at 10 frames/s, tagged or not.
    auto oneFrame = [&](const char* name, const io::ChunkTag* t = nullptr) {
      io::VideoWriter w;
      REQUIRE(w.open((d / name).string(), 160, 120, 10, 18, t).ok());
      REQUIRE(w.write(Image(160, 120)).ok());
      REQUIRE(w.finish().ok());
    };
    // A chunk whose render stopped early holds fewer frames than its tag says.
    {
      const io::ChunkTag t{2, 3, 12, "cloth_tear", tag.film, ""};
      oneFrame("short.mp4", &t);
    }
    r = runReel("join c0.mp4 short.mp4 c2.mp4 c3.mp4 c4.mp4 -o early.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "short.mp4: holds 1 frames where its tag says 2"));
    // A tag moved onto another chunk's frames (the same count): its check does not match them.
    {
      auto c1 = io::probeVideo((d / "c1.mp4").string());
      REQUIRE(c1.ok());
      io::ChunkTag t1;
      REQUIRE(io::ChunkTag::parse(c1.value().comment, t1));
      CHECK(t1.check.size() == 16);
      REQUIRE(io::joinVideos({(d / "c3.mp4").string()}, (d / "forged.mp4").string(), &t1).ok());  // c3's frames, c1's tag
      r = runReel("join c0.mp4 forged.mp4 c2.mp4 c3.mp4 c4.mp4 -o moved.mp4", cd);
      CHECK(r.code == 2);
      CHECK(has(r.out, "forged.mp4: its frames are not the ones its tag was written for (frames 2-3)"));
      // A tag whose film is said to be far longer: named as an edited tag, not as another film.
      const io::ChunkTag huge{2, 3, 2000000000, "cloth_tear", tag.film, ""};
      REQUIRE(io::joinVideos({(d / "c1.mp4").string()}, (d / "huge.mp4").string(), &huge).ok());
      r = runReel("join c0.mp4 huge.mp4 c2.mp4 c3.mp4 c4.mp4 -o long.mp4", cd);
      CHECK(r.code == 2);
      CHECK(has(r.out, "huge.mp4: its tag says film " + tag.film + " has 2000000000 frames, c0.mp4's says 12"));
      // A chunk cut short: named as damaged, without libav's own log lines.
      fs::copy_file(d / "c1.mp4", d / "cut.mp4");
      fs::resize_file(d / "cut.mp4", fs::file_size(d / "cut.mp4") / 3);
      r = runReel("join c0.mp4 cut.mp4 c2.mp4 c3.mp4 c4.mp4 -o cut_film.mp4", cd);
      CHECK(r.code == 2);
      CHECK(has(r.out, "cut.mp4: a damaged or truncated video"));
      CHECK(!has(r.out, "@ 0x"));  // "[h264 @ 0x55...]": libav's log
      for (const char* f : {"moved.mp4", "long.mp4", "cut_film.mp4"}) CHECK_FALSE(fs::exists(d / f));
    }
    // A video reel did not tag among reel's chunks.
    oneFrame("plain.mp4");
    r = runReel("join c0.mp4 plain.mp4 -o mixed.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "plain.mp4: not a chunk reel rendered"));
    // A GIF named .mp4: refused when it is opened, before any of libav's other decoders sees it.
    oneFrame("anim.gif");
    fs::copy_file(d / "anim.gif", d / "anim.mp4");
    r = runReel("join c0.mp4 anim.mp4 -o mixed.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "anim.mp4: not a video file reel joins (MP4 of H.264 or WebM of VP9)"));
    std::ofstream(d / "not.mp4") << "not a video";
    r = runReel("join c0.mp4 not.mp4 -o bad.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "not.mp4"));
    CHECK(runReel("join c0.mp4 missing.mp4 -o bad.mp4", cd).code == 2);
    r = runReel("join c0.mp4 c1.mp4 c2.mp4 c3.mp4 c4.mp4 -o film.gif", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "join writes .mp4 or .webm"));
    for (const char* f : {"gap.mp4", "head.mp4", "tail.mp4", "twice.mp4", "sizes.mp4", "raw.mp4", "early.mp4", "mixed.mp4", "bad.mp4", "film.gif"})
      CHECK_FALSE(fs::exists(d / f));
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
  // A run killed for real (SIGKILL, mid-write wherever it is after 0.3 s) resumes to the same bytes.
  runReel("simulate " + kTear + " --cache killed -q", cd + "timeout -s KILL 0.3 ");
  REQUIRE(runReel("simulate " + kTear + " --cache killed --resume -q", cd).code == 0);
  CHECK(test::fileBytes(d / "killed" / "frames.bin") == bin);
  CHECK(test::fileBytes(d / "killed" / "frames.idx") == idx);
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
  // A lost or damaged index is rebuilt from the records themselves.
  fs::remove(d / "cut" / "frames.idx");
  r = runReel("render " + kTear + " --cache cut -q --frames 0-1 -o w_#.png", cd);
  CHECK(r.code == 2);
  CHECK(has(r.out, "frames.idx: missing or not a reel frame index"));
  REQUIRE(runReel("simulate " + kTear + " --cache cut --resume -q", cd).code == 0);
  CHECK(test::fileBytes(d / "cut" / "frames.idx") == idx);
  CHECK(test::fileBytes(d / "cut" / "frames.bin") == bin);
  // A complete cache resumes to nothing; --resume of a missing cache starts one.
  r = runReel("simulate " + kTear + " --cache cut --resume -q", cd);
  CHECK(r.code == 0);
  CHECK(has(r.out, "complete (12 frames)"));
  REQUIRE(runReel("simulate " + kTear + " --cache fresh --resume -q", cd).code == 0);
  CHECK(test::fileBytes(d / "fresh" / "frames.bin") == bin);
}

TEST_CASE("farm cache: a record whose header names a huge raw size is refused before anything is allocated") {
  // The header's sizes are outside the checksum: one changed field once ran reel out of memory
  // (std::bad_alloc, exit 134) before any check. Each is refused as a damaged frame, and --resume
  // rewrites it.
  const fs::path d = test::freshDir("farm_raw_size");
  const std::string cd = "cd " + d.string() + " && ";
  REQUIRE(runReel("simulate " + kTear + " --cache c -q", cd).code == 0);
  const std::string bin = test::fileBytes(d / "c" / "frames.bin"), idx = test::fileBytes(d / "c" / "frames.idx");
  std::uint64_t e3[2];
  std::memcpy(e3, idx.data() + 8 + 16 * 3, 16);
  for (const std::uint64_t raw : {std::uint64_t{1} << 33, std::uint64_t{3} << 29, std::uint64_t{5}}) {
    std::string forged = bin;
    std::memcpy(forged.data() + e3[0] + 8, &raw, 8);  // RecordHeader: magic, frame, raw_size, ...
    writeBytes(d / "c" / "frames.bin", forged);
    // Under a 4 GB address space: a believed size could not even be allocated.
    const std::string limit = test::kSanitizerAddressSpace ? "" : "ulimit -v 4000000 && ";
    Run r = runReel("render " + kTear + " --cache c -q -o o/f_####.png", cd + limit);
    CHECK(r.code == 2);
    CHECK(has(r.out, "frame 3: its record header is damaged"));
    r = runReel("still " + kTear + " --cache c --frame 3 -q -o s.png", cd + limit);
    CHECK(r.code == 2);
    CHECK(has(r.out, "frame 3: its record header is damaged"));
    CHECK_FALSE(fs::exists(d / "s.png"));
    r = runReel("simulate " + kTear + " --cache c --resume -q", cd + limit);
    CHECK(r.code == 0);
    CHECK(has(r.out, "resumed after frame 2"));
    CHECK(test::fileBytes(d / "c" / "frames.bin") == bin);
  }
  // An index entry longer than the file holds is a cut-short frame, not an allocation.
  std::string idx_forged = idx;
  const std::uint64_t huge = std::uint64_t{1} << 33;
  std::memcpy(idx_forged.data() + 8 + 16 * 3 + 8, &huge, 8);
  writeBytes(d / "c" / "frames.idx", idx_forged);
  Run r = runReel("still " + kTear + " --cache c --frame 3 -q -o s.png",
                  cd + (test::kSanitizerAddressSpace ? "" : "ulimit -v 4000000 && "));
  CHECK(r.code == 2);
  CHECK(has(r.out, "frame 3"));
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
  // A damaged manifest is named in plain words, never with the JSON library's exception text.
  for (const auto& [text, why] : std::vector<std::pair<std::string, std::string>>{
           {"{ not json", "it is not JSON"}, {R"({"format": 5})", "a field has the wrong type"},
           {R"({"format": "reel-cache/1"})", "a field reel writes is missing"}}) {
    CAPTURE_BINDING(text);
    writeBytes(d / "cache" / "cache.json", text);
    r = runReel("render " + kTear + " --cache cache -q -o o.mp4", cd);
    CHECK(r.code == 2);
    CHECK(has(r.out, "cache.json: damaged (" + why + ")"));
    CHECK_FALSE(has(r.out, "json.exception"));
  }
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
  const auto entries = [&] { return std::distance(fs::directory_iterator(d), fs::directory_iterator{}); };
  const auto before = entries();
  r = runReel("simulate " + kTear + " --cache new/" + std::string(300, 'n') + " -q", cd);
  CHECK(r.code == 4);
  CHECK(has(r.out, "cannot create the cache folder"));
  CHECK(entries() == before);  // not even new/
  // A cache whose start was cut short (its files, but no cache.json yet) is started again.
  fs::create_directories(d / "cut_short");
  writeBytes(d / "cut_short" / "frames.bin", "REELFRM1");
  writeBytes(d / "cut_short" / "scene.json.part", "{");
  REQUIRE(runReel("simulate " + kTear + " --cache cut_short -q", cd).code == 0);
  CHECK(test::fileBytes(d / "cut_short" / "frames.bin") == test::fileBytes(d / "cache" / "frames.bin"));
}
