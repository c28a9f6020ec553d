#include "sim/rigid/solver.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/parallel.h"
#include "core/profile.h"
#include "core/union_find.h"
#include "sim/rigid/parts.h"
#include "sim/rigid/rigid_body.h"
#include "sim/rigid/solver_detail.h"

namespace reel {
namespace {

using namespace rigid_detail;

// The row of direction d at arms ra, rb (B: none for an object).
Axis axisOf(const Motion& A, const Motion* B, const Vec3& ra, const Vec3& rb, const Vec3& d) {
  Axis x;
  x.ja = ra.cross(d);
  x.ia = A.inv_inertia * x.ja;
  double k = A.inv_mass + x.ja.dot(x.ia);
  if (B) {
    x.jb = rb.cross(d);
    x.ib = B->inv_inertia * x.jb;
    k += B->inv_mass + x.jb.dot(x.ib);
  }
  x.mass = k > 0 ? 1.0 / k : 0.0;
  return x;
}

// Kinematic bodies follow their colliders; the others take gravity and what was handed them.
void gatherBodies(Step& t, std::span<RigidBody* const> entries) {
  Scratch& S = t.S;
  std::vector<Collider>& colliders = t.colliders;
  StepContext& ctx = t.ctx;
  const double h = t.h;
  std::vector<SolverBody>& bodies = S.bodies;
  std::vector<std::uint32_t>& global = S.global;  // per solver body: its index among all the World's rigid bodies
  std::vector<Motion>& motion = S.motion;
  bodies.clear(), global.clear(), motion.clear();
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
      Motion mo;
      mo.inv_mass = m.inv_mass;
      mo.inv_inertia = inverseInertia(m, s);
      if (!s.asleep) {
        s.v += m.inv_mass * J;
        s.w += mo.inv_inertia * L;
      }
      SolverBody b;
      b.model = &m;
      b.state = &s;
      b.pose = {s.q.toRotationMatrix(), s.x};
      b.margin = 0.004 + h * (s.v.norm() + s.w.norm() * m.extent);
      shapeBounds(m.shape, b.pose, b.lo, b.hi);
      b.lo -= Vec3::Constant(b.margin);
      b.hi += Vec3::Constant(b.margin);
      bodies.push_back(b);
      global.push_back(g);
      motion.push_back(mo);
    }
  }
  t.nb = static_cast<int>(bodies.size());
}

// Contacts: one per touching pair, a point per manifold point.
// (Here the contacts only; their points are filled in parallel once they are coloured.)
void contactsAndIslands(Step& t) {
  Scratch& S = t.S;
  RigidSolverCache& cache = t.cache;
  std::vector<Collider>& colliders = t.colliders;
  RigidSolverStats& stats = t.stats;
  const int nb = t.nb;
  std::vector<SolverBody>& bodies = t.S.bodies;
  std::vector<Motion>& motion = t.S.motion;
  auto& pairs = t.S.pairs;
  std::vector<Manifold>& manifolds = t.S.manifolds;
  auto& contacts = S.contacts;
  auto& keys = S.keys;
  auto& source = S.source;  // per contact: its pair
  contacts.clear(), source.clear();
  int& npoints = t.npoints;
  npoints = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Scratch::Pair& p = pairs[k];
    const Manifold& m = manifolds[k];
    if (m.count == 0) continue;
    const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
    const Surface& sa = A.model->surface;
    const Collider* object = p.b >= 0 ? nullptr : &colliders[cache.parts[p.part].collider];
    const Surface sb = p.b >= 0 ? bodies[static_cast<std::size_t>(p.b)].model->surface : object->shape->surface;
    Contact c;
    c.a = p.a;
    c.b = p.b;
    c.first = npoints;
    c.count = m.count;
    c.n = m.normal;
    c.t1 = perpendicular(c.n);
    c.t2 = c.n.cross(c.t1);
    c.mu = std::sqrt(sa.friction * sb.friction);
    c.e = std::max(sa.restitution, sb.restitution);
    contacts.push_back(c);
    source.push_back(static_cast<int>(k));
    npoints += m.count;
    // An object moving at a body's contact wakes it.
    if (object && object->moving())
      for (int i = 0; i < m.count; ++i)
        if (object->velocityAt(m.points[static_cast<std::size_t>(i)].position).norm() > kSleepSpeed)
          A.state->rest = 0.0, A.state->asleep = false;
  }
  stats.contacts = npoints;
  stats.contact_total += stats.contacts;
  keys.resize(static_cast<std::size_t>(npoints));

  // Islands: bodies joined by contacts sleep together once every one has rested long enough.
  std::vector<int>& parent = S.parent;
  parent.resize(static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) parent[static_cast<std::size_t>(i)] = i;
  for (const Contact& c : contacts)
    if (c.b >= 0) unite(parent, c.a, c.b);
  // An island sleeps when each of its bodies has rested its own sleep time (a body that never
  // sleeps keeps its island awake).
  std::vector<double>& island_rest = S.island_rest;
  island_rest.assign(static_cast<std::size_t>(nb), 1e300);
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
    motion[static_cast<std::size_t>(i)].v = s.v;
    motion[static_cast<std::size_t>(i)].w = s.w;
  }
}

// Colours (Box2D v3's constraint graph colouring, Catto 2024): contacts that share no moving
// body take the same colour, the lowest one free for both (an object takes none), so a colour's
// contacts can be solved at once on any number of threads. A colour is solved four contacts at
// a time (wide contacts) in contact order, the colours one after another; from the first colour
// of fewer than kWideColour contacts on, the colours, and one at a time the overflow past 64
// colours, run on one thread, in that order, so every thread count gives the same bits.
// Contacts of sleeping islands are left out.
void colourContacts(Step& t) {
  Scratch& S = t.S;
  RigidSolverStats& stats = t.stats;
  const int nb = t.nb;
  std::vector<SolverBody>& bodies = t.S.bodies;
  auto& contacts = t.S.contacts;
  std::vector<std::uint64_t>& used = S.used;
  used.assign(static_cast<std::size_t>(nb), 0);
  std::vector<int>& colour = S.colour;
  colour.assign(contacts.size(), -1);
  auto& start = t.start;
  start.fill(0);
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    if (bodies[static_cast<std::size_t>(c.a)].state->asleep) continue;
    std::uint64_t& ua = used[static_cast<std::size_t>(c.a)];
    const std::uint64_t taken = ua | (c.b >= 0 ? used[static_cast<std::size_t>(c.b)] : 0);
    const int col = ~taken ? std::countr_zero(~taken) : kColours;
    if (col < kColours) {
      ua |= std::uint64_t{1} << col;
      if (c.b >= 0) used[static_cast<std::size_t>(c.b)] |= std::uint64_t{1} << col;
    }
    colour[k] = col;
    ++start[static_cast<std::size_t>(col) + 1];
  }
  for (int k = 0; k <= kColours; ++k) start[static_cast<std::size_t>(k) + 1] += start[static_cast<std::size_t>(k)];
  int& wide = t.wide;  // colours [0, wide) run in parallel
  wide = 0;
  while (wide < kColours && start[static_cast<std::size_t>(wide) + 1] - start[static_cast<std::size_t>(wide)] >= kWideColour) ++wide;
  stats.shared_colours = wide;
  auto& cc = S.coloured;
  cc.resize(static_cast<std::size_t>(start[kColours + 1]));
  {
    std::array<int, kColours + 2> at = start;
    for (std::size_t k = 0; k < contacts.size(); ++k)
      if (colour[k] >= 0) cc[static_cast<std::size_t>(at[static_cast<std::size_t>(colour[k])]++)] = static_cast<int>(k);
  }
  // Batches of four (the overflow's one at a time, as they may share bodies), each contact's points
  // in slots.
  auto& batches = S.batches;
  auto& where = S.where;
  batches.clear();
  where.assign(contacts.size(), -1);
  auto& bstart = t.bstart;
  bstart.fill(0);
  int nslots = 0;
  for (int k = 0; k <= kColours; ++k) {
    bstart[static_cast<std::size_t>(k)] = static_cast<int>(batches.size());
    const int lanes = k < kColours ? 4 : 1;
    for (int i = start[static_cast<std::size_t>(k)]; i < start[static_cast<std::size_t>(k) + 1]; i += lanes) {
      WideContact w;
      w.first = nslots;
      for (int l = 0; l < lanes && i + l < start[static_cast<std::size_t>(k) + 1]; ++l) {
        const int ci = cc[static_cast<std::size_t>(i + l)];
        const Contact& c = contacts[static_cast<std::size_t>(ci)];
        w.a[static_cast<std::size_t>(l)] = c.a, w.b[static_cast<std::size_t>(l)] = c.b, w.contact[static_cast<std::size_t>(l)] = ci;
        w.count = std::max(w.count, c.count);
        where[static_cast<std::size_t>(ci)] = static_cast<int>(batches.size()) * 4 + l;
      }
      nslots += w.count;
      batches.push_back(w);
    }
  }
  bstart[kColours + 1] = static_cast<int>(batches.size());
  auto& wp = S.wide_points;
  wp.resize(static_cast<std::size_t>(nslots));
}

// Each lane's contact: directions, effective masses, anchors, and last step's impulses of the
// matching points (warm start): a point of the same bodies takes those of last step's nearest
// point within 2% of the smaller body's size (measured on body A; feature keys alone can swap
// between the corners of aligned faces). The batches in parallel.
void setUpPoints(Step& t) {
  RigidSolverCache& cache = t.cache;
  std::vector<Collider>& colliders = t.colliders;
  std::vector<SolverBody>& bodies = t.S.bodies;
  const std::vector<std::uint32_t>& global = t.S.global;
  std::vector<Motion>& motion = t.S.motion;
  auto& pairs = t.S.pairs;
  std::vector<Manifold>& manifolds = t.S.manifolds;
  auto& contacts = t.S.contacts;
  auto& keys = t.S.keys;
  auto& source = t.S.source;
  auto& batches = t.S.batches;
  auto& wp = t.S.wide_points;
  parallelBlocks(static_cast<std::ptrdiff_t>(batches.size()), 4, [&](std::ptrdiff_t b0, std::ptrdiff_t b1) {
    for (std::ptrdiff_t bi = b0; bi < b1; ++bi) {
      WideContact& w = batches[static_cast<std::size_t>(bi)];
      WidePoint* pts = &wp[static_cast<std::size_t>(w.first)];
      std::fill(pts, pts + w.count, WidePoint{});
      for (int l = 0; l < 4; ++l) {
        const int ci = w.contact[static_cast<std::size_t>(l)];
        if (ci < 0) continue;
        const Contact& c = contacts[static_cast<std::size_t>(ci)];
        const SolverBody& BA = bodies[static_cast<std::size_t>(c.a)];
        const Motion& A = motion[static_cast<std::size_t>(c.a)];
        const Motion* B = c.b >= 0 ? &motion[static_cast<std::size_t>(c.b)] : nullptr;
        const SolverBody* BB = c.b >= 0 ? &bodies[static_cast<std::size_t>(c.b)] : nullptr;
        setLane(w.n, l, c.n), setLane(w.t1, l, c.t1), setLane(w.t2, l, c.t2);
        w.mu[l] = c.mu, w.e[l] = c.e, w.ima[l] = A.inv_mass, w.imb[l] = B ? B->inv_mass : 0.0;
        const double extent = std::min(BA.model->extent, BB ? BB->model->extent : 1e300);
        const double reach = 0.02 * extent;
        const Scratch::Pair& pair = pairs[static_cast<std::size_t>(source[static_cast<std::size_t>(ci)])];
        const Manifold& mf = manifolds[static_cast<std::size_t>(source[static_cast<std::size_t>(ci)])];
        const Collider* object = BB ? nullptr : &colliders[cache.parts[pair.part].collider];
        const CachedImpulse first = {global[static_cast<std::size_t>(c.a)], BB ? global[static_cast<std::size_t>(c.b)] : (kObjectBit | pair.part), 0};
        const auto from = std::lower_bound(cache.impulses.begin(), cache.impulses.end(), first);
        for (int i = 0; i < c.count; ++i) {
          const ContactPoint& cpt = mf.points[static_cast<std::size_t>(i)];
          WidePoint& r = pts[i];
          const Vec3 ra = cpt.position - BA.state->x;
          const Vec3 rb = BB ? Vec3(cpt.position - BB->state->x) : Vec3::Zero();
          const Vec3 vs = !BB && object->moving() ? object->velocityAt(cpt.position) : Vec3::Zero();
          r.slop[l] = std::min(0.005, 0.01 * extent);
          r.base[l] = -cpt.depth;
          setLane(r.vs, l, vs);
          auto setAxis = [&](WideAxis& x, const Vec3& d) {
            const Axis a = axisOf(A, B, ra, rb, d);
            setLane(x.ja, l, a.ja), setLane(x.jb, l, a.jb), setLane(x.ia, l, a.ia), setLane(x.ib, l, a.ib);
            x.mass[l] = a.mass;
            return a;
          };
          const Axis an = setAxis(r.n, c.n);
          setAxis(r.t1, c.t1);
          setAxis(r.t2, c.t2);
          const Vec3 la = BA.pose.R.transpose() * ra;
          setLane(r.la, l, la);
          setLane(r.lb, l, BB ? Vec3(BB->pose.R.transpose() * rb) : Vec3(BA.pose.p + ra));
          CachedImpulse& key = keys[static_cast<std::size_t>(c.first + i)];
          key = first;
          key.id = cpt.id;
          key.anchor = {la.x(), la.y(), la.z()};
          const CachedImpulse* match = nullptr;
          double nearest = reach * reach;
          for (auto it = from; it != cache.impulses.end() && it->a == key.a && it->b == key.b; ++it) {
            const double d2 = (Vec3(it->anchor[0], it->anchor[1], it->anchor[2]) - la).squaredNorm();
            if (d2 < nearest || (d2 == nearest && match && it->id == key.id)) {
              nearest = d2;
              match = &*it;
            }
          }
          if (match) r.ln[l] = match->normal, r.lt1[l] = match->t1, r.lt2[l] = match->t2;
          // The approach speed at the start (restitution).
          const Vec3 vb = B ? Vec3(B->v) : vs;
          r.vn0[l] = c.n.dot(vb - A.v) + (B ? an.jb.dot(B->w) : 0.0) - an.ja.dot(A.w);
        }
      }
    }
  }, static_cast<std::ptrdiff_t>(batches.size()) * 64);
}

// Sub-steps (Box2D v3's soft step): gravity, warm start, solve with the soft push, move, relax
// without it; then restitution. One parallel region for them all: each colour is a loop that
// ends in a barrier.
void solveSubSteps(Step& t, int iterations) {
  Scratch& S = t.S;
  StepContext& ctx = t.ctx;
  const double h = t.h;
  const int nb = t.nb;
  const int npoints = t.npoints;
  const int wide = t.wide;
  const auto& bstart = t.bstart;
  std::vector<SolverBody>& bodies = t.S.bodies;
  std::vector<Motion>& motion = t.S.motion;
  auto& batches = t.S.batches;
  auto& wp = t.S.wide_points;
  std::vector<Place>& place = S.place;
  place.resize(static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) place[static_cast<std::size_t>(i)] = {bodies[static_cast<std::size_t>(i)].pose.R, bodies[static_cast<std::size_t>(i)].state->x};
  const double hs = h / iterations;
  const Soft soft(std::min(kContactHertz, 0.25 / hs), 10.0, hs);
  const int nbatch = static_cast<int>(batches.size());
  auto colours = [&](auto&& fn) {
    for (int k = 0; k < wide; ++k) {
#pragma omp for schedule(static)
      for (int i = bstart[static_cast<std::size_t>(k)]; i < bstart[static_cast<std::size_t>(k) + 1]; ++i)
        fn(batches[static_cast<std::size_t>(i)]);
    }
    if (bstart[static_cast<std::size_t>(wide)] < nbatch) {  // (the same answer on every thread)
#pragma omp single
      for (int i = bstart[static_cast<std::size_t>(wide)]; i < nbatch; ++i) fn(batches[static_cast<std::size_t>(i)]);
    }
  };
  const Vec3 gravity = ctx.gravity;
#pragma omp parallel if (npoints >= parallelMin() && wide > 0)
  for (int sub = 0; sub < iterations; ++sub) {
#pragma omp for schedule(static)
    for (int i = 0; i < nb; ++i) {
      const SolverBody& b = bodies[static_cast<std::size_t>(i)];
      if (b.state->asleep) continue;
      // Gravity, the body's own force and torque, damping (implicit, so any rate is stable).
      Motion& mo = motion[static_cast<std::size_t>(i)];
      const RigidModel& m = *b.model;
      mo.v += hs * (gravity + m.inv_mass * m.force);
      mo.w += hs * (mo.inv_inertia * m.torque);
      if (m.linear_damping > 0) mo.v /= 1.0 + hs * m.linear_damping;
      if (m.angular_damping > 0) mo.w /= 1.0 + hs * m.angular_damping;
    }
    colours([&](const WideContact& c) { warmStart(c, &wp[static_cast<std::size_t>(c.first)], motion); });
    colours([&](const WideContact& c) { solveContact(c, &wp[static_cast<std::size_t>(c.first)], motion, place, hs, soft, true); });
#pragma omp for schedule(static)
    for (int i = 0; i < nb; ++i) {
      const SolverBody& b = bodies[static_cast<std::size_t>(i)];
      RigidState& s = *b.state;
      if (s.asleep) continue;
      Motion& mo = motion[static_cast<std::size_t>(i)];
      s.x += hs * mo.v;
      s.w = mo.w;
      rotateFree(*b.model, s, hs);
      mo.w = s.w;
      place[static_cast<std::size_t>(i)] = {s.q.toRotationMatrix(), s.x};
    }
    colours([&](const WideContact& c) { solveContact(c, &wp[static_cast<std::size_t>(c.first)], motion, place, hs, soft, false); });
  }
  for (const WideContact& c : batches) bounce(c, &wp[static_cast<std::size_t>(c.first)], motion);
}

// Keep the impulses for the next step; count each body's time at rest.
// (Contacts come in the keys' order: only a manifold's own points need sorting.)
void keepForNextStep(Step& t) {
  RigidSolverCache& cache = t.cache;
  const double h = t.h;
  const int nb = t.nb;
  std::vector<SolverBody>& bodies = t.S.bodies;
  std::vector<Motion>& motion = t.S.motion;
  auto& contacts = t.S.contacts;
  auto& keys = t.S.keys;
  auto& batches = t.S.batches;
  auto& where = t.S.where;
  auto& wp = t.S.wide_points;
  cache.impulses.clear();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (where[k] < 0) continue;
    const Contact& c = contacts[k];
    const WideContact& w = batches[static_cast<std::size_t>(where[k] / 4)];
    const int l = where[k] % 4;
    for (int i = 0; i < c.count; ++i) {
      const WidePoint& p = wp[static_cast<std::size_t>(w.first + i)];
      CachedImpulse key = keys[static_cast<std::size_t>(c.first + i)];
      key.normal = p.ln[l];
      key.t1 = p.lt1[l];
      key.t2 = p.lt2[l];
      cache.impulses.push_back(key);
    }
    std::sort(cache.impulses.end() - c.count, cache.impulses.end());
  }
  if (!std::is_sorted(cache.impulses.begin(), cache.impulses.end())) std::sort(cache.impulses.begin(), cache.impulses.end());
  for (int i = 0; i < nb; ++i) {
    const SolverBody& b = bodies[static_cast<std::size_t>(i)];
    RigidState& s = *b.state;
    if (s.asleep) continue;
    s.v = motion[static_cast<std::size_t>(i)].v;
    s.w = motion[static_cast<std::size_t>(i)].w;
    const bool slow = s.v.norm() < kSleepSpeed && s.w.norm() * b.model->extent < kSleepSpeed;
    s.rest = slow ? s.rest + h : 0.0;
  }
}

}  // namespace

void stepRigidBodies(std::span<RigidBody* const> entries, StepContext& ctx, RigidSolverCache& cache,
                     RigidSolverStats& stats) {
  static thread_local Scratch scratch;
  std::vector<Collider>& colliders = *ctx.colliders;
  if (!cache.built) buildParts(colliders, cache);
  int iterations = 1;
  for (RigidBody* e : entries) iterations = std::max(iterations, e->iterations());
  Step t{scratch, cache, colliders, ctx, stats, ctx.h};
  gatherBodies(t, entries);
  {
    profile::Scope stage(profile::Stage::Neighbours);
    broadPhase(t);
  }
  {
    profile::Scope stage(profile::Stage::Contacts);
    narrowPhase(t);
  }
  {
    profile::Scope stage(profile::Stage::Integration);
    contactsAndIslands(t);
    colourContacts(t);
    setUpPoints(t);
    solveSubSteps(t, iterations);
    keepForNextStep(t);
  }
  for (RigidBody* e : entries) e->pose(colliders, ctx.h);
}

}  // namespace reel
