// A body of the scene as its entry describes it: the keys every body has (name, type, material)
// and what its kind reads (`params`, one of core/scene/<kind>.h). io reads it through the body
// kinds' readers, sim builds it through their builders (app/body_kinds.cpp lists the kinds).
#pragma once

#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "core/scene/material.h"
#include "core/scene/object.h"
#include "core/types.h"

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
  // The body's own per-species surfaces (a cloth's, for the liquids it meets), under its
  // `surface` key: each must name a species of some body.
  virtual const SpeciesSurfaces* speciesSurfaces() const { return nullptr; }
  // Objects the body is and moves (rigid bodies): the World makes a collider of each after the
  // scene's objects, draws them at their pose, and tells the builder where they start.
  virtual std::span<const ObjectDesc> ownObjects() const { return {}; }
};

// Where a group's members start (a school's agents, a body's fish): random points in a ball or a
// box, with one heading for all or random headings.
struct StartRegion {
  bool sphere = true;
  Vec3 center{0, 0, 0};
  double radius = 5.0;                 // m
  Vec3 min{-5, -5, -5}, max{5, 5, 5};  // m
  std::optional<Vec3> heading;         // unit; absent: random
  // The point of three uniforms in [0, 1): uniform in the ball or the box.
  Vec3 point(double u0, double u1, double u2) const {
    if (sphere) return center + radius * std::cbrt(u0) * sphereDirection(u1, u2);
    return min + Vec3(u0, u1, u2).cwiseProduct(max - min);
  }
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
