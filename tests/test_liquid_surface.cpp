// The surface a liquid is drawn with (sim/fluid/fluid_surface.*): anisotropic kernels (Yu & Turk
// 2013) keep a resting pool flat and a thin stream whole, the surface stays by its particles, and
// it is the same bits on any number of threads.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <set>

#include "core/isosurface.h"
#include "core/union_find.h"
#include "contact_helpers.h"
#include "fluid_helpers.h"
#include "render_helpers.h"
#include "sim/fluid/fluid_body.h"
#include "sim/fluid/fluid_diffuse.h"
#include "sim/fluid/fluid_surface.h"

using namespace reel;
using namespace reel::test;

namespace {

// A world of one liquid (the tests' water, 2 cm apart at rest) at the given particles, without
// gravity, drawn as a surface with `kernels` ("anisotropic" or "isotropic"); at rest, or at the
// velocities `v` (one per particle); `extra`: more keys of the liquid ("\"shutter\": 0, ").
World liquidAt(const std::vector<Vec3>& p, const std::string& kernels, int smoothing = 2, const std::vector<Vec3>& v = {},
               const std::string& extra = "") {
  std::string list, vel;
  for (const Vec3& x : p) list += (list.empty() ? "" : ",") + vec(x);
  for (const Vec3& u : v) vel += (vel.empty() ? "" : ",") + vec(u);
  return makeWorld(std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 30, "gravity": [0, 0, 0],
    "bodies": [{"type": "fluid", "name": "f", "radius": 0.01, "draw": "surface", "surface_kernels": ")") + kernels +
                   R"(", "surface_smoothing": )" + std::to_string(smoothing) + ", " + extra + R"("species": [)" + kWater +
                   R"(], "particles": [{"positions": [)" + list + "]" + (v.empty() ? "" : ", \"velocities\": [" + vel + "]") +
                   "}]}]}");
}

// The liquid's drawn surface.
TriMesh surfaceOf(const World& w) {
  DrawList list;
  w.draw(list);
  REQUIRE(list.meshes.size() == 1);
  return *list.meshes[0].mesh;
}

Vec3 vertex(const TriMesh& m, std::size_t v) { return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}; }

// A pool packed as a settled liquid packs (1.6 cm apart, 0.8 of the rest distance), each particle
// moved up to 0.3 of that at random (seeded), 16 × 4 × 16 particles from the origin: its top layer
// at 4.8 cm.
std::vector<Vec3> roughPool(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.005, 0.005);
  std::vector<Vec3> p;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 16; ++i) p.push_back(0.016 * Vec3(i, j, k) + Vec3(jitter(rng), jitter(rng), jitter(rng)));
  return p;
}

// The mean height of the pool's top surface over its middle (5 cm from its sides) and its
// standard deviation, m.
std::pair<double, double> topHeights(const TriMesh& m) {
  double s1 = 0, s2 = 0;
  int n = 0;
  for (std::size_t v = 0; v < m.vertexCount(); ++v) {
    const Vec3 x = vertex(m, v);
    if (x.y() < 0.03 || std::abs(x.x() - 0.12) > 0.07 || std::abs(x.z() - 0.12) > 0.07) continue;
    s1 += x.y(), s2 += x.y() * x.y(), ++n;
  }
  REQUIRE(n > 100);
  const double mean = s1 / n;
  return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean))};
}

// How many pieces the mesh is in (triangles joined through shared vertices).
int pieces(const TriMesh& m) {
  std::vector<int> parent(m.vertexCount());
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = static_cast<int>(v);
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    unite(parent, static_cast<int>(m.indices[t]), static_cast<int>(m.indices[t + 1]));
    unite(parent, static_cast<int>(m.indices[t]), static_cast<int>(m.indices[t + 2]));
  }
  int n = 0;
  for (std::size_t v = 0; v < parent.size(); ++v) n += findRoot(parent, static_cast<int>(v)) == static_cast<int>(v);
  return n;
}

}  // namespace

TEST_CASE("a resting pool's surface is flat, and flatter with anisotropic kernels") {
  const std::vector<Vec3> pool = roughPool(7);
  const auto [amean, astd] = topHeights(surfaceOf(liquidAt(pool, "anisotropic")));
  const auto [imean, istd] = topHeights(surfaceOf(liquidAt(pool, "isotropic", 0)));
  MESSAGE("top surface over the middle: anisotropic " << amean << " ± " << astd << " m, isotropic unsmoothed " << imean
                                                       << " ± " << istd << " m");
  // Its heights spread by less than a tenth of the particle spacing (their own jitter: ±0.3).
  CHECK(astd < 0.1 * 0.016);
  CHECK(istd < 0.1 * 0.016);
  CHECK(astd < 0.95 * istd);
  // Above the top layer (4.8 cm), and within half a spacing of where the isotropic surface is
  // (the centres' smoothing draws the surface in a little).
  CHECK(amean > 0.048);
  CHECK(std::abs(amean - imean) < 0.5 * 0.016);
}

TEST_CASE("a thin stream stays one connected surface along its length") {
  // A falling stream thinned to three particles across, 3 cm apart along it (stretched by its
  // fall beyond the 2 cm of rest), its particles jittered: 40 cm long.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  std::vector<Vec3> stream;
  for (int k = 0; k < 14; ++k)
    for (int a = 0; a < 3; ++a) {
      const double t = 2.0944 * a + 0.6 * k;  // the three turn about the axis as they fall
      stream.push_back(Vec3(0.01 * std::cos(t), 0.03 * k, 0.01 * std::sin(t)) + Vec3(jitter(rng), jitter(rng), jitter(rng)));
    }
  const TriMesh a = surfaceOf(liquidAt(stream, "anisotropic"));
  double top = -1e9, bottom = 1e9, widest = 0;
  for (std::size_t v = 0; v < a.vertexCount(); ++v) {
    const Vec3 x = vertex(a, v);
    top = std::max(top, x.y()), bottom = std::min(bottom, x.y());
    widest = std::max(widest, std::hypot(x.x(), x.z()));
  }
  const World iso = liquidAt(stream, "isotropic", 0);
  DrawList list;
  iso.draw(list);
  const int iso_pieces = list.meshes.empty() ? 0 : pieces(*list.meshes[0].mesh);
  MESSAGE("anisotropic: " << pieces(a) << " piece(s) from y = " << bottom << " to " << top << " m, " << widest
                          << " m from the axis at most; isotropic: " << iso_pieces << " piece(s)");
  CHECK(pieces(a) == 1);
  CHECK(bottom < 0.01);  // from within 1 cm of the first particle (at 0) to the last (0.39 m)
  CHECK(top > 0.38);
  CHECK(widest < 0.035);  // a stream, not a row of blobs: within 3.5 cm of its axis
  CHECK(iso_pieces != 1);  // the isotropic kernels of so few particles leave beads or nothing
}

TEST_CASE("the liquid's surface stays within a kernel radius of its particles") {
  for (const char* kernels : {"anisotropic", "isotropic"}) {
    CAPTURE(kernels);
    const std::vector<Vec3> pool = roughPool(11);
    const TriMesh m = surfaceOf(liquidAt(pool, kernels));
    REQUIRE(m.vertexCount() > 100);
    double farthest = 0;
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
      double d = 1e9;
      for (const Vec3& p : pool) d = std::min(d, (vertex(m, v) - p).norm());
      farthest = std::max(farthest, d);
    }
    MESSAGE("farthest vertex from a particle: " << farthest << " m");
    CHECK(farthest < 0.04);  // the kernel radius, 4 × the particle radius
  }
}

TEST_CASE("the liquid's surface is the same bits on one thread and two") {
  const std::vector<Vec3> pool = roughPool(5);
  auto mesh = [&](int threads) {
    const ParallelForTest parallel(threads);
    return surfaceOf(liquidAt(pool, "anisotropic"));
  };
  const TriMesh one = mesh(1), two = mesh(2);
  REQUIRE(one.vertexCount() > 100);
  CHECK(one.positions == two.positions);
  CHECK(one.normals == two.normals);
  CHECK(one.indices == two.indices);
}

TEST_CASE("surface_kernels and surface_smoothing: bad values are refused with their path") {
  const std::string text = R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "fluid", "name": "f", "draw": "surface",
    "surface_kernels": "elliptic", "surface_smoothing": 40, "species": [{"name": "w"}],
    "blocks": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1], "spacing": 0.02}]}]})";
  const std::string all = badInputErrors(text);
  CAPTURE(all);
  CHECK(all.find("/bodies/0/surface_kernels") != std::string::npos);
  CHECK(all.find("/bodies/0/surface_smoothing") != std::string::npos);
}

TEST_CASE("marching in slabs: one mesh, no vertex made twice, the same on one thread and two") {
  // A torus's field over 40 node layers (slabs of 3): its surface crosses every slab boundary.
  const GridField f = sampledField(40, 0.05, Vec3::Constant(-1.0), [](const Vec3& p) {
    return 0.3 - std::hypot(std::hypot(p.x(), p.z()) - 0.6, p.y() * 1.5);
  });
  auto march = [&](int threads) {
    const ParallelForTest parallel(threads);
    return isosurface(f, 0.0123);  // (no node exactly on the level: its edges would share a point)
  };
  const TriMesh one = march(1), two = march(2);
  REQUIRE(one.triangleCount() > 500);
  CHECK(one.positions == two.positions);
  CHECK(one.indices == two.indices);
  std::set<std::array<float, 3>> distinct;
  for (std::size_t v = 0; v < one.vertexCount(); ++v) distinct.insert({one.positions[3 * v], one.positions[3 * v + 1], one.positions[3 * v + 2]});
  CHECK(distinct.size() == one.vertexCount());
  CHECK(pieces(one) == 1);
  // Every vertex is used, every edge has two triangles (closed across the slabs' seams).
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  std::vector<char> used(one.vertexCount(), 0);
  for (std::size_t t = 0; t < one.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = one.indices[t + static_cast<std::size_t>(e)], b = one.indices[t + static_cast<std::size_t>((e + 1) % 3)];
      used[a] = 1;
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  CHECK(std::count(used.begin(), used.end(), 1) == static_cast<std::ptrdiff_t>(one.vertexCount()));
  int open = 0;
  for (const auto& [e, count] : edges) open += count != 2;
  CHECK(open == 0);
}

TEST_CASE("a fast droplet of spray is drawn as the streak it leaves over half a frame") {
  // A pool, and one particle far above it falling at 3 m/s; the scene runs at 30 frames a second.
  std::vector<Vec3> p = roughPool(2);
  const Vec3 drop(0.1, 0.5, 0.1);
  p.push_back(drop);
  std::vector<Vec3> v(p.size(), Vec3::Zero());
  v.back() = Vec3(0, -3, 0);
  const World w = liquidAt(p, "anisotropic", 2, v);
  DrawList out;
  w.draw(out);
  REQUIRE(out.tubes.size() == 1);
  const std::vector<float>& e = out.tubes[0].ends;
  REQUIRE(e.size() == 6);
  // From where it was half a frame ago (5 cm higher) to where it is.
  CHECK(e[1] == doctest::Approx(0.5 + 3.0 / 60.0));
  CHECK(e[4] == doctest::Approx(0.5));
  CHECK(e[0] == doctest::Approx(0.1));
  CHECK(out.tubes[0].radius == doctest::Approx(0.006));
  // Capped by a droplet at each end.
  REQUIRE(out.spheres.size() == 1);
  CHECK(out.spheres[0].centers.size() == 6);
}

TEST_CASE("reel check says when a nozzle pours separate discs, and the rate that pours a stream") {
  auto notes = [](double rate) {
    const World w = makeWorld(std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 30,
      "bodies": [{"type": "fluid", "name": "f", "radius": 0.01, "draw": "surface", "species": [)") + kWater +
                              R"(], "emitters": [{"position": [0, 1, 0], "speed": 1.5, "radius": 0.05, "rate": )" +
                              std::to_string(rate) + "}]}]}");
    std::string all;
    for (const auto& b : w.bodies())
      for (const std::string& line : b->notes(w.stepSize())) all += line + "\n";
    return all;
  };
  const std::string sparse = notes(900);  // cloth_liquid's pours: 1.5 m/s, 5 cm, 900 a second
  CAPTURE(sparse);
  const auto at = sparse.find("emitter 0: its layers leave ");
  REQUIRE(at != std::string::npos);
  CHECK(sparse.find("pours separate discs") != std::string::npos);
  const auto rate_at = sparse.find("\"rate\": ", at);
  REQUIRE(rate_at != std::string::npos);
  const double suggested = std::stod(sparse.substr(rate_at + 8));
  CHECK(suggested > 900 * 0.02725 / 0.02);  // at least so much more that the layers come within the cutoff
  // At the suggested rate the layers leave 2 cm apart, within the cutoff: no note.
  CHECK(notes(suggested).find("emitter 0") == std::string::npos);
}

TEST_CASE("foam: a blob thrown into a pool seeds foam that lingers, drifts and dies out; a pool at rest has none") {
  // A pool at rest, and a blob thrown down into it at 3 m/s; under gravity, 30 frames a second;
  // diffuse particles live 0.3 s on average (0.15 to 0.45 s).
  auto scene = [](double foam, bool thrown) {
    std::string blocks = R"({"min": [0, 0, 0], "max": [0.3, 0.06, 0.3], "spacing": 0.016})";
    if (thrown) blocks += R"(, {"min": [0.1, 0.15, 0.1], "max": [0.2, 0.22, 0.2], "spacing": 0.016, "velocity": [0, -3, 0]})";
    return std::string(R"({"format": "reel/1", "duration": 2, "fps": 30, "substeps": 40,
      "objects": [{"type": "container", "center": [0.15, 0.1, 0.15], "size": [0.34, 0.2, 0.34], "wall": 0.02}],
      "bodies": [{"type": "fluid", "name": "f", "radius": 0.008, "draw": "surface", "foam_life": 0.3, "foam": )") +
           std::to_string(foam) + R"(, "species": [)" + kWater + R"(], "blocks": [)" + blocks + "]}]}";
  };
  // The white flecks drawn (foam, bubbles, spray: white, casting no shadow).
  auto flecks = [](const World& w) {
    DrawList out;
    w.draw(out);
    std::size_t n = 0;
    for (const DrawSpheres& s : out.spheres)  // (droplets carry their species' colours per sphere)
      if (s.material.color.x() > 0.9 && !s.material.casts_shadow && s.colors.empty()) n += s.centers.size() / 3;
    return n;
  };
  World still = makeWorld(scene(1.0, false)), thrown = makeWorld(scene(1.0, true)), plain = makeWorld(scene(0.0, true));
  std::size_t at_rest = 0, churned = 0, none = 0;  // the most in any of the first 8 frames
  for (int f = 0; f < 8; ++f) {
    run(still, 1);
    run(thrown, 1);
    run(plain, 1);
    at_rest = std::max(at_rest, flecks(still)), churned = std::max(churned, flecks(thrown)), none = std::max(none, flecks(plain));
  }
  MESSAGE("foam flecks: pool at rest " << at_rest << ", blob thrown in " << churned << ", foam 0 " << none);
  CHECK(at_rest == 0);
  CHECK(churned > 50);
  CHECK(none == 0);
  CHECK(fluid(thrown).diffuse_x.size() == flecks(thrown));
  // Carried from step to step: the foam of the landing is still there a tick after the churn
  // ends, where the liquid has carried it, and none of it outlives its longest life once the pool
  // is calm.
  run(thrown, 1);
  const Fluid& fl = fluid(thrown);
  REQUIRE(!fl.diffuse_x.empty());
  // Foam and bubbles ride the liquid: each within two cutoffs of a particle.
  int riding = 0;
  for (std::size_t d = 0; d < fl.diffuse_x.size(); ++d) {
    if (fl.diffuse_kind[d] == static_cast<std::uint8_t>(DiffuseKind::Spray)) continue;
    double nearest = 1e9;
    for (const Vec3& x : fl.x) nearest = std::min(nearest, (x - fl.diffuse_x[d]).norm());
    CHECK(nearest < 2 * fl.cutoff_max);
    ++riding;
  }
  CHECK(riding > 20);
  for (double l : fl.diffuse_life) {  // 0.5 to 1.5 times foam_life, aged since
    CHECK(l > 0);
    CHECK(l <= 0.45);
  }
  // A restored state with a speck out of its life, or a serial number never given, is refused.
  {
    FluidBody good(fluid(thrown), "fluid", Material{});
    StateBlob blob;
    good.snapshot(blob);
    FluidBody target(fluid(thrown), "fluid", Material{});
    CHECK(target.restore(blob));
    for (int damage = 0; damage < 2; ++damage) {
      Fluid bad_state = fluid(thrown);
      REQUIRE(!bad_state.diffuse_life.empty());
      if (damage == 0) bad_state.diffuse_life[0] = -1.0;
      else bad_state.diffuse_id[0] = bad_state.diffuse_made;
      FluidBody bad(std::move(bad_state), "fluid", Material{});
      StateBlob b;
      bad.snapshot(b);
      CHECK(!target.restore(b));
    }
  }
  run(thrown, 45);  // 1.5 s more
  MESSAGE("flecks 1.5 s later: " << flecks(thrown));
  CHECK(flecks(thrown) < churned / 4);
  // The same bits on 1 and 2 threads, and resumed from a snapshot (the diffuse particles are in the
  // state and its hash).
  sameBitsThreadsAndResume(scene(1.0, true), 8);
  CHECK(runHash(scene(1.0, true), 1, 8) != runHash(scene(0.5, true), 1, 8));
  // Bad keys named.
  const std::string bad = badInputErrors(std::string(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "fluid", "name": "f",
    "foam": 2, "foam_life": 0, "species": [{"name": "w"}], "blocks": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1], "spacing": 0.02}]}]})"));
  CAPTURE(bad);
  CHECK(bad.find("/bodies/0/foam:") != std::string::npos);
  CHECK(bad.find("/bodies/0/foam_life") != std::string::npos);
}

TEST_CASE("a falling string of drops is drawn as the streak an open shutter sees: one stream, not beads") {
  // Eight drops of 14 particles, 7 cm apart, falling at 3.5 m/s (a pour a metre down); 30 frames a
  // second, the shutter open half a frame (5.8 cm of travel) or not at all.
  std::vector<Vec3> p;
  for (int b = 0; b < 8; ++b)
    for (int layer = 0; layer < 2; ++layer) {
      const Vec3 c(0, 0.07 * b + 0.016 * layer, 0);
      p.push_back(c);
      for (int a = 0; a < 6; ++a) p.push_back(c + 0.016 * Vec3(std::cos(1.0472 * a + layer), 0, std::sin(1.0472 * a + layer)));
    }
  auto surface = [&](double shutter) {
    return surfaceOf(liquidAt(p, "anisotropic", 2, std::vector<Vec3>(p.size(), Vec3(0, -3.5, 0)),
                              "\"shutter\": " + std::to_string(shutter) + ", "));
  };
  const TriMesh sharp = surface(0.0), swept = surface(0.5);
  double top = -1e9, bottom = 1e9;
  for (std::size_t v = 0; v < swept.vertexCount(); ++v) top = std::max(top, vertex(swept, v).y()), bottom = std::min(bottom, vertex(swept, v).y());
  MESSAGE("drops: " << pieces(sharp) << " pieces sharp, " << pieces(swept) << " swept, from y = " << bottom << " to " << top);
  CHECK(pieces(sharp) >= 4);
  CHECK(pieces(swept) == 1);
  // The streak trails above the drops (where they were), not below them.
  CHECK(top > 0.07 * 7 + 0.016 + 0.03);
  CHECK(bottom > -0.03);
}

TEST_CASE("a kernel's sweep runs back along its particle's path and is at most as long as asked") {
  const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(0.02, 0, 0), Vec3(0, 0.02, 0)};
  const std::vector<Vec3> v = {Vec3(0, -100, 0), Vec3(1, 0, 0), Vec3(0, 0, 0)};  // flung, a pour, at rest
  const std::vector<std::size_t> part = {0, 1, 2};
  std::vector<SurfaceKernel> k = surfaceKernels(x, part, 0.04, true);
  sweepKernels(k, v, part, 1.0 / 60.0, 0.08);
  CHECK(k[0].travel.isApprox(Vec3(0, 0.08, 0)));           // 1.67 m cut to 8 cm, up where it came from
  CHECK(k[1].travel.isApprox(Vec3(-1.0 / 60.0, 0, 0)));  // 1.7 cm back
  CHECK(k[2].travel == Vec3::Zero());
  // Along the sweep the kernel is as dense as at its centre; beyond its ends it falls off.
  CHECK(k[0].q2(k[0].centre + 0.5 * k[0].travel) == doctest::Approx(0.0).epsilon(1e-12));
  CHECK(k[0].q2(k[0].centre + 1.2 * k[0].travel) > 0.0);
  CHECK(k[0].hi().y() >= k[0].centre.y() + 0.08);
}

TEST_CASE("each species its own clarity: clear water and opaque paint in one surface") {
  // A pool 24 cm square and 6 cm deep, water (clear, the liquid's transmission 0.9) on the left
  // half and paint (transmission 0) on the right, seen from above with no light against a grey
  // background: all that shows is what passes through.
  std::string water, paint;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 16; ++i)
        (i < 8 ? water : paint) += std::string((i < 8 ? water : paint).empty() ? "" : ",") + vec(0.016 * Vec3(i, j, k));
  auto scene = [&](const std::string& paint_transmission) {
    return std::string(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 30, "gravity": [0, 0, 0],
      "render": {"width": 96, "height": 96, "samples": 1, "background": [0.6, 0.6, 0.6]},
      "camera": {"position": [0.12, 0.9, 0.1201], "target": [0.12, 0, 0.12], "fov_deg": 20}, "lights": [],
      "bodies": [{"type": "fluid", "name": "f", "radius": 0.01, "draw": "surface", "transmission": 0.9, "absorption_depth": 0.5,
        "species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "color": [0.9, 0.9, 0.9]},
                    {"name": "paint", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "color": [0.9, 0.2, 0.1])") +
           paint_transmission + R"(}],
        "particles": [{"species": "water", "positions": [)" + water + R"(]}, {"species": "paint", "positions": [)" + paint + "]}]}]}";
  };
  const std::string two = scene(R"(, "transmission": 0)"), one = scene("");
  World w = makeWorld(two);
  const TriMesh m = surfaceOf(w);
  DrawList list;
  w.draw(list);
  CHECK(list.meshes[0].material.transmission == doctest::Approx(0.9));  // the clearest species'
  REQUIRE(m.clarity.size() == m.vertexCount());
  int clear = 0, opaque = 0;
  for (std::size_t v = 0; v < m.vertexCount(); ++v) {
    const double x = vertex(m, v).x();
    if (x < 0.06) {
      CHECK(m.clarity[v] > 0.95f);
      ++clear;
    }
    if (x > 0.18) {
      CHECK(m.clarity[v] < 0.05f);
      ++opaque;
    }
  }
  CHECK(clear > 100);
  CHECK(opaque > 100);
  // One clarity for the whole liquid: none per vertex.
  CHECK(surfaceOf(makeWorld(one)).clarity.empty());
  // Drawn: the background shows through the water, not through the paint (unlit: black).
  const Image img = renderScene(two);
  const double to_px = 48.0 / (0.9 * std::tan(10.0 * kPi / 180.0));  // pixels per metre at the pool's depth
  const int water_px = static_cast<int>(48 - 0.08 * to_px), paint_px = static_cast<int>(48 + 0.08 * to_px);
  CAPTURE(int(img.pixel(water_px, 48)[1]));
  CAPTURE(int(img.pixel(paint_px, 48)[1]));
  CHECK(img.pixel(water_px, 48)[1] > 80);
  CHECK(img.pixel(paint_px, 48)[1] < 8);
  // Bad clarity refused with its path.
  const std::string bad = badInputErrors(scene(R"(, "transmission": 1.5)"));
  CAPTURE(bad);
  CHECK(bad.find("/bodies/0/species/1/transmission") != std::string::npos);
}
