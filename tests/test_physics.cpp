// Physics of spring networks: catenary, momentum, stability bounds, implicit stiffness, contacts.
#include <doctest/doctest.h>

#include <cmath>

#include "core/math.h"
#include "core/random.h"
#include "helpers.h"
#include "sim/springs/generators.h"
#include "sim/springs/springs_body.h"
#include "sim/collide.h"
#include "sim/stability.h"
#include "sim/world.h"

using namespace reel;

namespace {

// A stiff 16 x 16 net pinned at two corners, for the implicit integrators at long steps.
MassSpringDesc stiffNet() {
  NetDesc net;
  net.resolution = {16, 16};
  net.mass = 0.5;
  net.structural = {2000.0, 0.5};
  net.shear = {500.0, 0.2};
  net.pinned = {0, 15};
  return buildNet(net);
}

}  // namespace
using namespace reel::test;

TEST_CASE("a hanging chain settles to the catenary of its length") {
  // Chain of length L = 3 between supports 2 m apart; stiff springs keep its stretch tiny.
  RopeDesc r;
  r.start = Vec3(-1, 0, 0);
  r.end = Vec3(1, 0, 0);
  r.segments = 60;
  r.length = 3.0;
  r.mass = 0.6;
  r.spring = {2e5, 5.0};
  r.node_damping = 0.02;
  r.pinned = {0, 60};
  System s(buildRope(r), Vec3(0, -9.78, 0));
  // Start on a sagging parabola-ish arc so the springs are not compressed on the straight line.
  for (int i = 0; i <= 60; ++i) s.state.x[i].y() = -0.9 * std::sin(kPi * i / 60.0);
  for (int i = 0; i < 6000; ++i) s.step(IntegratorKind::ImplicitEuler, 2e-3);
  CHECK(kineticEnergy(s.model, s.state) < 1e-9);
  // Catenary y = a cosh(x/a) + c through the supports: L = 2a sinh(d/(2a)), d = 2.
  double lo = 0.1, hi = 10.0;
  for (int it = 0; it < 200; ++it) {
    const double a = 0.5 * (lo + hi);
    (2 * a * std::sinh(1.0 / a) > 3.0 ? lo : hi) = a;
  }
  const double a = 0.5 * (lo + hi);
  double worst = 0.0;
  for (const Vec3& p : s.state.x) {
    const double y = a * std::cosh(p.x() / a) - a * std::cosh(1.0 / a);
    worst = std::max(worst, std::abs(p.y() - y));
  }
  const double sag = a * std::cosh(1.0 / a) - a;  // ≈ 1.0 m
  CHECK(sag > 0.9);
  CHECK(worst < 0.005 * sag);
  CHECK(std::abs(s.state.x[30].x()) < 1e-9);  // symmetric
}

TEST_CASE("a free spring network conserves linear momentum") {
  NetDesc net;
  net.resolution = {12, 9};
  net.mass = 2.0;
  net.structural = {300.0, 0.4};
  net.shear = {100.0, 0.2};
  MassSpringDesc d = buildNet(net);
  // Deterministic pseudo-random velocities and masses.
  std::uint64_t seed = 12345;
  auto rnd = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(seed >> 11) * 0x1.0p-53 - 0.5;
  };
  for (auto& n : d.nodes) {
    n.velocity = Vec3(rnd(), rnd(), rnd());
    n.mass *= 1.0 + rnd();
  }
  for (IntegratorKind k : allIntegrators()) {
    CAPTURE(integratorName(k));
    System s(d, Vec3::Zero());
    auto momentum = [&] {
      Vec3 p = Vec3::Zero();
      for (std::size_t i = 0; i < s.model.nodes(); ++i) p += s.model.mass[i] * s.state.v[i];
      return p;
    };
    const Vec3 p0 = momentum();
    for (int i = 0; i < 500; ++i) s.step(k, 1e-3);
    CHECK((momentum() - p0).norm() < 1e-11);
  }
}

TEST_CASE("the estimated step bound separates stable from unstable symplectic Euler") {
  // Two free equal masses on one spring: ω² = 2k/m exactly, so the bound is sharp.
  MassSpringDesc d;
  d.nodes.push_back({Vec3(0, 0, 0), Vec3::Zero(), 0.2, 0.0, false});
  d.nodes.push_back({Vec3(1.05, 0, 0), Vec3::Zero(), 0.2, 0.0, false});
  d.springs.push_back({0, 1, 500.0, 0.0, 1.0});
  System probe(d, Vec3::Zero());
  const StepBound b = stableStep(probe.model, IntegratorKind::SymplecticEuler);
  CHECK(b.h_max == doctest::Approx(2.0 / std::sqrt(2 * 500.0 / 0.2)));
  auto amplitude = [&](double h) {
    System s(d, Vec3::Zero());
    double amp = 0;
    for (int i = 0; i < 2000; ++i) {
      s.step(IntegratorKind::SymplecticEuler, h);
      amp = std::max(amp, std::abs((s.state.x[1] - s.state.x[0]).norm() - 1.0));
    }
    return amp;
  };
  CHECK(amplitude(0.98 * b.h_max) < 1.0);   // stays bounded (initial stretch 0.05)
  CHECK(amplitude(1.02 * b.h_max) > 10.0);  // grows without bound
  // Explicit Euler has no stable step for undamped springs; damping gives it one.
  CHECK(stableStep(probe.model, IntegratorKind::ExplicitEuler).h_max == 0.0);
  CHECK(std::isinf(stableStep(probe.model, IntegratorKind::ImplicitEuler).h_max));
}

TEST_CASE("implicit Euler's linear system matches the assembled Baraff-Witkin matrix, and the step solves it") {
  // A net of uneven masses, stretched and compressed springs (the transverse term on and
  // clamped off), node drag and two pins; a random direction p.
  NetDesc net;
  net.resolution = {9, 7};
  net.mass = 0.3;
  net.structural = {800.0, 0.4};
  net.shear = {150.0, 0.1};
  net.node_damping = 0.02;
  net.pinned = {0, 8};
  MassSpringDesc d = buildNet(net);
  std::uint64_t draw = 0;
  auto rnd = [&] { return uniformAt(99, 0, draw++) - 0.5; };  // reel's own numbers, from a seed
  for (auto& nd : d.nodes) {
    if (nd.fixed) continue;
    nd.velocity = Vec3(rnd(), rnd(), rnd());
    nd.mass *= 1.0 + rnd();
  }
  const Vec3 g(0, -9.78, 0);
  System sys(d, g);
  for (std::size_t i = 0; i < sys.model.nodes(); ++i)
    if (!sys.model.fixed[i]) sys.state.x[i] += 0.04 * Vec3(rnd(), rnd(), rnd());  // off their rest lengths
  const MassSpringModel& m = sys.model;
  const std::size_t n = m.nodes();
  const double h = 0.01;
  std::vector<Vec3> rhs(n), p(n), out(n);
  std::vector<Mat3> pinv(n);
  sys.dyn.linearize(sys.state.x.data(), sys.state.v.data(), sys.state.v.data(), h, rhs.data(), pinv.data());
  for (auto& q : p) q = Vec3(rnd(), rnd(), rnd());
  sys.dyn.applySystem(p.data(), out.data());
  // The reference, spring by spring in double precision (helpers.h), and
  // rhs = h (m g − γ v + Σ ±(s + h K (v_b − v_a))).
  const AssembledSystem A = assembleSystem(m, sys.state.x, h);
  const std::vector<Vec3> Ap = A.product(m, h, p);
  std::vector<Vec3> rhs_ref(n);
  for (std::size_t i = 0; i < n; ++i) rhs_ref[i] = m.mass[i] * g - m.drag[i] * sys.state.v[i];
  int stretched = 0, compressed = 0;
  for (std::size_t s = 0; s < m.springs.size(); ++s) {
    const auto a = static_cast<std::size_t>(m.springs.a[s]), b = static_cast<std::size_t>(m.springs.b[s]);
    const Vec3 r = sys.state.x[b] - sys.state.x[a];
    const double len = r.norm(), k = m.springs.stiffness[s], c = m.springs.damping[s], L = m.springs.rest[s];
    const Vec3 u = r / len;
    const double t = std::max(0.0, 1.0 - L / len);
    (t > 0 ? stretched : compressed)++;
    const Mat3 K = k * (u * u.transpose() + t * (Mat3::Identity() - u * u.transpose()));
    const Vec3 dv = sys.state.v[b] - sys.state.v[a];
    const Vec3 w = (k * (len - L) + c * dv.dot(u)) * u + h * (K * dv);
    rhs_ref[a] += w;
    rhs_ref[b] -= w;
  }
  CHECK(stretched > 10);
  CHECK(compressed > 10);
  double scale = 0;
  for (const Vec3& y : Ap) scale = std::max(scale, y.norm());
  int pinned = 0;
  for (std::size_t i = 0; i < n; ++i) {
    CAPTURE(i);
    CHECK((rhs[i] - h * rhs_ref[i]).norm() <= 1e-12 * (1.0 + h * rhs_ref[i].norm()));
    if (m.fixed[i]) {  // a fixed node's row is never used: the product gives 0 there
      CHECK(out[i] == Vec3::Zero());
      ++pinned;
      continue;
    }
    // The product uses the blocks rounded to single precision: agreement to 10⁻⁶.
    CHECK((out[i] - Ap[i]).norm() <= 1e-6 * scale);
    // Block Jacobi: the inverse of the node's 3×3 diagonal block.
    CHECK((pinv[i] * A.diag[i] - Mat3::Identity()).norm() < 1e-10);
  }
  CHECK(pinned > 0);
  // One step: Δv solves A Δv = rhs on the free nodes (pins keep Δv = 0), up to the rounding of
  // the blocks.
  const std::vector<Vec3> v0 = sys.state.v;
  sys.implicit = {1e-12, 1000};
  sys.step(IntegratorKind::ImplicitEuler, h);
  std::vector<Vec3> dv(n);
  for (std::size_t i = 0; i < n; ++i) dv[i] = sys.state.v[i] - v0[i];
  const std::vector<Vec3> Adv = A.product(m, h, dv);
  double rnorm = 0, bnorm = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (m.fixed[i]) {
      CHECK(dv[i] == Vec3::Zero());
      continue;
    }
    rnorm += (Adv[i] - h * rhs_ref[i]).squaredNorm();
    bnorm += (h * rhs_ref[i]).squaredNorm();
  }
  CHECK(std::sqrt(rnorm) <= 1e-6 * std::sqrt(bnorm));
}

TEST_CASE("implicit Euler stays stable at 50x the explicit step bound") {
  const MassSpringDesc d = stiffNet();
  System probe(d, Vec3(0, -9.78, 0));
  const double hb = stableStep(probe.model, IntegratorKind::SymplecticEuler).h_max;
  REQUIRE(hb > 0);
  const double h = 50.0 * hb;
  // Symplectic Euler at that step explodes...
  System ex(d, Vec3(0, -9.78, 0));
  bool blew = false;
  for (int i = 0; i < 200 && !blew; ++i) {
    ex.step(IntegratorKind::SymplecticEuler, h);
    blew = !(ex.state.x[100].norm() < 1e3);
  }
  CHECK(blew);
  // ...implicit Euler hangs the net calmly below its pins.
  System im(d, Vec3(0, -9.78, 0));
  const double e0 = totalEnergy(im.model, im.state);
  for (int i = 0; i < 400; ++i) {
    im.step(IntegratorKind::ImplicitEuler, h);
    REQUIRE(im.state.x[100].allFinite());
    CHECK(totalEnergy(im.model, im.state) <= e0 + 1e-9);
  }
  for (const Vec3& p : im.state.x) CHECK(p.norm() < 5.0);
  // Nearly at rest: what still moves is a small part of the energy released by the fall.
  CHECK(kineticEnergy(im.model, im.state) < 0.02 * (e0 - totalEnergy(im.model, im.state)));
  CHECK(im.state.x[0] == d.nodes[0].position);  // pins never move
}

TEST_CASE("BDF2 is second order and implicit Euler first on the oscillator; BDF2 also stays calm at 50x the explicit bound") {
  // m u'' = −k u − c u' from u0 = 0.1 over 1 s, against the closed form, at h and h/2.
  const double m = 1.0, k = 400.0, c = 2.0, u0 = 0.1, T = 1.0;
  auto error = [&](IntegratorKind kind, int steps) {
    System s(oscillator(m, k, c, u0), Vec3::Zero());
    const double h = T / steps;
    for (int i = 0; i < steps; ++i) s.step(kind, h);
    return std::abs((s.state.x[1].x() - 1.0) - oscillatorExact(k / m, c / m, u0, T));
  };
  const double ie1 = error(IntegratorKind::ImplicitEuler, 2000), ie2 = error(IntegratorKind::ImplicitEuler, 4000);
  const double b1 = error(IntegratorKind::Bdf2, 2000), b2 = error(IntegratorKind::Bdf2, 4000);
  CAPTURE(ie1);
  CAPTURE(ie2);
  CAPTURE(b1);
  CAPTURE(b2);
  CHECK(ie1 / ie2 == doctest::Approx(2.0).epsilon(0.15));
  CHECK(b1 / b2 == doctest::Approx(4.0).epsilon(0.15));
  CHECK(b1 < 0.05 * ie1);
  // A fixed node a body poses each step (as the face's bone nodes), at rest: the step leaves it there.
  System posed(oscillator(m, k, c, u0), Vec3::Zero());
  for (int i = 0; i < 20; ++i) {
    const Vec3 pose(0.01 * i, 0, 0);
    posed.state.x[0] = pose, posed.state.v[0].setZero();
    posed.step(IntegratorKind::Bdf2, 0.01);
    CHECK(posed.state.x[0] == pose);
  }

  // A stiff net stepped at 50x the symplectic bound hangs calmly below its pins.
  const MassSpringDesc d = stiffNet();
  System b(d, Vec3(0, -9.78, 0));
  const double h = 50.0 * stableStep(b.model, IntegratorKind::SymplecticEuler).h_max;
  const double e0 = totalEnergy(b.model, b.state);
  for (int i = 0; i < 400; ++i) {
    b.step(IntegratorKind::Bdf2, h);
    REQUIRE(b.state.x[100].allFinite());
  }
  for (const Vec3& p : b.state.x) CHECK(p.norm() < 5.0);
  CHECK(kineticEnergy(b.model, b.state) < 0.02 * (e0 - totalEnergy(b.model, b.state)));
  CHECK(b.state.x[0] == d.nodes[0].position);
}

TEST_CASE("contacts: resting on a plane, restitution, Coulomb friction on an incline") {
  const Vec3 g(0, -9.78, 0);
  SUBCASE("a dropped node comes to rest on the floor at its radius") {
    ObjectDesc floor;
    floor.shape = PlaneShape{};
    std::vector<Collider> cs{makeCollider(floor)};
    MassSpringDesc d;
    d.nodes.push_back({Vec3(0.2, 1.0, 0), Vec3(0, 0, 0), 1.0, 0.0, false});
    System s(d, g);
    for (int i = 0; i < 2000; ++i) {
      s.step(IntegratorKind::SymplecticEuler, 1e-3);
      resolveContacts(cs, 0.05, 1e-3, s.model.fixed.data(), s.state.x, s.state.v);
    }
    CHECK(s.state.x[0].y() == doctest::Approx(0.05));
    CHECK(s.state.v[0].norm() < 0.02);
  }
  SUBCASE("restitution e returns the ball to e² of its drop height") {
    ObjectDesc floor;
    floor.surface.restitution = 0.8;
    std::vector<Collider> cs{makeCollider(floor)};
    MassSpringDesc d;
    d.nodes.push_back({Vec3(0, 1.0, 0), Vec3::Zero(), 1.0, 0.0, false});
    System s(d, g);
    double peak = 0, prev_vy = 0;
    bool bounced = false;
    for (int i = 0; i < 10000; ++i) {
      s.step(IntegratorKind::SymplecticEuler, 1e-4);
      resolveContacts(cs, 0.0, 1e-4, s.model.fixed.data(), s.state.x, s.state.v);
      if (s.state.v[0].y() > 0) bounced = true;
      if (bounced && prev_vy > 0 && s.state.v[0].y() <= 0) peak = s.state.x[0].y();
      prev_vy = s.state.v[0].y();
    }
    CHECK(peak == doctest::Approx(0.64).epsilon(0.01));
  }
  SUBCASE("a node on an incline stays when tan θ < μ and slides when tan θ > μ") {
    for (double deg : {20.0, 35.0}) {
      ObjectDesc ramp;
      const double th = deg * kPi / 180.0;
      ramp.shape = PlaneShape{Vec3::Zero(), Vec3(-std::sin(th), std::cos(th), 0), std::nullopt};
      ramp.surface.friction = 0.5;  // tan 26.6°
      std::vector<Collider> cs{makeCollider(ramp)};
      MassSpringDesc d;
      d.nodes.push_back({Vec3::Zero(), Vec3::Zero(), 1.0, 0.0, false});
      System s(d, g);
      for (int i = 0; i < 1000; ++i) {
        s.step(IntegratorKind::SymplecticEuler, 1e-3);
        resolveContacts(cs, 0.0, 1e-3, s.model.fixed.data(), s.state.x, s.state.v);
      }
      const double slid = s.state.x[0].norm();
      if (deg < 26.0) {
        CHECK(slid < 1e-4);
      } else {
        // Sliding with a = g (sin θ − μ cos θ): distance a t²/2 after 1 s.
        const double a = 9.78 * (std::sin(th) - 0.5 * std::cos(th));
        CHECK(slid == doctest::Approx(0.5 * a).epsilon(0.02));
      }
    }
  }
  SUBCASE("a finite plane catches nodes just below it, not ones passing far beneath") {
    ObjectDesc shelf;
    shelf.shape = PlaneShape{Vec3::Zero(), Vec3::UnitY(), std::array<double, 2>{2.0, 2.0}};
    const Collider c = makeCollider(shelf);
    double d;
    Vec3 n;
    CHECK(c.distance(Vec3(0.5, -0.04, 0), d, n));   // crossed it this step
    CHECK(!c.distance(Vec3(0.5, -0.5, 0), d, n));   // far beneath
    CHECK(!c.distance(Vec3(1.5, 0.01, 0), d, n));   // beside it
  }
  SUBCASE("sphere, box and capsule push nodes out along their normals") {
    ObjectDesc sph, box, cap;
    sph.shape = SphereShape{Vec3::Zero(), 1.0};
    box.shape = BoxShape{Vec3::Zero(), Vec3(2, 2, 2), Vec3(0, 45, 0)};
    cap.shape = CapsuleShape{Vec3(0, -1, 0), Vec3(0, 1, 0), 0.5};
    for (const ObjectDesc& o : {sph, box, cap}) {
      std::vector<Collider> cs{makeCollider(o)};
      std::vector<Vec3> x{Vec3(0.3, 0.2, 0.1)}, v{Vec3(-1, 0, 0)};
      const std::uint8_t fixed = 0;
      resolveContacts(cs, 0.0, 0.0, &fixed, x, v);  // h = 0: projection only
      double d;
      Vec3 n;
      REQUIRE(cs[0].distance(x[0], d, n));
      CHECK(std::abs(d) < 1e-12);
      CHECK(v[0].dot(n) >= -1e-12);
    }
    // The rotated box: a point on the diagonal at distance √2 (the corner) touches it.
    double d;
    Vec3 n;
    makeCollider(box).distance(Vec3(std::sqrt(2.0) + 0.1, 0, 0), d, n);
    CHECK(d == doctest::Approx(0.1));
  }
}

// The shortcut a liquid takes before measuring a container's five parts: wherever it says a point
// is clear by a margin, every part is at least that far; and it does say so deep in the cavity.
TEST_CASE("a container's cavity: a point it calls clear is farther than the margin from every part") {
  for (const Vec3 rot : {Vec3(0, 0, 0), Vec3(10, 35, -20)}) {
    CAPTURE(rot);
    ObjectDesc o;
    o.shape = ContainerShape{Vec3(0.3, 0.5, -0.2), Vec3(1.0, 0.6, 0.8), 0.05, rot};
    const Collider c = makeCollider(o);
    const Mat3 R = c.shape->R;
    // Points around the container (safety), then points in its cavity (the shortcut takes them).
    for (const bool cavity : {false, true}) {
      CAPTURE(cavity);
      const Vec3 span = cavity ? Vec3(0.9, 0.55, 0.7) : Vec3(1.4, 1.0, 1.2);
      const Vec3 low = cavity ? Vec3(-0.45, -0.25, -0.35) : Vec3(-0.7, -0.5, -0.6);
      int clear = 0, far = 0;
      for (int k = 0; k < 10000; ++k) {
        const Vec3 u(uniformAt(5, 1, 3 * k), uniformAt(5, 1, 3 * k + 1), uniformAt(5, 1, 3 * k + 2));
        const Vec3 p = Vec3(0.3, 0.5, -0.2) + R * (low + span.cwiseProduct(u));
        const double margin = 0.1 * uniformAt(5, 2, k);
        double d[ColliderShape::kMaxParts];
        Vec3 n[ColliderShape::kMaxParts];
        const int parts = c.partDistances(p, d, n);
        REQUIRE(parts == 5);
        double nearest = INFINITY;
        for (int q = 0; q < parts; ++q) nearest = std::min(nearest, d[q]);
        far += nearest > margin + 1e-6;
        if (c.clearOfParts(p, margin)) {
          ++clear;
          CHECK(nearest >= margin);
        }
      }
      if (cavity) CHECK(clear >= far);  // in the cavity, every point farther than the margin (and a hair)
      else CHECK(clear < far);          // outside it, the test says nothing
    }
  }
  // A keyframed container, moved and turned: the test follows it.
  ObjectDesc moving;
  moving.shape = ContainerShape{Vec3(0, 0.3, 0), Vec3(1.0, 0.6, 0.8), 0.05, Vec3(0, 0, 0)};
  moving.motion = {{0.0, Vec3(0, 0.3, 0), Vec3(0, 0, 0)}, {1.0, Vec3(2, 0.3, 1), Vec3(0, 90, 0)}};
  Collider box = makeCollider(moving);
  box.moveTo(1.0, 1.0);
  CHECK(box.clearOfParts(Vec3(2, 0.3, 1), 0.1));         // the cavity's middle, where it went
  CHECK(!box.clearOfParts(Vec3(0, 0.3, 0), 0.1));        // where it was: outside it now
  CHECK(!box.clearOfParts(Vec3(2 + 0.3, 0.3, 1), 0.1));   // 0.05 from a wall (turned: x is its z)
  CHECK(box.clearOfParts(Vec3(2 + 0.2, 0.3, 1 + 0.3), 0.1));
  ObjectDesc ball;
  ball.shape = SphereShape{Vec3::Zero(), 1.0};
  CHECK(!makeCollider(ball).clearOfParts(Vec3(0, 0, 0), 0.1));  // other shapes: never
}

TEST_CASE("the jelly lattice lands on the floor and bounces back up") {
  LatticeDesc l;
  l.position = Vec3(0, 1.0, 0);
  l.size = Vec3(0.5, 0.5, 0.5);
  l.resolution = {4, 4, 4};
  l.mass = 1.0;
  l.edge = l.face = l.body = {1500.0, 0.2};
  SceneDesc scene;
  scene.fps = 60;
  scene.substeps = 40;
  scene.duration = 1.5;
  ObjectDesc floor;
  scene.objects.push_back(floor);
  BodyDesc b;
  b.name = "jelly";
  b.type = "lattice";
  b.params = std::make_shared<LatticeDesc>(l);
  scene.bodies.push_back(b);
  auto w = app::makeWorld(scene);
  REQUIRE(w.ok());
  double min_y = 1e9;
  bool touched = false, rose = false;
  double prev_cy = 1.0;
  for (int f = 0; f < 90; ++f) {
    REQUIRE(w.value().advanceFrame().ok());
    const auto& x = w.value().first<SpringsBody>()->network().state.x;
    double cy = 0;
    for (const Vec3& p : x) {
      min_y = std::min(min_y, p.y());
      cy += p.y() / static_cast<double>(x.size());
    }
    if (min_y < 0.03) touched = true;
    if (touched && cy > prev_cy + 1e-4) rose = true;  // the centre moves up again: a bounce
    prev_cy = cy;
  }
  CHECK(touched);
  CHECK(rose);
  CHECK(min_y >= 0.02 - 1e-9);  // never below the floor + node radius
}
