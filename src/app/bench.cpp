// reel bench: one JSON line per measurement (DESIGN 8).
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "core/parallel.h"
#include "sim/builders.h"
#include "sim/integrators.h"
#include "sim/mass_spring.h"

namespace reel::app {
namespace {

using Clock = std::chrono::steady_clock;

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
    MassSpringDynamics dyn(model);
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
    if (kind == IntegratorKind::ImplicitEuler)
      j["cg_iterations_per_step"] = cg_iterations / steps;
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
}

}  // namespace

int bench(const std::vector<std::string>& names, double seconds) {
  const std::vector<std::string> all = {"springs"};
  const std::vector<std::string>& run = names.empty() ? all : names;
  for (const auto& n : run) {
    if (n != "springs") {
      std::fprintf(stderr, "reel: unknown benchmark \"%s\" (available: springs)\n", n.c_str());
      return 2;
    }
  }
  for (const auto& n : run)
    if (n == "springs") benchSprings(seconds);
  return 0;
}

}  // namespace reel::app
