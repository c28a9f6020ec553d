// The layers' view of reel's head: a skull sculpted after the skull's anatomy (orbits, a nasal
// aperture, teeth) where the bone layer is an egg, and the muscles drawn on it as bellies, bands
// and the frontalis' sheet (sim/face/face_layers.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "face_scene.h"
#include "helpers.h"
#include "sim/face/face_body.h"
#include "sim/face/head_shape.h"
#include "sim/geometry.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

std::string scene(const std::string& extra) { return faceSceneText(extra, 1.0, "[64, 40]", "1e-3"); }

}  // namespace

TEST_CASE("face: the layers' skull has orbits, a nasal aperture and teeth, where the bone layer was an egg") {
  World w = worldFromText(scene(R"(, "draw": [{"time": 0, "mode": "layers"}])"));
  const FaceBody& f = face(w);
  DrawList list;
  f.draw(list);
  const std::size_t n = f.surface().size();
  const auto& x = f.network().state.x;
  const TriMesh* skull = nullptr;
  int teeth = 0;
  for (const DrawMesh& m : list.meshes) {
    if (m.mesh->vertexCount() == n && m.mesh->colors.size() == 3 * n) skull = m.mesh.get();
    if (m.material.color == Vec3(1, 1, 1) && m.material.roughness == 0.3) ++teeth;
  }
  REQUIRE(skull);
  CHECK(teeth == 2);
  // The skull's vertex nearest a rest point of the head frame (at the head's scale): how far it
  // lies in from the bone layer's node, and its shade.
  const double s = f.surface().scale;
  auto at = [&](const Vec3& rest) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < n; ++k)
      if ((f.surface().bone[k] - rest * s).norm() < (f.surface().bone[best] - rest * s).norm()) best = k;
    const Vec3 p(skull->positions[3 * best], skull->positions[3 * best + 1], skull->positions[3 * best + 2]);
    return std::pair{(p - x[2 * n + best]).norm() / s, double(skull->colors[3 * best])};
  };
  // The orbit's: the front vertex nearest the eye's axis (the one nearest a point in front of the
  // eye may be the brow's rim, which stands out over a deep-set eye).
  const auto [orbit_in, orbit_shade] = [&] {
    std::size_t best = 0;
    double d2 = 1e9;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 p = f.surface().bone[k] / s;
      const double e = head::sq(p.x() - head::kEyeX) + head::sq(p.y() - head::kEyeY);
      if (p.z() > 0.02 && e < d2) d2 = e, best = k;
    }
    const Vec3 p(skull->positions[3 * best], skull->positions[3 * best + 1], skull->positions[3 * best + 2]);
    return std::pair{(p - x[2 * n + best]).norm() / s, double(skull->colors[3 * best])};
  }();
  const auto [nose_in, nose_shade] = at(Vec3(0, -0.04, 0.11));
  const auto [crown_in, crown_shade] = at(Vec3(0, 0.12, 0));
  MESSAGE("orbit " << orbit_in << " m in, shade " << orbit_shade << "; nasal aperture " << nose_in << " m in, shade " << nose_shade);
  CHECK(orbit_in > 0.012);  // (the nearest vertex, not the bowl's deepest point)
  CHECK(orbit_shade < 0.4);
  CHECK(nose_in > 0.015);
  CHECK(nose_shade < 0.3);
  CHECK(crown_in == doctest::Approx(0.0).epsilon(1e-9));  // the vault is the bone layer's
  CHECK(crown_shade == 1.0);
  // The linear muscles lie on the skull as bellies: one mesh each in the relaxed muscle's red
  // (13 rings of 16 and the ends' centres), 95% of their vertices within 5 mm of the skull's
  // surface, 3.5 mm on average (straight sticks from attachment to insertion stood up to 8.9 mm off
  // it, passing in and out); the sphincters are bands round their rings (24 rings of 16), in the
  // tissue.
  // The frontalis is one sheet over the forehead (41 columns of 15), not four bellies.
  std::size_t linear = 0, midline = 0, frontalis = 0;  // (a linear muscle on the midline, as the mentalis, is drawn as a pair)
  for (const FaceMuscle& mu : f.muscles()) {
    frontalis += mu.desc.name.rfind("frontalis", 0) == 0 ? 1 : 0;
    linear += mu.desc.sphincter || mu.desc.name.rfind("frontalis", 0) == 0 ? 0 : 1;
    midline += !mu.desc.sphincter && std::abs(mu.desc.attachment.x()) < 1e-3 * s && std::abs(mu.desc.insertion.x()) < 1e-3 * s ? 1 : 0;
  }
  auto vert = [&](const TriMesh& m, std::uint32_t v) { return Vec3(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]); };
  std::vector<double> off;
  std::size_t bellies = 0, bands = 0;
  const TriMesh* sheet = nullptr;
  int sheets = 0;
  for (const DrawMesh& m : list.meshes)
    if (m.mesh->vertexCount() == 41 * 15 && m.mesh->colors.size() == 3 * 41 * 15) sheet = m.mesh.get(), ++sheets;
  REQUIRE(sheets == 1);
  double left = -1e9, right = 1e9;
  for (std::uint32_t v = 0; v < sheet->vertexCount(); ++v) {
    const double across = (f.rotation().transpose() * vert(*sheet, v)).x() / s;  // (plus a constant: the head's position)
    left = std::max(left, across), right = std::min(right, across);
    CHECK(sheet->colors[3 * v] > 2 * sheet->colors[3 * v + 1]);  // muscle red
  }
  CHECK(left - right > 0.09);  // across the forehead, m at 0.24 m
  for (const DrawMesh& m : list.meshes) {
    if (m.material.color != Vec3(0.42, 0.07, 0.06)) continue;  // not a relaxed muscle's
    if (m.mesh->vertexCount() == 24 * 16) ++bands;
    if (m.mesh->vertexCount() != 13 * 16 + 2) continue;
    ++bellies;
    for (std::uint32_t v = 0; v < m.mesh->vertexCount(); v += 3) {
      const Vec3 p = vert(*m.mesh, v);
      double near = 1e9;
      for (std::size_t q = 0; q + 2 < skull->indices.size(); q += 3) {
        const Vec3 a = vert(*skull, skull->indices[q]), b = vert(*skull, skull->indices[q + 1]), c = vert(*skull, skull->indices[q + 2]);
        const Vec3 bary = closestOnTriangle(p, a, b, c);
        near = std::min(near, (bary.x() * a + bary.y() * b + bary.z() * c - p).norm());
      }
      off.push_back(near / s);
    }
  }
  REQUIRE(off.size() > 300);
  std::sort(off.begin(), off.end());
  double mean = 0;
  for (double d : off) mean += d / static_cast<double>(off.size());
  const double p95 = off[off.size() * 95 / 100];
  MESSAGE(bellies << " bellies, " << off.size() << " points: 95% within " << p95 * 1000 << " mm of the skull, " << mean * 1000
                  << " mm on average, the farthest " << off.back() * 1000 << " mm");
  CHECK(midline == 2);  // the mentalis and the procerus
  CHECK(bellies == linear + midline);
  CHECK(frontalis == 4);
  CHECK(bands == f.muscles().size() - linear - frontalis - 1);  // (the lips' pucker lies in the orbicularis oris' band)
  CHECK(p95 < 0.005);
  CHECK(mean < 0.0035);
}

TEST_CASE("face: in a dissolve back to the skin the teeth keep the skin's shade, not the layers' dark") {
  // The same teeth are in both views; in a dissolve the layers' are drawn solid and hide the
  // skin's. Lit by the reveal alone they showed as near-black bars as the skin faded back in.
  const std::string jaw = R"(, "activations": [{"time": 0, "muscles": {"jaw_open": 0}}, {"time": 0.3, "muscles": {"jaw_open": 0.08}}])";
  World dissolve = worldFromText(scene(jaw + R"(, "draw": [{"time": 0, "mode": "layers"}, {"time": 0.1, "mode": "skin", "fade": 0.5}])"));
  World skin = worldFromText(scene(jaw));
  run(dissolve, 15);  // 0.5 s: 80% of the way back to the skin
  run(skin, 15);
  auto teethShades = [](const World& w) {
    DrawList list;
    face(w).draw(list);
    std::vector<double> shade;  // each teeth mesh's brightest vertex colour
    for (const DrawMesh& m : list.meshes)
      if (m.material.color == Vec3(1, 1, 1) && m.material.roughness == 0.3)
        shade.push_back(*std::max_element(m.mesh->colors.begin(), m.mesh->colors.end()));
    return shade;
  };
  const std::vector<double> fading = teethShades(dissolve), plain = teethShades(skin);
  REQUIRE(plain.size() == 2);
  REQUIRE(fading.size() == 4);  // the layers' two rows, then the skin's
  MESSAGE("teeth's brightest: skin view " << plain[0] << ", dissolve " << fading[0] << " " << fading[1] << " (mouth " << face(skin).mouthOpening() * 1e3 << " mm open)");
  // The mouth a few millimetres open: the skin's view's teeth in part shade (FaceBody::mouthLight),
  // the layers' a fifth of the way from it to full light (the reveal at 80% of the dissolve).
  CHECK(face(skin).mouthOpening() > 0.002);
  CHECK(face(skin).mouthOpening() < 0.008);
  CHECK(plain[0] < 0.9 * 0.768f);
  for (double s : fading) CHECK(s >= plain[0] - 1e-6);
  CHECK(fading[0] > plain[0] + 0.01);
}
