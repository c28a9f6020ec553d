#include "sim/rigid/solver.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/parallel.h"
#include "sim/rigid/rigid_body.h"
#include "core/union_find.h"
#include "sim/rigid/parts.h"

namespace reel {
namespace {

constexpr double kMaxPush = 3.0;          // m/s, the fastest push out of overlap
constexpr double kContactHertz = 60.0;    // stiffness of the soft push (Box2D: 30; 60 sinks a stack less)
constexpr double kBounceSpeed = 0.5;      // m/s: slower approaches do not bounce
constexpr double kSleepSpeed = 0.05;      // m/s (and rad/s times the body's extent)
constexpr std::uint32_t kObjectBit = 0x80000000u;

// A body as the solver sees it.
struct SolverBody {
  RigidModel* model = nullptr;
  RigidState* state = nullptr;
  Mat3 inv_inertia = Mat3::Zero();  // world, 1/(kg·m²)
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};    // box grown by the margin
  double margin = 0.0;               // m
  Pose pose;
};

// A contact point as a row of the solver.
struct Row {
  int a = -1, b = -1;  // solver bodies; b = −1: an object (its surface moves at vs)
  Vec3 n{0, 1, 0}, t1{1, 0, 0}, t2{0, 0, 1};
  Vec3 ra{0, 0, 0}, rb{0, 0, 0}, vs{0, 0, 0};
  double mn = 0, mt1 = 0, mt2 = 0;  // effective masses, kg
  double depth = 0, slop = 0, mu = 0, e = 0, vn0 = 0;
  double near = 0;  // m: how far last step's point may be to warm-start this one
  double ln = 0, lt1 = 0, lt2 = 0;  // accumulated impulses, N·s
  Vec3 la{0, 0, 0}, lb{0, 0, 0};    // the point on A (body frame); on B (body frame), or world for an object
  double base = 0;                  // separation at the start, less the anchors' gap along n, m
  CachedImpulse key;
};

// The velocity of a body's point at r from its centre of mass (zero for no body).
Vec3 pointVelocity(const std::vector<SolverBody>& bodies, int i, const Vec3& r) {
  if (i < 0) return Vec3::Zero();
  const RigidState& s = *bodies[static_cast<std::size_t>(i)].state;
  return s.v + s.w.cross(r);
}

void applyImpulse(std::vector<SolverBody>& bodies, const Row& row, const Vec3& P) {
  SolverBody& A = bodies[static_cast<std::size_t>(row.a)];
  A.state->v -= A.model->inv_mass * P;
  A.state->w -= A.inv_inertia * row.ra.cross(P);
  if (row.b >= 0) {
    SolverBody& B = bodies[static_cast<std::size_t>(row.b)];
    B.state->v += B.model->inv_mass * P;
    B.state->w += B.inv_inertia * row.rb.cross(P);
  }
}

double relativeAlong(const std::vector<SolverBody>& bodies, const Row& row, const Vec3& dir) {
  const Vec3 vb = row.b >= 0 ? pointVelocity(bodies, row.b, row.rb) : row.vs;
  return (vb - pointVelocity(bodies, row.a, row.ra)).dot(dir);
}

double effectiveMass(const std::vector<SolverBody>& bodies, const Row& row, const Vec3& dir) {
  const SolverBody& A = bodies[static_cast<std::size_t>(row.a)];
  const Vec3 ca = row.ra.cross(dir);
  double k = A.model->inv_mass + ca.dot(A.inv_inertia * ca);
  if (row.b >= 0) {
    const SolverBody& B = bodies[static_cast<std::size_t>(row.b)];
    const Vec3 cb = row.rb.cross(dir);
    k += B.model->inv_mass + cb.dot(B.inv_inertia * cb);
  }
  return k > 0 ? 1.0 / k : 0.0;
}

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

// The point's separation now (negative: overlap), from how far its two anchors moved apart
// along the normal since the step began.
double separation(const std::vector<SolverBody>& bodies, const Row& r) {
  const RigidState& A = *bodies[static_cast<std::size_t>(r.a)].state;
  Vec3 d = -(A.x + A.q * r.la);
  d += r.b >= 0 ? Vec3(bodies[static_cast<std::size_t>(r.b)].state->x + bodies[static_cast<std::size_t>(r.b)].state->q * r.lb) : r.lb;
  return d.dot(r.n) + r.base;
}

// One pass over every row: the normal (a separated point may close its gap this sub-step; an
// overlap beyond the slop is pushed out softly when `push`), then friction in the circle of radius
// μ·λ_n.
void solvePass(std::vector<SolverBody>& bodies, std::vector<Row>& rows, double h, const Soft& soft, bool push) {
  for (Row& r : rows) {
    const double s = separation(bodies, r) + r.slop;
    double bias = 0.0, mass_scale = 1.0, impulse_scale = 0.0;
    if (s > 0) {
      bias = s / h;
    } else if (push) {
      bias = std::max(soft.bias_rate * s, -kMaxPush);
      mass_scale = soft.mass_scale;
      impulse_scale = soft.impulse_scale;
    }
    const double vn = relativeAlong(bodies, r, r.n);
    const double ln = std::max(0.0, r.ln - r.mn * mass_scale * (vn + bias) - impulse_scale * r.ln);
    applyImpulse(bodies, r, (ln - r.ln) * r.n);
    r.ln = ln;
    const double l1 = r.lt1 - r.mt1 * relativeAlong(bodies, r, r.t1);
    const double l2 = r.lt2 - r.mt2 * relativeAlong(bodies, r, r.t2);
    const double lim = r.mu * r.ln, len = std::sqrt(l1 * l1 + l2 * l2);
    const double scale = len > lim && len > 0 ? lim / len : 1.0;
    const double d1 = l1 * scale - r.lt1, d2 = l2 * scale - r.lt2;
    r.lt1 += d1;
    r.lt2 += d2;
    applyImpulse(bodies, r, d1 * r.t1 + d2 * r.t2);
  }
}

}  // namespace

void stepRigidBodies(std::span<RigidBody* const> entries, StepContext& ctx, RigidSolverCache& cache,
                     RigidSolverStats& stats) {
  std::vector<Collider>& colliders = *ctx.colliders;
  const double h = ctx.h;
  if (!cache.built) buildParts(colliders, cache);
  int iterations = 1;
  for (RigidBody* e : entries) {
    iterations = std::max(iterations, e->iterations());
  }
  // Kinematic bodies follow their colliders; the others take gravity and what was handed them.
  std::vector<SolverBody> bodies;
  std::vector<std::uint32_t> global;  // per solver body: its index among all the World's rigid bodies
  std::uint32_t g = 0;
  for (RigidBody* e : entries) {
    e->follow(colliders);
    auto& states = e->states();
    for (std::size_t i = 0; i < states.size(); ++i, ++g) {
      RigidModel& m = const_cast<RigidModel&>(e->models()[i]);
      if (m.kinematic) continue;
      RigidState& s = states[i];
      const std::size_t c = m.collider;
      const Vec3 J = ctx.coupling->impulse[c];
      const Vec3 L = ctx.coupling->angular[c] + (colliders[c].pose.pos - s.x).cross(J);
      const double wake = 1e-3 * m.mass * kSleepSpeed;  // N·s: a push that would move it a little
      if (s.asleep && (J.norm() > wake || L.norm() > wake * m.extent)) s.asleep = false, s.rest = 0.0;
      SolverBody b;
      b.model = &m;
      b.state = &s;
      b.inv_inertia = inverseInertia(m, s);
      if (!s.asleep) {
        s.v += m.inv_mass * J;
        s.w += b.inv_inertia * L;
      }
      b.pose = {s.q.toRotationMatrix(), s.x};
      b.margin = 0.004 + h * (s.v.norm() + s.w.norm() * m.extent);
      shapeBounds(m.shape, b.pose, b.lo, b.hi);
      b.lo -= Vec3::Constant(b.margin);
      b.hi += Vec3::Constant(b.margin);
      bodies.push_back(b);
      global.push_back(g);
    }
  }
  const int nb = static_cast<int>(bodies.size());

  // Broad phase: body pairs by sweeping boxes sorted along an axis; each body's object parts.
  struct Pair {
    int a, b;           // b < 0: object part −b − 1
    std::uint32_t part = 0;
  };
  std::vector<Pair> pairs;
  std::vector<int> order(static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) order[static_cast<std::size_t>(i)] = i;
  // Along the axis the bodies spread most (a tall stack is swept along y).
  Vec3 spread_lo = Vec3::Constant(1e300), spread_hi = Vec3::Constant(-1e300);
  for (const SolverBody& b : bodies) {
    spread_lo = spread_lo.cwiseMin(b.lo);
    spread_hi = spread_hi.cwiseMax(b.lo);
  }
  int axis = 0;
  (spread_hi - spread_lo).maxCoeff(&axis);
  std::sort(order.begin(), order.end(), [&](int p, int q) {
    const double a = bodies[static_cast<std::size_t>(p)].lo[axis], b = bodies[static_cast<std::size_t>(q)].lo[axis];
    return a != b ? a < b : p < q;
  });
  for (std::size_t oi = 0; oi < order.size(); ++oi) {
    const SolverBody& A = bodies[static_cast<std::size_t>(order[oi])];
    for (std::size_t oj = oi + 1; oj < order.size(); ++oj) {
      const SolverBody& B = bodies[static_cast<std::size_t>(order[oj])];
      if (B.lo[axis] > A.hi[axis]) break;
      if (A.state->asleep && B.state->asleep) continue;
      if (!overlaps(A.lo, A.hi, B.lo, B.hi)) continue;
      pairs.push_back({std::min(order[oi], order[oj]), std::max(order[oi], order[oj])});
    }
  }
  std::vector<std::uint32_t> near;
  // A sleeping body meets only moving objects (which may wake it).
  for (int i = 0; i < nb; ++i) {
    const SolverBody& A = bodies[static_cast<std::size_t>(i)];
    partsNear(cache, colliders, A.lo, A.hi, near);
    for (std::uint32_t p : near)
      if (!A.state->asleep || colliders[cache.parts[p].collider].moving()) pairs.push_back({i, -1, p});
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& p, const Pair& q) {
    return p.a != q.a ? p.a < q.a : p.b != q.b ? p.b < q.b : p.part < q.part;
  });

  // Narrow phase, in parallel: each pair writes its own manifold.
  std::vector<Manifold> manifolds(pairs.size());
  parallelFor(static_cast<std::ptrdiff_t>(pairs.size()), [&](std::ptrdiff_t k) {
    const Pair& p = pairs[static_cast<std::size_t>(k)];
    const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
    Manifold& m = manifolds[static_cast<std::size_t>(k)];
    if (p.b >= 0) {
      const SolverBody& B = bodies[static_cast<std::size_t>(p.b)];
      collide(A.model->shape, A.pose, B.model->shape, B.pose, A.margin + B.margin, m);
    } else {
      const ObjectPart& part = cache.parts[p.part];
      collidePart(A.model->shape, A.pose, part, colliders[part.collider], A.margin, m);
    }
  });

  // Rows: one per point, warm-started from last step's matching point.
  std::vector<Row> rows;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Pair& p = pairs[k];
    const Manifold& m = manifolds[k];
    const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
    const Surface& sa = A.model->surface;
    const Surface sb = p.b >= 0 ? bodies[static_cast<std::size_t>(p.b)].model->surface
                                : colliders[cache.parts[p.part].collider].shape->surface;
    const double extent = std::min(A.model->extent, p.b >= 0 ? bodies[static_cast<std::size_t>(p.b)].model->extent : 1e300);
    for (int i = 0; i < m.count; ++i) {
      const ContactPoint& cp = m.points[static_cast<std::size_t>(i)];
      Row r;
      r.a = p.a;
      r.b = p.b;
      r.n = m.normal;
      r.t1 = perpendicular(r.n);
      r.t2 = r.n.cross(r.t1);
      r.ra = cp.position - A.state->x;
      if (p.b >= 0) r.rb = cp.position - bodies[static_cast<std::size_t>(p.b)].state->x;
      else if (colliders[cache.parts[p.part].collider].moving()) r.vs = colliders[cache.parts[p.part].collider].velocityAt(cp.position);
      r.depth = cp.depth;
      r.slop = std::min(0.005, 0.01 * extent);
      r.near = 0.02 * extent;
      r.mu = std::sqrt(sa.friction * sb.friction);
      r.e = std::max(sa.restitution, sb.restitution);
      r.key = {global[static_cast<std::size_t>(p.a)], p.b >= 0 ? global[static_cast<std::size_t>(p.b)] : (kObjectBit | p.part), cp.id};
      rows.push_back(r);
    }
  }
  stats.contacts = static_cast<int>(rows.size());
  stats.contact_total += stats.contacts;

  // An object moving at a body's contact wakes it.
  for (const Row& r : rows) {
    RigidState& s = *bodies[static_cast<std::size_t>(r.a)].state;
    if (r.b < 0 && r.vs.norm() > kSleepSpeed) s.rest = 0.0, s.asleep = false;
  }
  // Islands: bodies joined by contacts sleep together once every one has rested long enough.
  std::vector<int> parent(static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) parent[static_cast<std::size_t>(i)] = i;
  for (const Row& r : rows)
    if (r.b >= 0) unite(parent, r.a, r.b);
  // An island sleeps when each of its bodies has rested its own sleep time (a body that never
  // sleeps keeps its island awake).
  std::vector<double> island_rest(static_cast<std::size_t>(nb), 1e300);
  for (int i = 0; i < nb; ++i) {
    const SolverBody& b = bodies[static_cast<std::size_t>(i)];
    const double spare = b.model->sleep_time <= 0 ? -1e300 : b.state->asleep ? 1e300 : b.state->rest - b.model->sleep_time;
    double& ir = island_rest[static_cast<std::size_t>(findRoot(parent, i))];
    ir = std::min(ir, spare);
  }
  stats.awake = stats.asleep = 0;
  for (int i = 0; i < nb; ++i) {
    RigidState& s = *bodies[static_cast<std::size_t>(i)].state;
    const double ir = island_rest[static_cast<std::size_t>(findRoot(parent, i))];
    const bool sleep = ir >= 0;
    if (sleep && !s.asleep) s.v = s.w = Vec3::Zero();
    if (!sleep && s.asleep) s.rest = 0.0;
    s.asleep = sleep;
    ++(sleep ? stats.asleep : stats.awake);
  }
  std::erase_if(rows, [&](const Row& r) { return bodies[static_cast<std::size_t>(r.a)].state->asleep; });

  // Effective masses, anchors, and last step's impulses of the matching points (warm start).
  for (Row& r : rows) {
    const SolverBody& A = bodies[static_cast<std::size_t>(r.a)];
    r.mn = effectiveMass(bodies, r, r.n);
    r.mt1 = effectiveMass(bodies, r, r.t1);
    r.mt2 = effectiveMass(bodies, r, r.t2);
    const Vec3 p = A.state->x + r.ra;
    r.la = A.state->q.conjugate() * r.ra;
    r.lb = r.b >= 0 ? Vec3(bodies[static_cast<std::size_t>(r.b)].state->q.conjugate() * r.rb) : p;
    r.base = -r.depth;
    const Vec3 anchor = r.la;
    r.key.anchor = {anchor.x(), anchor.y(), anchor.z()};
    const CachedImpulse* match = nullptr;
    double nearest = r.near * r.near;
    CachedImpulse first = r.key;
    first.id = 0;
    for (auto it = std::lower_bound(cache.impulses.begin(), cache.impulses.end(), first);
         it != cache.impulses.end() && it->a == r.key.a && it->b == r.key.b; ++it) {
      const double d2 = (Vec3(it->anchor[0], it->anchor[1], it->anchor[2]) - anchor).squaredNorm();
      if (d2 < nearest || (d2 == nearest && match && it->id == r.key.id)) {
        nearest = d2;
        match = &*it;
      }
    }
    if (match) {
      r.ln = match->normal;
      r.lt1 = match->t1;
      r.lt2 = match->t2;
    }
  }
  for (Row& r : rows) r.vn0 = relativeAlong(bodies, r, r.n);
  // Sub-steps (Box2D v3's soft step): gravity, warm start, solve with the soft push, move, relax
  // without it; then restitution.
  const double hs = h / iterations;
  const Soft soft(std::min(kContactHertz, 0.25 / hs), 10.0, hs);
  for (int sub = 0; sub < iterations; ++sub) {
    for (SolverBody& b : bodies)
      if (!b.state->asleep) {
        // Gravity, the body's own force and torque, damping (implicit, so any rate is stable).
        RigidState& st = *b.state;
        const RigidModel& m = *b.model;
        st.v += hs * (ctx.gravity + m.inv_mass * m.force);
        st.w += hs * (b.inv_inertia * m.torque);
        if (m.linear_damping > 0) st.v /= 1.0 + hs * m.linear_damping;
        if (m.angular_damping > 0) st.w /= 1.0 + hs * m.angular_damping;
      }
    for (const Row& r : rows) applyImpulse(bodies, r, r.ln * r.n + r.lt1 * r.t1 + r.lt2 * r.t2);
    solvePass(bodies, rows, hs, soft, true);
    for (SolverBody& b : bodies) {
      RigidState& s = *b.state;
      if (s.asleep) continue;
      s.x += hs * s.v;
      rotateFree(*b.model, s, hs);
    }
    solvePass(bodies, rows, hs, soft, false);
  }
  for (Row& r : rows) {
    if (r.e <= 0 || r.vn0 > -kBounceSpeed || r.ln <= 0) continue;
    const double ln = std::max(0.0, r.ln - r.mn * (relativeAlong(bodies, r, r.n) + r.e * r.vn0));
    applyImpulse(bodies, r, (ln - r.ln) * r.n);
    r.ln = ln;
  }
  // Keep the impulses for the next step; count rest; pose the colliders.
  cache.impulses.clear();
  for (const Row& r : rows) {
    CachedImpulse c = r.key;
    c.normal = r.ln;
    c.t1 = r.lt1;
    c.t2 = r.lt2;
    cache.impulses.push_back(c);
  }
  std::sort(cache.impulses.begin(), cache.impulses.end());
  for (SolverBody& b : bodies) {
    RigidState& s = *b.state;
    if (s.asleep) continue;
    const bool slow = s.v.norm() < kSleepSpeed && s.w.norm() * b.model->extent < kSleepSpeed;
    s.rest = slow ? s.rest + h : 0.0;
  }
  for (RigidBody* e : entries) e->pose(colliders, h);
}

}  // namespace reel
