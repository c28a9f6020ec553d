// reel bench: the simulation benchmarks, one JSON line per measurement (app/bench.h).
#include "app/bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/body_kinds.h"
#include "app/commands.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "core/profile.h"
#include "core/random.h"
#include "sim/cloth/cloth_body.h"
#include "sim/face/face_body.h"
#include "sim/fluid/fluid_body.h"
#include "sim/integrators.h"
#include "sim/mass_spring.h"
#include "sim/rigid/rigid_body.h"
#include "sim/row_grid.h"
#include "sim/school/school_body.h"
#include "sim/springs/generators.h"
#include "sim/world.h"

namespace reel::app {
namespace {

using Clock = std::chrono::steady_clock;

// The World of a benchmark's scene; `frames`, when given, gets the scene's frame count.
Result<World> benchWorld(const std::string& text, const char* file, int* frames = nullptr) {
  auto scene = parseScene(text, file);
  if (!scene.ok()) return scene.error();
  if (frames) *frames = scene.value().frameCount();
  return makeWorld(scene.value());
}

// The World of a benchmark's scene, advanced `frames` frames; `wall`: the time the frames took, s.
Result<World> runFrames(const std::string& text, const char* file, int frames, double& wall) {
  auto world = benchWorld(text, file);
  if (!world.ok()) return world.error();
  const auto t0 = Clock::now();
  for (int k = 0; k < frames; ++k)
    if (Status st = world.value().advanceFrame(); !st) return st.error();
  wall = std::chrono::duration<double>(Clock::now() - t0).count();
  return world;
}

}  // namespace

// Spring-network throughput: a 256 x 256 net (1 cm spacing, pinned at two corners) stepped
// under gravity with each integrator. A spring update is one evaluation of one spring's force.
void benchSprings(double seconds) {
  NetDesc net;
  net.resolution = {256, 256};
  net.size = {2.55, 2.55};
  net.mass = 65.536;  // 1 g per node
  net.structural = {100.0, 0.05};
  net.shear = {100.0, 0.05};
  net.pinned = {0, 255};
  const MassSpringDesc desc = buildNet(net);
  const double h = 2e-4;  // inside every explicit integrator's bound for this net
  for (auto name : kIntegratorNames) {
    const IntegratorKind kind = *integratorFromName(name);
    MassSpringModel model;
    MassSpringState state;
    buildMassSpring(desc, Vec3(0, -9.78, 0), model, state);
    MassSpringSystem dyn(model);
    IntegratorWorkspace ws;
    ImplicitSettings implicit;
    StepStats stats;
    double cg_iterations = 0;
    // Warm up (allocations, caches), then step until the time is spent.
    integrate(kind, dyn, state.x, state.v, h, ws, implicit, &stats);
    const std::uint64_t evals0 = dyn.springEvaluations();
    double steps = 0;
    const auto t0 = Clock::now();
    double elapsed = 0.0;
    do {
      for (int i = 0; i < 5; ++i) {
        integrate(kind, dyn, state.x, state.v, h, ws, implicit, &stats);
        cg_iterations += stats.cg_iterations;
      }
      steps += 5;
      elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    } while (elapsed < seconds);
    const double evals = static_cast<double>(dyn.springEvaluations() - evals0);
    nlohmann::ordered_json j = {
        {"name", "springs"},
        {"integrator", name},
        {"nodes", model.nodes()},
        {"springs", model.springs.size()},
        {"threads", threadCount()},
        {"steps", steps},
        {"seconds", elapsed},
        {"steps_per_s", steps / elapsed},
        {"spring_updates_per_s", evals / elapsed},
        {"spring_steps_per_s", static_cast<double>(model.springs.size()) * steps / elapsed},
    };
    if (implicitIntegrator(kind))
      j["cg_iterations_per_step"] = cg_iterations / steps;
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
}

// Cloth: a 2 m x 2 m sheet of n x n nodes dropped from 1.5 m onto a sphere of radius 0.5 m at the
// origin (the setup of docs/bench/blender_cloth.py), self-collision off and on. Wall seconds per
// simulated second of the whole World step (integration, contacts, self-collision), and spring
// updates per second. Implicit Euler runs with the conjugate gradients stopped at a relative
// residual of 1e-2 (Blender's criterion: its cloth solver stops at ‖r‖ ≤ 0.01‖b‖) and of 1e-3.
int benchCloth(double simulated_64) {
  struct Case { int n; double seconds; };
  struct Solver { std::string integrator; double tolerance; };
  for (const Case cs : {Case{64, simulated_64}, Case{128, simulated_64}, Case{256, simulated_64}})
    for (const bool self : {false, true})
      for (const Solver& solver : {Solver{"implicit_euler", 1e-2}, Solver{"implicit_euler", 1e-3}, Solver{"symplectic_euler", 0}}) {
        const std::string& integrator = solver.integrator;
        // Air drag of 1.7 per second on every node's mass (nodal drag is per node, N·s/m: an
        // interior node's mass times 1.7), the same sheet at every grid. With it the sheet falls
        // the 0.95 m to the sphere in 0.5 s, as Blender's (air viscosity 1) does.
        const double node_damping = 1.7 * 0.15 * 4.0 / ((cs.n - 1.0) * (cs.n - 1.0));
        if (integrator == "symplectic_euler" && cs.n > 64) continue;  // its step shrinks with the grid
        const std::string substeps = integrator == "implicit_euler"
                                         ? R"("substeps": 5, "implicit": {"cg_tolerance": )" + nlohmann::json(solver.tolerance).dump() +
                                               R"(, "cg_max_iterations": 200})"
                                         : R"("substeps": 10, "auto_substeps": true)";
        const std::string text = R"({"format": "reel/1", "name": "bench_cloth", "fps": 30, "duration": )" +
                                 std::to_string(cs.seconds) + ", " + substeps + R"(, "integrator": ")" + integrator + R"(",
          "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "surface": {"friction": 0.3}}],
          "bodies": [{"type": "cloth", "name": "sheet", "position": [0, 1.5, 0], "size": [2, 2],
                      "resolution": [)" + std::to_string(cs.n) + ", " + std::to_string(cs.n) + R"(], "density": 0.15,
                      "stiffness": 1000, "damping": 0.5, "shear_stiffness": 200, "shear_damping": 0.1,
                      "bend_stiffness": 0.5, "bend_damping": 0.005, "node_damping": )" + nlohmann::json(node_damping).dump() + R"(,
                      "thickness": 0.004, "self_collision": )" + (self ? "true" : "false") + "}]}";
        int scene_frames = 0;
        auto world = benchWorld(text, "bench_cloth.json", &scene_frames);
        if (!world.ok()) return report(world.error());
        World& w = world.value();
        const int frames = scene_frames;
        const auto t0 = Clock::now();
        double cg = 0;
        for (int k = 0; k < frames; ++k) {
          if (Status st = w.advanceFrame(); !st) return report(st.error());
          cg += w.lastStepStats().cg_iterations;
        }
        const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
        const auto& body = *w.first<ClothBody>();
        const SpringNetwork& b = body.network();
        const double simulated = static_cast<double>(frames) / 30.0;
        nlohmann::ordered_json j = {{"name", "cloth"},
                                    {"grid", std::to_string(cs.n) + "x" + std::to_string(cs.n)},
                                    {"nodes", b.model.nodes()},
                                    {"springs", b.model.springs.size()},
                                    {"self_collision", self},
                                    {"integrator", integrator},
                                    {"steps_per_frame", w.stepsPerFrame()},
                                    {"threads", threadCount()},
                                    {"simulated_s", simulated},
                                    {"wall_s", wall},
                                    {"wall_per_simulated_s", wall / simulated},
                                    {"spring_updates_per_s", static_cast<double>(b.system->springEvaluations()) / wall}};
        if (integrator == "implicit_euler") {
          j["cg_tolerance"] = solver.tolerance;
          j["cg_iterations_last_step"] = cg / frames;
          j["cg_spring_products_per_s"] = static_cast<double>(b.system->springProducts()) / wall;
        }
        if (self) j["self_collision_passes"] = body.cloth().self_passes;
        std::printf("%s\n", j.dump().c_str());
        std::fflush(stdout);
      }
  return 0;
}

// The divergence-free SPH model on the dam break (scenes/dam_break.json's column: 9,600 particles
// 5 mm apart falling in a 1.5 m tank, 1,200 steps a second), timed from the release for `simulated`
// seconds (at least 0.2): particle-steps per second and the pressure solver's Jacobi iterations per step.
int benchDamBreak(double simulated) {
  auto num = [](double x) { return std::to_string(x); };
  const std::string text = R"({"format": "reel/1", "name": "bench_dam_break", "fps": 60, "substeps": 20, "duration": )" +
                           num(std::max(0.2, simulated)) + R"(,
    "objects": [{"type": "container", "center": [0.74, 0.14, 0], "size": [1.52, 0.3, 0.08], "wall": 0.01, "surface": {"friction": 0.3}}],
    "bodies": [{"type": "fluid", "name": "water", "model": "dfsph", "radius": 0.0024,
      "species": [{"name": "water", "mass": 0.000125, "density": 1000, "viscosity": 1}],
      "blocks": [{"min": [0, 0, -0.03], "max": [0.1, 0.2, 0.03], "spacing": 0.005}]}]})";
  int scene_frames = 0;
  auto world = benchWorld(text, "bench_dam_break.json", &scene_frames);
  if (!world.ok()) return report(world.error());
  World& w = world.value();
  const Fluid& fl = w.first<FluidBody>()->fluid();
  const int frames = scene_frames - 1;
  const auto t0 = Clock::now();
  for (int k = 0; k < frames; ++k)
    if (Status st = w.advanceFrame(); !st) return report(st.error());
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  const double steps = static_cast<double>(frames) * w.stepsPerFrame() + static_cast<double>(fl.split_steps);
  nlohmann::ordered_json j = {{"name", "fluid_dfsph"},
                              {"particles", fl.size()},
                              {"steps", steps},
                              {"threads", threadCount()},
                              {"simulated_s", static_cast<double>(frames) / 60.0},
                              {"wall_s", wall},
                              {"particle_steps_per_s", steps * static_cast<double>(fl.size()) / wall},
                              {"pressure_iterations_per_step", static_cast<double>(fl.sph.iterations) / steps}};
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  return 0;
}

// Fluid: n³ particles (8k, 32k, 128k) in a closed box that they fill at a 2 cm spacing (a
// repulsive gas, no gravity, so every size has the same density): about 40 neighbours inside the
// 4.6 cm cutoff. Timed over the second half of the run (the first lets the jittered block relax).
// Particle-steps and pair evaluations (neighbour-list entries the force loop visits) per second;
// the cost per particle-step should stay flat as n grows.
int benchFluid(double simulated) {
  for (const int n : {20, 32, 50}) {
    const double side = n * 0.02;
    auto num = [](double x) { return std::to_string(x); };
    const std::string text = R"({"format": "reel/1", "name": "bench_fluid", "fps": 30, "duration": )" + num(simulated) +
                             R"(, "substeps": 20, "auto_substeps": true, "gravity": [0, 0, 0],
      "objects": [{"type": "container", "center": [0, )" + num(side / 2 - 0.05) + R"(, 0], "size": [)" +
                             num(side + 0.14) + ", " + num(side + 0.12) + ", " + num(side + 0.14) + R"(], "wall": 0.05},
                  {"type": "plane", "point": [0, )" + num(side + 0.01) + R"(, 0], "normal": [0, -1, 0]}],
      "bodies": [{"type": "fluid", "name": "bench", "radius": 0.009,
        "species": [{"name": "gas", "mass": 0.008, "alpha": 0, "beta": 0.01, "cutoff": 0.046, "viscosity": 10}],
        "blocks": [{"min": [)" + num(-side / 2) + R"(, 0, )" + num(-side / 2) + R"(], "max": [)" + num(side / 2) + ", " +
                             num(side) + ", " + num(side / 2) + R"(], "spacing": 0.02, "jitter": 0.3}]}]})";
    int scene_frames = 0;
    auto world = benchWorld(text, "bench_fluid.json", &scene_frames);
    if (!world.ok()) return report(world.error());
    World& w = world.value();
    // The first half settles the block (untimed); the second half is measured.
    const int frames = scene_frames / 2, settle = scene_frames - frames;
    for (int k = 0; k < settle; ++k)
      if (Status st = w.advanceFrame(); !st) return report(st.error());
    const Fluid& fl = w.first<FluidBody>()->fluid();
    const long long pairs0 = fl.pair_tests, rebuilds0 = fl.rebuilds, split0 = fl.split_steps;
    const auto t0 = Clock::now();
    for (int k = 0; k < frames; ++k)
      if (Status st = w.advanceFrame(); !st) return report(st.error());
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    // Neighbours inside the cutoff now (the list also holds the skin).
    long long inside = 0;
    for (std::size_t i = 0; i < fl.size(); ++i)
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e)
        inside += (fl.x[i] - fl.x[static_cast<std::size_t>(fl.nbr[e])]).norm() < fl.cutoff_max;
    const double steps = static_cast<double>(frames) * w.stepsPerFrame() + static_cast<double>(fl.split_steps - split0);
    const double particle_steps = steps * static_cast<double>(fl.size());
    nlohmann::ordered_json j = {{"name", "fluid"},
                                {"particles", fl.size()},
                                {"neighbours_per_particle", static_cast<double>(inside) / static_cast<double>(fl.size())},
                                {"list_entries_per_particle", static_cast<double>(fl.nbr.size()) / static_cast<double>(fl.size())},
                                {"steps", steps},
                                {"list_rebuilds", fl.rebuilds - rebuilds0},
                                {"threads", threadCount()},
                                {"simulated_s", static_cast<double>(frames) / 30.0},
                                {"wall_s", wall},
                                {"particle_steps_per_s", particle_steps / wall},
                                {"pair_evaluations_per_s", static_cast<double>(fl.pair_tests - pairs0) / wall},
                                {"ns_per_particle_step", 1e9 * wall / particle_steps}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
  return benchDamBreak(simulated);
}

// Schools of 1k, 10k and 100k agents of Couzin's model at about 20 neighbours inside the
// attraction radius (r_a = 3 m, a random box at 20 agents per (4/3)π r_a³), deciding every step
// (h = τ): agent-steps per second and the candidates the row grid hands each agent (its 9 runs).
int benchSchool(double seconds) {
  for (const long long n : {1000ll, 10000ll, 100000ll}) {
    const double ra = 3.0, side = std::cbrt(static_cast<double>(n) * (4.0 / 3.0) * 3.14159265358979 * ra * ra * ra / 20.0);
    const int steps = std::max(5, static_cast<int>(std::lround(2e6 * std::max(seconds, 0.1) / static_cast<double>(n))));
    auto num = [](double x) { return std::to_string(x); };
    const std::string text = R"({"format": "reel/1", "name": "bench_school", "fps": 10, "substeps": 1, "duration": )" +
                             num((steps + 1) / 10.0) + R"(, "bodies": [{"type": "school", "name": "s", "count": )" +
                             std::to_string(n) + R"(, "start": {"min": [0, 0, 0], "max": [)" + num(side) + ", " + num(side) + ", " +
                             num(side) + R"(]}, "zones": {"repulsion": 1, "orientation": 2, "attraction": 3}}]})";
    auto world = benchWorld(text, "bench_school.json");
    if (!world.ok()) return report(world.error());
    World& w = world.value();
    const School& sc = w.first<SchoolBody>()->school();
    // Neighbours inside r_a and the candidates the row grid hands each agent, at the start.
    RowGrid g;
    g.build(sc.x, ra);
    double neighbours = 0, candidates = 0;
    g.visitRows(0, g.rows(), [&](std::uint32_t e, std::span<const RowGrid::Run> runs) {
      const Vec3 p = sc.x[static_cast<std::size_t>(g.order()[e])];
      for (const RowGrid::Run& run : runs)
        for (std::uint32_t k = run[0]; k < run[1]; ++k) {
          candidates += 1;
          neighbours += (sc.x[static_cast<std::size_t>(g.order()[k])] - p).squaredNorm() < ra * ra;
        }
    });
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k)
      if (Status st = w.advanceFrame(); !st) return report(st.error());
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const double agent_steps = static_cast<double>(n) * steps;
    nlohmann::ordered_json j = {{"name", "school"},
                                {"agents", n},
                                {"neighbours_per_agent", neighbours / static_cast<double>(n) - 1},
                                {"candidates_per_agent", candidates / static_cast<double>(n) - 1},
                                {"steps", steps},
                                {"threads", threadCount()},
                                {"wall_s", wall},
                                {"agent_steps_per_s", agent_steps / wall},
                                {"ns_per_agent_step", 1e9 * wall / agent_steps},
                                {"ns_per_candidate", 1e9 * wall / (agent_steps * (candidates / static_cast<double>(n) - 1))}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
  return 0;
}

// Artificial fish: 10, 100 and 1,000 prey schooling in water (perception and behaviour every
// 0.1 s), at 30 fps by implicit Euler at 10 substeps as the film runs them, then by BDF2 at 6
// (a driven 1 m fish swam as far at either: 6.10 m and 6.11 m in 5 s, 6.13 m by symplectic
// Euler at 800 substeps; tests/test_fish.cpp holds each within 5%): fish-steps per second and
// how many times faster than real time.
int benchFish(double seconds) {
  struct Setting {
    const char* integrator;
    int substeps;
  };
  for (const Setting& set : {Setting{"implicit_euler", 10}, Setting{"bdf2", 6}})
  for (const long long n : {10ll, 100ll, 1000ll}) {
    const double radius = 0.6 * std::cbrt(static_cast<double>(n));  // about 5 fish per m³
    const int frames = std::max(3, static_cast<int>(std::lround(std::max(seconds, 0.1) * 3000.0 / static_cast<double>(n))));
    auto num = [](double x) { return std::to_string(x); };
    const std::string text = R"({"format": "reel/1", "name": "bench_fish", "fps": 30, "substeps": )" + std::to_string(set.substeps) +
                             R"(, "integrator": ")" + set.integrator + R"(",
        "implicit": {"cg_tolerance": 1e-4}, "duration": )" + num((frames + 1) / 30.0) +
                             R"(, "bodies": [{"type": "fish", "name": "f", "count": )" + std::to_string(n) +
                             R"(, "start": {"center": [0, 0, 0], "radius": )" + num(radius) + R"(}, "mental": {"hunger": 0}}]})";
    double wall = 0.0;
    auto world = runFrames(text, "bench_fish.json", frames, wall);
    if (!world.ok()) return report(world.error());
    World& w = world.value();
    const double fish_steps = static_cast<double>(n) * frames * w.stepsPerFrame();
    nlohmann::ordered_json j = {{"name", "fish"},
                                {"fish", n},
                                {"integrator", set.integrator},
                                {"frames", frames},
                                {"steps_per_frame", w.stepsPerFrame()},
                                {"threads", threadCount()},
                                {"wall_s", wall},
                                {"fish_steps_per_s", fish_steps / wall},
                                {"times_real_time", frames / 30.0 / wall}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
  return 0;
}

// Rigid bodies: 1,000 cubes of 0.5 m (125 kg, friction 0.5) dropped in a 10 × 10 × 10 block onto
// the ground, each turned about y, for 5 s at h = 1/120 s with 10 iterations (the pile of
// docs/bench/bullet_pile.cpp, which runs it in Bullet): steps and contact points per second, and
// how still the pile ends (its fastest box, its mean height); with sleeping and without.
int benchRigid() {
  for (const bool sleeping : {true, false}) {
  const int n = 1000, frames = 150;
  std::string bodies;
  for (int i = 0; i < n; ++i) {
    const double x = (i % 10 - 4.5) * 0.75, z = ((i / 10) % 10 - 4.5) * 0.75, y = 0.3 + (i / 100) * 0.55;
    bodies += std::string(i ? ", " : "") + R"({"type": "rigid", "name": "box)" + std::to_string(i) +
              R"(", "shape": "box", "size": [0.5, 0.5, 0.5], "surface": {"friction": 0.5}, "position": [)" +
              std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + R"(], "rotation_deg": [0, )" +
              std::to_string(7 * ((i * 37) % 13)) + ", 0]" + (sleeping ? "" : R"(, "sleep_time": 0)") + "}";
  }
  const std::string text = R"({"format": "reel/1", "name": "bench_rigid", "fps": 30, "substeps": 4, "duration": 5,
      "gravity": [0, -9.81, 0], "objects": [{"type": "plane", "name": "ground", "surface": {"friction": 0.5}}],
      "bodies": [)" + bodies + "]}";
  double wall = 0.0;
  profile::enable(true);
  auto world = runFrames(text, "bench_rigid.json", frames, wall);
  const profile::Seconds stage = profile::totals();
  profile::enable(false);
  if (!world.ok()) return report(world.error());
  World& w = world.value();
  const auto* first = w.first<RigidBody>();
  double fastest = 0.0, height = 0.0;
  for (const auto& b : w.bodies())
    if (const auto* r = dynamic_cast<const RigidBody*>(b.get()))
      for (const RigidState& s : r->states()) {
        fastest = std::max(fastest, s.v.norm());
        height += s.x.y() / n;
      }
  const double steps = static_cast<double>(frames) * w.stepsPerFrame();
  nlohmann::ordered_json j = {{"name", "rigid"},
                              {"boxes", n},
                              {"steps", steps},
                              {"threads", threadCount()},
                              {"wall_s", wall},
                              {"steps_per_s", steps / wall},
                              {"contacts_per_s", static_cast<double>(first->solverStats().contact_total) / wall},
                              {"mean_contacts", static_cast<double>(first->solverStats().contact_total) / steps},
                              {"final_max_speed", fastest},
                              {"final_mean_height", height},
                              {"asleep", first->solverStats().asleep},
                              {"sleeping", sleeping},
                              {"broad_s", stage[static_cast<std::size_t>(profile::Stage::Neighbours)]},
                              {"narrow_s", stage[static_cast<std::size_t>(profile::Stage::Contacts)]},
                              {"solver_s", stage[static_cast<std::size_t>(profile::Stage::Integration)]}};
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  }
  return 0;
}

// Articulated figures: 1, 10 and 100 humans (16 links, 33 joint degrees of freedom, servos and
// the balance controller) standing on the ground 2 m apart, for 2 s at h = 1/240 s: steps per
// second, figure-steps per second, and how many times faster than real time.
int benchArticulated() {
  for (const int n : {1, 10, 100}) {
    const int frames = 60;
    std::string bodies;
    const int row = static_cast<int>(std::ceil(std::sqrt(n)));
    for (int i = 0; i < n; ++i)
      bodies += std::string(i ? ", " : "") + R"({"type": "articulated", "name": "man)" + std::to_string(i) +
                R"(", "figure": "human", "balance": true, "surface": {"friction": 0.9}, "position": [)" +
                std::to_string(2.0 * (i % row)) + ", 0, " + std::to_string(2.0 * (i / row)) + "]}";
    const std::string text = R"({"format": "reel/1", "name": "bench_articulated", "fps": 30, "substeps": 8, "duration": 2,
        "objects": [{"type": "plane", "name": "ground", "surface": {"friction": 0.9}}], "bodies": [)" + bodies + "]}";
    double wall = 0.0;
    auto world = runFrames(text, "bench_articulated.json", frames, wall);
    if (!world.ok()) return report(world.error());
    const double steps = static_cast<double>(frames) * world.value().stepsPerFrame();
    nlohmann::ordered_json j = {{"name", "articulated"},
                                {"figures", n},
                                {"steps", steps},
                                {"threads", threadCount()},
                                {"wall_s", wall},
                                {"steps_per_s", steps / wall},
                                {"figure_steps_per_s", n * steps / wall},
                                {"times_real_time", frames / 30.0 / wall}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
  return 0;
}

// Cloth and liquid: the film's hammock (a 26 × 26 sheet held at its corners, water poured into it
// at 900 particles/s) for 2 s: steps per second, and the time of the coupling stage (the contact
// layer with the cloth–liquid hook) against the rest (the cloth and the liquid stepping): what the
// coupling adds.
int benchClothLiquid() {
  const std::string text = R"({"format": "reel/1", "name": "bench_cloth_liquid", "fps": 30, "substeps": 24, "duration": 2,
      "integrator": "implicit_euler", "implicit": {"cg_tolerance": 1e-3}, "gravity": [0, -9.81, 0],
      "objects": [{"type": "plane", "name": "floor"}],
      "bodies": [{"type": "cloth", "name": "hammock", "position": [0, 1, 0], "size": [1, 1], "resolution": [26, 26],
                  "mass": 0.25, "stiffness": 2500, "damping": 2, "shear_stiffness": 600, "bend_stiffness": 1,
                  "node_damping": 0.01, "thickness": 0.006, "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"],
                  "surface": {"friction": 0.4}},
                 {"type": "fluid", "name": "water", "radius": 0.01,
                  "species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}],
                  "emitters": [{"position": [0.05, 1.72, 0], "direction": [0, -1, 0], "speed": 1.2, "radius": 0.035,
                                "rate": 900}]}]})";
  // The coupling stage (the contact layer, here the hook of cloth and liquid) timed inside the run:
  // its share is what the coupling adds to cloth and liquid.
  profile::enable(true);
  const int frames = 60;
  double wall = 0.0;
  auto world = runFrames(text, "bench_cloth_liquid.json", frames, wall);
  const double exchange_s = profile::totals()[static_cast<std::size_t>(profile::Stage::Coupling)];
  profile::enable(false);
  if (!world.ok()) return report(world.error());
  const double steps = frames * 24.0;
  nlohmann::ordered_json j = {{"name", "cloth_liquid"},
                              {"nodes", 26 * 26},
                              {"particles_at_end", world.value().first<FluidBody>()->fluid().size()},
                              {"steps", steps},
                              {"threads", threadCount()},
                              {"wall_s", wall},
                              {"steps_per_s", steps / wall},
                              {"exchange_s", exchange_s},
                              {"coupling_overhead", exchange_s / (wall - exchange_s)}};
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  return 0;
}

// The face: reel's head at three resolutions (the default one has about 5,000 tissue nodes) going
// from neutral to surprise and back to happiness over 2 s at the film's settings (implicit Euler,
// 30 fps × 2 substeps, CG tolerance 1e-3): steps per second and how many times faster than real time.
int benchFace() {
  for (const auto& [columns, rows] : {std::pair{48, 32}, std::pair{64, 40}, std::pair{96, 64}}) {
    const std::string text = R"({"format": "reel/1", "name": "bench_face", "fps": 30, "substeps": 2, "duration": 2,
        "integrator": "implicit_euler", "implicit": {"cg_tolerance": 1e-3},
        "bodies": [{"type": "face", "name": "face", "resolution": [)" + std::to_string(columns) + ", " + std::to_string(rows) + R"(],
                    "activations": [{"time": 0, "preset": "surprise", "amount": 0}, {"time": 0.6, "preset": "surprise"},
                                    {"time": 1.4, "preset": "happiness"}]}]})";
    const int frames = 60;
    auto world = benchWorld(text, "bench_face.json");
    if (!world.ok()) return report(world.error());
    World& w = world.value();
    const FaceBody& face = *w.first<FaceBody>();
    double cg = 0, worst = 0, wall = 0;
    for (int k = 0; k < frames; ++k) {
      const auto t0 = Clock::now();
      if (Status st = w.advanceFrame(); !st) return report(st.error());
      wall += std::chrono::duration<double>(Clock::now() - t0).count();
      cg += w.lastStepStats().cg_iterations;
      worst = std::max(worst, worstVolumeChange(face.tissue(), face.network().state.x));  // (untimed)
    }
    const double steps = frames * 2.0;
    nlohmann::ordered_json j = {{"name", "face"},
                                {"tissue_nodes", 2 * face.surface().size()},
                                {"springs", face.network().model.springs.size()},
                                {"elements", face.tissue().prisms.size()},
                                {"steps", steps},
                                {"threads", threadCount()},
                                {"wall_s", wall},
                                {"steps_per_s", steps / wall},
                                {"times_real_time", frames / 30.0 / wall},
                                {"cg_iterations_last_step", cg / frames},
                                {"worst_volume_change", worst}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace reel::app
