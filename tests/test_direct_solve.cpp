// The implicit solve's direct path (sim/skyline.h): envelope Cholesky against a dense one, the
// pieces a network splits into, the same step as a tight CG, auto's choice, and the scene key.
#include <doctest/doctest.h>

#include <Eigen/Cholesky>

#include <random>

#include "helpers.h"
#include "sim/fish/fish.h"
#include "sim/forces.h"
#include "sim/grid.h"
#include "sim/skyline.h"

using namespace reel;
using namespace reel::test;

namespace {

// The nodes' couplings in compressed rows: the springs' own incidence (sim/mass_spring.h).
Incidence graph(int n, const std::vector<std::array<int, 2>>& edges) {
  Springs sp;
  for (auto [a, b] : edges) sp.add(a, b, 1.0, 0.0, 1.0);
  Incidence inc;
  inc.build(static_cast<std::size_t>(n), sp);
  return inc;
}

// `count` fish of the template side by side, moving and bent out of rest.
MassSpringDesc school(int count) {
  const FishTemplate t = makeFishTemplate(0.3, 1000.0);
  MassSpringDesc d;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int f = 0; f < count; ++f) {
    const int base = static_cast<int>(d.nodes.size());
    for (int i = 0; i < kFishNodes; ++i) {
      const Vec3 jitter = 0.01 * Vec3(u(rng), u(rng), u(rng));
      d.nodes.push_back({t.x[static_cast<std::size_t>(i)] + Vec3(0.5 * f, 0, 0) + jitter, Vec3(u(rng), u(rng), u(rng)),
                         t.mass[static_cast<std::size_t>(i)], 0.01, false});
    }
    for (std::size_t s = 0; s < t.springs.size(); ++s)
      d.springs.push_back({base + t.springs.a[s], base + t.springs.b[s], t.springs.stiffness[s], t.springs.damping[s], t.springs.rest[s]});
  }
  return d;
}

}  // namespace

TEST_CASE("envelope Cholesky: a sparse positive definite system solved as a dense Cholesky solves it") {
  // 12 nodes: a chain with a few longer couplings (3 and 5 apart), random blocks, dominant diagonal.
  const int n = 12;
  std::vector<std::array<int, 2>> edges;
  for (int i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1});
  edges.push_back({2, 5}), edges.push_back({4, 9}), edges.push_back({7, 10});
  const Incidence g = graph(n, edges);
  SkylinePlan plan;
  const std::vector<std::uint8_t> fixed(n, 0);
  plan.build(n, g.start.data(), g.other.data(), fixed.data());
  REQUIRE(plan.pieces() == 1);
  CHECK(plan.first[9] == 4);  // the envelope reaches the lowest coupled node
  CHECK(plan.first[10] == 7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  SkylineFactor F;
  F.begin(plan, 0);
  for (auto [a, b] : edges) {
    Mat3 C;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) C(r, c) = u(rng);
    const int i = std::max(a, b), j = std::min(a, b);
    A.block<3, 3>(3 * i, 3 * j) += C;
    A.block<3, 3>(3 * j, 3 * i) += C.transpose();
    F.add(i, j, C);
  }
  for (int i = 0; i < n; ++i) {
    Mat3 S;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) S(r, c) = u(rng);
    const Mat3 D = S * S.transpose() + 8.0 * Mat3::Identity();
    A.block<3, 3>(3 * i, 3 * i) += D;
    F.add(i, i, D);
  }
  REQUIRE(F.factor());
  Eigen::VectorXd b(3 * n);
  for (int r = 0; r < 3 * n; ++r) b[r] = u(rng);
  const Eigen::VectorXd want = A.llt().solve(b);
  Eigen::VectorXd x = b;
  F.solve(x.data());
  CHECK((x - want).norm() <= 1e-12 * want.norm());
  CHECK((A * x - b).norm() <= 1e-12 * b.norm());

  // Not positive definite: refused, not solved.
  SkylineFactor G;
  G.begin(plan, 0);
  G.add(0, 0, Mat3::Identity());
  G.add(1, 0, 2.0 * Mat3::Identity());
  for (int i = 1; i < n; ++i) G.add(i, i, Mat3::Identity());
  CHECK_FALSE(G.factor());
}

TEST_CASE("envelope Cholesky, four pieces of one envelope side by side: the same bits as one by one; a failed lane named alone") {
  // Five chains of 6 nodes with a coupling 3 apart, then a chain of 4: pieces 0-3 go together,
  // piece 4 (fifth of its kind) and piece 5 (another envelope) alone.
  std::vector<std::array<int, 2>> edges;
  auto chain = [&](int base, int n) {
    for (int i = 0; i + 1 < n; ++i) edges.push_back({base + i, base + i + 1});
    if (n >= 6) edges.push_back({base + 1, base + 4});
  };
  for (int c = 0; c < 5; ++c) chain(6 * c, 6);
  chain(30, 4);
  const int n = 34;
  const Incidence g = graph(n, edges);
  const std::vector<std::uint8_t> fixed(n, 0);
  SkylinePlan plan;
  plan.build(n, g.start.data(), g.other.data(), fixed.data());
  REQUIRE(plan.pieces() == 6);
  CHECK(plan.batch_start == std::vector<int>{0, 4, 5, 6});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto fill = [&](std::size_t p, bool broken, auto&& add) {
    const int k0 = plan.piece_start[p], size = plan.piece_start[p + 1] - k0;
    for (auto [a, b] : edges) {
      if (plan.local[static_cast<std::size_t>(a)] < 0 || a < plan.nodes[static_cast<std::size_t>(k0)] ||
          a > plan.nodes[static_cast<std::size_t>(k0 + size - 1)])
        continue;
      Mat3 C;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) C(r, c) = u(rng);
      add(std::max(plan.local[static_cast<std::size_t>(a)], plan.local[static_cast<std::size_t>(b)]),
          std::min(plan.local[static_cast<std::size_t>(a)], plan.local[static_cast<std::size_t>(b)]), C);
    }
    for (int i = 0; i < size; ++i) add(i, i, (broken && i == 3 ? -1.0 : 12.0) * Mat3::Identity());
  };
  for (const int broken : {-1, 2}) {
    CAPTURE(broken);
    SkylineFactor one[4];
    SkylineBatch four;
    four.begin(plan, 0);
    std::vector<std::vector<double>> b(4, std::vector<double>(18));
    std::vector<LaneSlot> b4(18);
    for (int l = 0; l < 4; ++l) {
      const std::mt19937 at = rng;
      one[l].begin(plan, static_cast<std::size_t>(l));
      fill(static_cast<std::size_t>(l), l == broken, [&](int i, int j, const Mat3& C) { one[l].add(i, j, C); });
      rng = at;  // (the same blocks again, into the lane)
      fill(static_cast<std::size_t>(l), l == broken, [&](int i, int j, const Mat3& C) { four.add(l, i, j, C); });
      for (int r = 0; r < 18; ++r) b[static_cast<std::size_t>(l)][static_cast<std::size_t>(r)] = b4[static_cast<std::size_t>(r)].v[l] = u(rng);
    }
    const unsigned bad = four.factor();
    CHECK(bad == (broken < 0 ? 0u : 1u << broken));
    if (broken >= 0) {
      CHECK_FALSE(one[broken].factor());
      continue;
    }
    four.solve(b4.data());
    for (int l = 0; l < 4; ++l) {
      REQUIRE(one[l].factor());
      one[l].solve(b[static_cast<std::size_t>(l)].data());
      for (int r = 0; r < 18; ++r) CHECK(b[static_cast<std::size_t>(l)][static_cast<std::size_t>(r)] == b4[static_cast<std::size_t>(r)].v[l]);
    }
  }
}

TEST_CASE("direct solve: the pieces are the free nodes joined by couplings; a fixed node splits a chain") {
  // A chain 0-1-2-3-4 with node 2 fixed, a pair 5-6, and node 7 alone.
  const Incidence g = graph(8, {{{0, 1}}, {{1, 2}}, {{2, 3}}, {{3, 4}}, {{5, 6}}});
  std::vector<std::uint8_t> fixed(8, 0);
  fixed[2] = 1;
  SkylinePlan plan;
  plan.build(8, g.start.data(), g.other.data(), fixed.data());
  REQUIRE(plan.pieces() == 4);
  CHECK(plan.piece_start == std::vector<int>{0, 2, 4, 6, 7});
  CHECK(plan.nodes == std::vector<int>{0, 1, 3, 4, 5, 6, 7});
  CHECK(plan.local == std::vector<int>{0, 1, -1, 0, 1, 0, 1, 0});
  CHECK(plan.first == std::vector<int>{0, 0, 0, 0, 0, 0, 0});
}

TEST_CASE("direct solve: a school of fish steps as a tight CG steps it; auto takes it for fish, CG for a sheet") {
  const MassSpringDesc d = school(3);
  auto run = [&](LinearSolver solver, int* iterations) {
    System s(d, Vec3(0, -9.8, 0));
    s.implicit = {1e-13, 5000, true, solver};
    StepStats stats;
    for (int k = 0; k < 20; ++k) {
      integrate(IntegratorKind::ImplicitEuler, s.dyn, s.state.x, s.state.v, 1.0 / 300.0, s.ws, s.implicit, &stats);
      iterations[k] = stats.cg_iterations;
    }
    return s.state;
  };
  int it_cg[20], it_direct[20], it_auto[20];
  const MassSpringState cg = run(LinearSolver::Cg, it_cg), direct = run(LinearSolver::Direct, it_direct),
                        automatic = run(LinearSolver::Auto, it_auto);
  double dx = 0, dv = 0, vmax = 0;
  for (std::size_t i = 0; i < cg.x.size(); ++i) {
    dx = std::max(dx, (direct.x[i] - cg.x[i]).norm());
    dv = std::max(dv, (direct.v[i] - cg.v[i]).norm());
    vmax = std::max(vmax, cg.v[i].norm());
  }
  CAPTURE(dx);
  CAPTURE(dv);
  // (CG solves the system with the springs' blocks rounded to single precision, 6·10⁻⁸ of a
  // block; the direct solve takes them in double: the steps differ by about that much.)
  CHECK(dv <= 1e-6 * vmax);
  CHECK(dx <= 1e-7);
  CHECK(it_cg[19] > 10);  // (the CG run did iterate)
  CHECK(it_direct[19] == 0);
  CHECK(it_auto[19] == 0);  // a fish's factor costs less than a few CG iterations
  CHECK(automatic.x == direct.x);

  // A 24 × 24 sheet: one piece whose envelope is a row wide; auto leaves it to CG.
  MassSpringDesc sheet;
  const int m = 24;
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < m; ++c) sheet.nodes.push_back({Vec3(0.02 * c, 0, 0.02 * r), Vec3::Zero(), 1e-3, 0.0, r == 0});
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < m; ++c) {
      if (c + 1 < m) sheet.springs.push_back({r * m + c, r * m + c + 1, 50.0, 0.01, -1.0});
      if (r + 1 < m) sheet.springs.push_back({r * m + c, (r + 1) * m + c, 50.0, 0.01, -1.0});
    }
  System s(sheet, Vec3(0, -9.8, 0));
  s.implicit = {1e-6, 1000, true, LinearSolver::Auto};
  StepStats stats;
  integrate(IntegratorKind::ImplicitEuler, s.dyn, s.state.x, s.state.v, 1.0 / 150.0, s.ws, s.implicit, &stats);
  CHECK(stats.cg_iterations > 0);
}

TEST_CASE("direct solve: fish four at a time, their springs linearised four at a time, get the bits each gets alone; a failed one among four goes to CG") {
  // Five fish: one batch of four and one alone. Fish 2 has a spring with coincident ends (no
  // force, no direction); the predictor is on (a compressed spring's force at the predicted
  // positions). In the school a fish's 91 springs fall into the groups of four at another
  // offset than alone (91 = 4·22 + 3), so a spring takes another lane, or the last group padded
  // with its last spring, in the school than alone.
  MassSpringDesc d = school(5);
  d.nodes[2 * kFishNodes + 2].position = d.nodes[2 * kFishNodes + 1].position;  // ring 0's first two corners
  const double h = 1.0 / 300.0;
  auto solve = [&](const MassSpringDesc& desc, std::vector<Vec3>& rhs, std::vector<Vec3>& dv) {
    System s(desc, Vec3(0, -9.8, 0));
    const std::size_t n = s.model.nodes();
    rhs.assign(n, Vec3::Zero()), dv.assign(n, Vec3::Zero());
    std::vector<Mat3> pinv(n);
    s.dyn.setLinearSolver(LinearSolver::Direct);
    s.dyn.setPredictor(true);
    s.dyn.linearize(s.state.x.data(), s.state.v.data(), s.state.v.data(), h, rhs.data(), pinv.data());
    return s.dyn.solveDirect(rhs.data(), dv.data());
  };
  std::vector<Vec3> rhs, dv;
  REQUIRE(solve(d, rhs, dv));
  const std::size_t springs = d.springs.size() / 5;
  for (int f = 0; f < 5; ++f) {
    CAPTURE(f);
    MassSpringDesc one;
    for (int i = 0; i < kFishNodes; ++i) one.nodes.push_back(d.nodes[static_cast<std::size_t>(f * kFishNodes + i)]);
    for (std::size_t k = 0; k < springs; ++k) {
      SpringDesc sd = d.springs[static_cast<std::size_t>(f) * springs + k];
      sd.a -= f * kFishNodes, sd.b -= f * kFishNodes;
      one.springs.push_back(sd);
    }
    std::vector<Vec3> rhs1, dv1;
    REQUIRE(solve(one, rhs1, dv1));
    for (int i = 0; i < kFishNodes; ++i) {
      CHECK(rhs1[static_cast<std::size_t>(i)] == rhs[static_cast<std::size_t>(f * kFishNodes + i)]);
      CHECK(dv1[static_cast<std::size_t>(i)] == dv[static_cast<std::size_t>(f * kFishNodes + i)]);
    }
  }
  // Fish 1 not positive definite: the batch names it, and the step goes to CG.
  d.springs[springs].stiffness = -1e9;
  CHECK_FALSE(solve(d, rhs, dv));
}

TEST_CASE("direct solve: a pinned chain with a drag toward a flow, by implicit Euler and BDF2, as a tight CG; after a pin and a new spring too") {
  // 30 nodes, neighbours and next-but-one joined, node 0 fixed; each node a drag D (symmetric,
  // not diagonal) toward a flow.
  MassSpringDesc d;
  const int n = 30;
  for (int i = 0; i < n; ++i)
    d.nodes.push_back({Vec3(0.05 * i, 0.01 * std::sin(i), 0.003 * i), Vec3(0.1 * std::cos(i), 0, 0.05), 0.01, 0.001, i == 0});
  for (int i = 0; i + 1 < n; ++i) d.springs.push_back({i, i + 1, 400.0, 0.05, -1.0});
  for (int i = 0; i + 2 < n; ++i) d.springs.push_back({i, i + 2, 40.0, 0.01, -1.0});
  Mat3 D;
  D << 0.02, 0.005, 0.0, 0.005, 0.03, 0.004, 0.0, 0.004, 0.01;
  const std::vector<Mat3> drag(n, D);
  const std::vector<Vec3> flow(n, D * Vec3(0.3, 0, -0.1));
  for (IntegratorKind k : {IntegratorKind::ImplicitEuler, IntegratorKind::Bdf2}) {
    CAPTURE(integratorName(k));
    auto run = [&](LinearSolver solver, int* last_iterations) {
      System s(d, Vec3(0, -9.8, 0));
      s.dyn.setNodeDrag(drag.data(), flow.data());
      s.implicit = {1e-13, 5000, true, solver};
      StepStats stats;
      for (int step = 0; step < 30; ++step) {
        if (step == 10) {  // pin node 15 (the chain is now two pieces)
          s.model.fixed[15] = 1, s.model.inv_mass[15] = 0.0, s.state.v[15].setZero();
        }
        if (step == 20) {  // a new spring joins nodes 3 and 25 (one piece again, with node 15 pinned)
          s.model.springs.add(3, 25, 50.0, 0.01, (s.state.x[25] - s.state.x[3]).norm());
          s.model.incidence.build(s.model.nodes(), s.model.springs);
        }
        integrate(k, s.dyn, s.state.x, s.state.v, 1.0 / 200.0, s.ws, s.implicit, &stats);
      }
      *last_iterations = stats.cg_iterations;
      return s.state;
    };
    int it_cg = 0, it_direct = -1;
    const MassSpringState cg = run(LinearSolver::Cg, &it_cg), direct = run(LinearSolver::Direct, &it_direct);
    CHECK(it_cg > 0);
    CHECK(it_direct == 0);
    double dv = 0, vmax = 0;
    for (int i = 0; i < n; ++i) dv = std::max(dv, (direct.v[i] - cg.v[i]).norm()), vmax = std::max(vmax, cg.v[i].norm());
    CAPTURE(dv);
    CHECK(dv <= 1e-6 * vmax);
    CHECK(direct.v[15] == Vec3::Zero());
    CHECK(direct.v[0] == Vec3::Zero());
  }
}

TEST_CASE("the neighbour grid lists no empty box") {
  BoxGrid g;
  std::vector<Vec3> lo = {Vec3(0, 0, 0), Vec3::Zero(), Vec3(0, 1, 0), Vec3(0, std::nan(""), 0)};
  std::vector<Vec3> hi = {Vec3(0.1, 0.1, 0.1), Vec3::Zero(), Vec3(0.1, 0.5, 0.1), Vec3(0.1, 0.1, 0.1)};
  BoxGrid::unlist(lo[1], hi[1]);
  g.build(lo, hi, 0.2);
  CHECK(g.entries() == 1);  // only the first: the second is empty, the third inverted in y, the fourth NaN
  std::vector<int> found;
  g.forEachNear(Vec3(0.05, 0.05, 0.05), [&](int k) { found.push_back(k); });
  CHECK(found == std::vector<int>{0});
}

TEST_CASE("direct solve: a piece that is not positive definite goes back to CG") {
  MassSpringDesc d = school(1);
  d.springs[0].stiffness = -1e9;  // (refused in a scene; here to break A's definiteness)
  System s(d, Vec3(0, -9.8, 0));
  std::vector<Vec3> rhs(s.model.nodes()), dv(s.model.nodes()), q(s.model.nodes());
  std::vector<Mat3> pinv(s.model.nodes());
  s.dyn.setLinearSolver(LinearSolver::Direct);
  s.dyn.linearize(s.state.x.data(), s.state.v.data(), s.state.v.data(), 1.0 / 300.0, rhs.data(), pinv.data());
  CHECK_FALSE(s.dyn.solveDirect(rhs.data(), dv.data()));
  // CG's arrays are then ready: a product with A couples the nose to the ring behind it.
  std::vector<Vec3> e(s.model.nodes(), Vec3::Zero());
  e[0] = Vec3(1, 0, 0);
  s.dyn.applySystem(e.data(), q.data());
  CHECK(q[0].x() > 0.0);
  CHECK(q[1].norm() > 0.0);
  d.springs[0].stiffness = 1e3;
  System t(d, Vec3(0, -9.8, 0));
  t.dyn.setLinearSolver(LinearSolver::Direct);
  t.dyn.linearize(t.state.x.data(), t.state.v.data(), t.state.v.data(), 1.0 / 300.0, rhs.data(), pinv.data());
  CHECK(t.dyn.solveDirect(rhs.data(), dv.data()));
  t.dyn.setLinearSolver(LinearSolver::Cg);
  t.dyn.linearize(t.state.x.data(), t.state.v.data(), t.state.v.data(), 1.0 / 300.0, rhs.data(), pinv.data());
  CHECK_FALSE(t.dyn.solveDirect(rhs.data(), dv.data()));
}

TEST_CASE("implicit.solver: auto, cg or direct; anything else is named with its path") {
  const std::string base = R"({"format": "reel/1", "duration": 1, "integrator": "implicit_euler")";
  CHECK(sceneFromText(base + "}").implicit.solver == LinearSolver::Auto);
  CHECK(sceneFromText(base + R"(, "implicit": {"solver": "cg"}})").implicit.solver == LinearSolver::Cg);
  CHECK(sceneFromText(base + R"(, "implicit": {"solver": "direct"}})").implicit.solver == LinearSolver::Direct);
  checkHas(badInputError(base + R"(, "implicit": {"solver": "gauss"}})"), "/implicit/solver");
}

TEST_CASE("the four-lane spring force and Jacobians give each lane the bits of the one-spring forms") {
  // Stretched, compressed, coincident ends and an arbitrary spring, one a lane.
  const Vec3 xa[4] = {Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(0.5, 0.5, 0.5), Vec3(-0.3, 0.7, 0.11)};
  const Vec3 xb[4] = {Vec3(0.3, 1.2, -0.4), Vec3(1.01, 2.02, 2.97), Vec3(0.5, 0.5, 0.5), Vec3(0.9, -0.2, 0.35)};
  const Vec3 va[4] = {Vec3(0.1, 0, 0), Vec3(0, -1, 0.5), Vec3(1, 1, 1), Vec3(0.2, 0.3, -0.4)};
  const Vec3 vb[4] = {Vec3(0, 0.2, 0), Vec3(0.3, 0, 0), Vec3(-1, 0, 2), Vec3(-0.5, 0.1, 0.9)};
  const double k[4] = {100, 2500, 40, 7.5}, damp[4] = {0.5, 3, 0.1, 0}, rest[4] = {0.9, 0.1, 0.2, 1.3};
  auto lanes = [](const Vec3* v) {
    L3 l;
    for (int i = 0; i < 4; ++i) l.x[i] = v[i].x(), l.y[i] = v[i].y(), l.z[i] = v[i].z();
    return l;
  };
  auto lane4 = [](const double* v) { return Lane4{v[0], v[1], v[2], v[3]}; };
  const SpringJacobians4 j4 = springJacobians4(lanes(xa), lanes(xb), lane4(rest));
  const L3 f4 = springForce4(lanes(xa), lanes(xb), lanes(va), lanes(vb), lane4(k), lane4(damp), lane4(rest));
  for (int i = 0; i < 4; ++i) {
    CAPTURE(i);
    const SpringJacobians j = springJacobians(xa[i], xb[i], rest[i]);
    const Vec3 f = springForce(xa[i], xb[i], va[i], vb[i], k[i], damp[i], rest[i]);
    CHECK(j4.u.x[i] == j.u.x());
    CHECK(j4.u.y[i] == j.u.y());
    CHECK(j4.u.z[i] == j.u.z());
    CHECK(j4.t[i] == j.t);
    CHECK(f4.x[i] == f.x());
    CHECK(f4.y[i] == f.y());
    CHECK(f4.z[i] == f.z());
  }
  CHECK(springJacobians(xa[2], xb[2], rest[2]).u == Vec3::Zero());  // coincident: no direction, no force
  CHECK(springForce(xa[2], xb[2], va[2], vb[2], k[2], damp[2], rest[2]) == Vec3::Zero());
}
