// Same scene, same binary: bit-identical state whatever the thread count (DESIGN 6).
#include <doctest/doctest.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include "core/parallel.h"
#include "helpers.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// A 64 x 64 net (4096 nodes, above the parallel threshold) falling onto a sphere and the floor.
std::string netScene(const std::string& integrator) {
  return R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 10, "auto_substeps": true,
    "integrator": ")" + integrator + R"(",
    "objects": [{"type": "sphere", "center": [0, -0.5, 0], "radius": 0.4},
                {"type": "plane", "point": [0, -1, 0]}],
    "bodies": [{"type": "net", "name": "net", "size": [2, 2], "resolution": [64, 64], "mass": 1,
                "stiffness": 200, "damping": 0.05, "node_damping": 0.01,
                "velocity": [0.1, 0, 0.05], "pinned": ["corner_00"]}]})";
}

}  // namespace

TEST_CASE("state is bit-identical for 1, 2 and 3 threads, for every integrator") {
  for (auto name : kIntegratorNames) {
    CAPTURE(name);
    const std::string s = netScene(std::string(name));
    const std::uint64_t h1 = runHash(s, 1, 8);
    CHECK(runHash(s, 2, 8) == h1);
    CHECK(runHash(s, 3, 8) == h1);
    CHECK(runHash(s, 1, 8) == h1);  // and run to run
  }
}

TEST_CASE("a different scene gives a different hash (the check can fail)") {
  std::string s = netScene("symplectic_euler");
  std::string t = s;
  t.replace(t.find("\"velocity\": [0.1"), 16, "\"velocity\": [0.2");
  CHECK(runHash(s, 2, 3) != runHash(t, 2, 3));
}

TEST_CASE("the determinism tests' small scenes go through the parallel paths (parallelMin lowered)") {
  // By default a loop under 2,048 elements runs on one thread, so a 1-vs-2-thread comparison of a
  // small scene compares the serial path with itself; ParallelForTest lowers the threshold.
  auto threadsUsed = [](std::ptrdiff_t n) {
    std::mutex m;
    std::set<std::thread::id> ids;
    parallelFor(n, [&](std::ptrdiff_t) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      std::lock_guard lock(m);
      ids.insert(std::this_thread::get_id());
    });
    return ids.size();
  };
  {
    const int before = threadCount();
    setThreadCount(2);
    CHECK(threadsUsed(64) == 1);  // below the default threshold: serial
    setThreadCount(before);
  }
  test::ParallelForTest parallel(2);
  CHECK(threadsUsed(64) == 2);
}

TEST_CASE("a body's step decides once: all its loops of 256 elements and more in parallel, or none") {
  REQUIRE(parallelMin() == kParallelMin);
  {
    const ParallelScope big(600);  // a 600-node sheet: its node loops too
    CHECK(parallelMin() == kScopeMin);
    {
      const ParallelScope small(100);  // nested: a small body's step runs serial
      CHECK(parallelMin() > std::ptrdiff_t{1} << 40);
      const ParallelScope none(-1);  // no decision: as it was
      CHECK(parallelMin() > std::ptrdiff_t{1} << 40);
    }
    CHECK(parallelMin() == kScopeMin);
  }
  CHECK(parallelMin() == kParallelMin);
  {
    test::ParallelForTest parallel(2);  // (the tests' threshold of 2 stays 2 in any body)
    const ParallelScope scope(3);
    CHECK(parallelMin() == 2);
  }
  // A sheet of 24 x 24 nodes (576: under the default threshold, over a quarter of it) steps in
  // parallel at the default threshold, and gives the same bits as on one thread.
  const std::string sheet = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 4, "integrator": "implicit_euler",
    "objects": [{"type": "sphere", "center": [0, -0.5, 0], "radius": 0.4}],
    "bodies": [{"type": "cloth", "name": "c", "size": [1, 1], "resolution": [24, 24]}]})";
  auto hashAt = [&](int threads) {
    const int before = threadCount();
    setThreadCount(threads);
    World w = worldFromText(sheet);
    CHECK(w.bodies()[0]->parallelWork() == 576);
    run(w, 6);
    setThreadCount(before);
    return w.stateHash();
  };
  CHECK(hashAt(1) == hashAt(2));
}

TEST_CASE("bodies that touch only their own state step side by side, with the bits of one after another") {
  // Two sheets (implicit: their solves' statistics are kept apart and merged in scene order), a
  // poured liquid, a rope, and a school between them (it reads what others show: it steps alone
  // and splits the run).
  const std::string scene = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24, "integrator": "implicit_euler",
    "objects": [{"type": "sphere", "center": [0, -0.5, 0], "radius": 0.4}, {"type": "plane", "point": [0, -1, 0]}],
    "bodies": [{"type": "cloth", "name": "a", "size": [1, 1], "resolution": [20, 20]},
               {"type": "cloth", "name": "b", "size": [1, 1], "resolution": [16, 16], "position": [2, 0, 0]},
               {"type": "fluid", "name": "w", "radius": 0.01,
                "species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}],
                "emitters": [{"position": [-2, 0.5, 0], "direction": [0, -1, 0], "speed": 1.5, "radius": 0.03, "rate": 900, "start": 0, "stop": 1}]},
               {"type": "school", "name": "s", "count": 30},
               {"type": "rope", "name": "r", "start": [3, 0.5, 0], "end": [4, 0.5, 0], "segments": 30, "stiffness": 500, "mass": 0.3},
               {"type": "cloth", "name": "c", "size": [1, 1], "resolution": [12, 12], "position": [-3, 0, 0]}]})";
  struct Run {
    std::uint64_t hash;
    long long side_by_side, unconverged;
    int cg;
    double residual, worst;
  };
  auto runAt = [&](int threads) {
    const int before = threadCount();
    setThreadCount(threads);
    World w = worldFromText(scene);
    run(w, 4);
    setThreadCount(before);
    return Run{w.stateHash(), w.sideBySideSteps(), w.unconvergedSteps(), w.lastStepStats().cg_iterations,
               w.lastStepStats().cg_relative_residual, w.worstResidual()};
  };
  const Run one = runAt(1), two = runAt(2), three = runAt(3);
  CHECK(one.side_by_side == 0);
  CHECK(two.side_by_side > 0);  // the path was taken
  CHECK(three.side_by_side > 0);
  for (const Run* r : {&two, &three}) {
    CHECK(r->hash == one.hash);
    CHECK(r->unconverged == one.unconverged);
    CHECK(r->cg == one.cg);
    CHECK(r->residual == one.residual);
    CHECK(r->worst == one.worst);
  }
}

TEST_CASE("bodies side by side report the first bad state in scene order, as one after another does") {
  // Two liquids that run away in the same step (a particle at 20 km/s) beside a sheet: the first in
  // scene order is named whichever thread finishes first.
  const std::string goo = R"("species": [{"name": "w", "mass": 0.01, "alpha": 200, "beta": 0.1, "cutoff": 0.05}],
                "particles": [{"positions": [[0, 0, 0], [0.05, 0, 0]], "velocities": [[20000, 0, 0], [0, 0, 0]]}]})";
  const std::string scene = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 1, "auto_substeps": true,
    "bodies": [{"type": "cloth", "name": "sheet", "size": [1, 1], "resolution": [12, 12], "position": [3, 0, 0]},
               {"type": "fluid", "name": "first", )" + goo + R"(,
               {"type": "fluid", "name": "second", )" + goo + "]}";
  auto errorAt = [&](int threads) {
    const int before = threadCount();
    setThreadCount(threads);
    World w = worldFromText(scene);
    Status st;
    for (int f = 0; f < 30 && st; ++f) st = w.advanceFrame();
    setThreadCount(before);
    REQUIRE(!st);
    return std::make_pair(st.error().headline(), w.sideBySideSteps());
  };
  const auto one = errorAt(1), two = errorAt(2);
  CHECK(one.first.find("body 'first'") != std::string::npos);
  CHECK(two.first == one.first);
  CHECK(two.second > 0);
}
