// The joint step of every rigid body of a World: the coupling stage's impulses and gravity,
// contacts between bodies and with every object, a sequential-impulse solver with warm starting,
// and islands of resting bodies that sleep.
//
// Contacts: a broad phase sorts the bodies' boxes along the axis they spread most and sweeps them (objects are tested
// box against box, a triangle mesh through its grid); the narrow phase (sim/rigid/contact.h) gives
// up to 4 points per pair, each with a feature key. Points closer than a margin that grows with
// the bodies' speed are kept as speculative contacts, so fast bodies do not tunnel.
//
// The solver is Box2D v3's soft step (Catto, "Solver2D", 2024) in 3D: the impulses of last step's
// matching points start the solve (warm starting: Catto, "Iterative Dynamics with Temporal
// Coherence", GDC 2005); the step is cut into `iterations` sub-steps, each: gravity, the warm
// start, one pass of sequential impulses over every point (the normal, with an overlap beyond the
// slop pushed out as a stiff damped spring, 60 Hz and damping ratio 10, at most 3 m/s; then Coulomb
// friction in a circle of radius μ·λ_n), the move (sim/rigid/rigid.h), and a pass without the
// push (relax) that takes back the velocity it added. Each point's separation is followed through
// the sub-steps from how far its anchors on the two bodies moved apart. Last, restitution: a point
// that was approaching faster than 0.5 m/s leaves at e times that speed. Friction μ = √(μ_a·μ_b),
// restitution e = max(e_a, e_b).
//
// Layout and threads, after Box2D v3: the sub-steps read and write one dense array of the bodies'
// velocities and inverse masses; a pair's points are one contact, solved together; contacts are
// graph-coloured (no two of a colour share a moving body), and each colour's contacts are solved
// in parallel, the colours in turn, with the same bits on any number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/body.h"
#include "sim/rigid/contact.h"
#include "sim/rigid/parts.h"

namespace reel {

class RigidBody;

// A contact point's accumulated impulses, kept for the next step's warm start: a point of the
// same bodies takes those of last step's nearest point within 2% of the smaller body's size
// (measured on body A; feature keys alone can swap between the corners of aligned faces).
struct CachedImpulse {
  std::uint32_t a = 0, b = 0, id = 0;  // bodies (b: 0x80000000 | object part) and feature key
  std::uint32_t pad = 0;               // (so that a snapshot's bytes are all defined)
  double normal = 0.0, t1 = 0.0, t2 = 0.0;  // N·s
  std::array<double, 3> anchor{};  // the point relative to A's centre of mass, in A's body frame, m
  bool operator<(const CachedImpulse& o) const {
    return a != o.a ? a < o.a : b != o.b ? b < o.b : id < o.id;
  }
};

// A pair of bodies' manifold, kept while the pair barely moves relative to itself (the idea of
// Jolt's body pair cache, Rouwé): B's pose in A's frame when it was computed, and each point as
// the two surface points it joins, on A (A's frame) and on B (B's frame). It is computed with the
// pair's speculative margin plus 2 mm, and kept while B's pose in A's frame stays within kReuse
// (1 mm, its turn counted at B's extent) of that pose and the pair's margin now, plus 1 mm, is
// still within the margin it was computed with: its points are carried by the bodies and their
// depths measured anew along the normal (which turns with A). A feature that was beyond that
// margin has come at most 1 mm closer, so it is still beyond the margin a fresh manifold would
// take now: nothing is missed.
struct CachedManifold {
  std::uint32_t a = 0, b = 0;  // bodies, as in CachedImpulse
  std::int32_t count = 0, pad = 0;
  double margin = 0;                    // m, the margin it was computed with
  std::array<double, 4> q{1, 0, 0, 0};  // B's orientation in A's frame (w, x, y, z)
  std::array<double, 3> t{};            // B's centre in A's frame, m
  std::array<double, 3> normal{};       // A's frame
  std::array<std::array<double, 3>, 4> on_a{}, on_b{};  // m
  std::array<std::uint32_t, 4> id{};
  bool operator<(const CachedManifold& o) const { return a != o.a ? a < o.a : b < o.b; }
};

struct RigidSolverCache : ObjectParts {
  std::vector<CachedImpulse> impulses;  // sorted
  std::vector<CachedManifold> manifolds;  // sorted
  // The broad phase's fattened boxes, the pairs whose fattened boxes overlap, and its order of
  // the bodies along its axis: they only spare work (the pairs found do not depend on them), so
  // they are not part of a snapshot.
  std::vector<Vec3> fat_lo, fat_hi;
  std::vector<std::array<int, 2>> candidates;
  std::vector<int> sweep_order;
};

struct RigidSolverStats {
  int contacts = 0;  // points touching or speculative, last step
  long long contact_total = 0;  // over every step so far
  int awake = 0, asleep = 0;
  int shared_colours = 0;  // colours of contacts shared between the threads, last step
};

// One step of every rigid entry (the World's RigidSystem keeps the cache and statistics).
void stepRigidBodies(std::span<RigidBody* const> entries, StepContext& ctx, RigidSolverCache& cache,
                     RigidSolverStats& stats);

}  // namespace reel
