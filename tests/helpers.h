// Small builders shared by the tests.
#pragma once

#include <doctest/doctest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "core/scene.h"
#include "app/body_kinds.h"
#include "sim/integrators.h"
#include "sim/mass_spring.h"

namespace reel::test {

// A fresh, empty folder under the temp directory (ctest runs cases in parallel processes: each
// case names its own).
inline std::filesystem::path freshDir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() / ("reel_test_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// A file's bytes ("" when it cannot be read).
inline std::string fileBytes(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The reel binary run through the shell with ARGS (quoted as a shell would need).
struct Run {
  int code = -1;
  std::string out;  // stdout and stderr together
};

inline Run runReel(const std::string& args, const std::string& prefix = "") {
  Run r;
  const std::string cmd = prefix + std::string(REEL_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p);
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// Implicit Euler's matrix assembled spring by spring from Baraff & Witkin's formulas, a reference
// for the tests: K = c[û ûᵀ + max(0, 1 − l/L)(I − û ûᵀ)] (L the length, l the rest length), D = γ û ûᵀ, each spring's block
// B = h²K + hD, and each node's diagonal block (m + hγ) I + Σ B.
struct AssembledSystem {
  std::vector<Mat3> B;     // springs
  std::vector<Mat3> diag;  // nodes
  // A p = (m + hγ) p_i + Σ over the springs at i of B (p_i − p_other).
  std::vector<Vec3> product(const MassSpringModel& m, double h, const std::vector<Vec3>& p) const {
    std::vector<Vec3> y(m.nodes());
    for (std::size_t i = 0; i < m.nodes(); ++i) y[i] = (m.mass[i] + h * m.drag[i]) * p[i];
    for (std::size_t s = 0; s < m.springs.size(); ++s) {
      const auto a = static_cast<std::size_t>(m.springs.a[s]), b = static_cast<std::size_t>(m.springs.b[s]);
      y[a] += B[s] * (p[a] - p[b]);
      y[b] += B[s] * (p[b] - p[a]);
    }
    return y;
  }
};

inline AssembledSystem assembleSystem(const MassSpringModel& m, const std::vector<Vec3>& x, double h) {
  AssembledSystem A;
  A.B.resize(m.springs.size());
  A.diag.resize(m.nodes());
  for (std::size_t i = 0; i < m.nodes(); ++i) A.diag[i] = (m.mass[i] + h * m.drag[i]) * Mat3::Identity();
  for (std::size_t s = 0; s < m.springs.size(); ++s) {
    const auto a = static_cast<std::size_t>(m.springs.a[s]), b = static_cast<std::size_t>(m.springs.b[s]);
    const Vec3 r = x[b] - x[a];
    const double len = r.norm();
    const Vec3 u = r / len;
    const Mat3 uu = u * u.transpose();
    const double t = std::max(0.0, 1.0 - m.springs.rest[s] / len);
    const Mat3 K = m.springs.stiffness[s] * (uu + t * (Mat3::Identity() - uu)), D = m.springs.damping[s] * uu;
    A.B[s] = h * h * K + h * D;
    A.diag[a] += A.B[s];
    A.diag[b] += A.B[s];
  }
  return A;
}

// A body built from explicit nodes and springs, ready to integrate.
struct System {
  MassSpringModel model;
  MassSpringState state;
  MassSpringSystem dyn{model};
  IntegratorWorkspace ws;
  ImplicitSettings implicit{1e-13, 1000};
  System(const MassSpringDesc& d, const Vec3& g) { buildMassSpring(d, g, model, state); }
  void step(IntegratorKind k, double h) { integrate(k, dyn, state.x, state.v, h, ws, implicit); }
};

// One free node of mass m on a spring (stiffness k, damping c, rest length 1) to a fixed node at
// the origin, displaced by x0 along x. Its displacement u = x − 1 obeys m u'' = −k u − c u'.
inline MassSpringDesc oscillator(double m, double k, double c, double x0, double node_drag = 0.0) {
  MassSpringDesc d;
  d.nodes.push_back({Vec3(0, 0, 0), Vec3::Zero(), 1.0, 0.0, true});
  d.nodes.push_back({Vec3(1.0 + x0, 0, 0), Vec3::Zero(), m, node_drag, false});
  d.springs.push_back({0, 1, k, c, 1.0});
  return d;
}

// Closed-form displacement of the underdamped oscillator u'' = −ω²u − βu', u(0)=u0, u'(0)=0.
inline double oscillatorExact(double w2, double beta, double u0, double t) {
  const double wd = std::sqrt(w2 - beta * beta / 4.0);
  return u0 * std::exp(-beta * t / 2.0) * (std::cos(wd * t) + beta / (2.0 * wd) * std::sin(wd * t));
}

inline SceneDesc sceneFromText(const std::string& text, const std::string& name = "test.json") {
  auto r = app::parseScene(text, name);
  if (!r.ok()) throw std::runtime_error(r.error().headline());
  return r.value();
}

// A world of the scene in `text` (throws on bad input), and frames of it (each must succeed).
inline World worldFromText(const std::string& text, const std::string& file = "test.json") {
  auto w = app::makeWorld(sceneFromText(text, file));
  if (!w.ok()) throw std::runtime_error(w.error().headline());
  return std::move(w.value());
}

// Advances `frames` frames; each must succeed (the message names what went wrong).
inline void run(World& w, int frames) {
  for (int f = 0; f < frames; ++f) {
    const Status st = w.advanceFrame();
    REQUIRE_MESSAGE(st.ok(), (st.ok() ? "" : st.error().headline()));
  }
}

// The first error line of a scene text that must be refused as bad input.
inline std::string badInputError(const std::string& text) {
  auto r = app::parseScene(text, "s.json");
  REQUIRE(!r.ok());
  CHECK(r.error().kind == ErrorKind::BadInput);
  return r.error().messages.front();
}

// Every error line of a scene text that must be refused as bad input, one per line.
inline std::string badInputErrors(const std::string& text) {
  auto r = app::parseScene(text, "bad.json");
  REQUIRE(!r.ok());
  CHECK(r.error().kind == ErrorKind::BadInput);
  std::string all;
  for (const std::string& l : r.error().messages) all += l + "\n";
  return all;
}

// Checks that `line` holds `part` (and shows the line when it does not).
inline void checkHas(const std::string& line, const std::string& part) {
  CAPTURE(line);
  CHECK(line.find(part) != std::string::npos);
}

// `threads` threads, every loop of 2 or more elements in parallel (the parallel paths taken even by
// a test's small scenes), for as long as it lives.
struct ParallelForTest {
  explicit ParallelForTest(int threads) : threads_(threadCount()), min_(parallelMin()) {
    setThreadCount(threads);
    setParallelMin(2);
  }
  ~ParallelForTest() {
    setThreadCount(threads_);
    setParallelMin(min_);
  }
  ParallelForTest(const ParallelForTest&) = delete;
  ParallelForTest& operator=(const ParallelForTest&) = delete;

 private:
  int threads_;
  std::ptrdiff_t min_;
};

// The state hash of the scene `text` after `frames` frames on `threads` threads (determinism),
// through the parallel paths.
inline std::uint64_t runHash(const std::string& text, int threads, int frames) {
  ParallelForTest parallel(threads);
  World w = worldFromText(text);
  run(w, frames);
  return w.stateHash();
}

inline const std::vector<IntegratorKind>& allIntegrators() {
  static const std::vector<IntegratorKind> k = {IntegratorKind::SymplecticEuler, IntegratorKind::ExplicitEuler,
                                                IntegratorKind::Verlet, IntegratorKind::Rk4,
                                                IntegratorKind::ImplicitEuler};
  return k;
}

}  // namespace reel::test
