// A body of the scene as its entry describes it: the keys every body has (name, type, material)
// and what its kind reads (`params`, one of core/scene/<kind>.h). io reads it through the body
// kinds' readers, sim builds it through their builders (app/body_kinds.cpp lists the kinds).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/scene/material.h"

namespace reel {

// What a body kind reads from its scene entry. The questions here are the ones the loader and the
// world ask of every body before any is built.
struct BodyParams {
  virtual ~BodyParams() = default;
  // Nodes and springs the body will have, for the scene's limits (0, 0: counted otherwise).
  virtual std::pair<long long, long long> nodesAndSprings() const { return {0, 0}; }
  // How close the body's points come to a surface (colliders find points this far), m.
  virtual double contactRadius(double node_radius) const { return node_radius; }
  // How far beyond contact a sticky surface pulls the body's points, m (liquids: their cutoff).
  virtual double adhesionRange() const { return 0.0; }
  // Species an object's per-species surface may name (liquids).
  virtual std::vector<std::string> speciesNames() const { return {}; }
};

struct BodyDesc {
  std::string name, type, path;  // type: the kind's scene name; path: JSON path, e.g. /bodies/0
  std::shared_ptr<const BodyParams> params;  // the kind's own description
  Material material;
  double node_radius = 0.02;  // m, for drawing nodes
  // The kind's description, as the type its reader made.
  template <class T>
  const T& as() const { return dynamic_cast<const T&>(*params); }
};

}  // namespace reel
