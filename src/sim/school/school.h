// Schools of fish (flocks, herds): agents that each see their neighbours and steer, by Couzin's
// zonal model or Reynolds' boids, plus the steering both share (obstacles, bounds, a goal, a
// predator). The behavioural layer that the artificial fish will school with.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/scene/school.h"
#include "core/types.h"
#include "sim/collide.h"
#include "sim/shared_view.h"
#include "sim/row_grid.h"

namespace reel {

// What the scene fixes: the description and what was drawn from the seed at the start.
struct SchoolModelData {
  std::string name;
  SchoolDesc desc;
  std::uint64_t seed = 0;
  std::vector<double> speed;          // Couzin: each agent's constant speed, m/s
  std::vector<std::uint8_t> informed;  // 1: knows the goal
  std::vector<float> tint;             // rgb per agent, multiplies the material colour
};

// What a step changes (snapshots hold exactly this).
struct SchoolState {
  std::vector<Vec3> x;        // positions, m
  std::vector<Vec3> v;        // velocities, m/s (never zero)
  std::vector<Vec3> desired;  // Couzin: the direction chosen at the last decision (unit)
  std::vector<double> turn;   // Couzin: the turning rate until the next decision, in units of θ
  std::vector<double> phase;  // tail beat phase, rad (drawing)
  std::int64_t decisions = 0; // Couzin: decisions taken (the noise's stream position)
};

// Per-step scratch: the agents sorted into the rows of a RowGrid (sim/row_grid.h) at the
// perception radius, and their headings in that order, padded with four more entries so that a
// loop may read a whole group of four past a run's end.
struct SortedHeadings {
  std::vector<double> ux, uy, uz;  // unit headings (Couzin) or velocities (boids)
};
struct SchoolScratch {
  RowGrid rows;
  SortedHeadings sorted;
  std::vector<Vec3> social;  // Couzin: each agent's direction from its neighbours (unit)
  std::vector<Vec3> steer;   // boids: each agent's acceleration, m/s²
};

// What a school sees of the other bodies: where its predator is (the points of a school or an
// object's collider), and the points of every body that has them, to steer around.
struct SchoolView {
  const std::vector<Vec3>* points = nullptr;  // a school's agents
  const std::vector<Vec3>* velocities = nullptr;  // and their velocities
  const Collider* object = nullptr;           // or an object
  const BodyPoints* bodies = nullptr;         // other bodies' points (sim/shared_view.h)
};

struct School : SchoolModelData, SchoolState, SchoolScratch {
  std::size_t size() const { return x.size(); }
};

// Steering both models share (and the artificial fish): what the surroundings ask of an agent.
struct Steering {
  Vec3 push{0, 0, 0};  // away from walls and obstacles (sum of unit normals times urgency)
  double avoid = 0.0;  // the most urgent of them, 0..1
  Vec3 away{0, 0, 0};  // unit, from the nearest predator
  double fear = 0.0;   // 0..1
  Vec3 goal{0, 0, 0};  // unit toward the goal (informed agents), or zero
};
// Obstacles within `margin` of probes at x, x + ahead/2 and x + ahead push the agent away.
void avoidObstacles(const std::vector<Collider>& cs, const Vec3& x, const Vec3& ahead, double margin, Steering& s);
// The same for other bodies' points (nodes, particles) within `margin` of their surfaces.
void avoidPoints(const BodyPoints& b, const Vec3& x, const Vec3& ahead, double margin, Steering& s);
// The walls of a bounding box or sphere within its margin push the agent back in.
void containBounds(const SchoolBoundsDesc& b, const Vec3& p, Steering& s);

// Builds the agents from the description (random ones from `seed`).
School makeSchool(const SchoolDesc& d, const std::string& name, std::uint64_t seed);

// Advances the school from t0 to t0 + h against the colliders at their pose at t0 + h.
void stepSchool(School& s, const std::vector<Collider>& colliders, const SchoolView& predator, double t0,
                double h);

// Collective order (Couzin et al. 2002): polarisation p = |Σ v̂_i|/N, milling m = |Σ r̂_ic × v̂_i|/N
// with r̂_ic the unit vector from the centroid to agent i, the centroid, and the mean distance to
// the nearest neighbour.
struct SchoolOrder {
  double polarization = 0.0, milling = 0.0;
  Vec3 centroid{0, 0, 0};
  double nearest = 0.0;  // m
};
SchoolOrder schoolOrder(const std::vector<Vec3>& x, const std::vector<Vec3>& v);

// One decision of Couzin's model for agent i, without noise and steering (tests, docs): the
// desired direction from the neighbours `nx`, `nv` (positions, velocities; i itself excluded).
Vec3 couzinDirection(const CouzinDesc& c, double field_of_view_deg, const Vec3& xi, const Vec3& vi,
                     const std::vector<Vec3>& nx, const std::vector<Vec3>& nv);

// Turns unit vector `from` toward unit vector `to` by at most `max_angle` radians.
Vec3 turnToward(const Vec3& from, const Vec3& to, double max_angle);
// The same with the cosine and sine of the largest angle given.
Vec3 turnToward(const Vec3& from, const Vec3& to, double cos_max, double sin_max);

}  // namespace reel
