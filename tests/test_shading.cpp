// Physically based shading: the BRDF's tables, the environment's prefiltering, the furnace test,
// the GGX highlight against the CPU's formula, tone mapping, environment files and their keys.
#include <doctest/doctest.h>

#include <ImfRgbaFile.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "capture.h"
#include "core/brdf.h"
#include "core/environment.h"
#include "core/image_compare.h"
#include "core/math.h"
#include "io/environment_file.h"
#include "render/projection.h"
#include "render_helpers.h"

using namespace reel;
using namespace reel::test;
namespace fs = std::filesystem;

namespace {

double linear(std::uint8_t v) {
  const double c = v / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// A sphere of radius 0.8 at the origin seen from +z, filling most of a 96x96 picture, under
// `lights` and a render section's `extra` keys.
std::string sphereScene(const std::string& material, const std::string& lights, const std::string& extra) {
  return R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 96, "height": 96, "samples": 1, "background": [0, 0, 0])" + extra + R"(},
    "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "fov_deg": 30},
    "lights": [)" + lights + R"(],
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.8, )" + material + "}]}";
}

// The pixels well inside the sphere's silhouette (3 pixels in from its edge).
template <class F>
void forSpherePixels(const Image& img, F&& f) {
  const double r_px = 48.0 * std::tan(std::asin(0.8 / 4.0)) / std::tan(15.0 * kPi / 180.0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (std::hypot(x + 0.5 - 48, y + 0.5 - 48) < r_px - 3) f(x, y);
}

std::string uniformSky(double L) {
  char b[256];
  std::snprintf(b, sizeof b, R"(, "environment": {"sky": {"zenith": [%g, %g, %g], "horizon": [%g, %g, %g], "ground": [%g, %g, %g]}})",
                L, L, L, L, L, L, L, L, L);
  return b;
}

}  // namespace

TEST_CASE("the split-sum table: a smooth mirror reflects everything, rough GGX loses energy, as documented") {
  const brdf::DfgTable t = brdf::integrateDfg(32, 512);
  // Nearly smooth, facing: A + B is the whole reflectance (F0 = F90 = 1 reflects all).
  const Vec2 smooth = t.at(0.98, 0.02);
  CHECK(smooth.x() + smooth.y() == doctest::Approx(1.0).epsilon(0.02));
  // Single-scattering GGX loses light with roughness (docs/rendering.md's table).
  double prev = 2;
  for (double r : {0.1, 0.4, 0.7, 1.0}) {
    const Vec2 ab = t.at(0.5, r);
    CAPTURE(r);
    CHECK(ab.x() + ab.y() <= prev + 1e-6);
    prev = ab.x() + ab.y();
  }
  // At roughness 1, n·v = 0.5, about half is lost (54% here; docs/rendering.md).
  CHECK(prev < 0.6);
  CHECK(prev > 0.35);
  // B (the Fresnel edge) grows at grazing angles.
  CHECK(t.at(0.05, 0.5).y() > t.at(0.95, 0.5).y());
}

TEST_CASE("a uniform environment prefilters to itself and its irradiance is the radiance") {
  const RadianceMap m = proceduralSky(Vec3(0.7, 0.7, 0.7), Vec3(0.7, 0.7, 0.7), Vec3(0.7, 0.7, 0.7), 64);
  const auto env = prefilterEnvironment(m, 1.0, 0.0);
  REQUIRE(env->levels.size() == 6);
  CHECK(env->levels[0].width == 256);
  CHECK(env->levels[5].width == 8);
  for (const Vec3& d : {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0.3, -0.9, 0.2), Vec3(0, 0, -1)}) {
    CHECK(env->diffuse(d).x() == doctest::Approx(0.7).epsilon(0.005));
    for (double r : {0.0, 0.5, 1.0}) CHECK(env->specular(d, r).y() == doctest::Approx(0.7).epsilon(0.005));
  }
}

TEST_CASE("a sky's irradiance from nine harmonics matches the cosine-weighted integral") {
  const RadianceMap m = proceduralSky(Vec3(0.2, 0.4, 1.0), Vec3(0.9, 0.9, 0.8), Vec3(0.1, 0.08, 0.05), 128);
  const auto env = prefilterEnvironment(m, 2.0, 0.0);
  const RadianceMap& m0 = env->levels[0];
  for (const Vec3& n0 : {Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(1, 0.2, 0), Vec3(0.3, 0.5, -0.8)}) {
    const Vec3 n = n0.normalized();
    Vec3 e = Vec3::Zero();  // ∫ L cos / π over the texels
    for (int y = 0; y < m0.height; ++y)
      for (int x = 0; x < m0.width; ++x) {
        const Vec3 d = m0.directionOf(x + 0.5, y + 0.5);
        const double w = (2 * kPi / m0.width) * (kPi / m0.height) * std::sin(kPi * (y + 0.5) / m0.height);
        e += m0.texel(x, y) * std::max(0.0, n.dot(d)) * w / kPi;
      }
    CAPTURE(n.transpose());
    // Order 2 keeps irradiance within a few percent (Ramamoorthi & Hanrahan: 1% average error);
    // the dark ground under a bright horizon is the hardest case.
    for (int k = 0; k < 3; ++k) CHECK(env->diffuse(n)[k] == doctest::Approx(e[k]).epsilon(0.06));
  }
  CHECK(env->diffuse(Vec3(0, 1, 0)).z() > 3 * env->diffuse(Vec3(0, -1, 0)).z());
  // Turning the map turns the light: a sky with a bright east looks bright from the north after 90°.
  RadianceMap east = m;
  for (int y = 0; y < east.height; ++y)
    for (int x = 0; x < east.width; ++x)
      if (east.directionOf(x + 0.5, y + 0.5).x() > 0.7)
        for (int k = 0; k < 3; ++k) east.rgb[3 * (static_cast<std::size_t>(y) * east.width + x) + k] = 20.0f;
  const auto turned = prefilterEnvironment(east, 1.0, 90.0);
  const auto plain = prefilterEnvironment(east, 1.0, 0.0);
  CHECK(plain->diffuse(Vec3(1, 0, 0)).x() > 2 * plain->diffuse(Vec3(0, 0, -1)).x());
  CHECK(turned->diffuse(Vec3(0, 0, -1)).x() == doctest::Approx(plain->diffuse(Vec3(1, 0, 0)).x()).epsilon(0.03));
}

TEST_CASE("furnace: a white rough sphere under a uniform white environment renders at its albedo") {
  const double L = 0.5;
  // Rough dielectric (4% Fresnel), a rough white metal, a smooth white metal, a grey Lambert ball.
  for (auto [material, albedo] : {std::pair{std::string(R"("color": [1, 1, 1], "specular": 0.5, "roughness": 0.8)"), 1.0},
                                  std::pair{std::string(R"("color": [1, 1, 1], "specular": 0.5, "roughness": 0.3)"), 1.0},
                                  std::pair{std::string(R"("color": [1, 1, 1], "metallic": 1, "roughness": 0.9)"), 1.0},
                                  std::pair{std::string(R"("color": [1, 1, 1], "metallic": 1, "roughness": 0.2)"), 1.0},
                                  std::pair{std::string(R"("color": [0.5, 0.5, 0.5])"), 0.5}}) {
    CAPTURE_BINDING(material);
    const double want = albedo;  // (a plain variable: the lambda below cannot capture a binding)
    const Image img = renderScene(sphereScene(material, "", uniformSky(L)));
    double worst = 0;
    int n = 0;
    forSpherePixels(img, [&](int x, int y) {
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(linear(img.pixel(x, y)[c]) / (want * L) - 1.0));
      ++n;
    });
    CHECK(n > 2000);
    CHECK(worst < 0.02);
  }
}

TEST_CASE("the GGX highlight of a directional light matches the BRDF computed on the CPU") {
  // Light and camera along the sphere's normal at the picture's centre: n = v = l = h there, so
  // the pixel is E·(ρ(1 − E_s) + F0·comp·D·V·π) with D = 1/(πα²), V = 1/4.
  const brdf::DfgTable t = brdf::integrateDfg(32, 256);
  for (double rough : {0.35, 0.6}) {
    CAPTURE(rough);
    const double rho = 0.4, f0 = 0.08 * 0.5, E = 0.9, alpha = rough * rough;
    const std::string mat = R"("color": [0.4, 0.4, 0.4], "specular": 0.5, "roughness": )" + std::to_string(rough);
    const Image img = renderScene(sphereScene(mat, R"({"type": "directional", "direction": [0, 0, -1], "intensity": 0.9})", ""));
    const Vec2 ab = t.at(1.0, rough);
    const double comp = 1.0 + f0 * (1.0 / (ab.x() + ab.y()) - 1.0);
    const double es = (f0 * ab.x() + 1.0 * ab.y()) * comp;
    const double spec = kPi * brdf::ggxD(1.0, alpha) * brdf::smithV(1.0, 1.0, alpha) * f0 * comp;
    const double want = E * (rho * (1.0 - es) + spec);
    CHECK(brdf::smithV(1.0, 1.0, alpha) == doctest::Approx(0.25));
    const double got = linear(img.pixel(48, 48)[1]);
    CHECK(got == doctest::Approx(want).epsilon(0.015));
    // Off the highlight, 30° round the sphere, the specular term has fallen away steeply.
    const double got_off = linear(img.pixel(48 + 20, 48)[1]);
    CHECK(got_off < got - 0.8 * E * spec);
  }
}

TEST_CASE("ACES keeps middle grey, compresses white to 0.73 and exposure doubles per EV") {
  auto plane = [](double ambient, const std::string& extra) {
    char b[1024];
    std::snprintf(b, sizeof b, R"({"format": "reel/1", "duration": 0.1,
      "render": {"width": 32, "height": 24, "samples": 1, "background": [0, 0, 0], "tonemap": "aces"%s},
      "camera": {"position": [0, 3, 0.001], "target": [0, 0, 0]},
      "lights": [{"type": "ambient", "intensity": %g}],
      "objects": [{"type": "plane", "color": [1, 1, 1]}]})", extra.c_str(), ambient);
    return renderScene(b).pixel(16, 12)[1];
  };
  CHECK(std::abs(int(plane(0.18, "")) - int(std::lround(255 * srgb(0.18)))) <= 1);
  CHECK(std::abs(int(plane(1.0, "")) - int(std::lround(255 * srgb(0.73)))) <= 2);
  CHECK(std::abs(int(plane(0.09, R"(, "exposure": 1)")) - int(std::lround(255 * srgb(0.18)))) <= 1);
}

TEST_CASE("a background's glow: a Gaussian pool of light on the gradient, where the scene puts it") {
  // A black backdrop with a glow of 0.5 about (0.25, 0.75) of the frame, σ 0.2 of its height: the
  // pixels are 0.5·exp(−r²/2σ²) (linear, no tone mapping), r measured in frame heights.
  constexpr int W = 64, H = 32;
  const Image img = renderScene(R"({"format": "reel/1", "duration": 0.1,
      "render": {"width": 64, "height": 32, "samples": 1, "background": {"top": [0, 0, 0], "bottom": [0, 0, 0],
                 "glow": {"color": [0.5, 0.25, 0], "x": 0.25, "y": 0.75, "radius": 0.2}}},
      "camera": {"position": [0, 3, 0], "target": [0, 4, 0]}})");
  double worst = 0;
  for (int y = 0; y < H; y += 3)
    for (int x = 0; x < W; x += 3) {
      const double u = (x + 0.5) / W - 0.25, v = (H - y - 0.5) / H - 0.75;  // (rows run down)
      const double r2 = (u * W / H) * (u * W / H) + v * v, want = 0.5 * std::exp(-0.5 * r2 / (0.2 * 0.2));
      worst = std::max(worst, std::abs(img.pixel(x, y)[0] - 255.0 * srgb(want)));
      CHECK(std::abs(img.pixel(x, y)[1] - 255.0 * srgb(0.5 * want)) <= 2.0);
      CHECK(img.pixel(x, y)[2] == 0);
    }
  MESSAGE("the glow within " << worst << " levels of the Gaussian");
  CHECK(worst <= 2.0);
  CHECK(img.pixel(W / 4, H / 4)[0] > 180);  // its middle bright, the far corner black
  CHECK(img.pixel(W - 1, H - 1)[0] <= 1);
}

TEST_CASE("environment files: Radiance .hdr (run-length and flat), OpenEXR and PNG") {
  const fs::path dir = freshDir("envfiles");
  // 8 x 2: a run-length scanline of (128, 64, 32 | e 129), then a flat one of (128, 128, 128 | 128).
  std::string hdr = "#?RADIANCE\n# reel test\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n";
  hdr += std::string{2, 2, 0, 8};
  for (int v : {128, 64, 32, 129}) hdr += std::string{static_cast<char>(128 + 8), static_cast<char>(v)};
  for (int x = 0; x < 8; ++x) hdr += std::string(4, static_cast<char>(128));
  std::ofstream(dir / "a.hdr", std::ios::binary) << hdr;
  auto m = io::readEnvironmentMap((dir / "a.hdr").string());
  REQUIRE_MESSAGE(m.ok(), (m.ok() ? "" : m.error().headline()));
  CHECK(m.value().width == 8);
  CHECK(m.value().height == 2);
  CHECK(m.value().texel(3, 0).x() == doctest::Approx(128.5 / 128));
  CHECK(m.value().texel(3, 0).y() == doctest::Approx(64.5 / 128));
  CHECK(m.value().texel(7, 0).z() == doctest::Approx(32.5 / 128));
  CHECK(m.value().texel(5, 1).x() == doctest::Approx(128.5 / 256));
  // Truncated, not RGBE, a foreign format: errors that name the file.
  std::ofstream(dir / "cut.hdr", std::ios::binary) << hdr.substr(0, hdr.size() - 3);
  auto cut = io::readEnvironmentMap((dir / "cut.hdr").string());
  REQUIRE(!cut.ok());
  CHECK(cut.error().headline().find("truncated") != std::string::npos);
  CHECK(cut.error().headline().find("cut.hdr") != std::string::npos);
  // A 20 MB resolution line: refused as a too-long header line, quoted short, without reading a
  // picture's worth of memory; a file larger than the largest picture is refused before reading.
  {
    std::ofstream f(dir / "long.hdr", std::ios::binary);
    f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X " << std::string(20u << 20, '9') << "\n";
  }
  auto long_line = io::readEnvironmentMap((dir / "long.hdr").string());
  REQUIRE(!long_line.ok());
  CHECK(long_line.error().headline().find("a header line longer than 4096 bytes") != std::string::npos);
  CHECK(long_line.error().headline().size() < 400);
  auto small_cap = io::readEnvironmentMap((dir / "long.hdr").string(), 1000);
  REQUIRE(!small_cap.ok());
  CHECK(small_cap.error().headline().find("more than a picture of at most 1000 pixels can take") != std::string::npos);
  std::ofstream(dir / "no.hdr", std::ios::binary) << "P6\n8 2\n255\n";
  CHECK(!io::readEnvironmentMap((dir / "no.hdr").string()).ok());
  CHECK(!io::readEnvironmentMap((dir / "a.tga").string()).ok());
  // OpenEXR: half floats, any value including above 1.
  {
    Imf::Rgba px[2 * 4];
    for (int k = 0; k < 8; ++k) px[k] = Imf::Rgba(static_cast<float>(k) * 1.5f, 0.25f, 3.0f, 1.0f);
    Imf::RgbaOutputFile out((dir / "e.exr").c_str(), 4, 2, Imf::WRITE_RGBA);
    out.setFrameBuffer(px, 1, 4);
    out.writePixels(2);
  }
  auto e = io::readEnvironmentMap((dir / "e.exr").string());
  REQUIRE_MESSAGE(e.ok(), (e.ok() ? "" : e.error().headline()));
  CHECK(e.value().texel(3, 1).x() == doctest::Approx(7 * 1.5));
  CHECK(e.value().texel(0, 0).z() == doctest::Approx(3.0));
  std::ofstream(dir / "bad.exr", std::ios::binary) << "not an exr";
  auto bad = io::readEnvironmentMap((dir / "bad.exr").string());
  REQUIRE(!bad.ok());
  CHECK(bad.error().kind == ErrorKind::BadInput);
}

TEST_CASE("an environment file lights the scene and is seen as its background") {
  const fs::path dir = freshDir("envscene");
  // Upper half bright blue-white sky, lower half dark brown ground.
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n";
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      hdr += y < 4 ? std::string{char(100), char(110), char(127), char(129)} : std::string{char(40), char(30), char(20), char(128)};
  std::ofstream(dir / "sky.hdr", std::ios::binary) << hdr;
  const std::string scene = R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 64, "height": 64, "samples": 1, "environment": {"file": "sky.hdr"}},
    "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "fov_deg": 40}, "lights": [],
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.8, "color": [0.8, 0.8, 0.8]}]})";
  const Image img = renderScene(scene, gl::Backend::OSMesa, 0, (dir / "s.json").string());
  // The sphere's top faces the sky, its bottom the ground.
  CHECK(img.pixel(32, 20)[2] > img.pixel(32, 44)[2] + 40);
  // The background: sky above the horizon, ground below, at the file's radiance.
  CHECK(std::abs(int(img.pixel(2, 2)[2]) - int(std::lround(255 * srgb(127.5 / 128)))) <= 3);
  CHECK(std::abs(int(img.pixel(2, 61)[0]) - int(std::lround(255 * srgb(40.5 / 256)))) <= 3);
  // background: false keeps the gradient.
  std::string hidden = scene;
  hidden.replace(hidden.find(R"("file": "sky.hdr")"), 17, R"("file": "sky.hdr", "background": false)");
  hidden.replace(hidden.find(R"("samples": 1,)"), 13, R"("samples": 1, "background": [0, 0, 0],)");
  CHECK(renderScene(hidden, gl::Backend::OSMesa, 0, (dir / "s.json").string()).pixel(2, 2)[2] == 0);
}

TEST_CASE("bad environment and material keys are named") {
  auto err = [](const std::string& render, const std::string& material) {
    const std::string text = R"({"format": "reel/1", "duration": 0.1, "render": {)" + render +
                             R"(}, "objects": [{"type": "sphere", "radius": 1)" + material + "}]}";
    auto r = app::parseScene(text, "bad.json");
    std::string all;
    if (!r.ok())
      for (const std::string& l : r.error().messages) all += l + "\n";
    return all;
  };
  CHECK(err(R"("environment": "moon")", "").find("/render/environment") != std::string::npos);
  CHECK(err(R"("environment": {"sky": true, "file": "a.hdr"})", "").find("not both") != std::string::npos);
  CHECK(err(R"("environment": {"intensity": 2})", "").find("missing") != std::string::npos);
  CHECK(err(R"("environment": {"file": "nowhere.hdr"})", "").find("/render/environment/file") != std::string::npos);
  CHECK(err(R"("environment": {"sky": {"zenith": [1, -1, 0]}})", "").find("zenith") != std::string::npos);
  CHECK(err(R"("exposure": 40)", "").find("/render/exposure") != std::string::npos);
  CHECK(err("", R"(, "roughness": 1.5)").find("roughness") != std::string::npos);
  CHECK(err("", R"(, "roughness": 0.5, "shininess": 20)").find("not both") != std::string::npos);
  CHECK(err("", R"(, "metallic": -0.1)").find("metallic") != std::string::npos);
  CHECK(err(R"("environment": "sky", "exposure": -1)", R"(, "roughness": 0.3, "metallic": 1, "sheen": 0.5)").empty());
}

namespace {

// The floor's mean brightness (green) by column, over the middle 40 rows of a top-down picture.
std::vector<double> columnProfile(const Image& img) {
  std::vector<double> p(static_cast<std::size_t>(img.width), 0.0);
  for (int y = img.height / 2 - 20; y < img.height / 2 + 20; ++y)
    for (int x = 0; x < img.width; ++x) p[static_cast<std::size_t>(x)] += img.pixel(x, y)[1] / 40.0;
  return p;
}

// A plate at height h whose edge at x = 0 runs along z, lit by a sun of angular diameter
// `angle` shining along (1, −1, 0): its shadow's edge falls at x = h. Seen from straight above,
// 60 px to the metre around x = h. Returns the 10–90% width of that edge in metres.
double penumbraWidth(double h, double angle) {
  char b[1400];
  std::snprintf(b, sizeof b, R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 200, "height": 120, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [%g, 8, 0.001], "target": [%g, 0, 0], "fov_deg": 14.25},
    "lights": [{"type": "directional", "direction": [1, -1, 0], "intensity": 1, "shadows": true, "angle_deg": %g},
               {"type": "ambient", "intensity": 0.1}],
    "objects": [{"type": "plane", "size": [6, 6], "color": [0.8, 0.8, 0.8]},
                {"type": "box", "center": [-1, %g, 0], "size": [2, 0.02, 3]}]})", h, h, angle, h);
  const std::vector<double> p = columnProfile(renderScene(b));
  // x = h is the middle column, 60 px to the metre: the full shadow 0.4 m left of it, full
  // light 0.6 m right (the plate itself, lit, lies left of x = 0).
  const double dark = p[76], lit = p[136];
  REQUIRE(lit - dark > 60);
  auto cross = [&](double f) {
    const double level = dark + f * (lit - dark);
    for (std::size_t x = 77; x < 136; ++x)
      if (p[x - 1] < level && p[x] >= level) return static_cast<double>(x - 1) + (level - p[x - 1]) / (p[x] - p[x - 1]);
    return -1.0;
  };
  const double m_per_px = 2.0 * 8 * std::tan(14.25 * kPi / 360) / 120;
  return (cross(0.9) - cross(0.1)) * m_per_px;
}

}  // namespace

TEST_CASE("soft shadows: the penumbra grows with the occluder's height and the sun's size") {
  // A disc light's 10–90% edge is 0.69 of the penumbra's full width, 2·d·tan(θ/2) across the
  // ray for a distance d = h√2 along it, √2 wider on the floor the ray meets at 45°.
  auto expected = [](double h, double angle) { return 0.69 * 2 * h * std::sqrt(2.0) * std::tan(angle * kPi / 360) * std::sqrt(2.0); };
  const double w1 = penumbraWidth(0.5, 8), w2 = penumbraWidth(1.0, 8);
  CAPTURE(w1);
  CAPTURE(w2);
  CHECK(w1 > 0.6 * expected(0.5, 8));
  CHECK(w1 < 1.5 * expected(0.5, 8));
  CHECK(w2 > 0.6 * expected(1.0, 8));
  CHECK(w2 < 1.5 * expected(1.0, 8));
  CHECK(w2 / w1 > 1.5);
  CHECK(w2 / w1 < 2.6);
  // No size: the fixed narrow filter, a few millimetres whatever the height.
  CHECK(penumbraWidth(1.0, 0) < 0.3 * w2);
}

TEST_CASE("ambient occlusion darkens the floor beside a box and not the open floor") {
  auto render = [](bool ao) {
    const std::string s = std::string(R"({"format": "reel/1", "duration": 0.1,
      "render": {"width": 160, "height": 120, "samples": 1, "background": [0, 0, 0])") +
                          (ao ? R"(, "ao": {"radius": 0.4})" : "") + R"(},
      "camera": {"position": [0, 3, 3], "target": [0, 0, 0], "fov_deg": 40},
      "lights": [{"type": "ambient", "intensity": 0.8}],
      "objects": [{"type": "plane", "size": [8, 8], "color": [0.8, 0.8, 0.8]},
                  {"type": "box", "center": [0, 0.3, 0], "size": [0.6, 0.6, 0.6]}]})";
    return renderScene(s);
  };
  const Image plain = render(false), occluded = render(true);
  // Ambient light alone shades every face alike: without occlusion the column through the box
  // is one brightness. With it, the floor at the box's base darkens clearly.
  int darkest = 255, at = -1;
  for (int y = 40; y < 120; ++y)
    if (occluded.pixel(80, y)[1] < darkest) darkest = occluded.pixel(80, y)[1], at = y;
  CAPTURE(at);
  CHECK(darkest < plain.pixel(80, at)[1] - 15);
  for (int y = 40; y < 120; ++y) CHECK(std::abs(int(plain.pixel(80, y)[1]) - int(plain.pixel(80, 119)[1])) <= 1);
  // Open floor far from the box, near and far from the camera: unchanged.
  for (auto [x, y] : {std::pair{10, 110}, std::pair{150, 110}, std::pair{20, 50}, std::pair{140, 45}})
    CHECK(std::abs(int(occluded.pixel(x, y)[1]) - int(plain.pixel(x, y)[1])) <= 2);
}

TEST_CASE("transmission: a see-through ball shows what is behind it, absorbed along its depth") {
  // A ball of radius 0.5 seen from 4 m against a uniform grey background, no lights: all its
  // colour is what passes through. At its centre the depth is 1 m = 2 absorption depths, so
  // albedo 0.7 keeps 0.7² of the background.
  const std::string s = R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 96, "height": 96, "samples": 1, "background": [0.6, 0.6, 0.6]},
    "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "fov_deg": 30}, "lights": [],
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "color": [0.7, 0.7, 0.7],
                 "transmission": 1, "absorption_depth": 0.5}]})";
  const Image img = renderScene(s);
  CHECK(std::abs(int(img.pixel(48, 48)[1]) - int(std::lround(255 * srgb(0.6 * 0.49)))) <= 3);
  // Thinner towards the rim: brighter, up to the background itself.
  CHECK(img.pixel(48 + 18, 48)[1] > img.pixel(48, 48)[1] + 10);
  CHECK(img.pixel(2, 2)[1] == std::lround(255 * srgb(0.6)));
  // Opaque, the same ball unlit is black.
  std::string opaque = s;
  opaque.replace(opaque.find(R"("transmission": 1)"), 17, R"("transmission": 0)");
  CHECK(renderScene(opaque).pixel(48, 48)[1] < 5);
}

TEST_CASE("a plane's checker_size sets the width of its squares; a bad one is named") {
  // Seen from 2 m straight above with a 60° lens, 2.3 m of floor across: the middle row crosses
  // about 4.6 squares of 0.5 m and 9.2 of 0.25 m.
  auto crossings = [](const std::string& size) {
    const Image img = renderScene(R"({"format": "reel/1", "duration": 0.1,
      "render": {"width": 96, "height": 96, "samples": 1, "background": [0, 0, 0]},
      "camera": {"position": [0.01, 2, 0.001], "target": [0.01, 0, 0], "fov_deg": 60},
      "lights": [{"type": "ambient", "intensity": 1}],
      "objects": [{"type": "plane", "checker": true)" + size + "}]}");
    int n = 0;
    for (int x = 1; x < img.width; ++x) n += std::abs(int(img.pixel(x, 48)[1]) - int(img.pixel(x - 1, 48)[1])) > 20;
    return n;
  };
  const int wide = crossings(""), narrow = crossings(R"(, "checker_size": 0.25)");
  CAPTURE(wide);
  CAPTURE(narrow);
  CHECK(wide >= 3);
  CHECK(wide <= 6);
  CHECK(narrow >= 2 * wide - 1);
  CHECK(narrow <= 2 * wide + 2);
  const std::string bad = badInputErrors(R"({"format": "reel/1", "duration": 1, "objects": [{"type": "plane", "checker": true, "checker_size": 0}]})");
  CHECK(bad.find("/objects/0/checker_size") != std::string::npos);
}

TEST_CASE("a small object's shadow on a small scene is kept: the lookup moves off the surface by texels, not centimetres") {
  // A plate 20 mm square, 6 mm over the floor, under a sun along (1, −1, 0): its shadow on the
  // floor runs from x = −4 to 16 mm, seen from above beyond the plate's edge at 10 mm. Seen from
  // straight above, 2 px to the millimetre. (With the lookup moved a fixed centimetre off the
  // floor, the floor there looked up the map above the plate and was lit.)
  const char* scene = R"({"format": "reel/1", "duration": 0.1,
    "render": {"width": 200, "height": 120, "samples": 1, "background": [0, 0, 0]},
    "camera": {"position": [0, 0.3, 0.0001], "target": [0, 0, 0], "fov_deg": 11.42},
    "lights": [{"type": "directional", "direction": [1, -1, 0], "intensity": 1, "shadows": true},
               {"type": "ambient", "intensity": 0.1}],
    "objects": [{"type": "plane", "size": [0.1, 0.1], "color": [0.8, 0.8, 0.8]},
                {"type": "box", "center": [0, 0.006, 0], "size": [0.02, 0.001, 0.02]}]})";
  const Image img = renderScene(scene);
  const auto green = [&](double x_mm) { return img.pixel(100 + static_cast<int>(std::lround(2 * x_mm)), 60)[1]; };
  CAPTURE(green(13));
  CAPTURE(green(-13));
  CAPTURE(green(20));
  CHECK(green(-13) > 100);               // open floor, lit
  CHECK(green(20) > 100);                // past the shadow, lit
  CHECK(green(13) + 60 < green(-13));    // in the plate's shadow
}

TEST_CASE("a flat ground is left out of a shadow map only where it can hide nothing in view") {
  // The test of a ground: a floor 400 m wide is one; one with a vertex lifted 1 m is not, nor a
  // 6 m quad, a strip 400 m long and 1 m wide, or two 400 m floors side by side with a gap.
  TriMesh floor = makeQuad(400, 400, 4);
  const GroundPlane g = groundPlane(floor);
  CHECK(g.flat);
  CHECK(std::abs(std::abs(g.normal.y()) - 1.0) < 1e-9);
  CHECK_FALSE(groundPlane(makeQuad(6, 6)).flat);
  CHECK_FALSE(groundPlane(makeQuad(400, 1)).flat);
  TriMesh two = makeQuad(400, 400), right = makeQuad(400, 400);
  right.transform(Mat3::Identity(), Vec3(401, 0, 0));
  for (const std::uint32_t k : right.indices) two.indices.push_back(k + 4);
  two.positions.insert(two.positions.end(), right.positions.begin(), right.positions.end());
  CHECK_FALSE(groundPlane(two).flat);
  TriMesh tilted = makeQuad(400, 400);
  tilted.transform(rotationFromUp(Vec3(1, 2, 0.5).normalized()), Vec3(3, -1, 2));
  CHECK(groundPlane(tilted).flat);
  floor.positions[1] += 1.0f;
  CHECK_FALSE(groundPlane(floor).flat);
  // A box 0.1 m over an unbounded floor at y = −10 (the world's origin under it, where a test of
  // sides that forgot the plane's point would put the camera), seen from above, lit from below (a
  // sun, a point light): the floor stands between the light and all the camera sees, so the light
  // adds nothing (the ground is in the map); without the floor it lights the box's faces turned
  // down and to the camera's side. (A pebble under the floor, out of sight, takes the scene's
  // bounds, which the maps are fitted to, down to where the floor meets the point light's rays: a
  // ground, left out of the bounds, is cut off by a map's near plane where it lies farther toward
  // the light than they reach, with or without this change.)
  auto scene = [](bool ground, const std::string& light) {
    char b[1400];
    std::snprintf(b, sizeof b, R"({"format": "reel/1", "duration": 0.1,
      "render": {"width": 96, "height": 64, "samples": 1, "background": [0, 0, 0]},
      "camera": {"position": [-3, -8, 3], "target": [0, -9.6, 0], "fov_deg": 40},
      "lights": [%s{"type": "ambient", "intensity": 0.2}],
      "objects": [%s{"type": "box", "center": [0, -9.4, 0], "size": [1, 1, 1]},
                  {"type": "sphere", "center": [-1, -10.8, 0.5], "radius": 0.05}]})",
                  light.empty() ? "" : (light + ",").c_str(),
                  ground ? R"({"type": "plane", "point": [0, -10, 0], "color": [0.8, 0.8, 0.8]},)" : "");
    return renderScene(b);
  };
  auto difference = [](const Image& a, const Image& b, int& largest) {
    const ImageDiff d = compareImages(a, b, 0);
    largest = d.max_abs;
    return std::lround(d.mean_abs * static_cast<double>(a.rgb.size()));  // the sum of the differences
  };
  for (const std::string below : {R"({"type": "directional", "direction": [0.6, 1, 0.3], "intensity": 2, "shadows": true})",
                                  R"({"type": "point", "position": [-2, -11.5, 1], "intensity": 12, "shadows": true})"}) {
    CAPTURE(below);
    int largest = 0;
    const long blocked = difference(scene(true, below), scene(true, ""), largest);
    CAPTURE(blocked);
    CHECK(largest <= 2);
    const long open = difference(scene(false, below), scene(false, ""), largest);
    CAPTURE(open);
    CHECK(largest > 60);
  }
  // Lit from above, the camera and the sun on one side: the ground is left out, and the box's
  // shadow still falls on it (shadows on and off differ there by the sun's light).
  int largest = 0;
  const std::string above = R"({"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 2, "shadows": )";
  const long shadow = difference(scene(true, above + "true}"), scene(true, above + "false}"), largest);
  CAPTURE(shadow);
  CHECK(largest > 60);
  CHECK(shadow > 20000);
}
