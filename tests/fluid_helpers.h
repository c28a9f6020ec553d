// What the liquid tests share: a world from scene text, running it, its liquid, the tests' water.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/isosurface.h"
#include "helpers.h"
#include "sim/fluid/fluid_body.h"
#include "sim/world.h"

namespace reel::test {

inline World makeWorld(const std::string& text) { return worldFromText(text, "fluid.json"); }

inline const Fluid& fluid(const World& w) { return w.first<FluidBody>()->fluid(); }

// The liquid of the tests and films at 2 cm: rest distance 2 cm, cutoff 2.725 cm.
inline const char* kWater = R"({"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725,
                         "viscosity": 10, "color": [0.1, 0.35, 0.9]})";

// A field on n × n × n nodes `cell` apart from `origin`, valued value(p) at each node's point p.
template <class F>
GridField sampledField(int n, double cell, const Vec3& origin, F&& value) {
  GridField f;
  f.dims = {n, n, n};
  f.cell = cell;
  f.origin = origin;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) f.value.push_back(static_cast<float>(value(Vec3(origin + cell * Vec3(i, j, k)))));
  return f;
}

// A dam break's surge front (scenes/dam_break.json and its pair-model twin: a column a = 10 cm wide
// against the back wall x = 0): Z = z/a at each frame's T = t·√(2g/a), the front being the
// farthest particle with two neighbours closer than 8.2 mm (a droplet thrown ahead does not count);
// checks that the front only advances.
inline std::map<double, double> damBreakFront(const std::string& path) {
  auto scene = app::loadScene(path);
  REQUIRE(scene.ok());
  auto made = app::makeWorld(scene.value());
  REQUIRE(made.ok());
  World& w = made.value();
  const double a = 0.1;
  std::map<double, double> sim;  // T → Z
  for (int f = 0; f < scene.value().frameCount(); ++f) {
    REQUIRE(w.advanceFrame().ok());
    const Fluid& fl = fluid(w);
    double front = 0;
    for (std::size_t i = 0; i < fl.size(); ++i) {
      int near = 0;
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e)
        near += (fl.x[i] - fl.x[static_cast<std::size_t>(fl.nbr[e])]).norm() < 0.0082;
      if (near >= 2) front = std::max(front, fl.x[i].x());
    }
    sim[w.time() * std::sqrt(2 * 9.78 / a)] = front / a;
  }
  double prev = 0.0;
  for (const auto& [T, Z] : sim) {
    CHECK(Z >= prev - 0.05);  // the front only advances
    prev = Z;
  }
  return sim;
}

// Martin & Moyce's (1952) measured fronts (T, Z) for the column of width `inch` (1.125 or 2.25),
// from tests/data/martin_moyce_1952.csv.
inline std::vector<std::pair<double, double>> martinMoyce(double inch) {
  std::ifstream in(REEL_SOURCE_DIR "/tests/data/martin_moyce_1952.csv");
  std::vector<std::pair<double, double>> data;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    double a, T, Z;
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &a, &T, &Z) == 3 && a == inch) data.emplace_back(T, Z);
  }
  REQUIRE(data.size() >= 10);
  return data;
}

// Z of a simulated front at T, interpolated between frames.
inline double frontAt(const std::map<double, double>& sim, double T) {
  auto hi = sim.lower_bound(T), lo = std::prev(hi);
  return lo->second + (hi->second - lo->second) * (T - lo->first) / (hi->first - lo->first);
}

// The mean x of species 0's particles and of the others', m.
inline std::array<double, 2> meanXBySpecies(const Fluid& f) {
  std::array<double, 2> sum{0, 0}, count{0, 0};
  for (std::size_t i = 0; i < f.size(); ++i) {
    const std::size_t k = f.s[i] == 0 ? 0 : 1;
    sum[k] += f.x[i].x(), count[k] += 1;
  }
  return {sum[0] / count[0], sum[1] / count[1]};
}

inline std::string vec(const Vec3& p) {
  std::ostringstream o;
  o.precision(17);
  o << "[" << p.x() << "," << p.y() << "," << p.z() << "]";
  return o.str();
}

}  // namespace reel::test
