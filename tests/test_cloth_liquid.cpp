// Cloth ↔ liquid: momentum kept, the weight of a filled hammock carried by its pins, no particle
// through an impermeable sheet, seepage through a porous one, mass soaked up exactly, drips,
// determinism, the dump's masses, bad input.
#include <doctest/doctest.h>

#include <cmath>

#include "helpers.h"
#include "sim/cloth/cloth_body.h"
#include "sim/fluid/fluid_body.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

const ClothBody& sheet(const World& w) { return *w.first<ClothBody>(); }
const Fluid& liquid(const World& w) { return w.first<FluidBody>()->fluid(); }

// Momentum of every node and particle, and the sum of their |m·v| (the scale of rounding).
Vec3 totalMomentum(const World& w, double& scale) {
  Vec3 p = Vec3::Zero();
  scale = 0.0;
  const SpringNetwork& net = sheet(w).network();
  for (std::size_t i = 0; i < net.model.nodes(); ++i) {
    p += net.model.mass[i] * net.state.v[i];
    scale += net.model.mass[i] * net.state.v[i].norm();
  }
  const Fluid& fl = liquid(w);
  for (std::size_t i = 0; i < fl.size(); ++i) {
    p += fl.m[i] * fl.v[i];
    scale += fl.m[i] * fl.v[i].norm();
  }
  return p;
}

double totalMass(const World& w) {
  double m = 0.0;
  for (double x : sheet(w).network().model.mass) m += x;
  for (double x : liquid(w).m) m += x;
  return m;
}

const std::string kWater = R"("species": [{"name": "water", "mass": 0.008, "alpha": 212.6, "beta": 0.085, "cutoff": 0.02725, "viscosity": 6}])";

// A free sheet and a ball of water thrown at it, with no gravity and nothing else: `extra` adds
// keys to the sheet.
std::string thrown(const std::string& extra) {
  return R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24, "gravity": [0, 0, 0],
    "auto_substeps": true,
    "bodies": [{"type": "cloth", "name": "c", "position": [0, 0, 0], "size": [0.5, 0.5], "resolution": [10, 10],
                "mass": 0.05, "stiffness": 800, "damping": 0.2)" + extra + R"(},
               {"type": "fluid", "name": "w", "radius": 0.01, )" + kWater + R"(,
                "blocks": [{"min": [-0.1, 0.03, -0.1], "max": [0.1, 0.13, 0.1], "spacing": 0.02, "velocity": [0.3, -1.5, 0.2]}]}]})";
}

}  // namespace

TEST_CASE("cloth and liquid together keep their momentum: contact, friction and adhesion, seepage, soaking up") {
  for (const std::string& extra : {std::string(R"(, "surface": {"friction": 0.5, "restitution": 0.3, "adhesion": 5})"),
                                  std::string(R"(, "porosity": 0.5)"), std::string(R"(, "absorbency": 1)")}) {
    CAPTURE(extra);
    World w = worldFromText(thrown(extra));
    double scale = 0.0;
    const Vec3 p0 = totalMomentum(w, scale);
    const double n0 = static_cast<double>(liquid(w).size());
    const double m0 = totalMass(w);
    run(w, 12);
    double s1 = 0.0;
    const Vec3 p1 = totalMomentum(w, s1);
    CHECK((p1 - p0).norm() < 1e-12 * scale);
    CHECK(totalMass(w) == doctest::Approx(m0).epsilon(1e-13));
    // The liquid reached the sheet and moved it.
    CHECK(sheet(w).network().state.v[55].y() < -0.05);
    if (extra.find("absorbency") != std::string::npos) CHECK(static_cast<double>(liquid(w).size()) < n0);
  }
}

TEST_CASE("a hammock of water: the pins carry the weight of sheet and liquid") {
  // 216 particles (1.7 kg) dropped into a 0.6 m sheet held at its corners; after it settles the
  // force of the four pins, averaged over half a second, equals the weight within 2%.
  World w = worldFromText(R"({"format": "reel/1", "duration": 4, "fps": 30, "substeps": 24, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "c", "position": [0, 1, 0], "size": [0.6, 0.6], "resolution": [14, 14],
                "mass": 0.1, "stiffness": 3000, "damping": 2, "node_damping": 0.02,
                "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"], "surface": {"friction": 0.5}},
               {"type": "fluid", "name": "w", "radius": 0.01, )" + kWater + R"(,
                "blocks": [{"min": [-0.06, 1.05, -0.06], "max": [0.06, 1.17, 0.06], "spacing": 0.02}]}]})");
  const std::size_t n = liquid(w).size();
  REQUIRE(n == 216);
  run(w, 75);
  double sum = 0.0;
  const int frames = 15;
  for (int f = 0; f < frames; ++f) {
    run(w, 1);
    std::vector<Statistic> st;
    sheet(w).statistics(st);
    REQUIRE(st.front().name == "support_force");
    sum += st.front().value;
  }
  // Every particle is still in the hammock: above its lowest node.
  double lowest = 1e9;
  for (const Vec3& x : sheet(w).network().state.x) lowest = std::min(lowest, x.y());
  for (const Vec3& x : liquid(w).x) REQUIRE(x.y() > lowest);
  const double weight = (0.1 + 0.008 * static_cast<double>(n)) * 9.78;
  CHECK(sum / frames == doctest::Approx(weight).epsilon(0.02));
  CHECK(lowest < 1.0 - 0.03);  // it sags
}

TEST_CASE("no particle passes through an impermeable coarse sheet; a porous one lets the liquid seep through") {
  // Water poured from 0.6 m (about 3.5 m/s at the sheet, as in the film) onto a sheet whose
  // cells (10 cm) are five particles wide.
  auto scene = [](const std::string& extra) {
    return R"({"format": "reel/1", "duration": 1.5, "fps": 30, "substeps": 24, "integrator": "implicit_euler",
      "bodies": [{"type": "cloth", "name": "c", "position": [0, 0, 0], "size": [0.8, 0.8], "resolution": [9, 9],
                  "mass": 0.1, "stiffness": 2000, "damping": 1, "pinned": ["corner_00", "corner_10", "corner_01", "corner_11"])" +
           extra + R"(},
                 {"type": "fluid", "name": "w", "radius": 0.01, )" + kWater + R"(,
                  "emitters": [{"position": [0.03, 0.6, 0.02], "direction": [0, -1, 0], "speed": 1, "radius": 0.04,
                                "rate": 500, "stop": 0.8}]}]})";
  };
  World tight = worldFromText(scene(""));
  run(tight, 45);
  double lowest = 1e9;
  for (const Vec3& x : sheet(tight).network().state.x) lowest = std::min(lowest, x.y());
  // Below the sheet and under it (splashes that leave over its edges fall outside).
  auto under = [](const Vec3& x, double y) { return x.y() < y && std::abs(x.x()) < 0.35 && std::abs(x.z()) < 0.35; };
  int below = 0;
  for (const Vec3& x : liquid(tight).x) below += under(x, lowest - 0.01);
  CHECK(liquid(tight).size() > 300);
  CHECK(below == 0);
  World porous = worldFromText(scene(R"(, "porosity": 0.6)"));
  run(porous, 45);
  below = 0;
  for (const Vec3& x : liquid(porous).x) below += under(x, -0.3);
  CHECK(below > 100);  // seeped through and fell
}

TEST_CASE("an absorbent sheet's mass is its dry mass plus the particles it soaked up, less its drips") {
  // A sheet hanging from one edge, a jet of water at it.
  World w = worldFromText(R"({"format": "reel/1", "duration": 3, "fps": 30, "substeps": 24, "integrator": "implicit_euler",
    "bodies": [{"type": "cloth", "name": "c", "position": [0, 0, 0], "size": [0.5, 0.5], "resolution": [12, 12],
                "mass": 0.2, "stiffness": 2000, "damping": 1, "pinned": ["edge_z0"], "absorbency": 1},
               {"type": "fluid", "name": "w", "radius": 0.01, )" + kWater + R"(,
                "emitters": [{"position": [0, -0.25, 0.1], "direction": [0, 0, -1], "speed": 1.5, "radius": 0.03, "rate": 300,
                              "start": 0.8, "stop": 2}]}]})");
  double dry = 0.0;
  for (double m : sheet(w).cloth().dry_mass) dry += m;
  run(w, 75);
  const Cloth& c = sheet(w).cloth();
  double mass = 0.0, wet = 0.0;
  for (double m : sheet(w).network().model.mass) mass += m;
  for (double x : c.wet) wet += x;
  CHECK(c.absorbed > 10);
  CHECK(c.dripped > 0);  // the hanging sheet drains to its free edge and drips
  CHECK(wet == doctest::Approx(0.008 * static_cast<double>(c.absorbed - c.dripped)).epsilon(1e-12));
  CHECK(mass == doctest::Approx(dry + wet).epsilon(1e-12));
  // Every particle emitted is in the liquid or in the sheet.
  const Fluid& fl = liquid(w);
  const long long emitted = fl.layers[0] * fl.emitters[0].desc.perLayer() - fl.skipped;
  CHECK(emitted == static_cast<long long>(fl.size()) + c.absorbed - c.dripped);
  // The dump lists the nodes' masses, wet ones heavier.
  BodyView v;
  REQUIRE(sheet(w).view(v));
  REQUIRE(v.masses.size() == v.positions.size());
  CHECK(*std::max_element(v.masses.begin(), v.masses.end()) > *std::min_element(c.dry_mass.begin(), c.dry_mass.end()) + 0.004);
}

TEST_CASE("cloth and liquid are bit-identical for 1 and 2 threads") {
  const std::string scene = thrown(R"(, "absorbency": 0.3, "surface": {"friction": 0.4, "adhesion": 3})");
  const std::uint64_t h1 = runHash(scene, 1, 10);
  CHECK(runHash(scene, 2, 10) == h1);
}

TEST_CASE("bad cloth wetting: porosity and absorbency outside [0, 1], a surface for an unknown species") {
  auto cloth = [](const std::string& keys) {
    return R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "cloth", "name": "c")" + keys + R"(},
      {"type": "fluid", "name": "w", )" + kWater + R"(, "blocks": [{"min": [0, 1, 0], "max": [0.1, 1.1, 0.1], "spacing": 0.02}]}]})";
  };
  checkHas(badInputError(cloth(R"(, "porosity": 1.5)")), "/bodies/0/porosity");
  checkHas(badInputError(cloth(R"(, "absorbency": -0.1)")), "/bodies/0/absorbency");
  const std::string e = badInputError(cloth(R"(, "surface": {"species": {"watr": {"adhesion": 2}}})"));
  checkHas(e, "/bodies/0/surface/species/watr");
  checkHas(e, "did you mean \"water\"");
  checkHas(badInputError(cloth(R"(, "grips": [{"nodes": ["corner_00"], "velocity": [1, 0, 0], "keys": [{"time": 0}]}])")),
           "not both");
}

TEST_CASE("the liquid meets the sheets through the contact layer's hook: two absorbent sheets share a blob, no drop counted twice") {
  // Two free absorbent sheets 2.5 cm apart, the second half under the first, and a ball of water
  // thrown at the first one's edge, without gravity: the layer finds the pairs and hands them to the
  // cloth–liquid hook; a drop soaked up by the first is gone for the second.
  World w = worldFromText(R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 24, "gravity": [0, 0, 0],
    "auto_substeps": true,
    "bodies": [{"type": "cloth", "name": "a", "position": [0, 0, 0], "size": [0.5, 0.5], "resolution": [10, 10],
                "mass": 0.05, "stiffness": 800, "damping": 0.2, "absorbency": 0.5},
               {"type": "cloth", "name": "b", "position": [0.3, -0.025, 0], "size": [0.5, 0.5], "resolution": [10, 10],
                "mass": 0.05, "stiffness": 800, "damping": 0.2, "absorbency": 0.5},
               {"type": "fluid", "name": "w", "radius": 0.01, )" + kWater + R"(,
                "blocks": [{"min": [0.13, 0.03, -0.1], "max": [0.33, 0.13, 0.1], "spacing": 0.02, "velocity": [0.1, -2.5, 0]}]}]})");
  const auto& bodies = w.bodies();
  auto sheetAt = [&](std::size_t k) -> const ClothBody& { return dynamic_cast<const ClothBody&>(*bodies[k]); };
  auto mass = [&] {
    double m = 0.0;
    for (std::size_t k = 0; k < 2; ++k)
      for (double x : sheetAt(k).network().model.mass) m += x;
    for (double x : liquid(w).m) m += x;
    return m;
  };
  auto momentum = [&](double& scale) {
    Vec3 p = Vec3::Zero();
    scale = 0.0;
    for (std::size_t k = 0; k < 2; ++k) {
      const SpringNetwork& net = sheetAt(k).network();
      for (std::size_t i = 0; i < net.model.nodes(); ++i) {
        p += net.model.mass[i] * net.state.v[i];
        scale += net.model.mass[i] * net.state.v[i].norm();
      }
    }
    const Fluid& fl = liquid(w);
    for (std::size_t i = 0; i < fl.size(); ++i) p += fl.m[i] * fl.v[i], scale += fl.m[i] * fl.v[i].norm();
    return p;
  };
  const long long n0 = static_cast<long long>(liquid(w).size());
  const double m0 = mass();
  double scale = 0.0;
  const Vec3 p0 = momentum(scale);
  run(w, 15);
  const Cloth &a = sheetAt(0).cloth(), &b = sheetAt(1).cloth();
  CHECK(w.contacts().total().hooked > 100);
  CHECK(a.absorbed > 10);
  CHECK(b.absorbed > 0);  // what passed the first sheet
  // Every particle is in the liquid or in one of the sheets, once.
  CHECK(n0 == static_cast<long long>(liquid(w).size()) + a.absorbed - a.dripped + b.absorbed - b.dripped);
  CHECK(mass() == doctest::Approx(m0).epsilon(1e-13));
  double s1 = 0.0;
  CHECK((momentum(s1) - p0).norm() < 1e-12 * scale);
  // The liquid and the sheets meet only by the hook's law: no particle is pushed off a node as
  // a sphere (the layer's own point–point law), so a porous sheet stays porous.
  CHECK(w.contacts().total().point_point == 0);
  CHECK(w.contacts().total().point_triangle > 0);  // the sheets against each other
}
