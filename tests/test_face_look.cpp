// reel's head as a viewer sees it: the eyes never poke through the skin or past the lids, the
// profile keeps its measured order (nose, lips, chin: no snout), the hairline is smooth, visemes
// shape the mouth, the looks change the head, and bad input.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
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

std::string scene(const std::string& extra, double duration = 1.0, const std::string& resolution = "[64, 40]") {
  return faceSceneText(extra, duration, resolution, "1e-3");
}

// A closed skin: points and triangles.
struct Skin {
  std::vector<Vec3> x;
  std::vector<std::uint32_t> tris;
};
Skin simulated(const FaceBody& f) {
  const auto& x = f.network().state.x;
  return {std::vector<Vec3>(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(f.surface().size())), f.surface().tris};
}
Skin drawn(const FaceBody& f) {
  const auto m = f.skinMesh();
  Skin s;
  for (std::size_t v = 0; v < m->vertexCount(); ++v) s.x.emplace_back(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]);
  s.tris = m->indices;
  return s;
}

// How many times the closed skin winds around q (1 inside, 0 outside): the sum of the solid
// angles its triangles make at q (Van Oosterom & Strackee 1983) over 4π.
double winding(const Skin& s, const Vec3& q) {
  double sum = 0.0;
  for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
    const Vec3 a = s.x[s.tris[t]] - q, b = s.x[s.tris[t + 1]] - q, c = s.x[s.tris[t + 2]] - q;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    sum += 2.0 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return sum / (4.0 * kPi);
}

// Points of the eyeballs that lie outside the skin where no lid covers them and the lids' opening
// does not show them (with `shut`, any point outside the skin that no lid covers); `step` takes
// every step-th sample.
int pokingOut(const FaceBody& f, const Skin& skin, bool shut, int step = 1) {
  int bad = 0;
  for (int e = 0; e < 2; ++e) {
    const FaceBody::Eye eye = f.eye(e);
    for (int i = 1; i < 24; i += step)
      for (int j = 0; j < 48; j += step) {
        const double th = kPi * i / 24, ph = 2 * kPi * j / 48;
        const Vec3 d = std::sin(th) * std::cos(ph) * eye.right + std::sin(th) * std::sin(ph) * eye.up + std::cos(th) * eye.ahead;
        const Vec3 q = eye.center + eye.radius * d;
        const Vec3 h = f.rotation().transpose() * d;  // in the head's frame
        const double el = std::asin(std::clamp(h.y(), -1.0, 1.0)), az = std::atan2(h.x(), h.z());
        const bool within = std::abs(az) <= eye.lid_azimuth;
        const bool lidded = within && (el >= eye.upperEdge(az) || el <= eye.lowerEdge(az));
        const bool opening = within && el > eye.lowerEdge(az) && el < eye.upperEdge(az);
        if (lidded || (!shut && opening)) continue;
        if (winding(skin, q) < 0.5) ++bad;  // not under the skin
      }
  }
  return bad;
}

}  // namespace

TEST_CASE("face: the eyes stay behind the skin and the lids, looking anywhere, wide open and shut") {
  // The head turned; the eyes look far left, up, right and down, wide open (surprise), then blink.
  World w = worldFromText(scene(R"(, "rotation_deg": [5, 30, 0], "blinks": [1.2],
      "gaze": [{"time": 0, "target": [2, 0, 0.3]}, {"time": 0.3, "target": [0, 2, 0.3]}, {"time": 0.6, "target": [-2, 0, 0.3]},
               {"time": 0.9, "target": [0, -2, 0.3]}],
      "activations": [{"time": 0, "preset": "surprise", "amount": 0}, {"time": 0.5, "preset": "surprise"}])",
                                  1.5));
  const FaceBody& f = face(w);
  // The simulated skin, and the finer skin drawn (SkinDetail: every third sample, it is 9 times
  // the triangles).
  int open_bad = 0, open_drawn = 0;
  for (int k = 0; k < 4; ++k) {
    open_bad += pokingOut(f, simulated(f), false);
    open_drawn += pokingOut(f, drawn(f), false, 3);
    run(w, 9);
  }
  MESSAGE("eyeball samples poking out, eyes open: " << open_bad << " (the skin drawn: " << open_drawn << ")");
  CHECK(open_bad == 0);
  CHECK(open_drawn == 0);
  // The mouth's inside (the skin's inner side, drawn dark) stays under the skin drawn: the
  // middles of its triangles in the face's front half all lie inside it.
  {
    DrawList list;
    f.draw(list);
    const Skin skin = drawn(f);
    int checked = 0, outside = 0;
    for (const DrawMesh& m : list.meshes) {
      if (!(m.material.color - FaceBody::kMouthInside).isZero(1e-9)) continue;
      // (Its triangles' middles: its corners lie on the exact shape, the middles cut across.)
      const auto& ix = m.mesh->indices;
      auto at = [&](std::size_t k) { return Vec3(m.mesh->positions[3 * ix[k]], m.mesh->positions[3 * ix[k] + 1], m.mesh->positions[3 * ix[k] + 2]); };
      for (std::size_t t = 0; t + 2 < ix.size(); t += 3) {
        const Vec3 p = (at(t) + at(t + 1) + at(t + 2)) / 3;
        if ((f.rotation().transpose() * p).z() < 0.0) continue;  // the front half
        ++checked;
        if (winding(skin, p) < 0.5) ++outside;
      }
    }
    MESSAGE("the mouth's inside: " << outside << " of " << checked << " points outside the skin drawn");
    CHECK(checked > 100);
    CHECK(outside == 0);
    // The lips part with their thickness: wet red strips along the parting's edges (among the
    // points checked above), three quads an edge (on curves: addLipRims), on both lips, each
    // facing the opening's middle at its inner end (its outer end rolls out with the skin). A
    // quad's vertices: its outer two in the rims' colour, then its inner two.
    std::vector<Vec3> rim, rim_normal;
    for (const DrawMesh& m : list.meshes)
      if ((m.material.color - FaceBody::kMouthInside).isZero(1e-9))
        for (std::size_t v = 0; v + 3 < m.mesh->vertexCount(); ++v)
          if (std::abs(m.mesh->colors[3 * v] - float(FaceBody::kLipRim.x())) < 1e-6f &&
              std::abs(m.mesh->colors[3 * v + 1] - float(FaceBody::kLipRim.y())) < 1e-6f) {
            for (std::size_t c = v; c < v + 4; ++c) {
              rim.emplace_back(m.mesh->positions[3 * c], m.mesh->positions[3 * c + 1], m.mesh->positions[3 * c + 2]);
              rim_normal.emplace_back(m.mesh->normals[3 * c + 0], m.mesh->normals[3 * c + 1], m.mesh->normals[3 * c + 2]);
            }
            v += 3;
          }
    REQUIRE(rim.size() % 4 == 0);
    Vec3 middle = Vec3::Zero();
    for (const Vec3& p : rim) middle += p;
    middle /= std::max<double>(1.0, static_cast<double>(rim.size()));
    int upper = 0, lower = 0, away = 0;
    for (std::size_t q = 0; q < rim.size(); q += 4) {
      const Vec3 mid = 0.25 * (rim[q] + rim[q + 1] + rim[q + 2] + rim[q + 3]);
      ++((f.rotation().transpose() * (mid - middle)).y() > 0 ? upper : lower);
      if (rim_normal[q + 2].dot(middle - mid) <= 0) ++away;
    }
    MESSAGE("the lips' rims: " << upper << " pieces above the opening's middle, " << lower << " below, " << away << " facing away");
    CHECK(upper >= 24);  // 8 edges or more across the mouth's 50 mm at about 4 mm a node, three pieces each
    CHECK(lower >= 24);
    CHECK(away == 0);
  }
  run(w, 3);  // 1.3 s: shut, 0.1 s into the blink at 1.2 s
  REQUIRE(f.eye(0).upperEdge(0.0) < f.eye(0).lowerEdge(0.0));
  const int shut_bad = pokingOut(f, simulated(f), true), shut_drawn = pokingOut(f, drawn(f), true, 3);
  MESSAGE("eyeball samples showing, eyes shut: " << shut_bad << " (the skin drawn: " << shut_drawn << ")");
  CHECK(shut_bad == 0);
  CHECK(shut_drawn == 0);
}

TEST_CASE("face: the lids open in an almond: the margins meet at the corners, the outer corner higher, pinched toward them") {
  World w = worldFromText(scene(R"(, "blinks": [0.5])"));
  const FaceBody& f = face(w);
  for (int e = 0; e < 2; ++e) {
    const FaceBody::Eye ey = f.eye(e);
    const double inner = -ey.outward * ey.corner, outer = ey.outward * ey.corner;
    // The margins meet at both corners, and stay shut beyond them.
    CHECK(std::abs(ey.upperEdge(inner) - ey.lowerEdge(inner)) < 1e-12);
    CHECK(std::abs(ey.upperEdge(1.1 * outer) - ey.lowerEdge(1.1 * outer)) < 1e-12);
    // The canthal tilt: the outer corner above the inner.
    CHECK(ey.upperEdge(outer) > ey.upperEdge(inner) + 0.05);
    // Three quarters of the way to each corner the opening is under 60% of its height in the
    // middle (a slot would keep it all).
    auto height = [&](double u) { return ey.upperEdge(ey.outward * u * ey.corner) - ey.lowerEdge(ey.outward * u * ey.corner); };
    MESSAGE("eye " << e << ": the opening " << height(0) << " rad high in the middle, " << height(-0.75) << " and " << height(0.75)
                   << " toward the inner and outer corners");
    CHECK(height(0) > 0.6);
    CHECK(height(-0.75) < 0.6 * height(0));
    CHECK(height(0.75) < 0.6 * height(0));
    // The upper margin is highest inside the middle (toward the nose).
    double best = -1, best_u = 0;
    for (int i = -50; i <= 50; ++i) {
      const double u = i / 50.0, el = ey.upperEdge(ey.outward * u * ey.corner);
      if (el > best) best = el, best_u = u;
    }
    CHECK(best_u < 0.0);
  }
  run(w, 18);  // 0.6 s: mid-blink
  for (int e = 0; e < 2; ++e) {
    const FaceBody::Eye ey = f.eye(e);
    CHECK(ey.closure > 0.97);
    for (int i = -10; i <= 10; ++i) CHECK(ey.upperEdge(ey.outward * 0.1 * i * ey.corner) < ey.lowerEdge(ey.outward * 0.1 * i * ey.corner));
  }
}

TEST_CASE("face: the ears are closed shells with a back: a line through one crosses it twice and encloses what lies between") {
  const auto ears = makeEars(1.0, Vec3(0.57, 0.36, 0.28));
  Skin ear;
  for (std::size_t v = 0; v < ears->vertexCount(); ++v)
    ear.x.emplace_back(ears->positions[3 * v], ears->positions[3 * v + 1], ears->positions[3 * v + 2]);
  // The left ear's triangles (+x).
  for (std::size_t t = 0; t + 2 < ears->indices.size(); t += 3)
    if (ear.x[ears->indices[t]].x() > 0)
      for (int k = 0; k < 3; ++k) ear.tris.push_back(ears->indices[t + static_cast<std::size_t>(k)]);
  int lines = 0;
  for (double y : {-0.025, -0.012, 0.0, 0.01})
    for (double z : {-0.018, -0.026}) {
      // Where the line along x at (y, z) crosses the ear (Möller & Trumbore 1997).
      std::vector<double> hits;
      for (std::size_t t = 0; t + 2 < ear.tris.size(); t += 3) {
        const Vec3 a = ear.x[ear.tris[t]], e1 = ear.x[ear.tris[t + 1]] - a, e2 = ear.x[ear.tris[t + 2]] - a, d(-1, 0, 0), o(0.2, y, z);
        const Vec3 p = d.cross(e2);
        const double det = e1.dot(p);
        if (std::abs(det) < 1e-15) continue;
        const Vec3 s0 = o - a;
        const double u = s0.dot(p) / det, v = d.dot(s0.cross(e1)) / det;
        if (u < 0 || v < 0 || u + v > 1) continue;
        hits.push_back(0.2 - e2.dot(s0.cross(e1)) / det);
      }
      std::sort(hits.begin(), hits.end());
      hits.erase(std::unique(hits.begin(), hits.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }), hits.end());
      if (hits.empty()) continue;
      ++lines;
      CHECK(hits.size() % 2 == 0);
      if (hits.size() < 2) continue;
      const double thick = hits[hits.size() - 1] - hits[hits.size() - 2];
      CHECK(thick > 0.0015);
      CHECK(winding(ear, Vec3(0.5 * (hits[hits.size() - 1] + hits[hits.size() - 2]), y, z)) > 0.9);
    }
  CHECK(lines >= 6);
}

TEST_CASE("face: the profile keeps its measured order: nose ahead of the lips, the lips just ahead of the chin") {
  World w = worldFromText(scene(""));
  const FaceSurface& s = face(w).surface();
  // The most forward skin near the midline in a band of heights (head frame, unturned).
  auto front = [&](double y0, double y1) {
    double z = -1.0;
    for (std::size_t k = 0; k < s.size(); ++k)
      if (std::abs(s.skin[k].x()) < 0.004 && s.skin[k].y() > y0 && s.skin[k].y() < y1) z = std::max(z, s.skin[k].z());
    return z;
  };
  double top = -1, bottom = 1;
  // (The chin: the lowest point well forward, not the throat below it.)
  for (const Vec3& p : s.skin) {
    if (p.z() > 0.03) top = std::max(top, p.y());
    if (p.z() > 0.05) bottom = std::min(bottom, p.y());
  }
  const double ym = s.mouth.y();
  const double nose = front(-0.045, -0.025), lips = front(ym - 0.012, ym + 0.012), chin = front(-0.112, -0.095);
  MESSAGE("nose " << nose << ", lips " << lips << ", chin " << chin << " m forward; eyes at " << s.eye[0].y() << " m, crown "
                  << top << ", chin " << bottom);
  CHECK(nose - lips > 0.01);   // the nose stands 1–2.5 cm ahead of the lips (Farkas 1994)
  CHECK(nose - lips < 0.025);
  CHECK(lips - chin > 0.0);    // the lips a little ahead of the chin: no snout
  CHECK(lips - chin < 0.012);
  // The eyes near the middle of the head's height.
  CHECK(std::abs(s.eye[0].y() - 0.5 * (top + bottom)) < 0.015);
}

TEST_CASE("face: the hairline is smooth in the skin's texture (no steps of the mesh)") {
  World w = worldFromText(scene("", 1.0, "[32, 24]"));
  const auto img = skinTexture(face(w).surface());
  REQUIRE(img->width == kSkinTexels);
  // Down each column over the face's front third, the first texel of skin below the hair.
  std::vector<int> edge;
  for (int x = img->width / 6; x < img->width / 3; ++x) {
    int y = 0;
    while (y < img->height && img->pixel(x, y)[0] < 110) ++y;  // hair is dark
    edge.push_back(y);
  }
  int jump = 0;
  for (std::size_t i = 1; i < edge.size(); ++i) jump = std::max(jump, std::abs(edge[i] - edge[i - 1]));
  MESSAGE("the hairline moves at most " << jump << " texels between neighbouring columns (of " << img->height << ")");
  CHECK(edge.front() > 0);
  CHECK(edge.front() < img->height / 2);
  CHECK(jump <= 6);  // a mesh row is 43 texels at this resolution: per-vertex colours would step by rows
}

TEST_CASE("face: visemes purse and open the mouth on top of the activations") {
  World w = worldFromText(scene(R"(, "visemes": [{"time": 0, "viseme": "rest"}, {"time": 0.4, "viseme": "oo"},
      {"time": 0.8, "viseme": "aa"}, {"time": 1.2, "viseme": "rest"}],
      "activations": [{"time": 0, "muscles": {"jaw_open": 0.1}}])",
                                1.3, "[48, 32]"));
  const FaceBody& f = face(w);
  const FaceSurface& s = f.surface();
  auto nearest = [&](const Vec3& p) {
    std::size_t best = 0;
    for (std::size_t k = 0; k < s.size(); ++k)
      if ((s.skin[k] - p).squaredNorm() < (s.skin[best] - p).squaredNorm()) best = k;
    return best;
  };
  const std::size_t left = nearest(s.mouth + Vec3(0.5 * s.mouth_width, 0, -0.003)), right = nearest(s.mouth - Vec3(0.5 * s.mouth_width, 0, 0.003));
  const std::size_t upper = nearest(s.mouth + Vec3(0, 0.005, 0)), lower = nearest(s.mouth - Vec3(0, 0.007, 0));
  const auto& x = f.network().state.x;
  const double width0 = (x[left] - x[right]).norm(), open0 = f.mouthOpening();
  const double upper0 = x[upper].z(), lower0 = x[lower].z();
  run(w, 12);  // 0.4 s: "oo"
  const int jaw = f.activations().index("jaw_open"), oris = f.activations().index("orbicularis_oris");
  CHECK(f.contractions()[static_cast<std::size_t>(oris)] == doctest::Approx(1.0));
  CHECK(f.contractions()[static_cast<std::size_t>(jaw)] == doctest::Approx(0.1 + 0.06));  // added to the activations
  const double width_oo = (x[left] - x[right]).norm();
  const double pout = std::min(x[upper].z() - upper0, x[lower].z() - lower0);
  // (The pucker keeps the face symmetric: the corners mirror each other.)
  CHECK((x[left] - Vec3(-x[right].x(), x[right].y(), x[right].z())).norm() < 1e-9);
  run(w, 12);  // 0.8 s: "aa"
  const double open_aa = f.mouthOpening();
  MESSAGE("mouth width at rest " << width0 << " m, at oo " << width_oo << "; lips out at oo " << pout << " m; opening at rest "
                                   << open0 << ", at aa " << open_aa);
  // Pursed: the corners drawn in and both lips pushed out (here 9.6 and 4.2 mm; at the default head
  // 10 and 5.6 mm, where the orbicularis oris alone, before the pucker's ring, gave 3.1 and 0.7).
  CHECK(width_oo < width0 - 0.006);
  CHECK(pout > 0.003);
  CHECK(open_aa > open0 + 0.008);    // open
}

TEST_CASE("face: the looks change the head: a man's jaw and brow, a heavier neck") {
  auto head = [](const std::string& looks) {
    World w = worldFromText(scene(looks, 1.0, "[48, 32]"));
    const FaceSurface& s = face(w).surface();
    double jaw = 0, brow = 0, neck = 0;
    for (const Vec3& p : s.skin) {
      if (p.y() > -0.1 && p.y() < -0.065 && p.z() > -0.01) jaw = std::max(jaw, std::abs(p.x()));
      if (std::abs(p.y() - 0.02) < 0.004 && std::abs(p.x() - 0.03) < 0.006) brow = std::max(brow, p.z());
      if (p.y() < -0.14 && p.y() > -0.25) neck = std::max(neck, std::abs(p.x()));  // below the jaw, above the cut
    }
    return std::array<double, 3>{jaw, brow, neck};
  };
  const auto woman = head(R"(, "sex": 0)"), man = head(R"(, "sex": 1)"), heavy = head(R"(, "build": 1)"), lean = head(R"(, "build": 0)");
  MESSAGE("jaw half-width " << woman[0] << " / " << man[0] << " m, brow " << woman[1] << " / " << man[1] << " m, neck "
                            << lean[2] << " / " << heavy[2] << " m");
  CHECK(man[0] > woman[0] + 0.001);
  CHECK(man[1] > woman[1] + 0.002);
  CHECK(heavy[2] > lean[2] + 0.005);
}

TEST_CASE("face: bad visemes and looks are refused with their JSON path") {
  checkHas(badInputError(scene(R"(, "visemes": [{"time": 0, "viseme": "rest"}, {"time": 0.5, "viseme": "ooh"}])")),
           "/bodies/0/visemes/1/viseme: unknown viseme \"ooh\" (did you mean \"oo\"?)");
  checkHas(badInputError(scene(R"(, "visemes": [{"time": 0.5, "viseme": "aa"}, {"time": 0.2, "viseme": "oo"}])")),
           "/bodies/0/visemes/1/time");
  checkHas(badInputError(scene(R"(, "visemes": [{"time": 0.5}])")), "/bodies/0/visemes/0/viseme");
  checkHas(badInputError(scene(R"(, "sex": 1.5)")), "/bodies/0/sex");
  checkHas(badInputError(scene(R"(, "age": 5)")), "/bodies/0/age");
  checkHas(badInputError(scene(R"(, "build": -1)")), "/bodies/0/build");
  checkHas(badInputError(scene(R"(, "draw": [{"time": 0}, {"time": 0.5, "mode": "layers", "fade": -1}])")), "/bodies/0/draw/1/fade");
  checkHas(badInputError(scene(R"(, "draw": [{"time": 0}, {"time": 0.5, "mode": "layers", "fade": 10.5}])")), "/bodies/0/draw/1/fade");
  checkHas(badInputError(scene(R"(, "draw": [{"time": 0}, {"time": 0.5, "mode": "skin", "fade": 1}])")),
           "/bodies/0/draw/1/fade: fades from \"skin\" into the same mode");
  checkHas(badInputError(scene(R"(, "draw": [{"time": 0, "mode": "layers", "fade": 0.5}, {"time": 0.3, "mode": "skin"}])")),
           "/bodies/0/draw/0/fade: runs past the next draw key, at 0.3 s");
  CHECK_NOTHROW(worldFromText(scene(R"(, "draw": [{"time": 0}, {"time": 0.5, "mode": "layers", "fade": 0}, {"time": 0.6, "mode": "skin", "fade": 10}])")));
}

TEST_CASE("face: a draw key's fade dissolves the skin into the layers and back, casting no shadow, then is gone") {
  World w = worldFromText(scene(R"(, "draw": [{"time": 0, "mode": "skin"}, {"time": 0.1, "mode": "layers", "fade": 0.4},
                                              {"time": 0.6, "mode": "skin", "fade": 0.2}])"));
  const FaceBody& f = face(w);
  struct Seen {
    int meshes = 0, blended = 0, casting = 0, outer = 0, tubes = 0, shoulders = 0;  // shoulders: solid wool
    double lo = 1.0, hi = 0.0, radius = 0.0;  // radius: the lattice's thickest strand
    bool shadows = false;  // a blended mesh casts a shadow
    bool front_only = true;  // every blended mesh blends its nearest surface alone
  };
  auto look = [&] {
    DrawList list;
    f.draw(list);
    Seen s;
    s.tubes = static_cast<int>(list.tubes.size());
    for (const DrawTubes& t : list.tubes) {
      CHECK(t.material.opacity == 1.0);
      s.radius = std::max(s.radius, double(t.radius));
    }
    s.meshes = static_cast<int>(list.meshes.size());
    for (const DrawMesh& m : list.meshes) {
      if (m.material.casts_shadow) ++s.casting;
      // (What lies inside the mouth casts no shadow and is not a sheet as the hair's strands and
      // the lashes are.)
      if (m.material.casts_shadow || m.material.double_sided) ++s.outer;
      if (m.material.sheen > 0 && m.material.opacity >= 1.0) ++s.shoulders;
      if (m.material.opacity >= 1.0) continue;
      ++s.blended;
      s.lo = std::min(s.lo, m.material.opacity), s.hi = std::max(s.hi, m.material.opacity);
      s.shadows = s.shadows || m.material.casts_shadow;
      s.front_only = s.front_only && m.material.front_only;
    }
    return s;
  };
  // How far the lattice's skin layer (its first tubes) lies from `frac` of the way from the
  // bone to the skin (the most over every tenth end, each against its nearest such point).
  const std::size_t n = f.surface().size();
  auto lifted = [&](double frac) {
    DrawList list;
    f.draw(list);
    REQUIRE(!list.tubes.empty());
    const auto& x = f.network().state.x;
    const std::vector<float>& ends = list.tubes.front().ends;
    double worst = 0.0;
    for (std::size_t e = 0; e + 2 < ends.size(); e += 30) {
      const Vec3 p(ends[e], ends[e + 1], ends[e + 2]);
      double best = 1e9;
      for (std::size_t k = 0; k < n; ++k) best = std::min(best, (x[2 * n + k] + frac * (x[k] - x[2 * n + k]) - p).norm());
      worst = std::max(worst, best);
    }
    return worst;
  };
  const Seen skin = look();  // 0 s: the skin alone
  CHECK(skin.blended == 0);
  CHECK(skin.tubes == 0);
  // (The skin's parts that cast shadows: the skin, ears, shoulders, eyes and lids; not the
  // mouth's lining, the teeth or the tongue, inside it, nor the hair's strands and the lashes.)
  CHECK(skin.casting >= 3);
  CHECK(skin.outer == skin.casting + 2);
  run(w, 9);  // 0.3 s: halfway into the layers (smoothstep(½) = ½)
  const Seen half = look();
  // Every part of the skin but the shoulders, the mouth's inside too (left out, the lips' rims went
  // with it and the mouth gaped open as the fade began), each blended as one solid: its nearest
  // surface alone (not the lids' shells under the skin, nor the mouth's lining behind the cheek).
  CHECK(half.blended == skin.meshes - 1);
  CHECK(half.front_only);
  CHECK(skin.shoulders == 1);
  CHECK(half.shoulders == 1);  // solid through the dissolve
  CHECK(half.lo == doctest::Approx(0.5));
  CHECK(half.hi == doctest::Approx(0.5));
  CHECK_FALSE(half.shadows);
  CHECK(half.tubes == 3);  // the layers' lattice (skin, fascia, the springs across), solid; the muscles are meshes
  // Its skin layer halfway up from the bone, under the half-faded skin (at the skin all through
  // the fade, it popped through the skin in one frame as the fade began).
  CHECK(lifted(0.5) < 1e-6);  // (the ends are floats)
  CHECK(lifted(1.0) > 1e-4 * f.surface().scale);
  run(w, 6);  // 0.5 s: the fade is over
  const Seen layers = look();
  CHECK(layers.blended == 0);
  CHECK(layers.tubes == half.tubes);
  CHECK(half.radius == layers.radius);
  CHECK(lifted(1.0) < 1e-6);  // at the skin once the skin is gone
  CHECK(layers.shoulders == 1);  // the layers' head on its shoulders, not a bare pole
  run(w, 6);  // 0.7 s: halfway back to the skin, the skin fading in over the solid layers
  const Seen back = look();
  CHECK(back.blended == half.blended);
  CHECK(back.lo == doctest::Approx(0.5));
  CHECK(back.tubes == half.tubes);
  run(w, 6);  // 0.9 s: the skin alone again
  const Seen after = look();
  CHECK(after.blended == 0);
  CHECK(after.tubes == 0);
}

TEST_CASE("face: after surprise, sadness and anger the face comes back to rest (no fold stays)") {
  // The film's order at full strength; a fold the brows press in must not stay when they let go.
  World w = worldFromText(scene(R"(, "activations": [{"time": 0, "preset": "surprise", "amount": 0},
      {"time": 0.4, "preset": "surprise"}, {"time": 0.8, "preset": "surprise"}, {"time": 1.2, "preset": "sadness"},
      {"time": 1.6, "preset": "sadness"}, {"time": 2.0, "preset": "anger"}, {"time": 2.4, "preset": "anger"},
      {"time": 2.9, "preset": "anger", "amount": 0}])",
                                4.5));
  const FaceBody& f = face(w);
  const std::vector<Vec3> x0 = f.network().state.x;
  run(w, 134);
  double moved = 0.0;
  for (std::size_t k = 0; k < f.surface().size(); ++k) moved = std::max(moved, (f.network().state.x[k] - x0[k]).norm());
  MESSAGE("1.6 s after the last expression, the skin is at most " << moved << " m from where it rested");
  CHECK(moved < 0.001);
}

TEST_CASE("face: the teeth and the tongue stay inside the skin drawn: at rest, smiling and with the jaw wide open") {
  // (Each seen only through the lips' parting: a tooth's root or the gum through the chin reads
  // as a sore.) Rest at 0 s, a smile at 0.6 s, surprise (the jaw at 0.8) at 1.2 s.
  World w = worldFromText(scene(R"(, "rotation_deg": [0, 20, 0],
      "activations": [{"time": 0, "preset": "happiness", "amount": 0}, {"time": 0.1, "preset": "happiness", "amount": 0},
                      {"time": 0.5, "preset": "happiness"}, {"time": 0.7, "preset": "happiness"}, {"time": 1.1, "preset": "surprise"}])",
                                  1.3));
  const FaceBody& f = face(w);
  for (const int frames : {0, 18, 18}) {
    run(w, frames);
    DrawList list;
    f.draw(list);
    const Skin skin = drawn(f);
    int checked = 0, outside = 0;
    for (const DrawMesh& m : list.meshes) {
      // The teeth and the tongue: the meshes inside that cast no shadow, less the mouth's lining
      // and the hair's strands (sheets, double-sided).
      if (m.material.casts_shadow || m.material.double_sided || (m.material.color - FaceBody::kMouthInside).isZero(1e-9)) continue;
      for (std::size_t v = 0; v < m.mesh->vertexCount(); v += 3) {
        ++checked;
        if (winding(skin, Vec3(m.mesh->positions[3 * v], m.mesh->positions[3 * v + 1], m.mesh->positions[3 * v + 2])) < 0.5) ++outside;
      }
    }
    MESSAGE("at " << w.time() << " s: " << outside << " of " << checked << " points of the teeth and tongue outside the skin drawn");
    CHECK(checked > 300);
    CHECK(outside == 0);
  }
}

TEST_CASE("face: the collar's rim hugs the neck, the neck inside it all round, its roll hidden in the neck, at rest and turned") {
  for (const double turn : {0.0, 35.0}) {
    CAPTURE(turn);
    World w = worldFromText(scene(R"(, "rotation_deg": [0, )" + std::to_string(turn) + R"(, 0])"));
    const FaceBody& f = face(w);
    DrawList list;
    f.draw(list);
    const TriMesh *bust = nullptr, *skin = nullptr;
    for (const DrawMesh& m : list.meshes) {
      if (m.material.sheen > 0) bust = m.mesh.get();
      if (m.material.bump) skin = m.mesh.get();
    }
    REQUIRE(bust);
    REQUIRE(skin);
    // The rim: the bust's fifth ring (64 vertices; the first four roll in over the neck above
    // it), its centre and its radius by angle about it; and the roll's top, the first ring.
    constexpr int kRing = 64, kRimRing = 4;
    Vec3 c = Vec3::Zero();
    std::vector<Vec3> rim, roll;
    for (int i = 0; i < kRing; ++i) {
      const std::size_t at = static_cast<std::size_t>(3 * (kRimRing * kRing + i));
      rim.emplace_back(bust->positions[at], bust->positions[at + 1], bust->positions[at + 2]);
      roll.emplace_back(bust->positions[3 * i], bust->positions[3 * i + 1], bust->positions[3 * i + 2]);
      c += rim.back() / kRing;
    }
    auto polar = [&](const Vec3& p) { return std::pair{std::atan2(p.x() - c.x(), p.z() - c.z()), std::hypot(p.x() - c.x(), p.z() - c.z())}; };
    // The neck's skin cut at the rim's height (its triangles' sections): its farthest out at each
    // rim vertex's angle.
    std::vector<double> neck(kRing, 0.0);
    auto vertex = [&](std::uint32_t v) { return Vec3(skin->positions[3 * v], skin->positions[3 * v + 1], skin->positions[3 * v + 2]); };
    for (std::size_t t = 0; t + 2 < skin->indices.size(); t += 3) {
      std::vector<Vec3> cut;
      for (int e = 0; e < 3; ++e) {
        const Vec3 a = vertex(skin->indices[t + static_cast<std::size_t>(e)]), b = vertex(skin->indices[t + static_cast<std::size_t>((e + 1) % 3)]);
        if ((a.y() - c.y()) * (b.y() - c.y()) < 0) cut.push_back(a + (c.y() - a.y()) / (b.y() - a.y()) * (b - a));
      }
      if (cut.size() != 2) continue;
      for (int k = 0; k <= 16; ++k) {
        const auto [a, r] = polar(cut[0] + (k / 16.0) * (cut[1] - cut[0]));
        for (int i = 0; i < kRing; ++i)
          if (std::abs(std::remainder(a - polar(rim[static_cast<std::size_t>(i)]).first, 2 * kPi)) < kPi / kRing)
            neck[static_cast<std::size_t>(i)] = std::max(neck[static_cast<std::size_t>(i)], r);
      }
    }
    double least = 1e9, most = 0, roll_out = -1e9;  // (the roll's top inside the neck: hidden in it)
    for (std::size_t i = 0; i < kRing; ++i) {
      REQUIRE(neck[i] > 0);  // the neck's skin found all round
      least = std::min(least, polar(rim[i]).second - neck[i]), most = std::max(most, polar(rim[i]).second - neck[i]);
      roll_out = std::max(roll_out, polar(roll[i]).second - neck[i]);
    }
    MESSAGE("rim's clearance over the neck " << least * 1000 << "–" << most * 1000 << " mm; the roll " << roll_out * 1000);
    CHECK(roll_out < -0.001);
    CHECK(least > 0.0005);  // the neck never pokes through
    CHECK(most < 0.0075);   // no wide dark band (the rim 6–10 mm off a squarer one measured more)
  }
}

TEST_CASE("face: the skin's tone differs from side to side (its texture is mirrored, its tint is not)") {
  World w = worldFromText(scene(""));
  const FaceBody& f = face(w);
  DrawList list;
  f.draw(list);
  const TriMesh* skin = nullptr;
  for (const DrawMesh& m : list.meshes)
    if (m.material.texture && m.per_frame) skin = m.mesh.get();
  REQUIRE(skin);
  REQUIRE(skin->colors.size() == skin->positions.size());
  auto at = [&](std::size_t v) { return Vec3(skin->positions[3 * v], skin->positions[3 * v + 1], skin->positions[3 * v + 2]); };
  double lo = 1e9, hi = -1e9;
  for (std::size_t v = 0; v < skin->vertexCount(); ++v) lo = std::min(lo, at(v).x()), hi = std::max(hi, at(v).x());
  const double mid = 0.5 * (lo + hi), s = f.surface().scale;
  // Each vertex of the left cheek and forehead against its mirror image on the right.
  double differ = 0.0, mean = 0.0, least = 1e9, most = -1e9;
  int pairs = 0;
  for (std::size_t v = 0; v < skin->vertexCount(); v += 7) {
    const Vec3 p = at(v);
    if (p.x() - mid < 0.015 * s || p.z() < 0.05 * s || p.y() < -0.09 * s || p.y() > 0.06 * s) continue;
    const Vec3 q(2 * mid - p.x(), p.y(), p.z());
    std::size_t m = 0;
    for (std::size_t k = 1; k < skin->vertexCount(); ++k)
      if ((at(k) - q).squaredNorm() < (at(m) - q).squaredNorm()) m = k;
    if ((at(m) - q).norm() > 1e-4 * s) continue;  // (the mesh is symmetric: its mirror vertex)
    for (int c = 0; c < 3; ++c) {
      const double a = skin->colors[3 * v + static_cast<std::size_t>(c)], b = skin->colors[3 * m + static_cast<std::size_t>(c)];
      differ += std::abs(a - b) / 3, mean += (a + b) / 6;
      least = std::min({least, a, b}), most = std::max({most, a, b});
    }
    ++pairs;
  }
  REQUIRE(pairs > 50);
  differ /= pairs, mean /= pairs;
  MESSAGE(pairs << " mirrored pairs: the tint differs by " << differ << " on average, mean " << mean << ", " << least << " .. " << most);
  CHECK(differ > 0.01);  // (0 with the tint left out: the texture alone is the same on both sides)
  CHECK(mean == doctest::Approx(1.0).epsilon(0.05));
  CHECK(least > 0.8);
  CHECK(most < 1.2);
}
