// Skin's shading: pre-integrated scattering per colour (the table and the renderer), a shadow's
// warm penumbra on skin, and light through a thin sheet.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "core/brdf.h"
#include "core/math.h"
#include "core/mesh.h"
#include "render_helpers.h"

using namespace reel;
using namespace reel::test;

TEST_CASE("pre-integrated skin: the table is Lambert on flat skin, conserves energy, and reaches past the terminator red first") {
  // The profile itself: each colour's weights sum to 1, ∫ R(r)·2πr dr = 1 (light is moved, not lost).
  {
    Vec3 total = Vec3::Zero();
    const double dr = 0.002;
    for (double r = 0.5 * dr; r < 40.0; r += dr) total += brdf::skinProfile(r) * (2.0 * kPi * r * dr);
    for (int ch = 0; ch < 3; ++ch) CHECK(total[ch] == doctest::Approx(1.0).epsilon(2e-3));
    // Red reaches farthest: at 2 mm out, red's share of what arrives is far above blue's.
    const Vec3 far = brdf::skinProfile(2.0);
    CHECK(far[0] > 20.0 * far[2]);
  }
  for (const double c : {1e-4, 0.05, 0.3, 1.0}) {
    CAPTURE(c);
    // ∫ D(θ) dθ over [0, π] is ∫ cos⁺θ dθ = 1 at every curvature: the profile moves light, it makes none.
    Vec3 e = Vec3::Zero();
    const int n = 720;
    for (int k = 0; k < n; ++k) e += brdf::preintegratedSkin(std::cos((k + 0.5) * kPi / n), c) * (kPi / n);
    for (int ch = 0; ch < 3; ++ch) CHECK(e[ch] == doctest::Approx(1.0).epsilon(2e-3));
  }
  for (const double theta : {0.0, 45.0, 89.0, 95.0}) {
    const double ct = std::cos(theta * kPi / 180.0);
    // Nearly flat skin (r = 10 m): the integral itself comes out Lambert.
    const Vec3 flat = brdf::preintegratedSkin(ct, 1e-4);
    for (int ch = 0; ch < 3; ++ch) CHECK(flat[ch] == doctest::Approx(std::max(ct, 0.0)).epsilon(1e-3).scale(1.0));
  }
  // At the terminator (θ = 90°, where Lambert gives 0): red, which travels farthest under skin,
  // leads green and blue, and more on curvier skin (an ear's rim against a cheek).
  const Vec3 nose = brdf::preintegratedSkin(0.0, 0.1), rim = brdf::preintegratedSkin(0.0, 0.5);
  CHECK(nose[0] > nose[1]);
  CHECK(nose[1] > nose[2]);
  CHECK(rim[0] > 2.0 * nose[0]);
  CHECK(rim[0] > 0.03);
  // The table the shader reads holds the same values at its texel centres and between them.
  const brdf::SkinTable t = brdf::integrateSkin(64);
  for (const auto& [ct, c] : {std::pair{0.0, 0.5}, std::pair{0.5, 0.1}, std::pair{-0.2, 0.8}, std::pair{0.9, 0.02}}) {
    CAPTURE(ct);
    CAPTURE(c);
    const Vec3 want = brdf::preintegratedSkin(ct, c), got = t.at(ct, c);
    for (int ch = 0; ch < 3; ++ch) CHECK(std::abs(got[ch] - want[ch]) < 0.005);
  }
}

TEST_CASE("pre-integrated skin in the renderer: a flat sheet is Lambert, a ball lit from beside is lit past its terminator as the table says") {
  const int W = 64, H = 48;
  DirectRenderer dr(W, H, 1);
  const double rho = 0.6;
  // A flat sheet: curvature 0, exactly Lambert in every colour.
  for (const double theta : {30.0, 60.0, 100.0}) {
    CAPTURE(theta);
    const double t = theta * kPi / 180.0;
    DrawList list = sunlit(Vec3(0, 3, 0.001), Vec3(std::sin(t), -std::cos(t), 0));
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(makeQuad(4, 4));
    d.material.color = Vec3(rho, rho, rho);
    d.material.scatter = 1.0;
    list.meshes = {d};
    const Image img = dr.draw(list);
    const std::uint8_t* p = img.pixel(W / 2, H / 2);
    const int want = static_cast<int>(std::lround(255.0 * srgb(rho * std::max(0.0, std::cos(t)))));
    for (int c = 0; c < 3; ++c) CHECK(std::abs(int(p[c]) - want) <= 1);
  }
  // A ball of radius 1 m with its profile scaled 400 times (1/r = 0.4 mm⁻¹ in the table), seen
  // from +z and lit at θ from its facing point: the pixel facing the camera has the table's value
  // (as the shader reads it: bilinear between its texels).
  const brdf::SkinTable table = brdf::integrateSkin(64);
  for (const double theta : {60.0, 90.0, 100.0}) {
    CAPTURE(theta);
    const double t = theta * kPi / 180.0;
    DrawList list = sunlit(Vec3(0, 0, 4), -Vec3(std::sin(t), 0, std::cos(t)));
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(makeIcosphere(1.0, 5));
    d.material.color = Vec3(rho, rho, rho);
    d.material.scatter = 400.0;
    list.meshes = {d};
    const Image img = dr.draw(list);
    const std::uint8_t* p = img.pixel(W / 2, H / 2);
    // The normal where the centre pixel's ray meets the ball (the pixel's centre is half a pixel
    // off the ball's, which at the terminator matters).
    const double half = std::tan(20.0 * kPi / 180.0);
    const Vec3 ray = Vec3((2.0 * (W / 2 + 0.5) / W - 1.0) * half * W / H, (1.0 - 2.0 * (H / 2 + 0.5) / H) * half, -1.0).normalized();
    const Vec3 eye(0, 0, 4);
    const double b = eye.dot(ray), hit = -b - std::sqrt(b * b - (eye.squaredNorm() - 1.0));
    const Vec3 normal = (eye + hit * ray).normalized();
    const Vec3 D = table.at(normal.dot(Vec3(std::sin(t), 0, std::cos(t))), 0.4);
    MESSAGE("theta " << theta << ": " << int(p[0]) << " " << int(p[1]) << " " << int(p[2]) << " want " << 255 * srgb(rho * D[0]) << " " << 255 * srgb(rho * D[1]) << " " << 255 * srgb(rho * D[2]));
    for (int c = 0; c < 3; ++c) CHECK(std::abs(p[c] - 255.0 * srgb(rho * D[c])) <= 2.0);
    if (theta >= 90.0) CHECK(int(p[0]) > int(p[2]) + 10);  // past the terminator: lit, and red
  }
}

TEST_CASE("translucency: a thin sheet of skin lit from behind shows red light through it; without translucency it stays dark") {
  const int W = 64, H = 48;
  DirectRenderer dr(W, H, 1);
  for (const double tr : {0.5, 0.0}) {
    CAPTURE(tr);
    // The camera above the sheet, the sun shining up at it from below.
    DrawList list = sunlit(Vec3(0, 3, 0.001), Vec3(0, 1, 0));
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(makeQuad(4, 4));
    d.material.color = Vec3(0.6, 0.6, 0.6);
    d.material.double_sided = true;
    d.material.scatter = 1.0;
    d.material.translucency = tr;
    list.meshes = {d};
    const std::uint8_t* p = dr.draw(list).pixel(W / 2, H / 2);
    if (tr > 0) {
      for (int c = 0; c < 3; ++c) CHECK(std::abs(p[c] - 255.0 * srgb(0.6 * tr * std::array{1.0, 0.4, 0.25}[c])) <= 1.5);
    } else {
      for (int c = 0; c < 3; ++c) CHECK(int(p[c]) == 0);
    }
  }
}

TEST_CASE("skin: a shadow's penumbra on skin reddens (red reaches furthest into it), a plain surface's stays grey") {
  // A grey floor lit from above by a sun of some size, a box held over it: across the shadow's soft
  // edge, red keeps more of its light than blue on skin, and the same on a plain surface.
  const int W = 160, H = 96;
  DirectRenderer dr(W, H, 1);
  auto draw = [&](double scatter) {
    DrawList list = ambientList(Vec3(0, 3, 0.01), Vec3(0, 0, 0));
    list.lights[0].intensity = 0.0;
    LightDesc sun;
    sun.direction = Vec3(0, -1, 0);
    sun.shadows = true;
    sun.size = 6.0;  // degrees: a wide penumbra
    list.lights.push_back(sun);
    DrawMesh floor{std::make_shared<const TriMesh>(makeQuad(6, 6)), false, DrawMaterial{}};
    floor.material.color = Vec3(0.5, 0.5, 0.5);
    floor.material.scatter = scatter;
    list.meshes.push_back(floor);
    DrawInstances above;
    above.mesh = std::make_shared<const TriMesh>(makeBox(Vec3(1, 0.1, 1)));
    addCopy(above, Mat3::Identity(), 1.0, Vec3(-1.0, 2.0, 0));
    list.instances.push_back(above);
    return dr.draw(list);
  };
  for (const double scatter : {1.0, 0.0}) {
    CAPTURE(scatter);
    const Image img = draw(scatter);
    // Along the row through the middle: the lit floor's values at the right edge, the umbra's
    // under the box; the largest lead of red's share of its light over blue's in between.
    const int y = H / 2;
    const std::uint8_t* lit = img.pixel(W - 4, y);
    int penumbra = 0;
    double lead = 0.0;
    for (int x = 0; x < W; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      const double r = p[0] / double(lit[0]), b = p[2] / double(lit[2]);
      if (b > 0.1 && b < 0.9) ++penumbra, lead = std::max(lead, r - b);
    }
    MESSAGE("penumbra " << penumbra << " px, red's share ahead of blue's by up to " << lead);
    REQUIRE(penumbra >= 3);
    if (scatter > 0) CHECK(lead > 0.1);
    else CHECK(lead < 0.03);
  }
}
