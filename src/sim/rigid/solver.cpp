#include "sim/rigid/solver.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/math.h"
#include "core/lanes.h"
#include "core/parallel.h"
#include "core/profile.h"
#include "core/union_find.h"
#include "sim/rigid/parts.h"
#include "sim/rigid/rigid_body.h"

namespace reel {
namespace {

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
// (Helpers that take and return four lanes are always inlined into the clones that call them:
// no call passes a vector across the ABI, whatever the -Wpsabi note says.)
// Four lanes are 32-byte aligned where AVX is on and 16 where it is not: every structure that holds
// them in memory is aligned to 32, so that both clones agree on where they lie.
#pragma GCC diagnostic ignored "-Wpsabi"  // (for the file: GCC reports it at the file's end)
struct alignas(32) L3 {
  alignas(32) Lane4 x{}, y{}, z{};
};
[[gnu::always_inline]] inline Lane4 dot(const L3& a, const L3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
[[gnu::always_inline]] inline L3 operator+(const L3& a, const L3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[gnu::always_inline]] inline L3 operator-(const L3& a, const L3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[gnu::always_inline]] inline L3 operator*(const Lane4& k, const L3& a) { return {k * a.x, k * a.y, k * a.z}; }
[[gnu::always_inline]] inline void setLane(L3& a, int l, const Vec3& v) { a.x[l] = v.x(), a.y[l] = v.y(), a.z[l] = v.z(); }
[[gnu::always_inline]] inline Vec3 lane(const L3& a, int l) { return {a.x[l], a.y[l], a.z[l]}; }
[[gnu::always_inline]] inline Lane4 splat(double v) { return Lane4{v, v, v, v}; }

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

// The four lanes' body velocities, gathered from the dense array and scattered back.
struct alignas(32) WideMotion {
  L3 va, wa, vb, wb;
  [[gnu::always_inline]] WideMotion(const WideContact& c, const std::vector<Motion>& motion) {
    for (int l = 0; l < 4; ++l) {
      if (c.a[static_cast<std::size_t>(l)] >= 0) {
        const Motion& A = motion[static_cast<std::size_t>(c.a[static_cast<std::size_t>(l)])];
        setLane(va, l, A.v), setLane(wa, l, A.w);
      }
      if (c.b[static_cast<std::size_t>(l)] >= 0) {
        const Motion& B = motion[static_cast<std::size_t>(c.b[static_cast<std::size_t>(l)])];
        setLane(vb, l, B.v), setLane(wb, l, B.w);
      }
    }
  }
  [[gnu::always_inline]] void store(const WideContact& c, std::vector<Motion>& motion) const {
    for (int l = 0; l < 4; ++l) {
      if (c.a[static_cast<std::size_t>(l)] >= 0) {
        Motion& A = motion[static_cast<std::size_t>(c.a[static_cast<std::size_t>(l)])];
        A.v = lane(va, l), A.w = lane(wa, l);
      }
      if (c.b[static_cast<std::size_t>(l)] >= 0) {
        Motion& B = motion[static_cast<std::size_t>(c.b[static_cast<std::size_t>(l)])];
        B.v = lane(vb, l), B.w = lane(wb, l);
      }
    }
  }
  // B's point velocity less A's along d (an object's surface moves at vs; B's terms are zero).
  [[gnu::always_inline]] Lane4 along(const WidePoint& p, const WideAxis& x, const L3& d) const {
    return dot(d, vb + p.vs - va) + dot(x.jb, wb) - dot(x.ja, wa);
  }
  // Impulses l1 along d1 and l2 along d2 on B (A takes the opposite).
  [[gnu::always_inline]] void apply(const WideContact& c, const WideAxis& x1, const L3& d1, const Lane4& l1,
                                    const WideAxis& x2, const L3& d2, const Lane4& l2) {
    const L3 P = l1 * d1 + l2 * d2;
    va = va - c.ima * P, wa = wa - (l1 * x1.ia + l2 * x2.ia);
    vb = vb + c.imb * P, wb = wb + (l1 * x1.ib + l2 * x2.ib);
  }
  [[gnu::always_inline]] void apply(const WideContact& c, const WideAxis& x, const L3& d, const Lane4& l) {
    va = va - (c.ima * l) * d, wa = wa - l * x.ia;
    vb = vb + (c.imb * l) * d, wb = wb + l * x.ib;
  }
};

// The four lanes' bodies' rotations and centres now (an object: the identity and zero, its
// anchor being in the world already).
struct alignas(32) WidePlace {
  std::array<L3, 3> ra, rb;  // rows
  L3 xa, xb;
  [[gnu::always_inline]] WidePlace(const WideContact& c, const std::vector<Place>& place) {
    for (int l = 0; l < 4; ++l) {
      const int ia = c.a[static_cast<std::size_t>(l)], ib = c.b[static_cast<std::size_t>(l)];
      if (ia < 0) continue;
      const Place& A = place[static_cast<std::size_t>(ia)];
      const Place B = ib >= 0 ? place[static_cast<std::size_t>(ib)] : Place{};
      for (int r = 0; r < 3; ++r) setLane(ra[static_cast<std::size_t>(r)], l, A.R.row(r)), setLane(rb[static_cast<std::size_t>(r)], l, B.R.row(r));
      setLane(xa, l, A.x), setLane(xb, l, B.x);
    }
  }
  [[gnu::always_inline]] static L3 turn(const std::array<L3, 3>& R, const L3& v) { return {dot(R[0], v), dot(R[1], v), dot(R[2], v)}; }
};

// Last step's impulses applied again (warm start).
REEL_CLONED void warmStart(const WideContact& c, const WidePoint* pts, std::vector<Motion>& motion) {
  WideMotion m(c, motion);
  for (int k = 0; k < c.count; ++k) {
    const WidePoint& p = pts[k];
    m.apply(c, p.n, c.n, p.ln);
    m.apply(c, p.t1, c.t1, p.lt1, p.t2, c.t2, p.lt2);
  }
  m.store(c, motion);
}

// One pass over a contact's points, in order: the normal (a separated point may close its gap
// this sub-step; an overlap beyond the slop is pushed out softly when `push`), then friction in
// the circle of radius μ·λ_n. A point's separation now (negative: overlap) follows from how far
// its two anchors moved apart along the normal since the step began.
REEL_CLONED void solveContact(const WideContact& c, WidePoint* pts, std::vector<Motion>& motion,
                              const std::vector<Place>& place, double h, const Soft& soft, bool push) {
  WideMotion m(c, motion);
  const WidePlace at(c, place);
  const Lane4 zero = splat(0.0), one = splat(1.0);
  const Lane4 push_rate = splat(push ? soft.bias_rate : 0.0), push_mass = splat(push ? soft.mass_scale : 1.0);
  const Lane4 push_impulse = splat(push ? soft.impulse_scale : 0.0), max_push = splat(push ? -kMaxPush : 0.0);
  for (int k = 0; k < c.count; ++k) {
    WidePoint& p = pts[k];
    const L3 d = (at.xb + WidePlace::turn(at.rb, p.lb)) - (at.xa + WidePlace::turn(at.ra, p.la));
    const Lane4 s = dot(d, c.n) + p.base + p.slop;
    const Lane4 pushed = push_rate * s;
    const auto apart = s > zero;
    const Lane4 bias = apart ? s / h : (pushed > max_push ? pushed : max_push);
    const Lane4 mass_scale = apart ? one : push_mass, impulse_scale = apart ? zero : push_impulse;
    const Lane4 vn = m.along(p, p.n, c.n);
    Lane4 ln = p.ln - p.n.mass * mass_scale * (vn + bias) - impulse_scale * p.ln;
    ln = ln > zero ? ln : zero;
    m.apply(c, p.n, c.n, ln - p.ln);
    p.ln = ln;
    const Lane4 l1 = p.lt1 - p.t1.mass * m.along(p, p.t1, c.t1);
    const Lane4 l2 = p.lt2 - p.t2.mass * m.along(p, p.t2, c.t2);
    const Lane4 lim = c.mu * p.ln, q = l1 * l1 + l2 * l2;
    Lane4 len;
    for (int l = 0; l < 4; ++l) len[l] = std::sqrt(q[l]);
    const Lane4 scale = (len > lim) & (len > zero) ? lim / len : one;
    const Lane4 d1 = l1 * scale - p.lt1, d2 = l2 * scale - p.lt2;
    p.lt1 += d1;
    p.lt2 += d2;
    m.apply(c, p.t1, c.t1, d1, p.t2, c.t2, d2);
  }
  m.store(c, motion);
}

// Restitution: a point that was approaching faster than kBounceSpeed leaves at e times that speed.
void bounce(const WideContact& c, WidePoint* pts, std::vector<Motion>& motion) {
  const Lane4 zero = splat(0.0);
  if (!((c.e > zero)[0] | (c.e > zero)[1] | (c.e > zero)[2] | (c.e > zero)[3])) return;
  WideMotion m(c, motion);
  for (int k = 0; k < c.count; ++k) {
    WidePoint& p = pts[k];
    const auto hit = (c.e > zero) & (p.vn0 <= splat(-kBounceSpeed)) & (p.ln > zero);
    Lane4 ln = p.ln - p.n.mass * (m.along(p, p.n, c.n) + c.e * p.vn0);
    ln = hit ? (ln > zero ? ln : zero) : p.ln;
    m.apply(c, p.n, c.n, ln - p.ln);
    p.ln = ln;
  }
  m.store(c, motion);
}

constexpr double kReuse = 1e-3;  // m: how far a pair may move against itself and keep its manifold
constexpr double kKeptMargin = 2e-3;  // m: added to the margin of a manifold that is kept

// B's pose in A's frame.
Eigen::Quaterniond relativeTurn(const SolverBody& A, const SolverBody& B) { return A.state->q.conjugate() * B.state->q; }
Vec3 relativeShift(const SolverBody& A, const SolverBody& B) { return A.pose.R.transpose() * (B.pose.p - A.pose.p); }

// A fresh manifold of A and B, kept with their relative pose.
CachedManifold keepManifold(std::uint32_t ga, std::uint32_t gb, const SolverBody& A, const SolverBody& B,
                            const Manifold& m, double margin) {
  CachedManifold c;
  c.a = ga, c.b = gb;
  c.count = m.count;
  c.margin = margin;
  const Eigen::Quaterniond q = relativeTurn(A, B);
  c.q = {q.w(), q.x(), q.y(), q.z()};
  const Vec3 t = relativeShift(A, B), n = A.pose.R.transpose() * m.normal;
  c.t = {t.x(), t.y(), t.z()};
  c.normal = {n.x(), n.y(), n.z()};
  for (int i = 0; i < m.count; ++i) {
    const ContactPoint& p = m.points[static_cast<std::size_t>(i)];
    // The surface points the midpoint joins: A's lies depth/2 along the normal, B's as far back.
    const Vec3 on_a = A.pose.R.transpose() * (p.position + 0.5 * p.depth * m.normal - A.pose.p);
    const Vec3 on_b = B.pose.R.transpose() * (p.position - 0.5 * p.depth * m.normal - B.pose.p);
    c.on_a[static_cast<std::size_t>(i)] = {on_a.x(), on_a.y(), on_a.z()};
    c.on_b[static_cast<std::size_t>(i)] = {on_b.x(), on_b.y(), on_b.z()};
    c.id[static_cast<std::size_t>(i)] = p.id;
  }
  return c;
}

// The kept manifold carried by the bodies as they are now, when B has moved less than kReuse in
// A's frame since it was computed (its turn measured at B's extent) and their margin now, plus
// kReuse, is within the one it was computed with.
bool reuseManifold(const CachedManifold& c, const SolverBody& A, const SolverBody& B, Manifold& m) {
  const Vec3 shift = relativeShift(A, B) - Vec3(c.t[0], c.t[1], c.t[2]);
  const Eigen::Quaterniond turn = Eigen::Quaterniond(c.q[0], c.q[1], c.q[2], c.q[3]).conjugate() * relativeTurn(A, B);
  const double angle = 2.0 * std::asin(std::min(1.0, turn.vec().norm()));
  if (!(shift.norm() + angle * B.model->extent <= kReuse) || !(A.margin + B.margin + kReuse <= c.margin)) return false;
  m.normal = A.pose.R * Vec3(c.normal[0], c.normal[1], c.normal[2]);
  m.count = c.count;
  for (int i = 0; i < c.count; ++i) {
    const auto& a = c.on_a[static_cast<std::size_t>(i)];
    const auto& b = c.on_b[static_cast<std::size_t>(i)];
    const Vec3 pa = A.pose.R * Vec3(a[0], a[1], a[2]) + A.pose.p, pb = B.pose.R * Vec3(b[0], b[1], b[2]) + B.pose.p;
    m.points[static_cast<std::size_t>(i)] = {0.5 * (pa + pb), (pa - pb).dot(m.normal), c.id[static_cast<std::size_t>(i)]};
  }
  return true;
}

// Sorts `order` by `less` (a strict total order), starting from the order it has (last step's,
// nearly sorted): insertion, or a full sort once it has moved too much. The result does not
// depend on where it started.
template <class Less>
void sortNearlySorted(std::vector<int>& order, Less less) {
  std::size_t moves = 0;
  const std::size_t budget = 8 * order.size() + 64;
  for (std::size_t i = 1; i < order.size(); ++i) {
    const int v = order[i];
    std::size_t j = i;
    for (; j > 0 && less(v, order[j - 1]); --j) order[j] = order[j - 1];
    order[j] = v;
    moves += i - j;
    if (moves > budget) {
      std::sort(order.begin(), order.end(), less);
      return;
    }
  }
}


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

// Broad phase. Candidates: the pairs whose fattened boxes overlap, kept while every body's box
// stays inside its fattened one (a resting pile keeps them for ever). The idea is Box2D's fat
// boxes (a fixed 0.1 m there); reel's margin is 5% of the body's size, at least 1 cm, and two
// steps of its motion. The pairs of a step are the candidates whose boxes overlap now (and not
// both asleep), so they are the same whatever candidates were kept. Candidates are found by sweep
// and prune (Baraff 1992; Cohen et al. 1995, I-COLLIDE) in strips: the fattened boxes are cut
// into strips across the axis they spread second most, each strip as wide as the widest box, and
// swept along the axis they spread most (a tall stack is swept along y). A box meets the boxes
// after it in its own strip and those of the next strip whose interval reaches it, each pair
// found once (a strip two away lies beyond the widest box): a pile of columns is swept column by
// column, not a row of columns at once. Sorted by strip, then the box's low end, then the body,
// starting from the last order.
void broadPhase(Step& t) {
  Scratch& S = t.S;
  RigidSolverCache& cache = t.cache;
  std::vector<Collider>& colliders = t.colliders;
  const double h = t.h;
  const int nb = t.nb;
  std::vector<SolverBody>& bodies = t.S.bodies;
  auto& pairs = S.pairs;
  pairs.clear();
  auto& fat_lo = cache.fat_lo;
  auto& fat_hi = cache.fat_hi;
  auto& candidates = cache.candidates;
  bool inside = fat_lo.size() == static_cast<std::size_t>(nb);
  for (int i = 0; i < nb && inside; ++i) {
    const SolverBody& b = bodies[static_cast<std::size_t>(i)];
    const Vec3& lo = fat_lo[static_cast<std::size_t>(i)];
    const Vec3& hi = fat_hi[static_cast<std::size_t>(i)];
    inside = lo.allFinite() && hi.allFinite() && (b.lo.array() >= lo.array()).all() && (b.hi.array() <= hi.array()).all();
  }
  if (!inside) {
    fat_lo.resize(static_cast<std::size_t>(nb));
    fat_hi.resize(static_cast<std::size_t>(nb));
    candidates.clear();
    Vec3 spread_lo = Vec3::Constant(1e300), spread_hi = Vec3::Constant(-1e300), widest = Vec3::Zero();
    double largest = 0.0;  // the largest coordinate, for the rounding slack below
    for (int i = 0; i < nb; ++i) {
      const SolverBody& b = bodies[static_cast<std::size_t>(i)];
      const RigidState& st = *b.state;
      const double fat = std::max(0.01, 0.05 * b.model->extent) + 2.0 * h * (st.v.norm() + st.w.norm() * b.model->extent);
      fat_lo[static_cast<std::size_t>(i)] = b.lo - Vec3::Constant(fat);
      fat_hi[static_cast<std::size_t>(i)] = b.hi + Vec3::Constant(fat);
      const Vec3& lo = fat_lo[static_cast<std::size_t>(i)];
      const Vec3& hi = fat_hi[static_cast<std::size_t>(i)];
      if (lo.allFinite() && hi.allFinite()) {
        spread_lo = spread_lo.cwiseMin(lo);
        spread_hi = spread_hi.cwiseMax(lo);
        widest = widest.cwiseMax(hi - lo);
        largest = std::max({largest, lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()});
      }
    }
    const Vec3 spread = (spread_hi - spread_lo).cwiseMax(0.0);
    int axis = 0;
    spread.maxCoeff(&axis);
    const int across = spread[(axis + 1) % 3] >= spread[(axis + 2) % 3] ? (axis + 1) % 3 : (axis + 2) % 3;
    // (Strips and the window along the axis take a slack far beyond the rounding of coordinates
    // this large, so no overlapping pair falls between them.)
    const double slack = 1e-9 * (1.0 + largest);
    const double strip_width = widest[across] + slack;
    auto& sweep = S.sweep;
    sweep.resize(static_cast<std::size_t>(nb));
    for (int i = 0; i < nb; ++i) {
      Scratch::Sweep& w = sweep[static_cast<std::size_t>(i)];
      w = {fat_lo[static_cast<std::size_t>(i)], fat_hi[static_cast<std::size_t>(i)], i, 0.0};
      // (A box with a non-finite bound goes last and meets nothing.)
      const double k = (w.lo[across] - spread_lo[across]) / strip_width;
      w.strip = w.lo.allFinite() && w.hi.allFinite() ? std::floor(std::clamp(k, 0.0, 1e15)) : 2e15;
      if (!std::isfinite(w.lo[axis])) w.lo[axis] = 1e300;
    }
    std::vector<int>& order = cache.sweep_order;
    if (order.size() != static_cast<std::size_t>(nb)) {
      order.resize(static_cast<std::size_t>(nb));
      for (int i = 0; i < nb; ++i) order[static_cast<std::size_t>(i)] = i;
    }
    sortNearlySorted(order, [&](int i, int j) {
      const Scratch::Sweep& p = sweep[static_cast<std::size_t>(i)];
      const Scratch::Sweep& q = sweep[static_cast<std::size_t>(j)];
      return p.strip != q.strip ? p.strip < q.strip : p.lo[axis] != q.lo[axis] ? p.lo[axis] < q.lo[axis] : i < j;
    });
    auto& sorted = S.sorted;
    sorted.resize(static_cast<std::size_t>(nb));
    for (int i = 0; i < nb; ++i) sorted[static_cast<std::size_t>(i)] = sweep[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])];
    auto test = [&](const Scratch::Sweep& A, const Scratch::Sweep& B) {
      if (A.strip < 1e15 && B.strip < 1e15 && overlaps(A.lo, A.hi, B.lo, B.hi))
        candidates.push_back({std::min(A.body, B.body), std::max(A.body, B.body)});
    };
    const std::size_t ns = sorted.size();
    for (std::size_t s0 = 0; s0 < ns;) {
      std::size_t s1 = s0;  // the strip [s0, s1), the next one [s1, s2)
      while (s1 < ns && sorted[s1].strip == sorted[s0].strip) ++s1;
      std::size_t s2 = s1;
      if (s1 < ns && sorted[s1].strip == sorted[s0].strip + 1 && sorted[s0].strip < 1e15)
        while (s2 < ns && sorted[s2].strip == sorted[s1].strip) ++s2;
      std::size_t from = s1;  // the next strip's first box that may reach the current one
      for (std::size_t i = s0; i < s1; ++i) {
        const Scratch::Sweep& A = sorted[i];
        const double end = A.hi[axis];
        for (std::size_t j = i + 1; j < s1 && sorted[j].lo[axis] <= end; ++j) test(A, sorted[j]);
        while (from < s2 && sorted[from].lo[axis] < A.lo[axis] - widest[axis] - slack) ++from;
        for (std::size_t j = from; j < s2 && sorted[j].lo[axis] <= end; ++j) test(A, sorted[j]);
      }
      s0 = s1;
    }
    std::sort(candidates.begin(), candidates.end());
  }
  // The pairs in the order of the cache's keys: by A, then B's bodies, then the object parts (a
  // sleeping body meets only moving objects, which may wake it).
  std::vector<std::uint32_t>& near = S.near;
  std::size_t cursor = 0;
  for (int i = 0; i < nb; ++i) {
    const SolverBody& A = bodies[static_cast<std::size_t>(i)];
    for (; cursor < candidates.size() && candidates[cursor][0] == i; ++cursor) {
      const SolverBody& B = bodies[static_cast<std::size_t>(candidates[cursor][1])];
      if (A.state->asleep && B.state->asleep) continue;
      if (overlaps(A.lo, A.hi, B.lo, B.hi)) pairs.push_back({i, candidates[cursor][1]});
    }
    partsNear(cache, colliders, A.lo, A.hi, near);
    for (std::uint32_t p : near)
      if (!A.state->asleep || colliders[cache.parts[p].collider].moving()) pairs.push_back({i, -1, p});
  }
}

// Narrow phase, in parallel: each pair writes its own manifold.
void narrowPhase(Step& t) {
  Scratch& S = t.S;
  RigidSolverCache& cache = t.cache;
  std::vector<Collider>& colliders = t.colliders;
  std::vector<SolverBody>& bodies = t.S.bodies;
  const std::vector<std::uint32_t>& global = t.S.global;
  auto& pairs = t.S.pairs;
  std::vector<Manifold>& manifolds = S.manifolds;
  manifolds.resize(pairs.size());
  // Body pairs take last step's manifold where they have barely moved against each other (see
  // CachedManifold), else compute it and keep it. (A pair costs about a microsecond, a few hundred
  // times an element of a plain loop: the threshold is taken on 16 times the pairs.)
  auto& reused = S.reused;  // per pair: the cached manifold it took, or −1
  reused.assign(pairs.size(), -1);
  const std::vector<CachedManifold>& kept = cache.manifolds;
  parallelBlocks(static_cast<std::ptrdiff_t>(pairs.size()), 8, [&](std::ptrdiff_t k0, std::ptrdiff_t k1) {
    for (std::ptrdiff_t k = k0; k < k1; ++k) {
      const Scratch::Pair& p = pairs[static_cast<std::size_t>(k)];
      const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
      Manifold& m = manifolds[static_cast<std::size_t>(k)];
      if (p.b < 0) {
        const ObjectPart& part = cache.parts[p.part];
        collidePart(A.model->shape, A.pose, part, colliders[part.collider], A.margin, m);
        continue;
      }
      const SolverBody& B = bodies[static_cast<std::size_t>(p.b)];
      CachedManifold key;
      key.a = global[static_cast<std::size_t>(p.a)], key.b = global[static_cast<std::size_t>(p.b)];
      const auto it = std::lower_bound(kept.begin(), kept.end(), key);
      if (it != kept.end() && it->a == key.a && it->b == key.b && reuseManifold(*it, A, B, m)) {
        reused[static_cast<std::size_t>(k)] = static_cast<int>(it - kept.begin());
        continue;
      }
      collide(A.model->shape, A.pose, B.model->shape, B.pose, A.margin + B.margin + kKeptMargin, m);
    }
  }, static_cast<std::ptrdiff_t>(pairs.size()) * 16);
  {
    auto& next = S.next_manifolds;
    next.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const Scratch::Pair& p = pairs[k];
      if (p.b < 0 || manifolds[k].count == 0) continue;
      if (reused[k] >= 0) next.push_back(kept[static_cast<std::size_t>(reused[k])]);
      else {
        const SolverBody& A = bodies[static_cast<std::size_t>(p.a)];
        const SolverBody& B = bodies[static_cast<std::size_t>(p.b)];
        next.push_back(keepManifold(global[static_cast<std::size_t>(p.a)], global[static_cast<std::size_t>(p.b)], A, B,
                                    manifolds[k], A.margin + B.margin + kKeptMargin));
      }
    }
    std::swap(cache.manifolds, next);
  }
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
