// What the liquid tests share: a world from scene text, running it, its liquid, the tests' water.
#pragma once

#include <sstream>
#include <string>

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

inline std::string vec(const Vec3& p) {
  std::ostringstream o;
  o.precision(17);
  o << "[" << p.x() << "," << p.y() << "," << p.z() << "]";
  return o.str();
}

}  // namespace reel::test
