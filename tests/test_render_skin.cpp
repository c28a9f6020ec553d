// Skin's shading in the renderer: wrap lighting per colour and a shadow's warm penumbra on skin.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/math.h"
#include "core/mesh.h"
#include "render_helpers.h"

using namespace reel;
using namespace reel::test;

TEST_CASE("wrap lighting: the diffuse term (n·l + w)/(1 + w) per colour (w, 0.75 w, 0.6 w), lit past the terminator; w = 0 is Lambert") {
  const int W = 64, H = 48;
  DirectRenderer dr(W, H, 1);
  const double rho = 0.6;
  for (const auto& row : {std::pair{60.0, 0.5}, std::pair{100.0, 0.5}, std::pair{100.0, 0.0}, std::pair{30.0, 0.2}}) {
    const double theta = row.first, wrap = row.second;
    CAPTURE(theta);
    CAPTURE(wrap);
    const double t = theta * kPi / 180.0;
    DrawList list = sunlit(Vec3(0, 3, 0.001), Vec3(std::sin(t), -std::cos(t), 0));
    DrawMesh d;
    d.mesh = std::make_shared<const TriMesh>(makeQuad(4, 4));
    d.material.color = Vec3(rho, rho, rho);
    d.material.wrap = wrap;
    list.meshes = {d};
    const Image img = dr.draw(list);
    const std::uint8_t* p = img.pixel(W / 2, H / 2);
    const double share[3] = {1.0, 0.75, 0.6};  // red travels farthest under skin
    for (int c = 0; c < 3; ++c) {
      const double w = wrap * share[c];
      const double lin = rho * std::max(0.0, (std::cos(t) + w) / (1.0 + w));
      const int want = static_cast<int>(std::lround(255.0 * srgb(lin)));
      CHECK(std::abs(int(p[c]) - want) <= 1);
    }
  }
}

TEST_CASE("wrap lighting: a shadow's penumbra on skin reddens (red reaches furthest into it), a plain surface's stays grey") {
  // A grey floor lit from above by a sun of some size, a box held over it: across the shadow's soft
  // edge, red keeps more of its light than blue on skin, and the same on a plain surface.
  const int W = 160, H = 96;
  DirectRenderer dr(W, H, 1);
  auto draw = [&](double wrap) {
    DrawList list = ambientList(Vec3(0, 3, 0.01), Vec3(0, 0, 0));
    list.lights[0].intensity = 0.0;
    LightDesc sun;
    sun.direction = Vec3(0, -1, 0);
    sun.shadows = true;
    sun.size = 6.0;  // degrees: a wide penumbra
    list.lights.push_back(sun);
    DrawMesh floor{std::make_shared<const TriMesh>(makeQuad(6, 6)), false, DrawMaterial{}};
    floor.material.color = Vec3(0.5, 0.5, 0.5);
    floor.material.wrap = wrap;
    list.meshes.push_back(floor);
    DrawInstances above;
    above.mesh = std::make_shared<const TriMesh>(makeBox(Vec3(1, 0.1, 1)));
    addCopy(above, Mat3::Identity(), 1.0, Vec3(-1.0, 2.0, 0));
    list.instances.push_back(above);
    return dr.draw(list);
  };
  for (const double wrap : {0.5, 0.0}) {
    CAPTURE(wrap);
    const Image img = draw(wrap);
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
    if (wrap > 0) CHECK(lead > 0.1);
    else CHECK(lead < 0.03);
  }
}
