// The school kind's description: agents that move by Couzin's zonal model or Reynolds' boids, and
// the steering both share (obstacles, bounds, a goal, a predator). docs/schools.md lists the keys.
#pragma once

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/keys.h"
#include "core/mesh.h"
#include "core/scene/body.h"
#include "core/types.h"

namespace reel {

enum class SchoolModel { Couzin, Boids };

// Couzin, Krause, James, Ruxton & Franks (2002): outer radii of the three zones (m), the
// perception cone, the turning rate, the constant speed, the angular noise and the reaction time.
struct CouzinDesc {
  double r_repulsion = 1.0, r_orientation = 6.0, r_attraction = 20.0;  // m, r_r ≤ r_o ≤ r_a
  double max_turn_deg_per_s = 40.0;  // θ
  double noise = 0.05;               // σ, rad: s.d. of the spherically wrapped Gaussian turn
  double reaction_time = 0.1;        // τ, s: the model decides every τ
  // r_o changing over time (Couzin et al.'s Fig. 3, collective memory): (time s, r_o m) keys,
  // linear between them and held outside; empty: r_orientation throughout.
  std::vector<std::pair<double, double>> orientation_keys;
  double orientationAt(double t) const {
    if (orientation_keys.empty()) return r_orientation;
    using Key = std::pair<double, double>;
    return keyedLinear(orientation_keys, t, [](const Key& k) { return k.first; }, [](const Key& k) { return k.second; });
  }
};

// Reynolds (1987, 1999): three rules, each with a radius (m) and a weight, and the limits.
struct BoidsDesc {
  double separation_radius = 1.0, separation_weight = 1.5;
  double alignment_radius = 3.0, alignment_weight = 1.0;
  double cohesion_radius = 5.0, cohesion_weight = 1.0;
  double min_speed = 1.0, max_speed = 4.0;  // m/s
  double max_accel = 8.0;                   // m/s², spent in priority order
};

// A point, or a keyframed path (positions linearly between keys, held outside).
struct TargetDesc {
  struct Key {
    double time = 0.0;  // s
    Vec3 position{0, 0, 0};
  };
  std::vector<Key> keys;  // one key: a fixed point
  Vec3 at(double t) const {
    if (keys.empty()) return Vec3::Zero();
    return keyedLinear(keys, t, [](const Key& k) { return k.time; }, [](const Key& k) -> Vec3 { return k.position; });
  }
};

struct SchoolGoalDesc {
  TargetDesc target;
  // Couzin, Krause, Franks & Levin (2005): an informed agent's desired direction is
  // (d + ω ĝ)/|d + ω ĝ|; `informed` is the fraction of agents that know the goal.
  double weight = 0.5;    // ω
  double informed = 1.0;  // 0..1
};

struct SchoolPredatorDesc {
  std::string name;             // a school or an object of the scene
  bool is_school = false;       // which of the two `name` is
  double fear_radius = 5.0;     // m: agents closer than this flee
  std::string path;             // JSON path, for messages
};

// A box or a sphere the agents stay inside (they turn back within `margin` of its wall).
struct SchoolBoundsDesc {
  bool sphere = false;
  Vec3 min{-50, -50, -50}, max{50, 50, 50};  // box, m
  Vec3 center{0, 0, 0};                      // sphere, m
  double radius = 50.0;
  double margin = 3.0;  // m
};

struct SchoolAgentDesc {
  Vec3 position{0, 0, 0};
  std::optional<Vec3> heading;  // unit after reading; absent: random
  std::optional<double> speed;  // m/s; absent: the model's
};

struct SchoolDesc : BodyParams {
  SchoolModel model = SchoolModel::Couzin;
  CouzinDesc couzin;
  BoidsDesc boids;
  double speed = 3.0;                // m/s: Couzin's constant speed; boids' starting speed
  double field_of_view_deg = 270.0;  // (0, 360]: the blind cone behind is the rest

  long long count = 0;                  // random agents inside `start` (when `agents` is empty)
  std::vector<SchoolAgentDesc> agents;  // given agents
  StartRegion start;                    // where random agents start, and their heading

  // Steering both models share.
  double look_ahead = 1.0;      // s: agents see obstacles this far ahead at their speed
  double avoid_margin = 1.0;    // m: and keep this clear of their surfaces
  std::optional<SchoolBoundsDesc> bounds;
  std::optional<SchoolGoalDesc> goal;
  std::optional<SchoolPredatorDesc> predator;

  // Look.
  double length = 0.8;            // m, nose to tail
  double color_variation = 0.15;  // 0..1, per-agent tint
  std::string mesh_file;          // an imported mesh instead of reel's fish (+z forward)
  std::shared_ptr<const TriMesh> mesh;

  std::size_t agentCount() const { return agents.empty() ? static_cast<std::size_t>(count) : agents.size(); }
  // The largest distance at which an agent reacts to another, m.
  double interactionRadius() const {
    if (model == SchoolModel::Couzin) return couzin.r_attraction;
    return std::max({boids.separation_radius, boids.alignment_radius, boids.cohesion_radius});
  }
  // The fastest an agent swims, m/s.
  double maxSpeed() const { return model == SchoolModel::Couzin ? speed : boids.max_speed; }
  // How far from a surface colliders must find agents: the avoidance margin (the probes ahead are
  // points of their own), the last guard's clearance, and the fear radius of an object predator.
  double contactRadius(double) const override {
    return std::max({avoid_margin, 0.1 * length, predator && !predator->is_school ? predator->fear_radius : 0.0});
  }
};

}  // namespace reel
