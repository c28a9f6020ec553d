// The rigid solver's own parts (sim/rigid/solver.h is what the World calls): the bodies, contacts
// and wide contacts of one step, the buffers kept between steps, and the phases that live in
// their own files: the pairs' search (body_pairs.cpp: broad and narrow phase, kept manifolds)
// and the wide contacts' passes (wide_contacts.cpp). Only the rigid solver's files include it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/lanes.h"
#include "core/math.h"
#include "sim/body.h"
#include "sim/rigid/contact.h"
#include "sim/rigid/rigid.h"
#include "sim/rigid/solver.h"

namespace reel::rigid_detail {

constexpr double kMaxPush = 3.0;          // m/s, the fastest push out of overlap
constexpr double kContactHertz = 60.0;    // stiffness of the soft push (Box2D: 30; 60 sinks a stack less)
constexpr double kBounceSpeed = 0.5;      // m/s: slower approaches do not bounce
constexpr double kSleepSpeed = 0.05;      // m/s (and rad/s times the body's extent)
constexpr std::uint32_t kObjectBit = 0x80000000u;
constexpr int kColours = 64;              // graph colours (a bit each); more: the serial overflow
constexpr int kWideColour = 64;           // from the first colour of fewer contacts on, one thread runs them

// A body as the step's set-up sees it.
struct SolverBody {
  RigidModel* model = nullptr;
  RigidState* state = nullptr;
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};    // box grown by the margin
  double margin = 0.0;               // m
  Pose pose;
};

// A body as the sub-steps see it, one dense array of them (Box2D v3's solver bodies): what each
// contact reads and writes, in two cache lines.
struct alignas(64) Motion {
  Vec3 v{0, 0, 0}, w{0, 0, 0};
  double inv_mass = 0.0;
  Mat3 inv_inertia = Mat3::Zero();  // world, 1/(kg·m²), fixed for the step
};
// Where a body is during the sub-steps (for the points' separations).
struct Place {
  Mat3 R = Mat3::Identity();
  Vec3 x{0, 0, 0};
};

// One direction d of a point's constraint (a row of the Jacobian): B's point velocity less A's
// along d is d·(v_B − v_A) + jb·ω_B − ja·ω_A, with ja = r_A × d and jb = r_B × d; an impulse λ
// along d turns ω_A by −λ·I_A⁻¹·ja and ω_B by λ·I_B⁻¹·jb. Kept for the step, so that a pass
// takes dot products and sums, not cross products and matrix products.
struct Axis {
  Vec3 ja{0, 0, 0}, jb{0, 0, 0}, ia{0, 0, 0}, ib{0, 0, 0};  // ia = I_A⁻¹·ja, ib = I_B⁻¹·jb
  double mass = 0;  // effective mass along d, kg
};

// A manifold: the points of one pair of bodies (or a body and an object part), solved together.
struct Contact {
  int a = -1, b = -1;  // solver bodies; b = −1: an object (its surface moves at the points' vs)
  int first = 0, count = 0;  // its points
  Vec3 n{0, 1, 0}, t1{1, 0, 0}, t2{0, 0, 1};
  double mu = 0, e = 0;
};

// Wide contacts (Box2D v3's wide constraints, Catto 2024, in 3D with four doubles): four contacts
// of one colour solved at once, a lane each, their points side by side (a contact's k-th point in
// slot k; slots past a contact's points, and lanes with no contact, hold zeros, whose impulses are
// zero). The arithmetic is lane-wise IEEE: the same bits in every clone and on any number of threads.
// (L3 and its helpers: core/lanes.h.)
[[gnu::always_inline]] inline void setLane(L3& a, int l, const Vec3& v) { a.x[l] = v.x(), a.y[l] = v.y(), a.z[l] = v.z(); }
[[gnu::always_inline]] inline Vec3 lane(const L3& a, int l) { return {a.x[l], a.y[l], a.z[l]}; }

struct alignas(32) WideAxis {
  L3 ja, jb, ia, ib;  // as in Axis
  alignas(32) Lane4 mass{};
};
struct alignas(32) WidePoint {
  WideAxis n, t1, t2;
  L3 la, lb, vs;  // anchors on A and B (B's: world for an object); an object's surface velocity
  alignas(32) Lane4 base{};  // separation at the start, less the anchors' gap along n, m
  alignas(32) Lane4 slop{};  // m
  alignas(32) Lane4 ln{}, lt1{}, lt2{};  // accumulated impulses, N·s
  alignas(32) Lane4 vn0{};   // approach speed at the start, m/s
};
struct alignas(32) WideContact {
  std::array<int, 4> a{-1, -1, -1, -1}, b{-1, -1, -1, -1};  // per lane: its bodies (−1: none, or an object)
  std::array<int, 4> contact{-1, -1, -1, -1};                // per lane: its contact
  int first = 0, count = 0;  // its slots of points (the most points of its lanes)
  L3 n, t1, t2;
  alignas(32) Lane4 mu{}, e{}, ima{}, imb{};  // friction, restitution, inverse masses
};

// The soft contact of Box2D v3 (Catto, "Solver2D", 2024): a push out of overlap as a damped spring
// of `hertz` and damping ratio 10, with the mass and impulse scales that make it stable at any
// step: ω = 2π·hertz, a1 = 2ζ + hω, a2 = hω·a1, bias rate ω/a1, mass scale a2/(1 + a2), impulse
// scale 1/(1 + a2).
struct Soft {
  double bias_rate = 0, mass_scale = 1, impulse_scale = 0;
  Soft(double hertz, double zeta, double h) {
    const double w = 2.0 * kPi * hertz, a1 = 2.0 * zeta + h * w, a2 = h * w * a1, a3 = 1.0 / (1.0 + a2);
    bias_rate = w / a1;
    mass_scale = a2 * a3;
    impulse_scale = a3;
  }
};

// The step's buffers, kept from step to step on each thread so that a step allocates nothing.
struct Scratch {
  std::vector<SolverBody> bodies;
  std::vector<std::uint32_t> global;
  std::vector<Motion> motion;
  std::vector<Place> place;
  struct Sweep {
    Vec3 lo, hi;
    int body = 0;
    double strip = 0;  // which strip across the sweep
  };
  std::vector<Sweep> sweep, sorted;
  struct Pair {
    int a, b;  // b < 0: an object part
    std::uint32_t part = 0;
  };
  std::vector<Pair> pairs;
  std::vector<std::uint32_t> near;
  std::vector<Manifold> manifolds;
  std::vector<int> reused;
  std::vector<CachedManifold> next_manifolds;
  std::vector<Contact> contacts;
  std::vector<int> coloured;  // the contacts in colour order
  std::vector<WideContact> batches;
  std::vector<WidePoint> wide_points;
  std::vector<int> where;  // per contact: its batch · 4 + its lane
  std::vector<CachedImpulse> keys;
  std::vector<int> parent, colour, source;
  std::vector<double> island_rest;
  std::vector<std::uint64_t> used;
};

// One step's state shared by its phases below: the buffers, the caches, and what a phase hands on.
struct Step {
  Scratch& S;
  RigidSolverCache& cache;
  std::vector<Collider>& colliders;
  StepContext& ctx;
  RigidSolverStats& stats;
  double h = 0;        // s
  int nb = 0;          // solver bodies
  int npoints = 0;     // contact points
  int wide = 0;        // colours shared between the threads
  std::array<int, kColours + 2> start{}, bstart{};  // each colour's first contact and first batch
};

// The pairs of the step (body_pairs.cpp): the broad phase fills S.pairs; the narrow phase their
// manifolds, S.manifolds, keeping the manifolds of body pairs in the cache.
void broadPhase(Step& t);
void narrowPhase(Step& t);

// The passes over one wide contact (wide_contacts.cpp), each on the dense velocities: last
// step's impulses again; a solving pass (push: with the soft push out of overlap) against the
// bodies' places now; restitution. (The first two are compiled in clones, core/lanes.h: the
// attribute stays on their definitions, so that callers take the dispatcher.)
void warmStart(const WideContact& c, const WidePoint* pts, std::vector<Motion>& motion);
void solveContact(const WideContact& c, WidePoint* pts, std::vector<Motion>& motion,
                  const std::vector<Place>& place, double h, const Soft& soft, bool push);
void bounce(const WideContact& c, WidePoint* pts, std::vector<Motion>& motion);

}  // namespace reel::rigid_detail
