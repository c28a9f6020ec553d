// Relief by bump mapping: the renderer's tilted normals against Lambert's law, the scene's keys,
// and the face's skin relief.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "core/math.h"
#include "core/mesh.h"
#include "face_scene.h"
#include "render_helpers.h"
#include "sim/face/face_body.h"
#include "sim/draw_material.h"
#include "sim/face/head.h"
#include "sim/face/head_shape.h"

using namespace reel;
using namespace reel::test;

namespace {

// A height ramp along u: column x holds x (0..255), the same in every row.
std::shared_ptr<const Image> ramp() {
  auto img = std::make_shared<Image>(256, 4);
  for (int y = 0; y < img->height; ++y)
    for (int x = 0; x < img->width; ++x) std::fill_n(img->pixel(x, y), 3, static_cast<std::uint8_t>(x));
  return img;
}

// The middle pixel of a 4 m grey quad (u along x) seen from above, lit by a sun at `theta` from
// the vertical in the x–y plane, with the bump map `bump` `depth` m deep.
const std::uint8_t* middle(DirectRenderer& dr, Image& img, double theta, std::shared_ptr<const Image> bump, double depth) {
  const double t = theta * kPi / 180.0;
  DrawList list = sunlit(Vec3(0, 3, 0.001), Vec3(std::sin(t), -std::cos(t), 0));
  DrawMesh d;
  d.mesh = std::make_shared<const TriMesh>(makeQuad(4, 4));
  d.material.color = Vec3(0.6, 0.6, 0.6);
  d.material.bump = std::move(bump);
  d.material.bump_depth = depth;
  list.meshes = {d};
  img = dr.draw(list);
  return img.pixel(img.width / 2, img.height / 2);
}

}  // namespace

TEST_CASE("bump mapping: a height ramp tilts the normal by its slope (Lambert of the tilted normal, ±1 level); no relief draws the flat plane's bits") {
  DirectRenderer dr(64, 48, 1);
  const auto map = ramp();
  // Heights (x + 0.5 − 0.5)/255 at texel centres, u = 0..1 over 4 m: the height rises along x by
  // depth · (256/255) / 4 per metre, so the normal leans back against x by that slope s, and a sun
  // at θ from the vertical lights it by (s sin θ + cos θ)/√(1 + s²).
  for (const double depth : {0.4, -0.4, 1.0}) {
    for (const double theta : {60.0, -60.0, 20.0}) {
      CAPTURE(depth);
      CAPTURE(theta);
      const double s = depth * (256.0 / 255.0) / 4.0, t = theta * kPi / 180.0;
      const double lin = 0.6 * std::max(0.0, (s * std::sin(t) + std::cos(t)) / std::sqrt(1 + s * s));
      Image img;
      const std::uint8_t* p = middle(dr, img, theta, map, depth);
      CHECK(std::abs(int(p[1]) - int(std::lround(255.0 * srgb(lin)))) <= 1);
    }
  }
  // No relief: depth 0, or no map, is the plane without one, bit for bit.
  Image flat, zero, none;
  middle(dr, flat, 60, nullptr, 0.0);
  middle(dr, zero, 60, map, 0.0);
  middle(dr, none, 60, nullptr, 0.5);
  CHECK(zero.rgb == flat.rgb);
  CHECK(none.rgb == flat.rgb);
  Image tilted;
  middle(dr, tilted, 60, map, 0.4);
  CHECK(tilted.rgb != flat.rgb);
}

TEST_CASE("a wrinkle map sinks as deep as the vertices' weights say: none at 0, the bump map's tilt at 1, its floor darker by the shade") {
  DirectRenderer dr(64, 48, 1);
  const auto map = ramp();
  auto draw = [&](float weight, double shade, bool as_bump) {
    DrawList list = sunlit(Vec3(0, 3, 0.001), Vec3(std::sin(kPi / 3), -std::cos(kPi / 3), 0));
    DrawMesh d;
    auto quad = std::make_shared<TriMesh>(makeQuad(4, 4));
    quad->wrinkle.assign(quad->vertexCount(), weight);
    d.mesh = quad;
    d.material.color = Vec3(0.6, 0.6, 0.6);
    (as_bump ? d.material.bump : d.material.wrinkles) = map;
    (as_bump ? d.material.bump_depth : d.material.wrinkle_depth) = 0.4;
    d.material.wrinkle_shade = shade;
    list.meshes = {d};
    return dr.draw(list);
  };
  Image flat;
  middle(dr, flat, 60, nullptr, 0.0);
  CHECK(draw(0.0f, 0.5, false).rgb == flat.rgb);
  {  // a mesh without weights under a wrinkled material: no wrinkles either
    DrawList list = sunlit(Vec3(0, 3, 0.001), Vec3(std::sin(kPi / 3), -std::cos(kPi / 3), 0));
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(makeQuad(4, 4));
    d.material.color = Vec3(0.6, 0.6, 0.6);
    d.material.wrinkles = map;
    d.material.wrinkle_depth = 0.4;
    d.material.wrinkle_shade = 0.5;
    list.meshes = {d};
    CHECK(dr.draw(list).rgb == flat.rgb);
  }
  const Image bumped = draw(0.0f, 0.0, true), full = draw(1.0f, 0.0, false), half = draw(0.5f, 0.0, false);
  CHECK(full.rgb == bumped.rgb);
  // Half the weight, half the slope: between the flat plane and the full tilt.
  const auto g = [](const Image& i) { return int(i.pixel(i.width / 2, i.height / 2)[1]); };
  CHECK(g(half) > g(flat));
  CHECK(g(half) < g(full));
  // The shade: at the ramp's middle the map's height is 0.5, so a shade s darkens the albedo by s/2.
  const Image shaded = draw(1.0f, 0.4, false);
  const double s = 0.4 * (256.0 / 255.0) / 4.0, lit = (s * std::sin(kPi / 3) + std::cos(kPi / 3)) / std::sqrt(1 + s * s);
  const double h = (128.0 - 0.5 + 0.5) / 255.0;  // about the middle column's height
  CHECK(std::abs(g(shaded) - int(std::lround(255.0 * srgb(0.6 * (1 - 0.4 * (1 - h)) * lit)))) <= 2);
}

TEST_CASE("relief seen from a sheet's back is the same surface from behind; a plain back has none; a texture may be its own bump map") {
  DirectRenderer dr(64, 48, 1);
  const auto map = ramp();
  const double t = kPi / 3, s = 0.4 * (256.0 / 255.0) / 4.0;
  auto quad = [&](std::shared_ptr<const Image> bump, bool plain_back, std::shared_ptr<const Image> texture, const Vec3& eye,
                  const Vec3& sun) {
    DrawList list = sunlit(eye, sun);
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(makeQuad(4, 4));
    d.material.color = Vec3(0.6, 0.6, 0.6);
    d.material.double_sided = true;
    if (plain_back) d.material.back_color = Vec3(0.6, 0.6, 0.6);
    d.material.texture = std::move(texture);
    d.material.bump = std::move(bump);
    d.material.bump_depth = 0.4;
    list.meshes = {d};
    return dr.draw(list);
  };
  const auto g = [](const Image& i) { return int(i.pixel(i.width / 2, i.height / 2)[1]); };
  // From below, lit from below at 60° toward +x: the front's height rises along x, so the back's
  // normal (the tilted front's reversed) leans toward +x, away from that light:
  // (−s sin θ + cos θ)/√(1 + s²).
  const Vec3 below(0, -3, 0.001), up_sun(std::sin(t), std::cos(t), 0);
  const double lin = 0.6 * (-s * std::sin(t) + std::cos(t)) / std::sqrt(1 + s * s);
  CHECK(std::abs(g(quad(map, false, nullptr, below, up_sun)) - int(std::lround(255.0 * srgb(lin)))) <= 1);
  // A plain back (its own colour) has neither the front's texture nor its relief.
  CHECK(quad(map, true, nullptr, below, up_sun).rgb == quad(nullptr, true, nullptr, below, up_sun).rgb);
  // The ramp as the texture and its own bump map (a pattern with `bump`): the albedo the
  // texture's, the light the tilted normal's. The ratio to the flat plane's is the tilt's.
  const Vec3 above(0, 3, 0.001), sun(std::sin(t), -std::cos(t), 0);
  auto linear = [](int v) {
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const double flat = linear(g(quad(nullptr, false, map, above, sun))), both = linear(g(quad(map, false, map, above, sun)));
  CHECK(flat > 0.05);
  CHECK(both / flat == doctest::Approx((s * std::sin(t) + std::cos(t)) / std::sqrt(1 + s * s) / std::cos(t)).epsilon(0.03));
}

TEST_CASE("a material's bump: from its bump_texture, its texture or its pattern; bad ones named with their paths") {
  auto parse = [](const std::string& material) {
    const std::string text = R"({"format": "reel/1", "duration": 0.1, "objects": [{"type": "plane", "size": [2, 2])" + material + "}]}";
    return app::parseScene(text, "bump.json");
  };
  auto err = [&](const std::string& material) {
    auto r = parse(material);
    std::string all;
    if (!r.ok())
      for (const std::string& l : r.error().messages) all += l + "\n";
    return all;
  };
  CHECK(err(R"(, "bump": 0.001)").find("/objects/0/bump: bump needs a map") != std::string::npos);
  CHECK(err(R"(, "pattern": "wood", "bump": 0.2)").find("/objects/0/bump") != std::string::npos);
  CHECK(err(R"(, "pattern": "wood", "bump": "deep")").find("/objects/0/bump") != std::string::npos);
  CHECK(err(R"(, "bump_texture": "nowhere.png", "bump": 0.001)").find("/objects/0/bump_texture") != std::string::npos);
  CHECK(err(R"(, "pattern": "wood", "bump_texture": "nowhere.png")").find("/objects/0/bump: bump_texture needs bump") !=
        std::string::npos);
  CHECK(err(R"(, "pattern": "wood", "bunp": 0.001)").find("did you mean \"bump\"") != std::string::npos);
  // A pattern is its own bump map; the renderer's material carries it and its depth.
  auto ok = parse(R"(, "pattern": "wood", "bump": -0.0005)");
  REQUIRE(ok.ok());
  const Material& m = ok.value().objects.at(0).material;
  CHECK(m.bump == doctest::Approx(-0.0005));
  const DrawMaterial d = drawMaterial(m);
  CHECK(d.bump == m.texture_image);
  CHECK(d.bump_depth == doctest::Approx(-0.0005));
  // A plain material has none.
  auto plain = parse("");
  REQUIRE(plain.ok());
  CHECK(drawMaterial(plain.value().objects.at(0).material).bump_depth == 0.0);
}

TEST_CASE("the face's skin relief: furrows across the lips about a millimetre apart, grain on the cheek, strands on the hair") {
  const FaceLook look;
  const double ym = head::kMouthY;  // the lips' parting (about where reel's head has it)
  // Along the lower lip's middle, the height rises and falls with the furrows: count its swings.
  const Vec3 d(0, 0, 1);
  auto along = [&](double y) {
    int swings = 0;
    double lo = 1, hi = 0, prev = 0.5;
    int dir = 0;
    for (int i = 0; i <= 200; ++i) {
      const double x = -0.01 + 0.02 * i / 200.0, h = head::skinRelief(Vec3(x, y, 0.09), d, ym, look);
      lo = std::min(lo, h), hi = std::max(hi, h);
      const int now = h > prev ? 1 : h < prev ? -1 : dir;
      if (dir != 0 && now != dir) ++swings;
      dir = now, prev = h;
    }
    return std::tuple{swings, lo, hi};
  };
  const auto [lip_swings, lip_lo, lip_hi] = along(ym - 0.0045);
  CHECK(lip_hi - lip_lo > 0.15);
  // 20 mm at about 1.1 mm apart: some 18 furrows, a rise and a fall each (grain adds a few).
  CHECK(lip_swings >= 24);
  CHECK(lip_swings <= 60);
  // The cheek: grain and pores about 0.5, far shallower than the lips' furrows.
  double lo = 1, hi = 0, sum = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 p(0.04 + 0.00005 * (i % 20), -0.03 + 0.00005 * (i / 20), 0.07);
    const double h = head::skinRelief(p, p.normalized(), ym, look);
    lo = std::min(lo, h), hi = std::max(hi, h), sum += h;
  }
  CHECK(sum / 400 == doctest::Approx(0.5).epsilon(0.1));
  CHECK(hi - lo > 0.03);
  CHECK(hi - lo < lip_hi - lip_lo);
  // The crown, under hair: raised strands.
  const Vec3 crown(0, 0.115, 0.0);
  CHECK(head::skinRelief(crown, Vec3::UnitY(), ym, look) > 0.6);
}

TEST_CASE("reel's face draws its skin with its relief and its wrinkle map, the wrinkles sunk only where an expression pulls") {
  // The skin's mesh in the draw list: the one with the skin's relief.
  auto skin = [](const std::string& preset, double amount) {
    World w = worldFromText(test::faceSceneText(R"(, "activations": [{"time": 0, "preset": ")" + preset + R"(", "amount": 0}, {"time": 0.4, "preset": ")" +
                                                    preset + R"(", "amount": )" + std::to_string(amount) + "}]",
                                                0.6, "[48, 32]", "1e-3"));
    run(w, 18);
    DrawList list;
    w.draw(list);
    const FaceBody& f = *w.first<FaceBody>();
    for (const DrawMesh& m : list.meshes)
      if (m.material.bump) {
        CHECK(m.material.bump_depth == doctest::Approx(kSkinReliefDepth * f.surface().scale));
        REQUIRE(m.material.wrinkles);
        CHECK(m.material.wrinkle_depth == doctest::Approx(kWrinkleDepth * f.surface().scale));
        REQUIRE(m.mesh->wrinkle.size() == m.mesh->vertexCount());
        return *std::max_element(m.mesh->wrinkle.begin(), m.mesh->wrinkle.end());
      }
    FAIL("no skin with relief drawn");
    return 0.0f;
  };
  CHECK(skin("surprise", 0.0) < 0.05f);
  CHECK(skin("surprise", 1.0) > 0.7f);
  CHECK(skin("anger", 1.0) > 0.7f);
}
