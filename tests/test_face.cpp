// The face: the tissue's elements and biphasic springs against their formulas, a face at rest
// staying at rest, what a zygomatic major does, symmetry, volumes kept, the skull never crossed,
// determinism, bad input.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "face_scene.h"
#include "helpers.h"
#include "sim/face/face_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// A face at a test resolution; `extra` adds keys to it.
std::string faceScene(const std::string& extra, double duration = 1.0, const std::string& resolution = "[48, 32]") {
  return faceSceneText(extra, duration, resolution, "1e-5");
}

// The head-frame position of skin vertex k now (the head is at the origin, unturned).
Vec3 skin(const World& w, std::size_t k) { return face(w).network().state.x[k]; }

}  // namespace

TEST_CASE("face: a prism's volume and biphasic springs by their phases") {
  // A right prism over the triangle (0,0)-(2,0)-(0,3), height 0.5: volume 3 · 0.5 = 1.5.
  std::array<Vec3, 6> p = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 0.5), Vec3(2, 0, 0.5), Vec3(0, 3, 0.5)};
  CHECK(prismVolume(p) == doctest::Approx(1.5).epsilon(1e-14));
  // Sheared (the top slid sideways): the same volume (Cavalieri).
  for (int c = 3; c < 6; ++c) p[static_cast<std::size_t>(c)] += Vec3(0.7, -0.2, 0);
  CHECK(prismVolume(p) == doctest::Approx(1.5).epsilon(1e-14));
  // Listed from another corner, or mirrored (x → −x, the order reversed to stay outward): the same.
  const std::array<Vec3, 6> turned = {p[1], p[2], p[0], p[4], p[5], p[3]};
  CHECK(prismVolume(turned) == doctest::Approx(1.5).epsilon(1e-14));
  // A twisted top (side faces not flat): mirroring gives the same volume.
  p[4] += Vec3(0.1, 0.3, 0.2);
  std::array<Vec3, 6> mirrored;
  for (int c : {0, 1, 2}) {
    const int m = c == 0 ? 0 : 3 - c;  // a0 a2 a1
    mirrored[static_cast<std::size_t>(c)] = p[static_cast<std::size_t>(m)].cwiseProduct(Vec3(-1, 1, 1));
    mirrored[static_cast<std::size_t>(3 + c)] = p[static_cast<std::size_t>(3 + m)].cwiseProduct(Vec3(-1, 1, 1));
  }
  CHECK(prismVolume(mirrored) == doctest::Approx(prismVolume(p)).epsilon(1e-14));
  // ... and is the divergence theorem's sum over its boundary with each side quad the mean of its
  // two splits into triangles (what the closed form for a quad stands for).
  {
    auto tri = [&](int i, int j, int k) {
      return p[static_cast<std::size_t>(i)].dot(p[static_cast<std::size_t>(j)].cross(p[static_cast<std::size_t>(k)])) / 6;
    };
    double v = tri(0, 2, 1) + tri(3, 4, 5);
    for (int i = 0; i < 3; ++i) {
      const int P = i, Q = (i + 1) % 3, R = 3 + Q, S = 3 + i;
      v += 0.5 * (tri(P, Q, R) + tri(P, R, S)) + 0.5 * (tri(P, Q, S) + tri(Q, R, S));
    }
    CHECK(prismVolume(p) == doctest::Approx(v).epsilon(1e-13));
    CHECK(std::abs(v - 1.5) > 0.01);  // (the twist changed it)
  }
  // Biphasic: one spring of stiffness c = 10, rest 1, ε_c = 0.1, β = 4. Its force at length L is
  // c(L − 1) within the strain, c·0.1 + 4c(L − 1.1) beyond (and the mirror in compression),
  // outside the band ε_c ± ε_c/3 where the stiffness turns.
  FaceTissue T;
  T.biphasic_strain = 0.1, T.biphasic_ratio = 4.0;
  T.stiffness = {10.0};
  T.rest = {1.0};
  MassSpringModel m;
  m.springs.add(0, 1, 10.0, 0.0, 1.0);
  for (double L : {0.7, 0.95, 1.05, 1.3}) {
    std::vector<Vec3> x = {Vec3::Zero(), Vec3(L, 0, 0)};
    phaseSprings(T, m, x);
    const double f = m.springs.stiffness[0] * (L - m.springs.rest[0]);
    const double e = L - 1.0;
    const double want = std::abs(e) <= 0.1 ? 10 * e : std::copysign(10 * 0.1 + 40 * (std::abs(e) - 0.1), e);
    CAPTURE(L);
    CHECK(f == doctest::Approx(want).epsilon(1e-12));
  }
  // Through the band the force is continuous and the spring's stiffness is its slope (the
  // tangent the implicit solve takes), rising from c to βc; in compression the mirror.
  auto force = [&](double L) {
    std::vector<Vec3> x = {Vec3::Zero(), Vec3(L, 0, 0)};
    phaseSprings(T, m, x);
    return std::pair{m.springs.stiffness[0] * (L - m.springs.rest[0]), m.springs.stiffness[0]};
  };
  double last_k = 0.0;
  for (double e = 0.05; e <= 0.15; e += 0.0025) {
    CAPTURE(e);
    const auto [f, k] = force(1 + e);
    const double slope = (force(1 + e + 1e-7).first - force(1 + e - 1e-7).first) / 2e-7;
    CHECK(k == doctest::Approx(slope).epsilon(1e-5));
    CHECK(k >= last_k);
    CHECK(k >= 10.0 - 1e-12);
    CHECK(k <= 40.0 + 1e-12);
    CHECK(force(1 - e).first == doctest::Approx(-f).epsilon(1e-12));
    last_k = k;
  }
  CHECK(force(1.05).second == doctest::Approx(10.0));
  CHECK(force(1.15).second == doctest::Approx(40.0));
  // No jump at the band's edges (strain 0.1 ∓ 0.1/3), and inside it within (β − 1)c·l·δ/4 of the
  // paper's piecewise force.
  for (double edge : {0.1 - 0.1 / 3, 0.1 + 0.1 / 3}) {
    CAPTURE(edge);
    CHECK(std::abs(force(1 + edge + 1e-9).first - force(1 + edge - 1e-9).first) < 1e-6);
  }
  for (double e = 0.07; e < 0.133; e += 0.005) {
    CAPTURE(e);
    const double paper = e <= 0.1 ? 10 * e : 10 * 0.1 + 40 * (e - 0.1);
    CHECK(std::abs(force(1 + e).first - paper) <= 3 * 10 * (0.1 / 3) / 4 + 1e-12);
  }
}

// The volumes of the tissue's elements now, m³.
std::vector<double> volumes(const FaceBody& f) {
  const FaceTissue& T = f.tissue();
  const auto& x = f.network().state.x;
  std::vector<double> v;
  for (const auto& P : T.prisms) {
    std::array<Vec3, 6> p;
    for (int c = 0; c < 6; ++c) p[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(P[static_cast<std::size_t>(c)])];
    v.push_back(prismVolume(p));
  }
  return v;
}

TEST_CASE("face: the volume term's force is minus its energy's gradient and its product the Gauss–Newton stiffness's") {
  // One prism (a skewed wedge, its top pushed 20% out of its rest volume): E = κ/(2V₀)(V − V₀)².
  FaceTissue T;
  T.prisms = {{0, 1, 2, 3, 4, 5}};
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0.1), Vec3(0.1, 0, 1.2), Vec3(1.1, 0.2, 1.3), Vec3(0.3, 1.1, 1.1)};
  T.rest_volume = {0.8 * prismVolume({x[0], x[1], x[2], x[3], x[4], x[5]})};
  T.volume_modulus = 3.0;
  indexCorners(T, 6);
  TissueVolume term(T);
  auto energy = [&](const std::vector<Vec3>& q) {
    const double V = prismVolume({q[0], q[1], q[2], q[3], q[4], q[5]});
    return T.volume_modulus / (2 * T.rest_volume[0]) * (V - T.rest_volume[0]) * (V - T.rest_volume[0]);
  };
  std::vector<Vec3> f(6, Vec3::Zero());
  term.addForces(x.data(), f.data());
  for (std::size_t i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c) {
      std::vector<Vec3> a = x, b = x;
      a[i][c] += 1e-6, b[i][c] -= 1e-6;
      CHECK(f[i][c] == doctest::Approx(-(energy(a) - energy(b)) / 2e-6).epsilon(1e-6));
    }
  // The product: s·κ/V₀·∇V (∇V·p), against the gradient by differences.
  std::vector<Mat3> diag(6, Mat3::Zero());
  std::vector<Vec3> f_lin(6, Vec3::Zero());
  term.linearize(x.data(), f_lin.data(), diag.data());
  for (std::size_t i = 0; i < 6; ++i) CHECK((f_lin[i] - f[i]).norm() <= 1e-12 * f[i].norm());  // the same force
  const std::vector<Vec3> p = {Vec3(1, 2, 3), Vec3(-1, 0, 2), Vec3(0.5, 0.5, -1), Vec3(2, -1, 0), Vec3(0, 1, 1), Vec3(-2, 1, 0.5)};
  std::vector<Vec3> grad(6);
  double gp = 0.0;
  for (std::size_t i = 0; i < 6; ++i) {
    for (int c = 0; c < 3; ++c) {
      std::vector<Vec3> a = x, b = x;
      a[i][c] += 1e-6, b[i][c] -= 1e-6;
      grad[i][c] = (prismVolume({a[0], a[1], a[2], a[3], a[4], a[5]}) - prismVolume({b[0], b[1], b[2], b[3], b[4], b[5]})) / 2e-6;
    }
    gp += grad[i].dot(p[i]);
  }
  std::vector<Vec3> out(6, Vec3::Zero());
  term.addProduct(p.data(), 0.5, out.data());
  // The same product in halves (as the mass-spring system takes it, inside its pass over the
  // nodes), the nodes in two ranges taken in reverse order: the same bits, and the stiffness's
  // product below.
  std::vector<Vec3> halves(6, Vec3::Zero());
  term.prepareProduct(p.data(), 0.5);
  term.addProductTo(4, 6, halves.data());
  term.addProductTo(0, 4, halves.data());
  for (std::size_t i = 0; i < 6; ++i) CHECK(halves[i] == out[i]);
  // A pair's block of H (what the preconditioner inverts with the pair), against products with
  // unit vectors: H_ab's column j is (H e_bj) at a.
  for (int a : {0, 4})
    for (int b : {3, 1}) {
      Mat3 block = Mat3::Zero();
      term.addPairBlock(a, b, 2.0, block);
      for (int j = 0; j < 3; ++j) {
        std::vector<Vec3> e(6, Vec3::Zero()), col(6, Vec3::Zero());
        e[static_cast<std::size_t>(b)][j] = 1.0;
        term.addProduct(e.data(), 2.0, col.data());
        CHECK((block.col(j) - col[static_cast<std::size_t>(a)]).norm() <= 1e-12 * (1.0 + col[static_cast<std::size_t>(a)].norm()));
      }
    }
  for (std::size_t i = 0; i < 6; ++i) {
    CHECK((out[i] - 0.5 * T.volume_modulus / T.rest_volume[0] * gp * grad[i]).norm() < 1e-6 * out[i].norm() + 1e-12);
    CHECK((diag[i] - T.volume_modulus / T.rest_volume[0] * grad[i] * grad[i].transpose()).norm() < 1e-6 * diag[i].norm());
  }
}

TEST_CASE("face: reel's head at any row count: every triangle makes its two elements") {
  // (Rays from the head's centre near straight down once landed on the neck's cut and folded
  // the neck's rings: at [96, 64] 196 elements had no volume and were dropped.)
  for (const auto& [columns, rows] : {std::pair{32, 16}, std::pair{64, 40}, std::pair{96, 64}, std::pair{64, 128}}) {
    CAPTURE(rows);
    const FaceSurface s = makeHead(0.24, {columns, rows}, 0.009);
    FaceTissue T;
    buildTissue(s, FaceDesc{}, T);
    CHECK(T.prisms.size() == 2 * (s.tris.size() / 3));
  }
}

TEST_CASE("face: a face at rest stays at rest for 10 s") {
  World w = worldFromText(faceScene("", 10.0, "[32, 24]"));
  const std::vector<Vec3> x0 = face(w).network().state.x;
  run(w, 299);
  const auto& x = face(w).network().state.x;
  double moved = 0.0, speed = 0.0;
  std::size_t most = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if ((x[i] - x0[i]).norm() > moved) moved = (x[i] - x0[i]).norm(), most = i;
    speed = std::max(speed, face(w).network().state.v[i].norm());
  }
  MESSAGE("at rest for 10 s: moved at most " << moved << " m (node " << most << " at " << x0[most].transpose()
                                              << "), fastest node " << speed << " m/s");
  CHECK(moved < 3e-4);   // m: under a thousandth of the head's height
  CHECK(speed < 1e-4);   // m/s
}

TEST_CASE("face: the zygomatic major lifts the mouth corner up and out and the cheek bulges") {
  World w = worldFromText(faceScene(R"(, "activations": [{"time": 0, "muscles": {"zygomatic_major_left": 0}},
                                                          {"time": 0.4, "muscles": {"zygomatic_major_left": 1}}])"));
  const FaceBody& f = face(w);
  const FaceSurface& s = f.surface();
  const std::size_t corner = vertexNear(f, s.mouth + Vec3(0.5 * s.mouth_width, 0, -0.003));
  const std::size_t other = vertexNear(f, s.mouth + Vec3(-0.5 * s.mouth_width, 0, -0.003));
  const Vec3 c0 = skin(w, corner), o0 = skin(w, other);
  const std::vector<Vec3> x0 = f.network().state.x;
  run(w, 24);
  const Vec3 dc = skin(w, corner) - c0;
  CAPTURE(dc.transpose());
  CHECK(dc.y() > 0.002);   // up, by more than 2 mm
  CHECK(dc.x() > 0.0005);  // outward (the head's left is +x)
  // The cheek bulges: tissue gathered toward the cheekbone rises along its normal (bone → skin).
  double bulge = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k)
    if ((s.skin[k] - Vec3(0.045, -0.02, 0.07)).norm() < 0.025) bulge = std::max(bulge, (skin(w, k) - x0[k]).dot(f.tissue().out[k]));
  MESSAGE("cheek bulge " << bulge << " m");
  CHECK(bulge > 0.0003);
  // The other corner, dragged along the lips, rises much less.
  CHECK(skin(w, other).y() - o0.y() < 0.5 * dc.y());
}

TEST_CASE("face: symmetric activations keep the face symmetric and keep volumes and the skull") {
  World w = worldFromText(faceScene(R"(, "activations": [{"time": 0, "preset": "happiness", "amount": 0},
      {"time": 0.3, "presets": {"anger": 1, "surprise": 0.6}}, {"time": 0.6, "preset": "fear"}])"));
  const FaceBody& f = face(w);
  const std::vector<double> v0 = volumes(f);
  const FaceSurface& s = f.surface();
  // Each vertex's mirror image (x → −x) at rest.
  std::vector<std::size_t> mirror(s.size());
  // (A lower lip's copy of a vertex of the parting mirrors to a copy.)
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3 m(-s.skin[k].x(), s.skin[k].y(), s.skin[k].z());
    std::size_t best = k;
    for (std::size_t j = 0; j < s.size(); ++j)
      if ((j >= s.lower_lip) == (k >= s.lower_lip) && (s.skin[j] - m).squaredNorm() < (s.skin[best] - m).squaredNorm()) best = j;
    mirror[k] = best;
  }
  double worst_volume = 0.0, worst_p99 = 0.0, lowest = 1.0;
  for (int frame = 0; frame < 27; ++frame) {
    run(w, 1);
    const std::vector<double> v = volumes(f);
    std::vector<double> change(v.size());
    for (std::size_t e = 0; e < v.size(); ++e) change[e] = std::abs(v[e] - v0[e]) / v0[e];
    std::sort(change.begin(), change.end());
    worst_volume = std::max(worst_volume, change.back());
    worst_p99 = std::max(worst_p99, change[change.size() * 99 / 100]);
    lowest = std::min(lowest, f.lowestAboveSkull());
  }
  MESSAGE("strongest expression: element volume change at most " << worst_volume << ", 99th percentile " << worst_p99
                                                                   << "; lowest node above the skull " << lowest << " m");
  // (0.72 and 0.34 when the volume was only projected after the solve; the default resolution
  // is held to 15% by the presets' test, this coarse head's floor of the mouth reaches 18.5%.)
  CHECK(worst_volume < 0.2);
  CHECK(worst_p99 < 0.08);
  CHECK(lowest > 0.0);
  double asym = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3 a = skin(w, k), b = skin(w, mirror[k]);
    asym = std::max(asym, (a - Vec3(-b.x(), b.y(), b.z())).norm());
  }
  MESSAGE("asymmetry " << asym << " m");
  CHECK(asym < 1e-6);
}

TEST_CASE("face: every preset at full strength, and the strongest visemes, keep every element within 15% of its volume (default head)") {
  // Lee, Terzopoulos & Waters' tissue is nearly incompressible: each of the six expressions,
  // reached in 0.4 s and held, at the default resolution and the film's solver tolerance; and the
  // most the lips do in speech ("oo" pushes them out, "aa" opens the jaw the most), reached in 0.3 s.
  auto worstChange = [](const std::string& keys, double duration, int frames) {
    World w = worldFromText(faceSceneText(keys, duration, "[64, 40]", "1e-3"));
    const FaceBody& f = face(w);
    const std::vector<double> v0 = volumes(f);
    double worst = 0.0;
    for (int frame = 0; frame < frames; ++frame) {
      run(w, 1);
      const std::vector<double> v = volumes(f);
      for (std::size_t e = 0; e < v.size(); ++e) worst = std::max(worst, std::abs(v[e] - v0[e]) / v0[e]);
    }
    return worst;
  };
  for (const std::string preset : {"happiness", "surprise", "sadness", "anger", "disgust", "fear"}) {
    CAPTURE(preset);
    const double worst = worstChange(R"(, "activations": [{"time": 0, "preset": ")" + preset + R"(", "amount": 0}, {"time": 0.4, "preset": ")" +
                                         preset + R"("}])",
                                     0.8, 23);
    MESSAGE(preset << ": largest element volume change " << worst);
    CHECK(worst < 0.15);
  }
  for (const std::string viseme : {"oo", "aa"}) {
    CAPTURE(viseme);
    const double worst = worstChange(R"(, "visemes": [{"time": 0, "viseme": "rest"}, {"time": 0.3, "viseme": ")" + viseme + R"("}])", 0.7, 20);
    MESSAGE(viseme << ": largest element volume change " << worst);
    CHECK(worst < 0.15);
  }
}

TEST_CASE("face: the jaw turns the mandible alone and glides as it opens; the neck has rings of its own") {
  World w = worldFromText(faceScene(R"(, "activations": [{"time": 0, "muscles": {"jaw_open": 0}}, {"time": 0.3, "muscles": {"jaw_open": 1}}])", 1.0,
                                    "[64, 40]"));
  const FaceBody& f = face(w);
  const FaceSurface& s = f.surface();
  const std::size_t n = s.size();
  const std::vector<Vec3> x0 = f.network().state.x;
  run(w, 12);
  REQUIRE(f.jawAngle() == doctest::Approx(kJawMaxRad));
  // The chin's bone goes down more than back (the condyles glide forward as the jaw turns).
  const std::size_t chin = vertexNear(f, Vec3(0, -0.1, 0.095));
  const Vec3 moved = f.network().state.x[2 * n + chin] - x0[2 * n + chin];
  MESSAGE("chin bone moved " << moved.transpose());
  CHECK(moved.y() < -0.015);
  CHECK(-moved.y() > -moved.z());
  // The throat's and the neck's bone stay.
  for (std::size_t k = 0; k < n; ++k)
    if (s.skin[k].y() < -0.14) CHECK((f.network().state.x[2 * n + k] - x0[2 * n + k]).norm() < 1e-12);
  // The neck is sampled down its length: no skin triangle that shows above the collar (at
  // −0.134 m) reaches far down it (the rays from the head's centre once left the throat one fan
  // of triangles 0.47 m tall).
  double tallest = 0.0;
  for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
    double top = -1.0, bottom = 1.0;
    for (int e = 0; e < 3; ++e) top = std::max(top, s.skin[s.tris[t + static_cast<std::size_t>(e)]].y()), bottom = std::min(bottom, s.skin[s.tris[t + static_cast<std::size_t>(e)]].y());
    if (top > -0.134) tallest = std::max(tallest, top - bottom);
  }
  MESSAGE("tallest skin triangle showing above the collar " << tallest << " m");
  CHECK(tallest < 0.08);
  // The bottom of the neck is a cap at the cut, inside the shoulders.
  double lowest = 0.0;
  for (const Vec3& p : s.skin) lowest = std::min(lowest, p.y());
  CHECK(lowest == doctest::Approx(-0.32).epsilon(1e-3));
}

TEST_CASE("face: activations and visemes are eased between their keys (no kink at a key)") {
  World w = worldFromText(faceScene(R"(, "activations": [{"time": 0, "muscles": {"zygomatic_major_left": 0}}, {"time": 1, "muscles": {"zygomatic_major_left": 0.8}}],
      "visemes": [{"time": 0, "viseme": "rest"}, {"time": 2, "viseme": "oo"}, {"time": 4, "viseme": "rest"}])", 4.0, "[32, 24]"));
  const FaceActivations& A = face(w).activations();
  REQUIRE(A.index("zygomatic_major_left") >= 0);
  REQUIRE(A.index("orbicularis_oris") >= 0);
  const auto zyg = static_cast<std::size_t>(A.index("zygomatic_major_left")), oris = static_cast<std::size_t>(A.index("orbicularis_oris"));
  std::vector<double> out;
  auto zygAt = [&](double t) {
    A.at(t, out);
    return out[zyg];
  };
  // smoothstep: 3s² − 2s³ of the key fraction s.
  for (double s : {0.0, 0.1, 0.25, 0.5, 0.75, 1.0}) CHECK(zygAt(s) == doctest::Approx(0.8 * (3 * s * s - 2 * s * s * s)).epsilon(1e-12));
  CHECK(zygAt(1.5) == doctest::Approx(0.8));  // held after the last key
  // Its rate starts and ends at 0 (a linear ramp's would be 0.8/s from the first instant).
  CHECK((zygAt(1e-3) - zygAt(0)) / 1e-3 < 0.01);
  CHECK((zygAt(1) - zygAt(1 - 1e-3)) / 1e-3 < 0.01);
  // The visemes likewise: a quarter of the way from rest to "oo" the lips' sphincter is at
  // 0.15625 of its "oo" contraction (a linear blend: a quarter).
  A.at(0.5, out);
  const double quarter = out[oris];
  A.at(2.0, out);
  CHECK(out[oris] > 0.5);
  CHECK(quarter == doctest::Approx(0.15625 * out[oris]).epsilon(1e-12));
}

TEST_CASE("face: the jaw opens the mouth and blinks close the eyes and the dump lists the muscles") {
  World w = worldFromText(faceScene(R"(, "blinks": [0.1], "activations": [{"time": 0, "muscles": {"jaw_open": 0}}, {"time": 0.5, "muscles": {"jaw_open": 1}}])"));
  const FaceBody& f = face(w);
  CHECK(f.mouthOpening() < 0.002);  // closed lips (the lower one a little lower after settling)
  run(w, 5);
  const int blink = f.activations().index("blink");
  REQUIRE(blink >= 0);
  CHECK(f.contractions()[static_cast<std::size_t>(blink)] == doctest::Approx(blinkClosure(5.0 / 30.0 - 0.1)));
  run(w, 20);
  CHECK(f.jawAngle() == doctest::Approx(kJawMaxRad));
  CHECK(f.mouthOpening() > 0.01);  // m
  BodyView view;
  REQUIRE(f.view(view));
  REQUIRE(view.fields.size() == 1);
  CHECK(view.fields[0].name == "muscles");
  CHECK(view.fields[0].values.size() == f.activations().controls.size());
  CHECK(view.masses.size() == view.positions.size());
}

TEST_CASE("face: the same at 1 and 2 threads") {
  // (With the lips' pucker, whose push follows the head's turn.)
  const std::string text = faceScene(R"(, "keys": [{"time": 0, "rotation_deg": [0, 30, 0]}, {"time": 0.5, "rotation_deg": [0, -10, 0]}],
      "activations": [{"time": 0, "preset": "disgust"}], "visemes": [{"time": 0, "viseme": "rest"}, {"time": 0.3, "viseme": "oo"}])", 0.4);
  CHECK(runHash(text, 1, 10) == runHash(text, 2, 10));
}

TEST_CASE("face: bad input") {
  auto build = [](const std::string& extra) {
    auto scene = app::parseScene(faceScene(extra), "s.json");
    if (!scene.ok()) return scene.error().messages.front();
    auto w = app::makeWorld(scene.value());
    REQUIRE(!w.ok());
    CHECK(w.error().kind == ErrorKind::BadInput);
    return w.error().messages.front();
  };
  // A muscle attached in the air, one inserted outside the tissue.
  checkHas(build(R"(, "muscles": [{"name": "m", "attachment": [0, 0, 0.3], "insertion": [0, 0, 0.08]}])"),
           "/bodies/0/muscles/0/attachment: muscle 'm' is attached outside the skull");
  checkHas(build(R"(, "muscles": [{"name": "m", "attachment": [0.05, 0.0, 0.0], "insertion": [0, 0, 0.0]}])"), "/bodies/0/muscles/0/");
  // A contraction outside [0, 1], an unknown muscle, an unknown preset.
  checkHas(badInputError(faceScene(R"(, "activations": [{"time": 0, "muscles": {"jaw_open": 1.5}}])")), "/bodies/0/activations/0/muscles/jaw_open");
  checkHas(badInputError(faceScene(R"(, "activations": [{"time": 0, "muscles": {"zygomatic_majr": 0.5}}])")), "did you mean");
  checkHas(badInputError(faceScene(R"(, "activations": [{"time": 0, "preset": "happines"}])")), "did you mean \"happiness\"");
  // Layers that would cross the skull; a mesh without its skull.
  checkHas(badInputError(faceScene(R"(, "dermis": {"thickness": 0.02}, "muscle": {"thickness": 0.02})")), "cross the skull");
  checkHas(badInputError(faceScene(R"(, "skull": "x.obj")")), "/bodies/0/skull");
  // A held scalp's reach below 0 or past a metre.
  checkHas(badInputError(faceScene(R"(, "held_beyond": -0.01)")), "/bodies/0/held_beyond");
  checkHas(badInputError(faceScene(R"(, "held_beyond": 2)")), "/bodies/0/held_beyond");
  // Past the largest resolution a film can use.
  checkHas(badInputError(faceScene("", 1.0, "[130, 40]")), "/bodies/0/resolution");
}

TEST_CASE("face: reel check builds without settling; a run settles before its first frame") {
  auto scene = app::parseScene(faceScene("", 1.0, "[32, 24]"), "s.json");
  REQUIRE(scene.ok());
  auto checked = app::makeWorld(scene.value(), /*check_only=*/true);
  auto run_world = app::makeWorld(scene.value());
  REQUIRE(checked.ok());
  REQUIRE(run_world.ok());
  // The same tissue, but only the run's has sagged under gravity to rest (Body::prepare).
  const auto& x0 = face(checked.value()).network().state.x;
  const auto& x1 = face(run_world.value()).network().state.x;
  REQUIRE(x0.size() == x1.size());
  double sag = 0.0;
  for (std::size_t i = 0; i < x0.size(); ++i) sag = std::max(sag, (x1[i] - x0[i]).norm());
  CHECK(sag > 1e-5);
  CHECK(face(checked.value()).stepLimit(IntegratorKind::SymplecticEuler).bound.h_max ==
        face(run_world.value()).stepLimit(IntegratorKind::SymplecticEuler).bound.h_max);
}

TEST_CASE("face: a user's mesh must be closed and its inset must not fold") {
  // A tetrahedron, closed; the same without a face, open; a thin slab inset deeper than it is thick.
  TriMesh tet;
  for (const Vec3& p : {Vec3(0, 0, 0.1), Vec3(0.1, 0, -0.05), Vec3(-0.1, 0, -0.05), Vec3(0, 0.1, 0)}) tet.addVertex(p, Vec3::UnitY());
  tet.indices = {0, 1, 3, 1, 2, 3, 2, 0, 3, 0, 2, 1};
  auto ok = userHead(tet, nullptr, 0.005, "s.json: /bodies/0/mesh");
  CHECK(ok.ok());
  TriMesh open = tet;
  open.indices.resize(9);
  auto bad = userHead(open, nullptr, 0.005, "s.json: /bodies/0/mesh");
  REQUIRE(!bad.ok());
  checkHas(bad.error().messages.front(), "must be closed");
  auto folded = userHead(makeBox(Vec3(0.1, 0.01, 0.1)), nullptr, 0.02, "s.json: /bodies/0/mesh");
  REQUIRE(!folded.ok());
  checkHas(folded.error().messages.front(), "cross the skull");
}


TEST_CASE("face: a user's mesh with an inset and a muscle of the scene") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "reel_test_face";
  fs::create_directories(dir);
  writeBallObj((dir / "ball.obj").string());
  // The looks shape reel's own head: a user's mesh has none.
  {
    auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "face", "name": "f", "mesh": "ball.obj",
        "inset": 0.008, "sex": 1, "shoulders": false, "held_beyond": 0.02}]})", (dir / "looks.json").string());
    REQUIRE(!r.ok());
    std::string all;
    for (const std::string& l : r.error().messages) all += l + "\n";
    checkHas(all, "/bodies/0/sex: shapes reel's own head");
    checkHas(all, "/bodies/0/shoulders");
    checkHas(all, "/bodies/0/held_beyond");
  }
  // A muscle from the skull above the front to the tissue below it: it pulls the front up.
  const Vec3 att = 0.092 * Vec3(0, 0.5, 1).normalized(), ins = 0.096 * Vec3(0, -0.3, 1).normalized();
  auto num = [](const Vec3& p) { return "[" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) + "]"; };
  World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 2, "integrator": "implicit_euler",
    "gravity": [0, 0, 0],
    "bodies": [{"type": "face", "name": "f", "mesh": "ball.obj", "inset": 0.008,
                "muscles": [{"name": "lift", "attachment": )" + num(att) + R"(, "insertion": )" + num(ins) + R"(, "strength": 5}],
                "activations": [{"time": 0, "muscles": {"lift": 0}}, {"time": 0.3, "muscles": {"lift": 1}}]}]})",
                          (dir / "scene.json").string());
  const FaceBody& f = face(w);
  CHECK_FALSE(f.surface().generated);
  // The nodes it pulls, by their weights: their centre comes closer to the attachment.
  const FaceMuscle& m = f.muscles().at(0);
  auto centre = [&] {
    Vec3 c = Vec3::Zero();
    for (std::size_t j = 0; j < m.nodes.size(); ++j) c += m.weight[j] * f.network().state.x[f.surface().size() + static_cast<std::size_t>(m.nodes[j])];
    return c;
  };
  const double d0 = (centre() - att).norm();
  run(w, 20);
  const double d1 = (centre() - att).norm();
  CAPTURE(d0);
  CHECK(d1 < d0 - 0.001);
  CHECK(f.lowestAboveSkull() > 0.0);
  // Without its inset or skull, and open: refused, naming the key.
  auto bare = app::parseScene(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "face", "name": "f", "mesh": "ball.obj"}]})",
                              (dir / "s.json").string());
  REQUIRE(!bare.ok());
  checkHas(bare.error().messages.front(), "/bodies/0/mesh: a face mesh needs its `skull` mesh or an `inset`");
  std::ofstream(dir / "open.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  auto scene = app::parseScene(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "face", "name": "f", "mesh": "open.obj", "inset": 0.005,
      "muscles": [{"name": "m", "type": "sphincter", "center": [0, 0, 0.05]}]}]})", (dir / "s.json").string());
  REQUIRE(scene.ok());
  auto world = app::makeWorld(scene.value());
  REQUIRE(!world.ok());
  checkHas(world.error().messages.front(), "/bodies/0/mesh: the face mesh must be closed");
}

TEST_CASE("face: the procerus pulls the brows' heads down; anger lowers them, not only draws them together") {
  // AU4, the brow lowerer: the corrugator draws the brows' heads in, the procerus pulls the skin
  // between them down (Ekman, Friesen & Hager 2002). With the corrugator alone the brows barely
  // lowered, and viewers read anger as puzzled.
  auto drop = [](const std::string& amount0, const std::string& amount1) {
    World w = worldFromText(faceScene(R"(, "activations": [{"time": 0, )" + amount0 + R"(}, {"time": 0.3, )" + amount1 + "}]", 0.7));
    const FaceBody& f = face(w);
    const std::size_t head = vertexNear(f, Vec3(0.016, 0.02, 0.1));
    const Vec3 x0 = skin(w, head);
    run(w, 20);
    return Vec3(skin(w, head) - x0);
  };
  const Vec3 anger = drop(R"("preset": "anger", "amount": 0)", R"("preset": "anger")");
  const Vec3 corrugator = drop(R"("muscles": {"corrugator": 0})", R"("muscles": {"corrugator": 1})");
  const Vec3 procerus = drop(R"("muscles": {"procerus": 0})", R"("muscles": {"procerus": 1})");
  MESSAGE("the left brow's head moves " << 1000 * anger.transpose() << " mm in anger, " << 1000 * corrugator.transpose()
                                        << " with the corrugator alone, " << 1000 * procerus.transpose() << " with the procerus");
  CHECK(procerus.y() < -0.0012);                       // the procerus pulls down,
  CHECK(-procerus.y() > 3 * std::abs(procerus.x()));   // not in
  CHECK(anger.y() < corrugator.y() - 0.0009);          // and lowers anger's brows about a millimetre more:
  CHECK(anger.y() < -0.0033);                          // 3.8 mm in all (the corrugator alone 2.8)
}
