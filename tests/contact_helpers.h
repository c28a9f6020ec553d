// What the contact tests ask of a World's bodies by name.
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "sim/world.h"

namespace reel::test {

inline const Body& bodyNamed(const World& w, const std::string& name) {
  for (const auto& b : w.bodies())
    if (b->name() == name) return *b;
  throw std::runtime_error("no body " + name);
}

// The points of a body as a dump shows them.
inline BodyView viewOf(const World& w, const std::string& name) {
  BodyView v;
  REQUIRE(bodyNamed(w, name).view(v));
  return v;
}

// The lowest of its points, m.
inline double lowest(const World& w, const std::string& name) {
  double y = 1e300;
  for (const Vec3& p : viewOf(w, name).positions) y = std::min(y, p.y());
  return y;
}

}  // namespace reel::test
