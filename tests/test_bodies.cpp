// The body interface: every kind's snapshot and restore resume a run bit for bit from any frame,
// the registry names each kind once, and the world refuses a snapshot of another scene.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>

#include "capture.h"
#include "body_scenes.h"
#include "helpers.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

World build(const std::string& text) { return worldFromText(text, "bodies.json"); }

}  // namespace

TEST_CASE("every body kind: a run resumed from a snapshot at frame k equals the uninterrupted run bit for bit") {
  for (const auto& [kind, text] : kScenes) {
    CAPTURE_BINDING(kind);
    World whole = build(text);
    const int frames = sceneFromText(text).frameCount() - 1;
    std::vector<std::uint64_t> hashes;
    std::vector<WorldSnapshot> snaps;
    for (int f = 0; f < frames; ++f) {
      hashes.push_back(whole.stateHash());
      snaps.push_back(whole.snapshot());
      run(whole, 1);
    }
    const std::uint64_t end = whole.stateHash();
    // Resumed in a new world of the same scene from several frames, including the first and the last.
    for (int k : {0, frames / 3, frames / 2, frames - 1}) {
      CAPTURE(k);
      World resumed = build(text);
      REQUIRE(resumed.restore(snaps[static_cast<std::size_t>(k)]).ok());
      CHECK(resumed.frame() == k);
      CHECK(resumed.stateHash() == hashes[static_cast<std::size_t>(k)]);
      run(resumed, frames - k);
      CHECK(resumed.stateHash() == end);
    }
  }
}

TEST_CASE("a world goes back to an earlier frame of its own and runs on as before") {
  for (const auto& [kind, text] : kScenes) {
    CAPTURE_BINDING(kind);
    World w = build(text);
    const int frames = sceneFromText(text).frameCount() - 1;
    run(w, frames / 3);
    const WorldSnapshot back = w.snapshot();
    run(w, frames - frames / 3);
    const std::uint64_t end = w.stateHash();
    REQUIRE(w.restore(back).ok());
    run(w, frames - frames / 3);
    CHECK(w.stateHash() == end);
  }
}

TEST_CASE("a damaged snapshot is refused and leaves the world as it was; one that reads leaves it runnable") {
  for (const auto& [kind, text] : kScenes) {
    CAPTURE_BINDING(kind);
    World w = build(text);
    run(w, 3);
    const WorldSnapshot good = w.snapshot();
    const std::uint64_t h = w.stateHash();
    WorldSnapshot off_frame = good;
    off_frame.step += 1;  // not a frame of this scene
    CHECK(!w.restore(off_frame).ok());
    for (std::size_t k = 0; k < good.bodies.size(); ++k) {  // every body of the scene, in turn
      CAPTURE(k);
      std::vector<WorldSnapshot> bad(3, good);
      bad[0].bodies[k].bytes.resize(good.bodies[k].bytes.size() / 2);  // cut short
      bad[1].bodies[k].bytes.push_back(std::byte{1});                   // a byte too many
      std::fill_n(bad[2].bodies[k].bytes.begin(), 8, std::byte{0x7F});  // the first array's length
      for (const WorldSnapshot& b : bad) {
        CHECK(!w.restore(b).ok());
        CHECK(w.stateHash() == h);
      }
      // Bytes overwritten all through: refused, or taken and stepped without crashing (a state
      // that reads but makes no sense may stop the run with exit 3, never with a crash).
      const std::size_t size = good.bodies[k].bytes.size();
      for (std::size_t at = 8; at + 8 <= size; at += std::max<std::size_t>(8, size / 16)) {
        CAPTURE(at);
        WorldSnapshot c = good;
        std::fill_n(c.bodies[k].bytes.begin() + static_cast<std::ptrdiff_t>(at), 8, std::byte{0xFF});
        if (w.restore(c).ok()) (void)w.advanceFrame();
        REQUIRE(w.restore(good).ok());
      }
    }
    CHECK(w.stateHash() == h);
  }
}

TEST_CASE("the snapshots see what changes: tears, emitted particles and a pushed ball") {
  World cloth = build(kScenes.at("cloth"));
  run(cloth, 1);
  const std::size_t blob0 = cloth.snapshot().bodies[0].bytes.size();
  run(cloth, 40);
  CHECK(cloth.snapshot().bodies[0].bytes.size() < blob0);  // fewer springs after the tear
  World fluid = build(kScenes.at("fluid"));
  const WorldSnapshot before = fluid.snapshot();
  run(fluid, 10);
  const WorldSnapshot after = fluid.snapshot();
  CHECK(after.bodies[0].bytes.size() > before.bodies[0].bytes.size());  // particles emitted
  REQUIRE(after.bodies.size() == 2);  // the liquid, then the free ball
  CHECK(after.bodies[1].bytes != before.bodies[1].bytes);
  CHECK(after.colliders[1].pos != before.colliders[1].pos);
}

TEST_CASE("restore refuses a snapshot of another scene") {
  World rope = build(kScenes.at("rope"));
  World net = build(kScenes.at("net"));
  const Status st = rope.restore(net.snapshot());
  REQUIRE(!st.ok());
  CHECK(st.error().kind == ErrorKind::BadInput);
  CHECK(st.error().headline().find("another scene") != std::string::npos);
  WorldSnapshot cut = rope.snapshot();
  cut.bodies[0].bytes.resize(cut.bodies[0].bytes.size() / 2);
  CHECK(!rope.restore(cut).ok());
}

TEST_CASE("the registry names every body kind once, and each has a resume test above") {
  std::set<std::string> names;
  for (const app::BodyKind& k : app::bodyKinds()) {
    CAPTURE(k.type);
    CHECK(names.insert(k.type).second);
    const bool complete = k.read != nullptr && k.build != nullptr;
    CHECK(complete);
    CHECK(kScenes.count(k.type) == 1);
  }
  CHECK(app::bodyReaders().size() == names.size());
  CHECK(app::bodyBuilders().size() == names.size());
  // An unknown kind is named with the nearest from the table.
  auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "clth", "name": "x"}]})", "k.json");
  REQUIRE(!r.ok());
  CHECK(r.error().headline().find("did you mean \"cloth\"? (one of: mass_spring, rope, net, lattice, cloth, fluid, school, fish, food, seaweed, rigid, face, articulated)") !=
        std::string::npos);
}
