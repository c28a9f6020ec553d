// The dfsph liquid model (divergence-free SPH, Bender & Koschier 2015): the dam break against
// Martin & Moyce, a pool that stays at rest at its volume's height, buoyancy, species of two
// densities, one world with a sheet, the same bits on 1 and 2 threads, bad input.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "capture.h"
#include "core/parallel.h"
#include "fluid_helpers.h"
#include "sim/cloth/cloth.h"
#include "sim/cloth/cloth_body.h"
#include "sim/fluid/fluid_dfsph.h"
#include "sim/rigid/rigid_body.h"

using namespace reel;
using namespace reel::test;

namespace {

// Water as divergence-free SPH at `spacing` (its particles weigh 1000 kg/m³ × spacing³).
std::string sphWater(double spacing, const std::string& name = "water", double density = 1000.0) {
  return R"({"name": ")" + name + R"(", "density": )" + std::to_string(density) + R"(, "mass": )" +
         std::to_string(density * spacing * spacing * spacing) + R"(, "viscosity": 1})";
}

// The mean of the highest tenth of values.
double topTenth(std::vector<double> ys) {
  std::sort(ys.begin(), ys.end());
  double top = 0;
  for (std::size_t i = ys.size() * 9 / 10; i < ys.size(); ++i) top += ys[i] / static_cast<double>(ys.size() - ys.size() * 9 / 10);
  return top;
}

}  // namespace

TEST_CASE("dfsph: the cubic kernel integrates to one, and a wall fills half of it at its surface") {
  const double H = 0.02;
  double sum = 0.0;
  const int n = 400;
  for (int k = 0; k < n; ++k) {
    const double r = (k + 0.5) * H / n;
    sum += 4.0 * std::numbers::pi * r * r * cubicKernel(r, H) * H / n;
    // dW/dr against a central difference
    const double dr = 1e-7;
    CHECK(cubicKernelSlope(r, H) == doctest::Approx((cubicKernel(r + dr, H) - cubicKernel(r - dr, H)) / (2 * dr)).epsilon(1e-4));
  }
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-4));
  CHECK(cubicKernel(H, H) == 0.0);
  World w = makeWorld(R"({"format": "reel/1", "duration": 0.1, "bodies": [{"type": "fluid", "name": "f", "model": "dfsph",
    "species": [)" + sphWater(0.01) + R"(], "blocks": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05], "spacing": 0.01}]}]})");
  const Fluid& fl = fluid(w);
  CHECK(fl.kernel_support == doctest::Approx(0.02));
  CHECK(wallVolume(fl, -fl.wall_offset, nullptr) == doctest::Approx(0.5).epsilon(1e-4));
  CHECK(wallVolume(fl, fl.kernel_support, nullptr) == 0.0);
  // The first layer of a lattice half a spacing from a wall is at rest density.
  CHECK(fl.wall_offset > 0.05 * 0.01);
  CHECK(fl.wall_offset < 0.12 * 0.01);
}

TEST_CASE("dfsph: the dam break's front within 10% of Martin & Moyce (1952), both columns, for 1.5 ≤ T ≤ 5") {
  const std::map<double, double> sim = damBreakFront(REEL_SOURCE_DIR "/scenes/dam_break.json");
  int compared = 0;
  for (double inch : {1.125, 2.25})
    for (const auto& [T, Z] : martinMoyce(inch)) {
      if (T < 1.5 || T > 5.0) continue;
      const double z = frontAt(sim, T);
      CAPTURE_BINDING(inch);
      CAPTURE_BINDING(T);
      CAPTURE_BINDING(Z);
      CAPTURE(z);
      CHECK(z > 0.9 * Z);
      CHECK(z < 1.1 * Z);
      ++compared;
    }
  CHECK(compared == 12);
}

TEST_CASE("dfsph: a pool stays at rest at the height its volume gives, compressed by under 1%") {
  // 12 × 10 × 12 particles 1 cm apart in a tank that fits them: 10 cm deep.
  World w = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 10,
    "objects": [{"type": "container", "center": [0.06, 0.09, 0.06], "size": [0.14, 0.2, 0.14], "wall": 0.01}],
    "bodies": [{"type": "fluid", "name": "f", "model": "dfsph", "radius": 0.0048, "species": [)" + sphWater(0.01) + R"(],
      "blocks": [{"min": [0, 0, 0], "max": [0.12, 0.1, 0.12], "spacing": 0.01}]}]})");
  REQUIRE(fluid(w).size() == 1440);
  run(w, 30);
  const Fluid& fl = fluid(w);
  double vmax = 0, mean = 0, highest = 0;
  std::vector<double> ys;
  for (std::size_t i = 0; i < fl.size(); ++i) {
    vmax = std::max(vmax, fl.v[i].norm());
    ys.push_back(fl.x[i].y());
    mean += fl.sph.density[i] / static_cast<double>(fl.size());
    highest = std::max(highest, fl.sph.density[i]);
  }
  MESSAGE("largest speed " << vmax << " m/s, mean density " << mean << ", highest " << highest << ", top " << topTenth(ys));
  // The slowest sloshing left: the median particle at 0.7 cm/s, the 99th percentile at 3.3 and the
  // fastest at 4–5 (measured). The largest of 1,440 moves by a fifth with the order of the sums
  // (0.048 m/s with the hashed grid's lists, 0.050 with the row grid's, 0.040 with the force
  // loop's two passes), the percentiles by under 1%: they carry the claim, each bound about 20%
  // over what was measured, and the largest has 10% over the largest seen.
  std::vector<double> speeds;
  for (std::size_t i = 0; i < fl.size(); ++i) speeds.push_back(fl.v[i].norm());
  std::sort(speeds.begin(), speeds.end());
  const double median = speeds[speeds.size() / 2], p99 = speeds[speeds.size() * 99 / 100];
  MESSAGE("speeds: median " << median << ", 99th percentile " << p99 << " m/s");
  CHECK(median < 0.0085);
  CHECK(p99 < 0.04);
  CHECK(vmax < 0.055);
  CHECK(topTenth(ys) == doctest::Approx(0.095).epsilon(0.05));  // the top layer's centres, half a spacing down
  CHECK(mean < 1.01);
  CHECK(highest < 1.06);
}

TEST_CASE("dfsph: a light ball floats on the pool and a heavy one sinks (Archimedes, through the contact layer)") {
  // A pool 12 cm deep of 1.5 cm particles; a ball of 4 cm radius displaces 0.268 kg of water.
  auto finalHeight = [&](double mass) {
    World w = makeWorld(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 10,
      "objects": [{"type": "container", "center": [0, 0.14, 0], "size": [0.32, 0.3, 0.32], "wall": 0.01},
                  {"type": "sphere", "name": "ball", "center": [0, 0.2, 0], "radius": 0.04, "dynamic": true, "mass": )" +
                        std::to_string(mass) + R"(}],
      "bodies": [{"type": "fluid", "name": "f", "model": "dfsph", "species": [)" + sphWater(0.015) + R"(],
        "blocks": [{"min": [-0.15, 0, -0.15], "max": [0.15, 0.12, 0.15], "spacing": 0.015}]}]})");
    run(w, 60);
    std::vector<double> ys;
    for (const Vec3& p : fluid(w).x) ys.push_back(p.y());
    MESSAGE("ball of " << mass << " kg at y = " << w.colliders()[1].pose.pos.y() << ", pool surface " << topTenth(ys));
    return std::make_pair(w.colliders()[1].pose.pos.y(), topTenth(ys));
  };
  const auto [light, top] = finalHeight(0.08);  // 300 kg/m³: about 30% of it under water
  const auto [heavy, top2] = finalHeight(0.8);  // 3000 kg/m³
  CHECK(heavy < 0.04 + 0.01);                   // on the floor
  CHECK(top2 > heavy + 0.03);
  CHECK(light > top - 0.01);                    // floating, its top well out of the water
  CHECK(light < top + 0.04);                    // and its bottom in it
}

TEST_CASE("dfsph: species of two densities in one liquid: released side by side, the oil runs over the water") {
  // A lock exchange: oil (800 kg/m³) in the left half of a tank, water in the right, released at
  // once. The oil runs along the top and the water under it (Benjamin 1968: fronts at about
  // 0.5·√(g'H) = 0.24 m/s here); the oil ends above the water.
  World w = makeWorld(R"({"format": "reel/1", "duration": 1.5, "fps": 30, "substeps": 10,
    "objects": [{"type": "container", "center": [0.05, 0.14, 0.05], "size": [0.12, 0.3, 0.12], "wall": 0.01}],
    "bodies": [{"type": "fluid", "name": "f", "model": "dfsph", "radius": 0.0048,
      "species": [)" + sphWater(0.01) + "," + sphWater(0.01, "oil", 800) + R"(],
      "blocks": [{"species": "oil", "min": [0, 0, 0], "max": [0.05, 0.12, 0.1], "spacing": 0.01},
                 {"species": "water", "min": [0.05, 0, 0], "max": [0.1, 0.12, 0.1], "spacing": 0.01}]}]})");
  const Fluid& fl = fluid(w);
  REQUIRE(fl.size() == 1200);
  auto heights = [&] {
    double oil = 0, water = 0, oil_reach = 0;
    for (std::size_t i = 0; i < fl.size(); ++i) {
      (fl.s[i] == 1 ? oil : water) += fl.x[i].y() / 600.0;
      if (fl.s[i] == 1 && fl.x[i].y() > 0.09) oil_reach = std::max(oil_reach, fl.x[i].x());
    }
    return std::array<double, 3>{oil, water, oil_reach};
  };
  run(w, 10);  // 0.33 s: the oil's front has crossed most of the water's half along the top
  CHECK(heights()[2] > 0.08);
  run(w, 35);
  const auto [oil, water, reach] = heights();
  MESSAGE("mean height: oil " << oil << " m, water " << water << " m");
  CHECK(oil > water + 0.02);
}

TEST_CASE("dfsph: one world: water poured on a sheet stays on it; a rigid box thrown at it in zero gravity keeps momentum") {
  World tight = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24, "integrator": "implicit_euler",
      "bodies": [{"type": "cloth", "name": "c", "position": [0, 0, 0], "size": [0.8, 0.8], "resolution": [9, 9],
                  "mass": 0.1, "stiffness": 2000, "damping": 1, "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"]},
                 {"type": "fluid", "name": "w", "model": "dfsph", "radius": 0.009, "species": [)" + sphWater(0.02) + R"(],
                  "emitters": [{"position": [0.03, 0.6, 0.02], "direction": [0, -1, 0], "speed": 1, "radius": 0.04,
                                "spacing": 0.02, "rate": 500, "stop": 0.6}]}]})");
  run(tight, 30);
  double lowest = 1e9;
  for (const Vec3& x : tight.first<ClothBody>()->network().state.x) lowest = std::min(lowest, x.y());
  int below = 0;
  for (const Vec3& x : fluid(tight).x) below += x.y() < lowest - 0.01 && std::abs(x.x()) < 0.35 && std::abs(x.z()) < 0.35;
  CHECK(fluid(tight).size() > 200);
  CHECK(below == 0);
  // Zero gravity: a box thrown into a resting blob; liquid and box momentum kept.
  World w = makeWorld(R"({"format": "reel/1", "duration": 0.5, "fps": 30, "substeps": 24, "gravity": [0, 0, 0],
    "bodies": [{"type": "rigid", "name": "box", "shape": "box", "size": [0.06, 0.06, 0.06], "mass": 0.3,
                "position": [-0.1, 0.05, 0.05], "velocity": [2, 0, 0]},
               {"type": "fluid", "name": "f", "model": "dfsph", "species": [)" + sphWater(0.01) + R"(],
      "blocks": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1], "spacing": 0.01}]}]})");
  const RigidBody& box = *w.first<RigidBody>();
  const Vec3 p0 = momentum(fluid(w)) + box.models()[0].mass * box.states()[0].v;
  run(w, 15);
  CHECK(momentum(fluid(w)).x() > 0.1);  // the box pushed the liquid
  CHECK((momentum(fluid(w)) + box.models()[0].mass * box.states()[0].v - p0).norm() < 1e-9 * p0.norm());
}

TEST_CASE("dfsph: an absorbent sheet soaks the water up and drips it back; per-species surfaces hold one species on a ramp") {
  // A sheet hanging from one edge, a jet of 2 cm water at it (as tests/test_cloth_liquid.cpp's).
  World w = makeWorld(R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 24, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "c", "position": [0, 0, 0], "size": [0.5, 0.5], "resolution": [12, 12],
                "mass": 0.2, "stiffness": 2000, "damping": 1, "pinned": ["edge_z0"], "absorbency": 1},
               {"type": "fluid", "name": "w", "model": "dfsph", "radius": 0.0095, "species": [)" + sphWater(0.02) + R"(],
                "emitters": [{"position": [0, -0.25, 0.1], "direction": [0, 0, -1], "speed": 1.5, "radius": 0.03, "rate": 300,
                              "start": 0.8, "stop": 2}]}]})");
  run(w, 75);
  const Cloth& c = w.first<ClothBody>()->cloth();
  CHECK(c.absorbed > 10);
  CHECK(c.dripped > 0);
  const Fluid& fl = fluid(w);
  const long long emitted = fl.layers[0] * fl.emitters[0].desc.perLayer() - fl.skipped;
  CHECK(emitted == static_cast<long long>(fl.size()) + c.absorbed - c.dripped);
  // Two species on one tilted plank: the ramp is slippery for water, sticky for honey.
  World r = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24,
    "objects": [{"type": "box", "center": [0, 0, 0], "size": [2, 0.1, 0.6], "rotation_deg": [0, 0, -25],
                 "surface": {"friction": 0.0, "species": {"honey": {"friction": 1.0, "adhesion": 30}}}}],
    "bodies": [{"type": "fluid", "name": "f", "model": "dfsph", "species": [)" + sphWater(0.02) + "," + sphWater(0.02, "honey", 1000) + R"(],
      "blocks": [{"species": "water", "min": [-0.1, 0.1, -0.2], "max": [0.0, 0.16, -0.05], "spacing": 0.02},
                 {"species": "honey", "min": [-0.1, 0.1, 0.05], "max": [0.0, 0.16, 0.2], "spacing": 0.02}]}]})");
  run(r, 30);
  const auto [water, honey] = meanXBySpecies(fluid(r));
  MESSAGE("mean x: water " << water << " m, honey " << honey << " m");
  CHECK(water > 0.6);  // slid down the slope (+x is downhill)
  CHECK(honey < 0.0);  // stayed about where it landed
}

TEST_CASE("dfsph: particles pressed together are pushed apart at a bounded speed, however short the step") {
  // A block of 1 cm water at rest in zero gravity with one more particle 1 mm from a block's
  // particle (as a contact or a nozzle may leave it), stepped at 0.1 ms: the density solve takes the
  // overlap out over the kernel's reach at 20 m/s, not in one step (which flung it at tens of m/s).
  World w = makeWorld(R"({"format": "reel/1", "duration": 0.1, "fps": 30, "substeps": 300, "gravity": [0, 0, 0],
    "bodies": [{"type": "fluid", "name": "f", "model": "dfsph", "radius": 0.0045, "species": [)" + sphWater(0.01) + R"(],
      "blocks": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05], "spacing": 0.01}],
      "particles": [{"positions": [[0.026, 0.025, 0.025]]}]}]})");
  run(w, 1);
  double vmax = 0;
  for (const Vec3& v : fluid(w).v) vmax = std::max(vmax, v.norm());
  MESSAGE("fastest particle after the overlap: " << vmax << " m/s");
  CHECK(vmax > 0.05);  // they were pushed apart
  CHECK(vmax < 6.0);   // (without the bound: 32 m/s)
}

TEST_CASE("dfsph: the same bits on 1 and 2 threads (emitter, two species, a dynamic ball)") {
  const std::string text = R"({"format": "reel/1", "duration": 0.3, "fps": 30, "substeps": 12, "seed": 5,
    "objects": [{"type": "container", "center": [0, 0.1, 0], "size": [0.4, 0.2, 0.3], "wall": 0.02},
                {"type": "sphere", "name": "ball", "center": [0.05, 0.25, 0], "radius": 0.04, "dynamic": true, "mass": 0.1}],
    "bodies": [{"type": "fluid", "name": "f", "model": "dfsph", "species": [)" + sphWater(0.015) + "," + sphWater(0.015, "oil", 800) + R"(],
      "blocks": [{"min": [-0.18, 0.02, -0.13], "max": [0.0, 0.14, 0.13], "spacing": 0.015, "jitter": 0.1}],
      "emitters": [{"species": "oil", "position": [0.1, 0.3, 0], "direction": [0, -1, 0], "speed": 1, "radius": 0.03, "rate": 400}]}]})";
  std::size_t start = 0;
  auto hashWith = [&](int threads) {
    test::ParallelForTest parallel(threads);
    World w = makeWorld(text);
    start = fluid(w).size();
    run(w, 9);
    return std::make_pair(w.stateHash(), fluid(w).size());
  };
  const auto one = hashWith(1), two = hashWith(2);
  CHECK(one.first == two.first);
  CHECK(one.second == two.second);
  CHECK(start > 1024);             // more than one chunk of the solver's sums (their parallel path)
  CHECK(one.second > start + 20);  // the emitter added particles to the block's
}

TEST_CASE("dfsph: bad input is refused with its JSON path") {
  auto errors = [](const std::string& liquid) {
    return badInputErrors(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "fluid", "name": "f", )" + liquid + "}]}");
  };
  const std::string block = R"("blocks": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1], "spacing": 0.01}])";
  std::string e = errors(R"("model": "dfsph", "species": [{"name": "w", "mass": 0.001, "alpha": 10, "beta": 1}], )" + block);
  CHECK(e.find("/bodies/0/species/0/alpha") != std::string::npos);
  CHECK(e.find("/bodies/0/species/0/beta") != std::string::npos);
  CHECK(e.find("no pair force") != std::string::npos);
  e = errors(R"("species": [{"name": "w", "mass": 0.001, "density": 1000}], )" + block);
  CHECK(e.find("/bodies/0/species/0/density") != std::string::npos);
  e = errors(R"("model": "dfsph", "species": [{"name": "w", "mass": 0.001, "density": -5}], )" + block);
  CHECK(e.find("/bodies/0/species/0/density") != std::string::npos);
  e = errors(R"("model": "dfsph", "species": [{"name": "w", "mass": 0.008}], )" + block);  // 2 cm particles in a 1 cm lattice
  CHECK(e.find("/bodies/0/blocks/0/spacing") != std::string::npos);
  e = errors(R"("model": "dfsph", "species": [{"name": "w", "mass": 0.001}], "emitters": [{"position": [0, 1, 0], "rate": 100, "spacing": 0.005}])");
  CHECK(e.find("/bodies/0/emitters/0/spacing") != std::string::npos);
  e = errors(R"("model": "dfsph", "species": [{"name": "a", "mass": 0.001}, {"name": "b", "mass": 0.0001}], )" + block);
  CHECK(e.find("/bodies/0/species/1") != std::string::npos);
  CHECK(e.find("share one kernel") != std::string::npos);
  e = errors(R"("model": "sph", "species": [{"name": "w"}], )" + block);
  CHECK(e.find("/bodies/0/model") != std::string::npos);
  e = errors(R"("model": "dfsph", "species": [{"name": "a", "mass": 0.001}, {"name": "b", "mass": 0.001}],
    "interactions": [{"species": ["a", "b"], "cutoff": 0.1}], )" + block);
  CHECK(e.find("/bodies/0/interactions/0/cutoff") != std::string::npos);
}
