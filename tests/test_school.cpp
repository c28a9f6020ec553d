// Schools: each of Couzin's rules alone, the turn cap, the order parameters on hand-built states,
// the collective states of Couzin et al. (2002), boids, steering (obstacles, bounds, goal,
// predator), determinism across thread counts, and bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/parallel.h"
#include "core/random.h"
#include "sim/row_grid.h"
#include "helpers.h"
#include "sim/school/school_body.h"
#include "core/union_find.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double angle(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)); }

// Couzin's paper's parameters: r_r = 1, zones as given, speed 3, 40°/s, σ = 0.05, 270°, τ = 0.1.
CouzinDesc zones(double ro, double ra) {
  CouzinDesc c;
  c.r_repulsion = 1;
  c.r_orientation = ro;
  c.r_attraction = ra;
  return c;
}

const School& schoolOf(const World& w) { return w.first<SchoolBody>()->school(); }

// N = 100 agents of Couzin's model stepping at exactly τ, from a random start in a ball of 4 m.
std::string couzinScene(double d_orient, double d_attract, int seed, double duration) {
  const double ro = 1 + d_orient, ra = ro + d_attract;
  return R"({"format": "reel/1", "fps": 10, "substeps": 1, "duration": )" + std::to_string(duration) +
         R"(, "seed": )" + std::to_string(seed) +
         R"(, "bodies": [{"type": "school", "name": "s", "count": 100, "start": {"center": [0, 0, 0], "radius": 4},
            "zones": {"repulsion": 1, "orientation": )" + std::to_string(ro) + R"(, "attraction": )" +
         std::to_string(ra) + "}}]}";
}

// Mean polarisation and milling over the last `tail` frames of a run.
std::pair<double, double> meanOrder(const std::string& text, int tail) {
  World w = worldFromText(text);
  const int frames = sceneFromText(text).frameCount() - 1;
  double p = 0, m = 0;
  for (int f = 1; f <= frames; ++f) {
    run(w, 1);
    if (f > frames - tail) {
      const SchoolOrder o = schoolOrder(schoolOf(w).x, schoolOf(w).v);
      p += o.polarization / tail;
      m += o.milling / tail;
    }
  }
  return {p, m};
}

}  // namespace

TEST_CASE("Couzin's rules one at a time") {
  const CouzinDesc c = zones(3, 10);
  const Vec3 xi(0, 0, 0), vi(1, 0, 0);
  SUBCASE("no neighbour: the heading is kept") { CHECK((couzinDirection(c, 270, xi, vi, {}, {}) - vi).norm() < 1e-12); }
  SUBCASE("repulsion turns away from a neighbour too close, and takes priority") {
    const Vec3 d = couzinDirection(c, 270, xi, vi, {Vec3(0.5, 0.5, 0), Vec3(0, 2, 0)}, {Vec3(1, 0, 0), Vec3(0, 1, 0)});
    CHECK((d - Vec3(-1, -1, 0).normalized()).norm() < 1e-12);  // the aligning neighbour at 2 m is ignored
  }
  SUBCASE("orientation aligns with neighbours, the focal agent counting itself") {
    const Vec3 d = couzinDirection(c, 270, xi, vi, {Vec3(0, 2, 0), Vec3(0, -2, 0)}, {Vec3(0, 0, 1), Vec3(0, 0, 1)});
    CHECK((d - Vec3(1, 0, 2).normalized()).norm() < 1e-12);
  }
  SUBCASE("attraction closes in") {
    const Vec3 d = couzinDirection(c, 270, xi, vi, {Vec3(0, 6, 0)}, {Vec3(-1, 0, 0)});
    CHECK((d - Vec3(0, 1, 0)).norm() < 1e-12);
  }
  SUBCASE("orientation and attraction together: the mean of the two unit directions") {
    const Vec3 d = couzinDirection(c, 270, xi, vi, {Vec3(0, 2, 0), Vec3(0, 0, 6)}, {Vec3(0, 1, 0), Vec3(1, 0, 0)});
    CHECK((d - (0.5 * (Vec3(1, 1, 0).normalized() + Vec3(0, 0, 1))).normalized()).norm() < 1e-12);
  }
  SUBCASE("the blind cone hides a neighbour behind") {
    const std::vector<Vec3> behind{Vec3(-0.5, 0.1, 0)}, v{Vec3(1, 0, 0)};
    CHECK((couzinDirection(c, 270, xi, vi, behind, v) - vi).norm() < 1e-12);
    CHECK(couzinDirection(c, 360, xi, vi, behind, v).x() > 0.9);  // seen all round: pushed forward
    // The edge of the cone: at 270° an agent sees up to 135° off its heading.
    const Vec3 at134(std::cos(134 * kDeg), std::sin(134 * kDeg), 0), at136(std::cos(136 * kDeg), std::sin(136 * kDeg), 0);
    CHECK((couzinDirection(c, 270, xi, vi, {0.5 * at134}, v) + at134).norm() < 1e-12);
    CHECK((couzinDirection(c, 270, xi, vi, {0.5 * at136}, v) - vi).norm() < 1e-12);
  }
  SUBCASE("zone edges: r_r and r_o belong to the outer zone, r_a is outside") {
    CHECK((couzinDirection(c, 270, xi, vi, {Vec3(0, 1, 0)}, {Vec3(0, 0, 1)}) - Vec3(1, 0, 1).normalized()).norm() < 1e-12);
    CHECK((couzinDirection(c, 270, xi, vi, {Vec3(0, 3, 0)}, {Vec3(0, 0, 1)}) - Vec3(0, 1, 0)).norm() < 1e-12);
    CHECK((couzinDirection(c, 270, xi, vi, {Vec3(0, 10, 0)}, {Vec3(0, 0, 1)}) - vi).norm() < 1e-12);
  }
}

TEST_CASE("the turn per decision is capped at θτ, and a smaller one is taken whole") {
  CHECK(angle(turnToward(Vec3(1, 0, 0), Vec3(0, 1, 0), 4 * kDeg), Vec3(1, 0, 0)) == doctest::Approx(4 * kDeg).epsilon(1e-12));
  CHECK((turnToward(Vec3(1, 0, 0), Vec3(1, 0.01, 0).normalized(), 4 * kDeg) - Vec3(1, 0.01, 0).normalized()).norm() < 1e-15);
  CHECK(angle(turnToward(Vec3(1, 0, 0), Vec3(-1, 0, 0), 4 * kDeg), Vec3(1, 0, 0)) == doctest::Approx(4 * kDeg).epsilon(1e-12));
  CHECK((turnToward(Vec3(1, 0, 0), Vec3(-1, 0.1, 0).normalized(), 1.5 * std::numbers::pi) - Vec3(-1, 0.1, 0).normalized()).norm() < 1e-15);
  // In a world stepping at τ: a neighbour half a metre to the side asks for a 90° turn; the agent
  // turns θτ = 40°/s · 0.1 s = 4° and swims speed·τ.
  World w = worldFromText(R"({"format": "reel/1", "fps": 10, "substeps": 1, "duration": 1,
      "bodies": [{"type": "school", "name": "s", "noise": 0,
                  "agents": [{"position": [0, 0, 0], "heading": [1, 0, 0]}, {"position": [0, 0.5, 0], "heading": [1, 0, 0]}]}]})");
  run(w, 1);
  const School& s = schoolOf(w);
  CHECK(angle(s.v[0], Vec3(1, 0, 0)) == doctest::Approx(4 * kDeg).epsilon(1e-9));
  CHECK(s.v[0].y() < 0);
  CHECK(s.v[0].norm() == doctest::Approx(3.0).epsilon(1e-12));
  CHECK((s.x[0] - 0.3 * s.v[0].normalized()).norm() < 1e-12);  // c(t + τ) = c(t) + v(t + τ)·s·τ
}

TEST_CASE("order parameters on hand-built states") {
  std::vector<Vec3> x, v;
  for (int i = 0; i < 50; ++i) x.emplace_back(i, 0, 0), v.emplace_back(0, 0, 2);
  SchoolOrder o = schoolOrder(x, v);
  CHECK(o.polarization == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(o.milling == doctest::Approx(0.0).epsilon(1e-12));  // r̂ ∥ x, v̂ = z: crosses cancel in pairs
  CHECK(o.centroid.isApprox(Vec3(24.5, 0, 0)));
  CHECK(o.nearest == doctest::Approx(1.0));
  x.clear();
  v.clear();
  for (int i = 0; i < 64; ++i) {  // a ring swimming round: milling 1, no polarisation
    const double a = 2 * std::numbers::pi * i / 64;
    x.emplace_back(5 * std::cos(a), 5 * std::sin(a), 1);
    v.emplace_back(-std::sin(a), std::cos(a), 0);
  }
  o = schoolOrder(x, v);
  CHECK(o.milling == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(o.polarization < 1e-12);
  CHECK(o.nearest == doctest::Approx(10 * std::sin(std::numbers::pi / 64)).epsilon(1e-12));
}

// Couzin et al. (2002), Fig. 2 at Δr_a = r_a − r_o = 14: swarm at Δr_o = 0, torus at Δr_o = 1,
// dynamic parallel at Δr_o = 4, highly parallel at Δr_o = 14 (docs/schools.md has the sweep).
TEST_CASE("Couzin's collective states: swarm, torus, dynamic parallel, highly parallel") {
  for (int seed : {1, 2, 3}) {
    CAPTURE(seed);
    auto [p0, m0] = meanOrder(couzinScene(0, 14, seed, 150), 100);
    CHECK(p0 < 0.35);
    CHECK(m0 < 0.35);
    auto [p1, m1] = meanOrder(couzinScene(1, 14, seed, 150), 100);
    CHECK(m1 > 0.75);
    CHECK(p1 < 0.35);
    auto [p4, m4] = meanOrder(couzinScene(4, 14, seed, 150), 100);
    CHECK(p4 > 0.8);
    CHECK(m4 < 0.2);
    auto [p14, m14] = meanOrder(couzinScene(14, 14, seed, 150), 100);
    CHECK(p14 > 0.97);
    CHECK(p14 > p4);
  }
}

TEST_CASE("r_o keyed over time: a torus opens into a parallel group as the zone of orientation widens") {
  World w = worldFromText(R"({"format": "reel/1", "fps": 10, "substeps": 1, "duration": 200, "seed": 2,
      "bodies": [{"type": "school", "name": "s", "count": 100, "start": {"center": [0, 0, 0], "radius": 4},
                  "zones": {"repulsion": 1, "orientation": [{"time": 0, "value": 2}, {"time": 100, "value": 2}, {"time": 120, "value": 15}],
                            "attraction": 16}}]})");
  CHECK(schoolOf(w).desc.couzin.orientationAt(110) == doctest::Approx(8.5));
  run(w, 1000);
  const SchoolOrder torus = schoolOrder(schoolOf(w).x, schoolOf(w).v);
  run(w, 999);
  const SchoolOrder parallel = schoolOrder(schoolOf(w).x, schoolOf(w).v);
  CHECK(torus.milling > 0.7);
  CHECK(parallel.polarization > 0.95);
}

TEST_CASE("boids: separation keeps apart, alignment and cohesion make a flock; speeds stay in bounds") {
  World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 2, "duration": 20, "seed": 5,
      "bodies": [{"type": "school", "name": "s", "model": "boids", "count": 200, "start": {"center": [0, 0, 0], "radius": 6},
                  "separation": {"radius": 1, "weight": 2}, "alignment": {"radius": 3}, "cohesion": {"radius": 6},
                  "min_speed": 1, "max_speed": 3, "max_accel": 6}]})");
  const double p_start = schoolOrder(schoolOf(w).x, schoolOf(w).v).polarization;
  run(w, 600);
  const School& s = schoolOf(w);
  const SchoolOrder o = schoolOrder(s.x, s.v);
  CHECK(p_start < 0.2);
  CHECK(o.polarization > 0.75);  // one or a few flocks, each aligned
  CHECK(o.nearest > 0.4);
  for (const Vec3& v : s.v) {
    CHECK(v.norm() >= 1 - 1e-12);
    CHECK(v.norm() <= 3 + 1e-12);
  }
}

TEST_CASE("steering: no agent ever inside an object; bounds hold; a goal draws; a predator scatters") {
  SUBCASE("a school swims at a column and the floor, and is never inside either") {
    World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 3, "duration": 8, "seed": 2,
        "objects": [{"type": "plane", "point": [0, -3, 0]},
                    {"type": "capsule", "start": [8, -5, 0], "end": [8, 5, 0], "radius": 1.5},
                    {"type": "box", "center": [16, 0, 2], "size": [2, 4, 2]}],
        "bodies": [{"type": "school", "name": "s", "count": 300, "start": {"center": [0, 0, 0], "radius": 2},
                    "heading": [1, 0, 0], "zones": {"repulsion": 0.5, "orientation": 3, "attraction": 8}, "length": 0.4}]})");
    const auto& cols = w.colliders();
    int split = 0;  // frames with a fifth of the school on each side of the column, abreast of it
    for (int f = 0; f < 240; ++f) {
      run(w, 1);
      int left = 0, right = 0;
      for (const Vec3& x : schoolOf(w).x) {
        for (const Collider& c : cols) {
          double d;
          Vec3 n;
          if (c.distance(x, d, n)) REQUIRE(d > 0.05);  // the steering kept it clear: the last guard (0.04 m) never acted
        }
        if (std::abs(x.x() - 8) < 1.5) (x.z() < 0 ? left : right)++;
      }
      split += left > 60 && right > 60;
    }
    CHECK(split > 3);
    const School& s = schoolOf(w);
    const SchoolOrder o = schoolOrder(s.x, s.v);
    CHECK(o.centroid.x() > 10);  // they went past the column
    // and re-formed behind it: one group, every fish linked to the rest well inside the
    // orientation radius (within 2 m of another), not two halves.
    std::vector<int> parent(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) parent[i] = static_cast<int>(i);
    for (std::size_t i = 0; i < s.size(); ++i)
      for (std::size_t j = i + 1; j < s.size(); ++j)
        if ((s.x[i] - s.x[j]).norm() < 2) unite(parent, static_cast<int>(i), static_cast<int>(j));
    std::vector<int> size(s.size(), 0);
    for (std::size_t i = 0; i < s.size(); ++i) ++size[static_cast<std::size_t>(findRoot(parent, static_cast<int>(i)))];
    CHECK(*std::max_element(size.begin(), size.end()) >= 285);  // a stray or two may trail
  }
  SUBCASE("a school steers around other bodies, not only objects: a rope standing across its path") {
    // Zero gravity: a rope (its nodes 0.1 m in radius) stands across the school's path at x = 8;
    // the school sees its points as it sees a surface and keeps clear of them.
    World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 3, "duration": 8, "seed": 2, "gravity": [0, 0, 0], "integrator": "implicit_euler",
        "bodies": [{"type": "school", "name": "s", "count": 300, "start": {"center": [0, 0, 0], "radius": 2},
                    "heading": [1, 0, 0], "zones": {"repulsion": 0.5, "orientation": 3, "attraction": 8}, "length": 0.4},
                   {"type": "rope", "name": "post", "start": [8, -5, 0], "end": [8, 5, 0], "segments": 40, "mass": 1,
                    "stiffness": 2000, "damping": 0.5, "node_radius": 0.1}]})");
    // Agent-frames within 0.05 m of a node's surface: 33 when the school did not see the rope
    // (it met it head on), none now that it steers round it.
    int close = 0;
    for (int f = 0; f < 240; ++f) {
      run(w, 1);
      BodyView post;
      REQUIRE(w.bodies()[1]->view(post));
      for (const Vec3& x : schoolOf(w).x)
        for (const Vec3& p : post.positions) close += (x - p).norm() - 0.1 < 0.05;
    }
    MESSAGE("agent-frames within 0.05 m of the rope: " << close);
    CHECK(close == 0);
    CHECK(schoolOrder(schoolOf(w).x, schoolOf(w).v).centroid.x() > 10);  // and the school went past it
  }
  SUBCASE("a bounds box keeps the school in") {
    World w = worldFromText(R"({"format": "reel/1", "fps": 10, "substeps": 1, "duration": 60, "seed": 4,
        "bodies": [{"type": "school", "name": "s", "count": 100, "zones": {"repulsion": 1, "orientation": 10, "attraction": 20},
                    "bounds": {"min": [-15, -15, -15], "max": [15, 15, 15], "margin": 5}}]})");
    for (int f = 0; f < 600; ++f) {
      run(w, 1);
      for (const Vec3& x : schoolOf(w).x) REQUIRE(x.cwiseAbs().maxCoeff() < 16.5);
    }
  }
  SUBCASE("a goal draws the school to it") {
    World w = worldFromText(R"({"format": "reel/1", "fps": 10, "substeps": 1, "duration": 20, "seed": 4,
        "bodies": [{"type": "school", "name": "s", "count": 50, "goal": {"position": [40, 0, 0], "weight": 1, "informed": 0.5}}]})");
    run(w, 200);
    CHECK((schoolOrder(schoolOf(w).x, schoolOf(w).v).centroid - Vec3(40, 0, 0)).norm() < 10);
  }
  SUBCASE("agents flee a predator school inside the fear radius") {
    const std::string text = R"({"format": "reel/1", "fps": 10, "substeps": 1, "duration": 3, "seed": 4,
        "bodies": [{"type": "school", "name": "shark", "agents": [{"position": [-6, 0, 0], "heading": [1, 0, 0]}], "noise": 0,
                    "goal": {"position": [100, 0, 0], "weight": 10}, "speed": 4},
                   {"type": "school", "name": "fish", "count": 100, "start": {"center": [0, 0, 0], "radius": 3},
                    "heading": [1, 0, 0], "speed": 2, "zones": {"repulsion": 0.5, "orientation": 4, "attraction": 10})";
    World calm = worldFromText(text + "}]}"), scared = worldFromText(text + R"(, "predator": {"school": "shark", "fear_radius": 4}}]})");
    auto close = [](const World& w) {  // fish within 2 m of the shark
      const auto& b = w.bodies();
      const Vec3 shark = dynamic_cast<const SchoolBody&>(*b[0]).school().x[0];
      int n = 0;
      for (const Vec3& x : dynamic_cast<const SchoolBody&>(*b[1]).school().x) n += (x - shark).norm() < 2.0;
      return n;
    };
    int near_calm = 0, near_scared = 0;
    for (int f = 0; f < 30; ++f) {
      run(calm, 1);
      run(scared, 1);
      near_calm += close(calm);
      near_scared += close(scared);
    }
    CHECK(near_calm > 100);  // the shark swims through the calm school
    CHECK(near_scared < near_calm / 3);
  }
}

// Every point within r of a point lies in exactly one of its runs; the sorted copies are the
// points in order; the runs hold a few times the sphere's points; a second build of the same
// points (or of the points dealt in another order) gives the same order.
TEST_CASE("the row grid finds every neighbour once, in runs of a few times the sphere") {
  const double r = 1.0;
  auto cloud = [](int n, const Vec3& size, std::uint64_t seed) {
    std::vector<Vec3> p(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int k = 0; k < 3; ++k) p[i][k] = size[k] * uniformAt(seed, 7, 3 * i + static_cast<std::size_t>(k));
    return p;
  };
  std::vector<Vec3> far = cloud(300, Vec3(4, 4, 4), 3);  // two far clusters: the rows widen
  for (std::size_t i = 150; i < far.size(); ++i) far[i] += Vec3(0, 5000, -3000);
  std::vector<Vec3> line = cloud(400, Vec3(60, 0, 0), 4);  // one row
  std::vector<Vec3> bad = cloud(500, Vec3(6, 6, 6), 5);
  bad[7] = Vec3(NAN, 1, 1), bad[8] = Vec3(1, NAN, 1), bad[9] = Vec3(1, 1, INFINITY);
  const std::vector<std::pair<const char*, std::vector<Vec3>>> cases = {
      {"cube", cloud(3000, Vec3(10, 10, 10), 1)}, {"plane", cloud(2000, Vec3(20, 20, 0), 2)},
      {"far clusters", far}, {"line", line}, {"non-finite", bad}, {"one", cloud(1, Vec3(1, 1, 1), 6)}, {"none", {}}};
  for (const auto& [name, p] : cases) {
    CAPTURE(name);
    RowGrid g;
    g.build(p, r);
    REQUIRE(g.size() == p.size());
    std::vector<int> hit(p.size(), 0);
    for (std::size_t k = 0; k < p.size(); ++k) {
      const auto i = static_cast<std::size_t>(g.order()[k]);
      ++hit[i];
      if (p[i].allFinite()) CHECK((Vec3(g.x()[k], g.y()[k], g.z()[k]) == p[i]));
    }
    CHECK(std::count(hit.begin(), hit.end(), 1) == static_cast<long>(p.size()));  // a permutation
    double candidates = 0, neighbours = 0;
    int missed = 0, twice = 0, visits = 0, non_finite_found = 0, non_finite_runs = 0;
    g.visitRows(0, g.rows(), [&](std::uint32_t e, std::span<const RowGrid::Run> runs) {
      const auto i = static_cast<std::size_t>(g.order()[e]);
      ++visits;
      non_finite_runs += !p[i].allFinite() && !runs.empty();
      std::vector<int> seen(p.size(), 0);
      for (const RowGrid::Run& run : runs)
        for (std::uint32_t k = run[0]; k < run[1]; ++k) {
          const auto j = static_cast<std::size_t>(g.order()[k]);
          ++seen[j], candidates += 1;
          non_finite_found += !p[j].allFinite();
        }
      for (std::size_t j = 0; j < p.size(); ++j) {
        twice += seen[j] > 1;
        if (j != i && (p[j] - p[i]).squaredNorm() <= r * r) neighbours += 1, missed += seen[j] == 0;
      }
    });
    CHECK(missed == 0);
    CHECK(twice == 0);
    CHECK(visits == static_cast<int>(p.size()));  // every point once, the non-finite ones too
    CHECK(non_finite_found == 0);                  // which no one finds
    CHECK(non_finite_runs == 0);                   // and which find no one
    if (std::string(name) == "cube") CHECK(candidates < 5.0 * neighbours);  // 27 cells of side r: 6.4
    RowGrid again;
    std::vector<Vec3> reversed(p.rbegin(), p.rend());
    again.build(reversed, r);
    again.build(p, r);  // dealt in the reversed build's order
    CHECK((std::vector<std::int32_t>(again.order().begin(), again.order().end()) ==
           std::vector<std::int32_t>(g.order().begin(), g.order().end())));
  }
}

TEST_CASE("schools are bit-identical for 1 and 2 threads (Couzin and boids, with obstacles)") {
  for (const char* model : {"couzin", "boids"}) {
    CAPTURE(model);
    const std::string text = std::string(R"({"format": "reel/1", "fps": 30, "substeps": 1, "duration": 1, "seed": 9,
        "objects": [{"type": "sphere", "center": [0, 0, 12], "radius": 3}],
        "bodies": [{"type": "school", "name": "s", "model": ")") + model +
                             R"(", "count": 5000, "start": {"center": [0, 0, 0], "radius": 12}, "heading": [0, 0, 1], )" +
                             (std::string(model) == "couzin" ? R"("zones": {"repulsion": 0.5, "orientation": 1.5, "attraction": 2.5}}]})"
                                                             : R"("separation": {"radius": 0.5}, "alignment": {"radius": 1.5}, "cohesion": {"radius": 2.5}}]})");
    CHECK(runHash(text, 1, 10) == runHash(text, 2, 10));
  }
}

TEST_CASE("bad school scenes: a clear error with the JSON path") {
  auto errors = [](const std::string& body) {
    return badInputError(R"({"format": "reel/1", "duration": 1, "objects": [{"type": "sphere", "name": "rock", "radius": 1}], "bodies": [)" + body + "]}");
  };
  auto has = checkHas;
  const std::string s = R"({"type": "school", "name": "f", )";
  has(errors(s + R"("count": 10, "zones": {"repulsion": 3, "orientation": 2, "attraction": 5}})"), "/bodies/0/zones");
  has(errors(s + R"("count": 10, "zones": {"repulsion": -1}})"), "/bodies/0/zones/repulsion");
  has(errors(s + R"("count": 10, "field_of_view_deg": 0})"), "/bodies/0/field_of_view_deg");
  has(errors(s + R"("count": 10, "field_of_view_deg": 361})"), "/bodies/0/field_of_view_deg");
  has(errors(s + R"("count": 10, "speed": 0})"), "/bodies/0/speed");
  has(errors(s + R"("count": 0})"), "/bodies/0/count");
  has(errors(s + R"("count": 10, "max_agents": 5})"), "/bodies/0/count: 10 agents, more than max_agents = 5");
  // The default stops at a million at most (a school that still steps in about 1.5 s), said as such.
  has(errors(s + R"("count": 2000000})"), "/bodies/0/count: 2000000 agents, more than max_agents = ");
  has(errors(s + R"("count": 2000000})"), "(set \"max_agents\" for more, up to 50000000)");
  has(errors(s + R"("agents": []})"), "/bodies/0/agents");
  has(errors(s + R"("count": 10, "noise": -0.1})"), "/bodies/0/noise");
  has(errors(s + R"("count": 10, "predator": {"object": "reef"}})"), "/bodies/0/predator/object");
  has(errors(s + R"("count": 10, "predator": {"school": "shark"}})"), "/bodies/0/predator/school");
  has(errors(s + R"("count": 10, "goal": {"weight": 1}})"), "/bodies/0/goal/position");
  has(errors(s + R"("count": 10, "goal": {"path": [{"time": 1, "position": [0,0,0]}, {"time": 1, "position": [1,0,0]}]}})"), "/bodies/0/goal/path/1/time");
  has(errors(s + R"("count": 10, "max_speed": 4})"), "/bodies/0/max_speed");
  has(errors(s + R"("count": 10, "model": "boids", "min_speed": 5, "max_speed": 4})"), "/bodies/0/min_speed");
  has(errors(s + R"("count": 10, "heading": [0, 0, 0]})"), "/bodies/0/heading");
  has(errors(s + R"("count": 10, "model": "flock"})"), "/bodies/0/model");
  has(errors(s + R"("count": 10, "zones": {"repulsion": 1, "orientation": [{"time": 0, "value": 2}, {"time": 5, "value": 30}], "attraction": 20}})"), "/bodies/0/zones/orientation");
  has(errors(s + R"("count": 10, "zones": {"orientation": [{"time": 2, "value": 2}, {"time": 1, "value": 3}]}})"), "/bodies/0/zones/orientation/1/time");
  // A predator object that exists is fine.
  CHECK(app::parseScene(R"({"format": "reel/1", "duration": 1, "objects": [{"type": "sphere", "name": "rock", "radius": 1}], "bodies": [)" + s +
                            R"("count": 10, "predator": {"object": "rock"}}]})", "s.json").ok());
}
