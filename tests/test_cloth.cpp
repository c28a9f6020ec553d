// Cloth: drape, friction on a slope, energy, tearing into pieces, self-collision, air forces,
// strain limiting, mesh and moving colliders, determinism, and the cloth rows of bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/math.h"
#include "core/parallel.h"
#include "core/random.h"
#include "helpers.h"
#include "io/png.h"
#include "sim/geometry.h"
#include "sim/cloth/cloth_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

World makeWorld(const std::string& text, const std::string& file = "cloth.json") { return worldFromText(text, file); }

const ClothBody& body(const World& w) { return *w.first<ClothBody>(); }

// Edges (intact structural springs) that pass through a drawn triangle they do not touch.
int edgeCrossings(const ClothBody& b) {
  const Cloth& c = b.cloth();
  const auto& x = b.network().state.x;
  const Springs& s = b.network().model.springs;
  int crossings = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (c.spring_id[k] >= c.structural) continue;
    const int a = s.a[k], e = s.b[k];
    for (std::size_t t = 0; t < c.tris.size(); ++t) {
      if (!c.tri_alive[t]) continue;
      const auto& tri = c.tris[t];
      if (tri[0] == a || tri[1] == a || tri[2] == a || tri[0] == e || tri[1] == e || tri[2] == e) continue;
      crossings += segmentCrossesTriangle(x[a], x[e], x[tri[0]], x[tri[1]], x[tri[2]]);
    }
  }
  return crossings;
}

}  // namespace

TEST_CASE("a sheet draped over a sphere comes to rest on it without sinking into it") {
  const double R = 0.4, thick = 0.01;
  World w = makeWorld(R"({"format": "reel/1", "duration": 4, "fps": 30, "substeps": 20, "auto_substeps": true,
    "objects": [{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.4}, {"type": "plane"}],
    "bodies": [{"type": "cloth", "name": "sheet", "position": [0, 1.1, 0], "size": [1.4, 1.4], "resolution": [24, 24],
                "mass": 0.3, "stiffness": 600, "damping": 0.3, "node_damping": 0.02, "thickness": 0.01}]})");
  double deepest = 1e9;
  for (int f = 0; f < 120; ++f) {
    REQUIRE(w.advanceFrame().ok());
    for (const Vec3& p : body(w).network().state.x) deepest = std::min(deepest, (p - Vec3(0, 0.5, 0)).norm() - R);
  }
  // Nodes keep their contact offset (the thickness) from the surface, and never go inside it.
  CHECK(deepest >= thick - 1e-9);
  // At rest: the centre node sits on top of the sphere, and nothing moves.
  const Vec3 centre = body(w).network().state.x[12 * 24 + 12];
  CHECK(centre.y() == doctest::Approx(0.5 + R + thick).epsilon(0.02));
  CHECK(kineticEnergy(body(w).network().model, body(w).network().state) < 1e-4);
}

TEST_CASE("a sheet on an inclined plane stays when tan θ < μ and slides otherwise") {
  const double mu = 0.5;
  for (double deg : {20.0, 35.0}) {
    CAPTURE(deg);
    const double th = deg * kPi / 180.0;
    std::string n = "[";
    n += std::to_string(-std::sin(th));
    n += ", ";
    n += std::to_string(std::cos(th));
    n += ", 0]";
    World w = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 20, "auto_substeps": true,
      "objects": [{"type": "plane", "normal": )" + n + R"(, "surface": {"friction": 0.5}}],
      "bodies": [{"type": "cloth", "name": "s", "size": [0.4, 0.4], "resolution": [8, 8], "mass": 0.1,
                  "stiffness": 500, "damping": 0.2, "thickness": 0.005,
                  "rotation_deg": [0, 0, )" + std::to_string(deg) + R"(], "position": [0, 0.005, 0]}]})");
    const Vec3 start = body(w).network().state.x[27];
    run(w, 30);
    const double moved = (body(w).network().state.x[27] - start).norm();
    if (std::tan(th) < mu) {
      CHECK(moved < 0.01);
    } else {
      // Sliding with a = g (sin θ − μ cos θ) for 1 s covers ½at².
      const double expect = 0.5 * 9.78 * (std::sin(th) - mu * std::cos(th));
      CHECK(moved == doctest::Approx(expect).epsilon(0.15));
    }
  }
}

TEST_CASE("the energy of a damped hanging sheet decreases") {
  World w = makeWorld(R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 4, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "s", "size": [1, 1], "resolution": [16, 16], "mass": 0.2,
                "stiffness": 2000, "damping": 0.5, "node_damping": 0.01, "rotation_deg": [90, 0, 0],
                "velocity": [0, 0, 0.5], "pinned": ["corner_00", "corner_10"]}]})");
  double before = totalEnergy(body(w).network().model, body(w).network().state);
  for (int f = 0; f < 60; ++f) {
    REQUIRE(w.advanceFrame().ok());
    const double e = totalEnergy(body(w).network().model, body(w).network().state);
    CHECK(e < before);
    before = e;
  }
}

TEST_CASE("a sheet pulled at two opposite edges tears into exactly two pieces") {
  const std::string scene = R"({"format": "reel/1", "duration": 4, "fps": 30, "substeps": 40, "auto_substeps": true,
    "seed": 3, "gravity": [0, 0, 0],
    "bodies": [{"type": "cloth", "name": "s", "rotation_deg": [90, 0, 0], "size": [1.2, 1.2], "resolution": [30, 30],
                "mass": 0.3, "stiffness": 600, "damping": 0.2, "node_damping": 0.005,
                "tear": {"strain": 0.25, "variation": 0.1},
                "grips": [{"nodes": ["edge_x0"], "velocity": [-0.1, 0, 0]},
                          {"nodes": ["edge_x1"], "velocity": [0.1, 0, 0]}]}]})";
  World w = makeWorld(scene);
  CHECK(clothPieces(body(w).network().model.nodes(), body(w).network().model.springs) == 1);
  run(w, 120);
  const ClothBody& b = body(w);
  CHECK(b.cloth().springs_broken > 0);
  CHECK(clothPieces(b.network().model.nodes(), b.network().model.springs) == 2);
  // Every spring left is intact (not stretched past its threshold).
  const Springs& s = b.network().model.springs;
  for (std::size_t k = 0; k < s.size(); ++k)
    CHECK((b.network().state.x[s.b[k]] - b.network().state.x[s.a[k]]).norm() <= (1.0 + b.cloth().tear_strain[k]) * s.rest[k]);
  // Tears are deterministic: same bits for 1 and 2 threads.
  CHECK(runHash(scene, 1, 60) == runHash(scene, 2, 60));
}

TEST_CASE("a tear through a line of nodes gives each side its own vertices, UVs and normals") {
  // 5 x 5 nodes; the threads along column i = 2 (between nodes (2, j) and (2, j + 1)) broken.
  ClothDesc d;
  d.resolution = {5, 5};
  d.size = {1, 1};
  Cloth c;
  const MassSpringDesc ms = buildCloth(d, 0, c);
  std::vector<Vec3> x;
  for (const auto& n : ms.nodes) x.push_back(n.position);
  CHECK(clothMesh(c, x).vertexCount() == 25);
  for (std::size_t s = 0; s < ms.springs.size(); ++s) {
    const auto& sp = ms.springs[s];
    if (static_cast<int>(s) < c.structural && sp.b == sp.a + 5 && sp.a % 5 == 2) c.intact[s] = 0;
  }
  refreshTriangles(c);
  const TriMesh m = clothMesh(c, x);
  CHECK(m.triangleCount() == 32 - 8);  // each broken thread takes the triangle on either side
  // Nodes 2, 12 and 22 on the cut (where the cells' diagonals meet) get a vertex per side; nodes
  // 7 and 17 touch only the four triangles beside the cut, all gone.
  CHECK(m.vertexCount() == 25 + 3 - 2);
  std::vector<int> copies(25, 0);
  for (std::size_t v = 0; v < m.vertexCount(); ++v) {
    const Vec3 p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
    std::size_t node = 0;
    while ((x[node] - p).norm() > 1e-6) ++node;
    ++copies[node];
    CHECK(m.uvs[2 * v] == c.uv[2 * node]);
    CHECK(m.uvs[2 * v + 1] == c.uv[2 * node + 1]);
    CHECK(m.normals[3 * v + 1] == doctest::Approx(1.0));
  }
  CHECK(copies[2] == 2);
  CHECK(copies[12] == 2);
  CHECK(copies[22] == 2);
  CHECK(copies[7] == 0);
  CHECK(copies[17] == 0);
  CHECK(copies[1] == 1);
}

TEST_CASE("a sheet folding onto itself with self-collision has no edge through a triangle") {
  // A tall sheet dropped edge-first onto the floor buckles and folds over itself.
  auto scene = [](bool self) {
    return std::string(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 20, "auto_substeps": true,
      "objects": [{"type": "plane"}],
      "bodies": [{"type": "cloth", "name": "s", "position": [0, 0.62, 0], "rotation_deg": [88, 0, 0],
                  "size": [0.6, 1.2], "resolution": [12, 24], "mass": 0.1, "stiffness": 300, "damping": 0.1,
                  "bend_stiffness": 2, "node_damping": 0.005, "thickness": 0.008, "self_collision": )") +
           (self ? "true" : "false") + "}]}";
  };
  World w = makeWorld(scene(true));
  int worst = 0;
  for (int f = 0; f < 60; ++f) {
    REQUIRE(w.advanceFrame().ok());
    worst = std::max(worst, edgeCrossings(body(w)));
  }
  CHECK(worst == 0);
  // The sheet did fold: some node ended above another part of the sheet.
  double top = -1e9;
  for (const Vec3& p : body(w).network().state.x) top = std::max(top, p.y());
  CHECK(top > 0.02);
  // Without self-collision the same fold passes through itself (the check can fail).
  World free = makeWorld(scene(false));
  int crossed = 0;
  for (int f = 0; f < 60; ++f) {
    REQUIRE(free.advanceFrame().ok());
    crossed = std::max(crossed, edgeCrossings(body(free)));
  }
  CHECK(crossed > 0);
}

TEST_CASE("air: the viscous normal force and quadratic drag on one triangle match the formulas") {
  // Three nodes, one triangle in the x–z plane (normal +y, area 0.5 m²), wind (1, 2, 0) m/s.
  ClothDesc d;
  d.resolution = {2, 2};
  d.size = {1, 1};
  d.air.viscous = 3.0;
  Cloth c;
  const MassSpringDesc ms = buildCloth(d, 0, c);
  std::vector<Vec3> x, v(4, Vec3::Zero());
  for (const auto& n : ms.nodes) x.push_back(n.position);
  WindDesc wd;
  wd.velocity = Vec3(1, 2, 0);
  const Wind wind(wd, 0);
  airForces(c, wind, 0.0, x, v);
  Vec3 total = Vec3::Zero();
  for (const Vec3& f : c.f_air) total += f;
  // Two triangles of 0.5 m² each: f = c·A·(n·w)·n = 3 · 1 · 2 · ŷ.
  CHECK(total.x() == doctest::Approx(0.0));
  CHECK(total.y() == doctest::Approx(6.0));
  CHECK(total.z() == doctest::Approx(0.0));
  // Quadratic drag along the wind, ½ρA|w|²·C_d·|cos θ|, and lift across it.
  d.air = AirDesc{0.0, 1.0, 0.0, 1.2};
  buildCloth(d, 0, c);
  airForces(c, wind, 0.0, x, v);
  total.setZero();
  for (const Vec3& f : c.f_air) total += f;
  const double w2 = 5.0, cosq = 2.0 / std::sqrt(5.0);
  const Vec3 expect = 0.5 * 1.2 * 1.0 * w2 * cosq * Vec3(1, 2, 0) / std::sqrt(5.0);
  CHECK((total - expect).norm() < 1e-12);
  d.air = AirDesc{0.0, 0.0, 1.0, 1.2};
  buildCloth(d, 0, c);
  airForces(c, wind, 0.0, x, v);
  total.setZero();
  for (const Vec3& f : c.f_air) total += f;
  CHECK(std::abs(total.dot(Vec3(1, 2, 0))) < 1e-12);               // lift is across the wind
  CHECK(total.norm() == doctest::Approx(0.5 * 1.2 * w2 * cosq * (1.0 / std::sqrt(5.0))));  // q·|cos θ|·sin θ
}

TEST_CASE("wind gusts come from the seed") {
  WindDesc d;
  d.velocity = Vec3(3, 0, 0);
  d.gust = 2.0;
  const Wind a(d, 1), b(d, 1), c(d, 2);
  double lo = 1e9, hi = -1e9;
  for (int k = 0; k < 400; ++k) {
    const double t = 0.05 * k;
    CHECK(a.at(Vec3(0.5, 0, 0), t) == b.at(Vec3(0.5, 0, 0), t));
    lo = std::min(lo, a.at(Vec3::Zero(), t).x());
    hi = std::max(hi, a.at(Vec3::Zero(), t).x());
  }
  CHECK(a.at(Vec3::Zero(), 1.0) != c.at(Vec3::Zero(), 1.0));
  CHECK(lo >= 3.0 - 1e-12);  // gusts only strengthen the mean wind
  CHECK(hi - lo > 0.5);      // and they vary
}

TEST_CASE("strain limiting keeps structural springs within the limit") {
  auto stretch = [](const std::string& limit) {
    World w = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 20, "auto_substeps": true,
      "bodies": [{"type": "cloth", "name": "s", "size": [1, 1], "resolution": [12, 12], "mass": 1.0,
                  "stiffness": 10, "shear_stiffness": 10, "damping": 0.5, "rotation_deg": [90, 0, 0], "strain_limit": )" + limit + R"(,
                  "pinned": ["edge_z0"]}]})");
    run(w, 30);
    const ClothBody& b = body(w);
    double worst = 0;
    for (std::size_t k = 0; k < b.network().model.springs.size(); ++k)
      if (b.cloth().spring_id[k] < b.cloth().structural)
        worst = std::max(worst, (b.network().state.x[b.network().model.springs.b[k]] - b.network().state.x[b.network().model.springs.a[k]]).norm() /
                                        b.network().model.springs.rest[k] - 1.0);
    return worst;
  };
  CHECK(stretch("0") > 0.2);  // soft and heavy: it stretches a lot without the limit
  CHECK(stretch("0.1") < 0.1 + 0.01);
}

TEST_CASE("cloth collides with an imported mesh and is pushed by a moving object") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "reel_test_cloth";
  fs::create_directories(dir);
  // A square pyramid (base 1 m, apex 0.5 m up), closed, counter-clockwise from outside.
  std::ofstream(dir / "pyramid.obj") << "v -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0.5 0 0.5\nv -0.5 0 0.5\nv 0 0.5 0\n"
                                        "f 1 2 3\nf 1 3 4\nf 1 5 2\nf 2 5 3\nf 3 5 4\nf 4 5 1\n";
  World w = makeWorld(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 20, "auto_substeps": true,
    "objects": [{"type": "mesh", "file": "pyramid.obj", "thickness": 0.01}, {"type": "plane"}],
    "bodies": [{"type": "cloth", "name": "s", "position": [0, 0.8, 0], "size": [1.2, 1.2], "resolution": [20, 20],
                "mass": 0.2, "stiffness": 500, "damping": 0.2, "node_damping": 0.02, "thickness": 0.005}]})",
                      (dir / "scene.json").string());
  run(w, 60);
  // The centre node rests on the apex, none is inside the pyramid.
  const auto& x = body(w).network().state.x;
  CHECK(x[10 * 20 + 10].y() > 0.45);
  for (const Vec3& p : x) {
    const bool inside = p.y() > 0.001 && p.y() < 0.5 - std::max(std::abs(p.x()), std::abs(p.z())) - 0.02;
    CHECK_FALSE(inside);
  }
  // Just outside a convex edge (the urn's lip) the distance is positive: the face that sees the
  // point best decides, not the one that sees it edge-on.
  auto urn = sceneFromText(R"({"format": "reel/1", "duration": 1, "objects": [{"type": "mesh", "file": "urn.obj"}]})",
                           REEL_SOURCE_DIR "/scenes/meshes/scene.json");
  const Collider lip = makeCollider(urn.objects[0], 0.06);
  double d = 0;
  Vec3 nrm;
  REQUIRE(lip.distance(Vec3(0.19, 0.92, 0), d, nrm));
  CHECK(d == doctest::Approx(std::sqrt(0.01 * 0.01 + 0.02 * 0.02)));
  CHECK(nrm.y() > 0.8);
  // A box sweeping along x at 1 m/s carries a sheet lying in its path.
  World m = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 20, "auto_substeps": true,
    "objects": [{"type": "plane"},
                {"type": "box", "center": [-0.6, 0.1, 0], "size": [0.2, 0.2, 1.0],
                 "motion": {"keys": [{"time": 0, "position": [-0.6, 0.1, 0]}, {"time": 1, "position": [0.4, 0.1, 0]}]}}],
    "bodies": [{"type": "cloth", "name": "s", "position": [0, 0.005, 0], "size": [0.3, 0.3], "resolution": [6, 6],
                "mass": 0.05, "stiffness": 300, "damping": 0.1}]})");
  run(m, 30);
  double minx = 1e9;
  for (const Vec3& p : body(m).network().state.x) minx = std::min(minx, p.x());
  CHECK(minx > 0.4 + 0.1 - 0.02);  // pushed ahead of the box's leading face
}

TEST_CASE("cloth state is bit-identical for 1 and 2 threads (wind, self-collision, tearing)") {
  const std::string scene = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 10, "auto_substeps": true,
    "seed": 7, "wind": {"velocity": [2, 0, 1], "gust": 3},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.3}, {"type": "plane", "point": [0, -0.5, 0]}],
    "bodies": [{"type": "cloth", "name": "s", "position": [0, 0.5, 0], "size": [1.5, 1.5], "resolution": [48, 48],
                "mass": 0.3, "stiffness": 400, "damping": 0.1, "self_collision": true, "strain_limit": 0.2,
                "air": {"viscous": 0.5, "drag": 0.3, "lift": 0.2}, "tear": {"strain": 0.3, "variation": 0.3}}]})";
  const std::uint64_t h1 = runHash(scene, 1, 6);
  CHECK(runHash(scene, 2, 6) == h1);
  CHECK(runHash(scene, 1, 6) == h1);
}

TEST_CASE("implicit Euler cloth is bit-identical for 1 and 2 threads (block-Jacobi CG, self-collision, tearing)") {
  // 2,304 nodes: above the size at which loops run in parallel; tearing rebuilds the springs'
  // groups of the conjugate-gradient product between steps.
  const std::string scene = R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 5, "integrator": "implicit_euler",
    "implicit": {"cg_tolerance": 1e-3, "cg_max_iterations": 200}, "seed": 3,
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.3}],
    "bodies": [{"type": "cloth", "name": "s", "position": [0, 0.5, 0], "size": [1.5, 1.5], "resolution": [48, 48],
                "mass": 0.3, "stiffness": 2000, "damping": 0.5, "self_collision": true,
                "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"], "tear": {"strain": 0.03, "variation": 0.3}}]})";
  const std::uint64_t h1 = runHash(scene, 1, 12);
  CHECK(runHash(scene, 2, 12) == h1);
  World w = makeWorld(scene);
  const std::size_t springs = body(w).network().model.springs.size();
  run(w, 12);
  const ClothBody& b = body(w);
  CHECK(b.network().model.springs.size() < springs);  // it tore
  // After the tear the springs' product still equals the matrix assembled from the intact springs.
  const std::size_t n = b.network().model.nodes();
  std::vector<Vec3> rhs(n), p(n), out(n);
  std::vector<Mat3> pinv(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = Vec3(uniformAt(5, 0, i) - 0.5, uniformAt(5, 1, i) - 0.5, uniformAt(5, 2, i) - 0.5);
  const double h = 1.0 / 150.0;
  b.network().system->linearize(b.network().state.x.data(), b.network().state.v.data(), b.network().state.v.data(), h, rhs.data(), pinv.data());
  b.network().system->applySystem(p.data(), out.data());
  const std::vector<Vec3> want = assembleSystem(b.network().model, b.network().state.x, h).product(b.network().model, h, p);
  double scale = 0, err = 0;
  for (std::size_t i = 0; i < n; ++i) {
    scale = std::max(scale, want[i].norm());
    // (A pinned corner's row is never used: the product gives 0 there.)
    err = std::max(err, (out[i] - (b.network().model.fixed[i] ? Vec3::Zero() : want[i])).norm());
  }
  CHECK(err <= 1e-6 * scale);
}

TEST_CASE("cloth bad input: resolution, size, mass, tear threshold, pins, mesh files") {
  auto errs = [](const std::string& body, const std::string& file = "s.json") {
    auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "cloth", "name": "c", )" + body + "}]}", file);
    std::string all;
    if (!r.ok())
      for (const auto& m : r.error().messages) all += m + "\n";
    return all;
  };
  CHECK(errs(R"("resolution": [1, 4])").find("/bodies/0/resolution/0: must be an integer in [2, 65536]") != std::string::npos);
  CHECK(errs(R"("size": [0, 1])").find("/bodies/0/size/0: must be > 0") != std::string::npos);
  CHECK(errs(R"("mass": -1)").find("/bodies/0/mass: must be > 0") != std::string::npos);
  CHECK(errs(R"("density": 0)").find("/bodies/0/density: must be > 0") != std::string::npos);
  CHECK(errs(R"("mass": 1, "density": 1)").find("/bodies/0/density: give mass or density, not both") != std::string::npos);
  CHECK(errs(R"("tear": {"strain": 0})").find("/bodies/0/tear/strain: must be > 0") != std::string::npos);
  CHECK(errs(R"("tear": {})").find("/bodies/0/tear/strain: missing required key") != std::string::npos);
  CHECK(errs(R"("resolution": [4, 3], "pinned": [12])").find("/bodies/0/pinned/0: must be an integer in [-12, 11]") != std::string::npos);
  CHECK(errs(R"("pinned": ["edge_x2"])").find("/bodies/0/pinned/0: unknown node name \"edge_x2\"; did you mean \"edge_x0\"?") != std::string::npos);
  CHECK(errs(R"("grips": [{"velocity": [1, 0, 0]}])").find("/bodies/0/grips/0/nodes: missing required key") != std::string::npos);
  CHECK(errs(R"("pinned": ["corner_00"], "grips": [{"nodes": [0]}])").find("/bodies/0/grips/0/nodes: node 0 is already pinned") != std::string::npos);
  CHECK(errs(R"("resolution": [4, 4], "thickness": 0)").find("/bodies/0/thickness: must be") != std::string::npos);
  CHECK(errs(R"("thickness": 2)").find("/bodies/0/thickness") != std::string::npos);
  CHECK(errs(R"("tear": {"strain": 0.1, "variation": 1})").find("/bodies/0/tear/variation") != std::string::npos);
  CHECK(errs(R"("grips": [{"nodes": [0], "start": 2, "stop": 1}])").find("/bodies/0/grips/0/stop: must be after start") != std::string::npos);
  // Meshes: missing, unsupported, corrupt, outside the allowed roots.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "reel_test_cloth_bad" / "sub";
  fs::create_directories(dir);
  std::ofstream(dir / "broken.obj") << "v 0 0 0\nf 1 2 3 4 5\nthis is not obj\n";
  std::ofstream(dir / "model.blend") << "blend";
  std::ofstream(dir.parent_path() / "outside.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  auto mesh = [&](const std::string& f) {
    auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "objects": [{"type": "mesh", "file": ")" + f + R"("}]})",
                            (dir / "scene.json").string());
    return r.ok() ? std::string() : r.error().headline();
  };
  CHECK(mesh("nope.obj").find("/objects/0/file: \"nope.obj\": no such file") != std::string::npos);
  CHECK(mesh("model.blend").find("/objects/0/file") != std::string::npos);
  CHECK(mesh("broken.obj").find("/objects/0/file") != std::string::npos);
  CHECK(mesh("../outside.obj").find("/objects/0/file") != std::string::npos);
  // Objects: motion keys must increase in time.
  auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "objects": [{"type": "sphere", "radius": 1,
      "motion": {"keys": [{"time": 1}, {"time": 0.5}]}}]})", "s.json");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().headline().find("/objects/0/motion/keys/1/time: keyframe times must increase") != std::string::npos);
}

TEST_CASE("a cloth that blows up stops as unstable (exit 3), with self-collision and strain limiting on") {
  auto w = app::makeWorld(sceneFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 2,
    "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "s", "resolution": [12, 12], "self_collision": true, "strain_limit": 0.1,
                "grips": [{"nodes": ["edge_x0"], "velocity": [1e300, 0, 0]}]}]})"));
  REQUIRE(w.ok());
  Status st;
  for (int f = 0; f < 5 && st; ++f) st = w.value().advanceFrame();
  REQUIRE_FALSE(st);
  CHECK(st.error().kind == ErrorKind::Unstable);
  CHECK(st.error().headline().find("body 's'") != std::string::npos);
}

TEST_CASE("a cloth's clamps and pins are drawn: a bar along each grip, a peg at each other pinned node") {
  World w = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "c", "position": [0, 1, 0], "size": [1, 1], "resolution": [6, 6],
                "pinned": ["corner_11"], "grips": [{"nodes": ["edge_x0"], "velocity": [-0.1, 0, 0]}]}]})");
  DrawList list;
  w.draw(list);
  REQUIRE(list.tubes.size() == 1);
  CHECK(list.tubes[0].ends.size() == 6 * 5);  // 6 gripped nodes along the edge: 5 bars
  // Each bar joins two neighbours of the gripped edge, x = −0.5, one grid step (0.2 m) apart.
  for (std::size_t b = 0; b < 5; ++b) {
    const float* e = &list.tubes[0].ends[6 * b];
    CHECK(e[0] == doctest::Approx(-0.5));
    CHECK(e[3] == doctest::Approx(-0.5));
    CHECK(std::hypot(e[3] - e[0], e[4] - e[1], e[5] - e[2]) == doctest::Approx(0.2).epsilon(1e-6));
  }
  REQUIRE(list.spheres.size() == 1);
  REQUIRE(list.spheres[0].centers.size() == 3);  // the one pinned corner
  CHECK(list.spheres[0].centers[0] == doctest::Approx(0.5));
  // A free sheet draws nothing but itself.
  World free = makeWorld(R"({"format": "reel/1", "duration": 1, "fps": 30, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "c", "position": [0, 1, 0], "size": [1, 1], "resolution": [6, 6]}]})");
  DrawList plain;
  free.draw(plain);
  CHECK(plain.tubes.empty());
  CHECK(plain.spheres.empty());
}

TEST_CASE("a cloth's back_color: its front (where its normal points: up for a level sheet) and its back differ") {
  const std::filesystem::path d = test::freshDir("cloth_back");
  // The centre pixel of a level sheet seen from above or below, with or without a back colour.
  auto centre = [&](const std::string& eye, const std::string& back) {
    std::ofstream(d / "s.json") << R"({"format": "reel/1", "duration": 0.2, "fps": 10, "integrator": "implicit_euler",
      "gravity": [0, 0, 0], "render": {"width": 64, "height": 48, "samples": 1},
      "camera": {"position": )" << eye << R"(, "target": [0, 0.5, 0]},
      "bodies": [{"type": "cloth", "name": "c", "position": [0, 0.5, 0], "size": [2, 2], "resolution": [4, 4],
                  "color": [0.8, 0.1, 0.1])" << back << "}]}";
    const Run r = runReel("still s.json --frame 0 --no-cache -q -o out.png", "cd " + d.string() + " && ");
    REQUIRE(r.code == 0);
    auto img = io::readPng((d / "out.png").string());
    REQUIRE(img.ok());
    const std::uint8_t* p = img.value().pixel(32, 24);
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  const std::string above = "[0, 2, 0.01]", below = "[0, -1.5, 0.01]", blue = R"(, "back_color": [0.1, 0.1, 0.8])";
  const auto front = centre(above, blue), back = centre(below, blue), same = centre(below, "");
  CHECK(front[0] > 2 * front[2]);  // red from above
  CHECK(back[2] > 2 * back[0]);    // blue from below
  CHECK(same[0] > 2 * same[2]);    // without back_color the back is the front's red
}
