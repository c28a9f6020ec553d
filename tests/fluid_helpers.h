// What the liquid tests share: a world from scene text, running it, its liquid, the tests' water.
#pragma once

#include <sstream>
#include <string>

#include "helpers.h"
#include "sim/fluid/fluid_body.h"
#include "sim/world.h"

namespace reel::test {

inline World makeWorld(const std::string& text) { return worldFromText(text, "fluid.json"); }

inline const Fluid& fluid(const World& w) { return w.first<FluidBody>()->fluid(); }

// The liquid of the tests and films at 2 cm: rest distance 2 cm, cutoff 2.725 cm.
inline const char* kWater = R"({"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725,
                         "viscosity": 10, "color": [0.1, 0.35, 0.9]})";

inline std::string vec(const Vec3& p) {
  std::ostringstream o;
  o.precision(17);
  o << "[" << p.x() << "," << p.y() << "," << p.z() << "]";
  return o.str();
}

}  // namespace reel::test
