// What the contact tests ask of a World's bodies by name.
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "helpers.h"
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

// The same bits for 1 and 2 threads over `frames` frames, and from a snapshot taken halfway and
// restored into a new World. Returns the World that ran the whole way (for the caller's counts).
inline World sameBitsThreadsAndResume(const std::string& text, int frames) {
  const std::uint64_t h1 = runHash(text, 1, frames);
  CHECK(runHash(text, 2, frames) == h1);
  World a = worldFromText(text);
  run(a, frames / 2);
  const WorldSnapshot s = a.snapshot();
  run(a, frames - frames / 2);
  World b = worldFromText(text);
  REQUIRE(b.restore(s).ok());
  run(b, frames - frames / 2);
  CHECK(a.stateHash() == b.stateHash());
  CHECK(a.stateHash() == h1);
  return a;
}

}  // namespace reel::test
