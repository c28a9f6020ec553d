// The particle fluid: the pair force against its formula, the force loop against brute force,
// momentum, a closed box, the left-pack, the neighbour grid against brute force, determinism, adhesion on an
// overhang, per-species surfaces, mixing and separation (scenes and bad input: test_fluid_scenes.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

#include "core/isosurface.h"
#include "core/lanes.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/random.h"
#include "fluid_helpers.h"

using namespace reel;
using namespace reel::test;

TEST_CASE("the pair force matches g_ij = m_i m_j (x_i - x_j)(-alpha/(r+eps)^a + beta/r^b) for every species pair") {
  // Three species, one pair overridden; two particles at several distances, no gravity.
  struct Sp { double m, alpha, beta, a, b, eps, cut; };
  const Sp sp[3] = {{0.01, 200, 0.1, 2, 4, 0.0, 0.05}, {0.02, 100, 0.3, 2, 4, 0.002, 0.04}, {0.005, 50, 0.02, 1.5, 3.5, 0.001, 0.06}};
  const std::string species = R"([
    {"name": "A", "mass": 0.01, "alpha": 200, "beta": 0.1, "cutoff": 0.05},
    {"name": "B", "mass": 0.02, "alpha": 100, "beta": 0.3, "epsilon": 0.002, "cutoff": 0.04},
    {"name": "C", "mass": 0.005, "alpha": 50, "beta": 0.02, "a": 1.5, "b": 3.5, "epsilon": 0.001, "cutoff": 0.06}])";
  const std::string interactions = R"([{"species": ["C", "A"], "alpha": 10, "b": 5}])";
  for (int s = 0; s < 3; ++s)
    for (int t = 0; t < 3; ++t)
      for (double r : {0.008, 0.015, 0.025, 0.035, 0.044, 0.046, 0.07}) {
        CAPTURE(s);
        CAPTURE(t);
        CAPTURE(r);
        const Vec3 xi(0.1, 0.2, 0.3), xj = xi + r * Vec3(0.48, -0.6, 0.64);
        const char* names[3] = {"A", "B", "C"};
        const SceneDesc scene = sceneFromText(std::string(R"({"format": "reel/1", "duration": 0.1,
          "gravity": [0, 0, 0], "bodies": [{"type": "fluid", "name": "f", "radius": 0.001, "species": )") + species +
                            R"(, "interactions": )" + interactions + R"(, "particles": [
            {"species": ")" + names[s] + R"(", "positions": [)" + vec(xi) + R"(]},
            {"species": ")" + names[t] + R"(", "positions": [)" + vec(xj) + R"(]}]}]})");
        // One step of a picosecond: the forces it computes are those of the positions above.
        Fluid fl = buildFluid(scene.bodies[0].as<FluidDesc>(), "f", {}, 0);
        stepFluid(fl, {}, Vec3::Zero(), 1e-12, 0.0, 1e-12);
        // Expected: the mean of the two species' parameters, C–A overridden.
        auto mean = [&](double Sp::*f) { return 0.5 * (sp[s].*f + sp[t].*f); };
        double alpha = mean(&Sp::alpha), beta = mean(&Sp::beta), a = mean(&Sp::a), b = mean(&Sp::b);
        const double eps = mean(&Sp::eps), cut = mean(&Sp::cut);
        if ((s == 0 && t == 2) || (s == 2 && t == 0)) {
          alpha = 10;
          b = 5;
        }
        const Vec3 d = xi - xj;
        // Inside kRepulsionCap of the rest distance the force keeps its magnitude there (PairParams::cap_r).
        const double rc = std::max(r, kRepulsionCap * restDistance(makePair(alpha, beta, a, b, eps, cut, 0)));
        const Vec3 g = r < cut ? Vec3(sp[s].m * sp[t].m * (d / r) * rc * (-alpha / std::pow(rc + eps, a) + beta / std::pow(rc, b)))
                               : Vec3::Zero();
        // Slots may be re-sorted; particle 0 (i) and 1 (j) by their ids.
        const std::size_t si = fl.id[0] == 0 ? 0 : 1, sj = 1 - si;
        const Vec3 f = fl.f[si];
        CHECK((f - g).norm() <= 1e-12 * std::max(1.0, g.norm()));
        if (r < cut) CHECK(f.dot(d) != 0.0);
        // Newton's third law: j feels the opposite force.
        CHECK((fl.f[sj] + f).norm() <= 1e-12 * std::max(1.0, g.norm()));
      }
  // Sign: repulsive inside the rest distance, attractive outside it.
  const PairParams p = makePair(200, 0.1, 2, 4, 0, 0.05, 0);
  const double r0 = restDistance(p);
  CHECK(r0 == doctest::Approx(std::sqrt(0.1 / 200)).epsilon(1e-9));
  CHECK(pairForce(p, 1, 1, Vec3(0.9 * r0, 0, 0), Vec3::Zero()).x() > 0);
  CHECK(pairForce(p, 1, 1, Vec3(1.1 * r0, 0, 0), Vec3::Zero()).x() < 0);
  CHECK(pairForce(p, 1, 1, Vec3(0.0501, 0, 0), Vec3::Zero()).isZero());
  // Closer than kRepulsionCap·r0 the repulsion stops growing: the same force there, at r0/5 and
  // at 10⁻⁷ m, still pushing apart.
  CHECK(p.cap_r == doctest::Approx(kRepulsionCap * r0));
  const double at_cap = pairForce(p, 1, 1, Vec3(kRepulsionCap * r0, 0, 0), Vec3::Zero()).x();
  CHECK(at_cap > 0);
  CHECK(pairForce(p, 1, 1, Vec3(0.2 * r0, 0, 0), Vec3::Zero()).x() == doctest::Approx(at_cap));
  CHECK(pairForce(p, 1, 1, Vec3(1e-7, 0, 0), Vec3::Zero()).x() == doctest::Approx(at_cap));
  CHECK(pairForce(p, 1, 1, Vec3(0.5 * r0, 0, 0), Vec3::Zero()).x() < at_cap);
}

TEST_CASE("the force loop equals a brute-force sum of pair and viscous forces (vector and scalar paths, threads)") {
  // A dense random cloud of 4,500 particles with random velocities (more than one list-building
  // chunk, and parallel loops): one species and two with the seed's exponents take the four-lane
  // loop (lists of every length mod 4, one parameter row or pairs of mixed species); with epsilon
  // on the second species every particle takes the scalar loop.
  struct Config { int species; const char* eps; bool seed_form; };
  for (const Config cfg : {Config{1, "0", true}, Config{2, "0", true}, Config{2, "0.001", false}}) {
    CAPTURE(cfg.species);
    CAPTURE(cfg.eps);
    const int n = 4500;
    std::vector<Vec3> x0(n), v0(n);
    std::string pos[2], vel[2];
    auto speciesOf = [&](int i) { return cfg.species == 2 && i % 3 == 0 ? 1 : 0; };
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        x0[i][a] = 0.223 * uniformAt(21, static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(i));
        v0[i][a] = uniformAt(21, 10 + static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(i)) - 0.5;
      }
      const int sp = speciesOf(i);
      pos[sp] += (pos[sp].empty() ? "" : ",") + vec(x0[i]);
      vel[sp] += (vel[sp].empty() ? "" : ",") + vec(v0[i]);
    }
    // Particles are created species by species: ids 0.. are water, then oil.
    std::vector<Vec3> xs, vs;
    std::vector<int> ss;
    for (int sp = 0; sp < cfg.species; ++sp)
      for (int i = 0; i < n; ++i)
        if (speciesOf(i) == sp) xs.push_back(x0[i]), vs.push_back(v0[i]), ss.push_back(sp);
    std::string bodies = std::string(R"({"format": "reel/1", "duration": 0.1, "gravity": [0, -9.81, 0],
      "bodies": [{"type": "fluid", "name": "f", "radius": 0.001, "species": [)") + kWater;
    if (cfg.species == 2)
      bodies += std::string(R"(, {"name": "oil", "mass": 0.006, "alpha": 150, "beta": 0.07, "cutoff": 0.03, "viscosity": 5, "epsilon": )") + cfg.eps + "}";
    bodies += R"(], "particles": [{"species": "water", "positions": [)" + pos[0] + "], \"velocities\": [" + vel[0] + "]}";
    if (cfg.species == 2)
      bodies += R"(, {"species": "oil", "positions": [)" + pos[1] + "], \"velocities\": [" + vel[1] + "]}";
    bodies += "]}]}";
    const SceneDesc scene = sceneFromText(bodies);
    const Fluid start = buildFluid(scene.bodies[0].as<FluidDesc>(), "f", {}, 0);
    // Which loop runs: the four-lane one for rows whose every pair has the seed's form.
    for (const PairParams& p : start.pairs) CHECK(p.seed_form == (cfg.seed_form || &p == &start.pairs[0]));
    Fluid fl = start;
    const Vec3 g(0, -9.81, 0);
    stepFluid(fl, {}, g, 1e-12, 0.0, 1e-12);  // the forces of the positions and velocities above
    const auto S = static_cast<std::size_t>(cfg.species);
    int checked = 0;
    for (std::size_t k = 0; k < fl.size(); ++k) {
      const auto i = static_cast<std::size_t>(fl.id[k]);
      const double mi = fl.species_mass[static_cast<std::size_t>(ss[i])];
      Vec3 expect = mi * g, scale = (mi * g).cwiseAbs();
      for (std::size_t j = 0; j < xs.size(); ++j) {
        if (j == i) continue;
        const PairParams& p = fl.pairs[static_cast<std::size_t>(ss[i]) * S + static_cast<std::size_t>(ss[j])];
        const double r = (xs[i] - xs[j]).norm();
        if (r >= p.cutoff) continue;
        const double mj = fl.species_mass[static_cast<std::size_t>(ss[j])];
        const Vec3 pair = pairForce(p, mi, mj, xs[i], xs[j]);
        const Vec3 viscous = p.viscosity * mi * mj / (mi + mj) * (1.0 - r / p.cutoff) * (vs[j] - vs[i]);
        expect += pair + viscous;
        scale += pair.cwiseAbs() + viscous.cwiseAbs();
      }
      for (int a = 0; a < 3; ++a) CHECK(std::abs(fl.f[k][a] - expect[a]) <= 1e-12 * scale[a] + 1e-300);
      checked += fl.nbr_start[k + 1] > fl.nbr_start[k] + 4;
    }
    CHECK(checked > n / 2);  // most particles have several neighbours
    // The same steps on 1 and 2 threads give the same bits.
    auto run = [&](int threads) {
      test::ParallelForTest parallel(threads);
      Fluid f = start;
      for (int k = 0; k < 5; ++k) stepFluid(f, {}, g, 1e-4, k * 1e-4, (k + 1) * 1e-4);
      return f.x;
    };
    CHECK(run(1) == run(2));
  }
}

TEST_CASE("momentum is conserved without external forces (pair forces and viscosity)") {
  // A random cloud of two species flying apart and together, no gravity, no objects.
  std::string pos, vel;
  for (int i = 0; i < 600; ++i) {
    Vec3 p, v;
    for (int a = 0; a < 3; ++a) {
      p[a] = 0.2 * uniformAt(7, static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(i));
      v[a] = uniformAt(7, 10 + static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(i)) - 0.5;
    }
    pos += (i ? "," : "") + vec(p);
    vel += (i ? "," : "") + vec(v);
  }
  World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24, "gravity": [0, 0, 0],
    "bodies": [{"type": "fluid", "name": "f", "species": [)") + kWater + R"(,
      {"name": "oil", "mass": 0.006, "alpha": 150, "beta": 0.07, "cutoff": 0.03, "viscosity": 5}],
      "particles": [{"species": "water", "positions": [)" + pos + "], \"velocities\": [" + vel + R"(]},
                    {"species": "oil", "positions": [[0.1, 0.1, 0.25], [0.11, 0.1, 0.25]]}]}]})");
  const Vec3 p0 = momentum(fluid(w));
  run(w, 15);
  const Vec3 p1 = momentum(fluid(w));
  CHECK(fluid(w).rebuilds > 1);
  CHECK((p1 - p0).norm() < 1e-12 * (1.0 + p0.norm() + kineticEnergy(fluid(w))));
}

TEST_CASE("particles in a closed box stay inside and settle") {
  // A container with a lid; particles thrown about inside it.
  std::string pos, vel;
  int n = 0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 8; ++k, ++n) {
        pos += (n ? "," : "") + vec(Vec3(-0.1 + 0.02 * i, 0.05 + 0.02 * j, -0.08 + 0.02 * k));
        vel += (n ? "," : "") + vec(Vec3(3 * (uniformAt(3, 0, static_cast<std::uint64_t>(n)) - 0.5), 3 * (uniformAt(3, 1, static_cast<std::uint64_t>(n)) - 0.5), 0));
      }
  World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 24,
    "objects": [{"type": "container", "center": [0, 0.15, 0], "size": [0.34, 0.3, 0.24], "wall": 0.02},
                {"type": "plane", "point": [0, 0.3, 0], "normal": [0, -1, 0]}],
    "bodies": [{"type": "fluid", "name": "f", "radius": 0.008, "species": [)") + kWater + R"(],
      "particles": [{"positions": [)" + pos + "], \"velocities\": [" + vel + "]}]}]}");
  const double e0 = kineticEnergy(fluid(w));
  double worst = 0.0;
  for (int f = 0; f < 90; ++f) {
    REQUIRE(w.advanceFrame().ok());
    // Inside: the container's inner space is [-0.15, 0.15] × [0.02, 0.3] × [-0.1, 0.1].
    for (const Vec3& p : fluid(w).x) {
      const Vec3 out = (p - Vec3(0, 0.16, 0)).cwiseAbs() - Vec3(0.15, 0.14, 0.1);
      worst = std::max(worst, out.maxCoeff());
    }
  }
  CHECK(worst <= 1e-9);
  CHECK(kineticEnergy(fluid(w)) < 0.02 * e0);
}

TEST_CASE("a left-pack keeps the masked lanes first and in order, for each of the 16 masks") {
  const Int4 v = {10, 11, 12, 13};
  for (unsigned bits = 0; bits < 16; ++bits) {
    const Mask4 mask = {bits & 1 ? -1LL : 0, bits & 2 ? -1LL : 0, bits & 4 ? -1LL : 0, bits & 8 ? -1LL : 0};
    CHECK(maskBits(mask) == bits);
    CHECK(keptCount(bits) == static_cast<unsigned>(__builtin_popcount(bits)));
    const Int4 packed = leftPack(v, bits);
    std::vector<int> kept, want;
    for (int l = 0; l < 4; ++l)
      if (bits >> l & 1) want.push_back(v[l]);
    for (int l = 0; l < __builtin_popcount(bits); ++l) kept.push_back(packed[l]);
    CHECK(kept == want);
  }
}

TEST_CASE("the grid's neighbour lists equal brute force on random sets") {
  for (int trial = 0; trial < 3; ++trial) {
    // Uniform points, a dense cluster, and points at negative and far coordinates.
    std::string pos;
    const int n = 1500;
    for (int i = 0; i < n; ++i) {
      const double spread = trial == 0 ? 0.3 : trial == 1 ? 0.05 : 2.0;
      const Vec3 base = trial == 2 ? Vec3(-100.3, 40, -7) : Vec3::Zero();
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = spread * uniformAt(11 + static_cast<std::uint64_t>(trial), static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(i));
      pos += (i ? "," : "") + vec(base + p);
    }
    World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 0.1, "fps": 10, "gravity": [0, 0, 0],
      "bodies": [{"type": "fluid", "name": "f", "radius": 0.001, "species": [{"name": "w", "cutoff": 0.04}],
                  "particles": [{"positions": [)") + pos + "]}]}]}");
    Fluid fl = fluid(w);
    buildNeighbours(fl);
    CHECK(fl.list_skin == fl.skin);  // (a first list: the default skin)
    const double reach = fl.cutoff_max + fl.list_skin;
    // Each list in the search's order (its runs in row order, each run's entries by x): the order
    // the force loop's lanes sum in, so a build that reordered them would change the bits.
    std::vector<std::size_t> at(fl.size());
    const auto order = fl.rows.order();
    for (std::size_t k = 0; k < order.size(); ++k) at[static_cast<std::size_t>(order[k])] = k;
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < fl.size(); ++i) {
      bool in_order = true;
      for (std::uint32_t e = fl.nbr_start[i] + 1; e < fl.nbr_start[i + 1]; ++e)
        in_order = in_order && at[static_cast<std::size_t>(fl.nbr[e - 1])] < at[static_cast<std::size_t>(fl.nbr[e])];
      CHECK(in_order);
      std::set<int> grid(fl.nbr.begin() + fl.nbr_start[i], fl.nbr.begin() + fl.nbr_start[i + 1]);
      CHECK(grid.size() == fl.nbr_start[i + 1] - fl.nbr_start[i]);  // no repeats
      std::set<int> brute;
      for (std::size_t j = 0; j < fl.size(); ++j)
        if (j != i && (fl.x[i] - fl.x[j]).squaredNorm() < reach * reach) brute.insert(static_cast<int>(j));
      CHECK(grid == brute);
      pairs += brute.size();
    }
    CHECK(pairs > 0);
  }
}

TEST_CASE("fluid state is bit-identical for 1 and 2 threads (emitter, objects, a dynamic ball)") {
  const std::string text = std::string(R"({"format": "reel/1", "duration": 0.5, "fps": 30, "substeps": 24, "seed": 5,
    "objects": [{"type": "container", "center": [0, 0.1, 0], "size": [0.4, 0.2, 0.3], "wall": 0.02},
                {"type": "sphere", "name": "ball", "center": [0.05, 0.25, 0], "radius": 0.04, "dynamic": true, "mass": 0.1}],
    "bodies": [{"type": "fluid", "name": "f", "species": [)") + kWater + R"(],
      "blocks": [{"min": [-0.18, 0.02, -0.13], "max": [0.0, 0.12, 0.13], "spacing": 0.02, "jitter": 0.1}],
      "emitters": [{"position": [0.1, 0.3, 0], "direction": [0, -1, 0], "speed": 1, "radius": 0.03, "rate": 400}]}]})";
  auto hashWith = [&](int threads) {
    test::ParallelForTest parallel(threads);
    World w = makeWorld(text);
    run(w, 15);
    return std::make_pair(w.stateHash(), fluid(w).size());
  };
  const auto one = hashWith(1), two = hashWith(2);
  CHECK(one.first == two.first);
  CHECK(one.second == two.second);
  CHECK(one.second > 9 * 5 * 13);  // the emitter added particles to the block's
}

TEST_CASE("adhesion holds a thin film under an overhang that a zero-adhesion surface sheds") {
  auto attached = [&](double adhesion) {
    std::string pos;
    int n = 0;
    for (int i = 0; i < 10; ++i)
      for (int k = 0; k < 10; ++k, ++n) pos += (n ? "," : "") + vec(Vec3(-0.09 + 0.02 * i, 0.465, -0.09 + 0.02 * k));
    World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24,
      "objects": [{"type": "box", "center": [0, 0.5, 0], "size": [0.4, 0.05, 0.4],
                   "surface": {"friction": 0.5, "adhesion": )") + std::to_string(adhesion) + R"(}}],
      "bodies": [{"type": "fluid", "name": "f", "radius": 0.008, "species": [)" + kWater + R"(],
                  "particles": [{"positions": [)" + pos + "]}]}]}");
    run(w, 30);
    int held = 0;
    for (const Vec3& p : fluid(w).x) held += p.y() > 0.44;
    return held;
  };
  CHECK(attached(40.0) == 100);  // adhesion (40 m/s²) beats gravity (9.78 m/s²)
  CHECK(attached(0.0) == 0);     // without it the film drops
}

TEST_CASE("per-species surfaces: the same ramp is slippery for one liquid and sticky for another") {
  // Two species on one tilted plank; honey gets adhesion and friction, water neither.
  World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24,
    "objects": [{"type": "box", "center": [0, 0, 0], "size": [2, 0.1, 0.6], "rotation_deg": [0, 0, -25],
                 "surface": {"friction": 0.0, "species": {"honey": {"friction": 1.0, "adhesion": 30}}}}],
    "bodies": [{"type": "fluid", "name": "f", "species": [)") + kWater + R"(,
      {"name": "honey", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 10}],
      "interactions": [{"species": ["water", "honey"], "alpha": 0}],
      "blocks": [{"species": "water", "min": [-0.1, 0.1, -0.2], "max": [0.0, 0.16, -0.05], "spacing": 0.02},
                 {"species": "honey", "min": [-0.1, 0.1, 0.05], "max": [0.0, 0.16, 0.2], "spacing": 0.02}]}]})");
  run(w, 30);
  const auto [water, honey] = meanXBySpecies(fluid(w));
  CHECK(water > 0.6);          // slid down the slope (+x is downhill)
  CHECK(honey < 0.0);          // stayed about where it landed
}

TEST_CASE("miscible species stay mixed, an immiscible pair separates") {
  // A random mixture of two species in a zero-gravity drop; count unlike nearest neighbours.
  auto unlike = [&](const std::string& cross) {
    std::string a, b;
    int na = 0, nb = 0;
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j)
        for (int k = 0; k < 10; ++k) {
          const bool first = uniformAt(21, 0, static_cast<std::uint64_t>((i * 10 + j) * 10 + k)) < 0.5;
          (first ? a : b) += ((first ? na++ : nb++) ? "," : "") + vec(Vec3(0.02 * i, 0.02 * j, 0.02 * k));
        }
    World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 24, "gravity": [0, 0, 0],
      "bodies": [{"type": "fluid", "name": "f", "species": [)") + kWater + R"(,
        {"name": "oil", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 10}],
        "interactions": [)" + cross + R"(],
        "particles": [{"species": "water", "positions": [)" + a + R"(]}, {"species": "oil", "positions": [)" + b + "]}]}]}");
    run(w, 60);
    const Fluid& fl = fluid(w);
    int diff = 0, total = 0;
    for (std::size_t i = 0; i < fl.size(); ++i) {
      double best = 1e9;
      int who = -1;
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
        const double d = (fl.x[i] - fl.x[static_cast<std::size_t>(fl.nbr[e])]).norm();
        if (d < best) {
          best = d;
          who = fl.nbr[e];
        }
      }
      if (who < 0) continue;
      ++total;
      diff += fl.s[i] != fl.s[static_cast<std::size_t>(who)];
    }
    return static_cast<double>(diff) / total;
  };
  const double mixed = unlike(""), separated = unlike(R"({"species": ["water", "oil"], "alpha": 30})");
  CHECK(mixed > 0.4);
  CHECK(separated < 0.3);
}
