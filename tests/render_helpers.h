// Rendering a scene in the test process (shared by the renderer's and the shading tests).
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <string>

#include "app/body_kinds.h"
#include "core/scene_view.h"
#include "helpers.h"
#include "render/renderer.h"

namespace reel::test {

// Renders frame `frame` of a scene in this process with the given backend.
inline Image renderScene(const std::string& text, gl::Backend backend = gl::Backend::OSMesa, int frame = 0,
                         const std::string& file = "test.json") {
  const SceneDesc scene = sceneFromText(text, file);
  auto w = app::makeWorld(scene);
  REQUIRE(w.ok());
  for (int k = 0; k < frame; ++k) REQUIRE(w.value().advanceFrame().ok());
  auto ctx = gl::createContext(backend);
  REQUIRE_MESSAGE(ctx.ok(), (ctx.ok() ? "" : ctx.error().headline()));
  RenderSettings rs;
  rs.width = scene.render.width;
  rs.height = scene.render.height;
  rs.samples = scene.render.samples;
  auto r = Renderer::create(*ctx.value(), rs, findShaderDir());
  REQUIRE_MESSAGE(r.ok(), (r.ok() ? "" : r.error().headline()));
  DrawList list;
  setSceneView(scene, w.value().time(), list, w.value().cameraRig());
  w.value().draw(list);
  Image img;
  REQUIRE(r.value()->draw(list, img).ok());
  return img;
}

// The sRGB encoding of a linear value 0..1.
inline double srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055; }

// Draws hand-made draw lists at a small size with a renderer of its own.
struct DirectRenderer {
  std::unique_ptr<gl::Context> ctx;
  std::unique_ptr<Renderer> r;
  DirectRenderer(int w, int h, int samples) {
    auto c = gl::createContext(gl::Backend::OSMesa);
    REQUIRE_MESSAGE(c.ok(), (c.ok() ? "" : c.error().headline()));
    ctx = std::move(c.value());
    RenderSettings rs;
    rs.width = w;
    rs.height = h;
    rs.samples = samples;
    rs.shadow_map_size = 512;
    auto made = Renderer::create(*ctx, rs, findShaderDir());
    REQUIRE_MESSAGE(made.ok(), (made.ok() ? "" : made.error().headline()));
    r = std::move(made.value());
  }
  Image draw(const DrawList& list) {
    Image img;
    REQUIRE(r->draw(list, img).ok());
    return img;
  }
};

// A list with one ambient light of intensity 1 on a black background, seen from `eye`.
inline DrawList ambientList(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitY()) {
  DrawList list;
  list.camera.position = eye;
  list.camera.target = target;
  list.camera.up = up;
  list.camera.fov_deg = 40;
  list.background_top = list.background_bottom = Vec3::Zero();
  LightDesc amb;
  amb.kind = LightKind::Ambient;
  amb.intensity = 1.0;
  list.lights = {amb};
  return list;
}

// The 12 floats of a copy placed by rotation R (its columns the local axes), scale and origin.
inline void addCopy(DrawInstances& d, const Mat3& R, double scale, const Vec3& origin) {
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) d.transforms.push_back(static_cast<float>(scale * R(k, a)));
  for (int k = 0; k < 3; ++k) d.transforms.push_back(static_cast<float>(origin[k]));
}

// A black background, a camera at `eye` looking at the origin, and one sun of intensity 1 shining
// along `direction`.
inline DrawList sunlit(const Vec3& eye, const Vec3& direction) {
  DrawList list;
  list.camera.position = eye;
  list.camera.target = Vec3::Zero();
  list.camera.fov_deg = 40;
  list.background_top = list.background_bottom = Vec3::Zero();
  LightDesc sun;
  sun.kind = LightKind::Directional;
  sun.direction = direction;
  sun.intensity = 1.0;
  list.lights = {sun};
  return list;
}

}  // namespace reel::test
