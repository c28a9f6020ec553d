// Rendering a scene in the test process (shared by the renderer's and the shading tests).
#pragma once

#include <doctest/doctest.h>

#include <cmath>
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

}  // namespace reel::test
