// The body interface: every kind's snapshot and restore resume a run bit for bit from any frame,
// the registry names each kind once, and the world refuses a snapshot of another scene.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>

#include "helpers.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

World build(const std::string& text) { return worldFromText(text, "bodies.json"); }

const std::string kHead = R"({"format": "reel/1", "fps": 30, "seed": 11, )";

// One scene per body kind, each using what makes its state more than positions and velocities:
// implicit Euler's warm start, tearing and self-collision, emitters, random forces, free objects.
const std::map<std::string, std::string> kScenes = {
    {"mass_spring", kHead + R"("duration": 1, "substeps": 50, "integrator": "implicit_euler",
      "objects": [{"type": "plane", "point": [0, -1, 0]}],
      "bodies": [{"type": "mass_spring", "name": "m",
        "nodes": [{"position": [0, 0, 0], "mass": 1, "fixed": true}, {"position": [0.5, 0, 0], "mass": 1},
                  {"position": [1, 0, 0], "mass": 1, "velocity": [0, 2, 1]}],
        "springs": [{"nodes": [0, 1], "stiffness": 300, "damping": 0.5}, {"nodes": [1, 2], "stiffness": 300}]}]})"},
    {"rope", kHead + R"("duration": 1, "substeps": 40, "integrator": "rk4",
      "objects": [{"type": "sphere", "center": [0.5, -0.6, 0], "radius": 0.3}],
      "bodies": [{"type": "rope", "name": "r", "start": [0, 0, 0], "end": [1, 0, 0], "segments": 12,
                  "stiffness": 400, "damping": 0.2, "pinned": ["start"]}]})"},
    {"net", kHead + R"("duration": 1, "substeps": 30, "integrator": "verlet",
      "objects": [{"type": "box", "center": [0, -0.5, 0], "size": [0.6, 0.2, 0.6], "rotation_deg": [0, 30, 0],
                   "motion": {"keys": [{"time": 0, "position": [0, -0.5, 0]}, {"time": 1, "position": [0.2, -0.3, 0]}]}}],
      "bodies": [{"type": "net", "name": "n", "size": [1, 1], "resolution": [8, 8], "stiffness": 300,
                  "damping": 0.3, "pinned": ["corner_00"]}]})"},
    {"lattice", kHead + R"("duration": 1, "substeps": 40, "integrator": "explicit_euler", "auto_substeps": true,
      "objects": [{"type": "plane", "point": [0, 0, 0]}],
      "bodies": [{"type": "lattice", "name": "l", "position": [0, 0.4, 0], "size": [0.3, 0.3, 0.3],
                  "resolution": [3, 3, 3], "stiffness": 800, "damping": 0.5}]})"},
    {"cloth", kHead + R"("duration": 1.4, "substeps": 20, "auto_substeps": true, "integrator": "implicit_euler",
      "wind": {"velocity": [1, 0, 0.5], "gust": 2},
      "objects": [{"type": "sphere", "center": [0, 0.3, 0], "radius": 0.25}],
      "bodies": [{"type": "cloth", "name": "c", "position": [0, 0.7, 0], "size": [1, 1], "resolution": [12, 12],
                  "mass": 0.2, "self_collision": true, "strain_limit": 0.1, "air": {"viscous": 0.5, "drag": 0.4},
                  "tear": {"strain": 0.08, "variation": 0.5},
                  "grips": [{"nodes": ["edge_x0"], "velocity": [-0.6, 0, 0]}, {"nodes": ["edge_x1"], "velocity": [0.6, 0, 0]}]}]})"},
    {"fluid", kHead + R"("duration": 0.6, "substeps": 24,
      "objects": [{"type": "container", "center": [0, 0.1, 0], "size": [0.4, 0.2, 0.3], "wall": 0.02},
                  {"type": "sphere", "name": "ball", "center": [0.05, 0.25, 0], "radius": 0.04, "dynamic": true, "mass": 0.1}],
      "bodies": [{"type": "fluid", "name": "f",
        "species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 10,
                     "agitation": 0.05},
                    {"name": "oil", "mass": 0.006, "alpha": 150, "beta": 0.06, "cutoff": 0.02725, "viscosity": 10}],
        "blocks": [{"min": [-0.18, 0.02, -0.13], "max": [0.0, 0.12, 0.13], "spacing": 0.02, "jitter": 0.1}],
        "emitters": [{"species": "oil", "position": [0.1, 0.3, 0], "direction": [0, -1, 0], "speed": 1, "radius": 0.03,
                      "rate": 400}]}]})"},
    // Cloth and liquid exchanging momentum; the sheet soaks some up and drips (its wetness resumes).
    {"cloth+fluid", kHead + R"("duration": 0.8, "substeps": 24, "integrator": "implicit_euler",
      "bodies": [{"type": "cloth", "name": "c", "position": [0, 0, 0], "size": [0.4, 0.4], "resolution": [8, 8], "mass": 0.05,
                  "pinned": ["edge_z0"], "absorbency": 0.5, "surface": {"adhesion": 2}},
                 {"type": "fluid", "name": "f",
                  "species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 10}],
                  "emitters": [{"position": [0, 0.2, 0.05], "direction": [0, -1, 0], "speed": 1, "radius": 0.03, "rate": 400}]}]})"},
    {"school", kHead + R"("duration": 1, "substeps": 3,
      "objects": [{"type": "capsule", "name": "kelp", "start": [4, -3, 0], "end": [4, 3, 0], "radius": 0.8,
                   "motion": {"keys": [{"time": 0, "position": [4, 0, 0]}, {"time": 1, "position": [3, 0, 1]}]}}],
      "bodies": [{"type": "school", "name": "shark", "model": "boids", "agents": [{"position": [-5, 0, 0], "heading": [1, 0, 0]}],
                  "goal": {"path": [{"time": 0, "position": [0, 0, 0]}, {"time": 1, "position": [6, 0, 0]}]}},
                 {"type": "school", "name": "s", "count": 120, "start": {"min": [-2, -2, -2], "max": [2, 2, 2]},
                  "zones": {"repulsion": 0.4, "orientation": 2, "attraction": 6}, "reaction_time": 0.05,
                  "bounds": {"center": [0, 0, 0], "radius": 12}, "predator": {"school": "shark", "fear_radius": 3},
                  "goal": {"position": [10, 0, 0], "informed": 0.3}}]})"},
    // The fish world: a hook, a predator, a school of prey, pacifists, food, seaweed in a current.
    {"fish", kHead + R"("duration": 1, "substeps": 6, "integrator": "implicit_euler",
      "water": {"currents": [{"type": "uniform", "velocity": [0.05, 0, 0], "amplitude": [0, 0, 0.05], "period": 3}]},
      "objects": [{"type": "plane", "point": [0, -2, 0]}, {"type": "sphere", "name": "rock", "center": [0, -1, 2], "radius": 0.5},
                  {"type": "sphere", "name": "hook", "center": [0.3, 0, 0.6], "radius": 0.03,
                   "motion": {"keys": [{"time": 0, "position": [0.3, 0, 0.6]}, {"time": 1, "position": [0.3, 0.3, 0.6]}]}}],
      "bodies": [{"type": "fish", "name": "shark", "species": "predator", "position": [0, 0, -2.5], "length": 0.8},
                 {"type": "fish", "name": "prey", "count": 6, "start": {"center": [0, 0, 0], "radius": 0.6},
                  "mental": {"hunger": 0.9}, "hook": "hook"},
                 {"type": "fish", "name": "pair", "species": "pacifist", "count": 2, "start": {"center": [1, 0, 1], "radius": 0.3},
                  "mental": {"libido": 0.9, "hunger": 0}},
                 {"type": "food", "name": "plankton", "region": {"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}, "initial": 30, "rate": 10},
                 {"type": "seaweed", "name": "kelp", "count": 3, "region": {"min": [-1, -2, 1], "max": [1, -2, 2]}, "height": 1.2}]})"},
    {"food", kHead + R"("duration": 1, "substeps": 2,
      "water": {"currents": [{"type": "source", "object": "vent", "rate": 0.05}]},
      "objects": [{"type": "sphere", "name": "vent", "center": [0, -1, 0], "radius": 0.1}],
      "bodies": [{"type": "food", "name": "plankton", "region": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]},
                  "initial": 20, "rate": 30, "max_alive": 40}]})"},
    {"seaweed", kHead + R"("duration": 1, "substeps": 20,
      "water": {"currents": [{"type": "uniform", "velocity": [0.3, 0, 0], "amplitude": [0.2, 0, 0], "period": 2}]},
      "bodies": [{"type": "seaweed", "name": "kelp", "bases": [[0, 0, 0], [0.3, 0, 0]], "height": 1, "segments": 8}]})"},
    {"rigid", kHead + R"("duration": 1, "substeps": 4,
      "objects": [{"type": "plane", "name": "floor"}],
      "bodies": [{"type": "rigid", "name": "crates", "shape": "box", "size": [0.3, 0.3, 0.3], "position": [0, 0.3, 0],
                  "rotation_deg": [20, 10, 0], "angular_velocity": [0, 3, 0], "array": {"count": [2, 2, 1], "spacing": [0.32, 0.35, 0]}},
                 {"type": "rigid", "name": "ball", "shape": "sphere", "radius": 0.1, "position": [0.1, 1.2, 0], "velocity": [0, -1, 0]},
                 {"type": "rigid", "name": "hanger", "shape": "capsule", "radius": 0.05, "length": 0.5, "position": [0.8, 0.5, 0],
                  "motion": {"keys": [{"time": 0, "position": [0.8, 0.5, 0]}, {"time": 1, "position": [0.2, 0.5, 0], "rotation_deg": [0, 0, 60]}]}}]})"},
    {"face", kHead + R"("duration": 0.5, "substeps": 2, "integrator": "implicit_euler",
      "bodies": [{"type": "face", "name": "f", "resolution": [24, 18], "blinks": [0.1],
                  "keys": [{"time": 0, "rotation_deg": [0, 20, 0]}, {"time": 0.5, "rotation_deg": [5, -10, 0]}],
                  "activations": [{"time": 0, "preset": "happiness", "amount": 0}, {"time": 0.3, "preset": "surprise"}]}]})"},
};

}  // namespace

TEST_CASE("every body kind: a run resumed from a snapshot at frame k equals the uninterrupted run bit for bit") {
  for (const auto& [kind, text] : kScenes) {
    CAPTURE(kind);
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
    CAPTURE(kind);
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
    CAPTURE(kind);
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
  CHECK(r.error().headline().find("did you mean \"cloth\"? (one of: mass_spring, rope, net, lattice, cloth, fluid, school, fish, food, seaweed, rigid, face)") !=
        std::string::npos);
}
