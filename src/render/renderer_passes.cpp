// The renderer's later passes: see-through bodies (transmission), the environment's texture and
// the background.
#include <algorithm>
#include <utility>

#include <Eigen/LU>

#include "render/renderer_impl.h"

namespace reel {

Status Renderer::Impl::initTransmission() {
  const int W = set.width, H = set.height;
  scene_color_tex = gl::makeTargetTexture(*gl, W, H, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, GL_LINEAR);
  scene_depth_tex = gl::makeTargetTexture(*gl, W, H, GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT, GL_NEAREST);
  back_depth_tex = gl::makeTargetTexture(*gl, W, H, GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT, GL_NEAREST);
  auto copy = gl::makeTargetFramebuffer(*gl, scene_color_tex.id(), scene_depth_tex.id(), "transmission copy");
  if (!copy.ok()) return copy.error();
  auto back = gl::makeTargetFramebuffer(*gl, 0, back_depth_tex.id(), "transmission depth");
  if (!back.ok()) return back.error();
  copy_fbo = std::move(copy.value());
  back_fbo = std::move(back.value());
  return {};
}

// See-through bodies (transmission > 0), after the opaque ones and the background: the picture
// so far and its depth are resolved into textures, the bodies' farthest depth is drawn (depth
// test GREATER from a cleared 0, so no face culling is needed), then the bodies are drawn with
// the TRANSMISSIVE variant, which reads all three (shaders/surface.frag).
Status Renderer::Impl::transmissionPass(const DrawList& list, const Mat4f& view_proj) {
  const Pass see_through{true, Layer::Transmissive};
  if (!see_through.wantsAny(list)) return {};
  if (!copy_fbo.id())
    if (Status st = initTransmission(); !st) return st;
  const int W = set.width, H = set.height;
  gl->BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo.id());
  gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, copy_fbo.id());
  gl->BlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
  gl->BindFramebuffer(GL_FRAMEBUFFER, back_fbo.id());
  gl->DepthMask(GL_TRUE);
  gl->ClearDepth(0.0);
  gl->Clear(GL_DEPTH_BUFFER_BIT);
  gl->ClearDepth(1.0);
  gl->DepthFunc(GL_GREATER);
  if (Status st = depthOnly(list, view_proj, Layer::Transmissive); !st) return st;
  surfaces.programChanged();
  gl->DepthFunc(GL_LESS);
  const std::pair<int, GLuint> bound[] = {
      {kSceneColorUnit, scene_color_tex.id()}, {kSceneDepthUnit, scene_depth_tex.id()}, {kBackDepthUnit, back_depth_tex.id()}};
  for (auto [unit, tex] : bound) {
    gl->ActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
    gl->BindTexture(GL_TEXTURE_2D, tex);
  }
  gl->ActiveTexture(GL_TEXTURE0);
  gl->BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo.id());
  return drawGeometry(list, Pass{true, Layer::Transmissive});
}

// The scene's environment as one mipmapped float texture, its levels the prefiltered roughness
// levels (each half the size of the one before, as a mipmap chain is), uploaded when it changes.
void Renderer::Impl::uploadEnvironment(const DrawList& list) {
  const Environment* env = list.environment.get();
  gl->ActiveTexture(GL_TEXTURE0 + kEnvUnit);
  gl->BindTexture(GL_TEXTURE_2D, env_tex.id());
  const bool same = env == env_uploaded && !env_owner.expired();
  if (env && !same) {
    for (std::size_t k = 0; k < env->levels.size(); ++k) {
      const RadianceMap& m = env->levels[k];
      gl->TexImage2D(GL_TEXTURE_2D, static_cast<GLint>(k), GL_RGB32F, m.width, m.height, 0, GL_RGB, GL_FLOAT, m.rgb.data());
    }
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(env->levels.size() - 1));
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    env_uploaded = env;
    env_owner = list.environment;
  }
  gl->ActiveTexture(GL_TEXTURE0);
}

// The background after the opaque geometry, at the far plane with depth testing on: it only
// shades the pixels nothing covers. The environment where the scene shows it, else the gradient.
Status Renderer::Impl::drawBackground(const DrawList& list, const Mat4f& view_proj) {
  const bool env = list.environment && list.environment->background;
  std::string defines;
  if (list.tonemap == "aces") defines += "#define ACES\n";
  if (env) defines += "#define ENVIRONMENT\n";
  auto it = backgrounds.find(defines);
  if (it == backgrounds.end()) {
    auto bg = gl::buildProgram(*gl, shader_dir, "background.vert", "background.frag", false, defines);
    if (!bg.ok()) return bg.error();
    it = backgrounds.emplace(defines, std::move(bg.value())).first;
  }
  const GLuint prog = it->second.id();
  gl->DepthFunc(GL_LEQUAL);
  gl->DepthMask(GL_FALSE);
  gl->UseProgram(prog);
  surfaces.programChanged();
  const Vec3& bt = list.background_top;
  const Vec3& bb = list.background_bottom;
  gl->Uniform3f(loc(prog, "u_top"), float(bt.x()), float(bt.y()), float(bt.z()));
  gl->Uniform3f(loc(prog, "u_bottom"), float(bb.x()), float(bb.y()), float(bb.z()));
  const BackgroundGlow& glow = list.background_glow;
  gl->Uniform3f(loc(prog, "u_glow"), float(glow.color.x()), float(glow.color.y()), float(glow.color.z()));
  gl->Uniform3f(loc(prog, "u_glow_at"), float(2 * glow.x - 1), float(2 * glow.y - 1), float(2 * glow.radius));
  gl->Uniform1f(loc(prog, "u_aspect"), float(set.width) / float(set.height));
  gl->Uniform1f(loc(prog, "u_exposure"), float(exposureScale(list)));
  const Mat4f inv = view_proj.inverse();
  gl->UniformMatrix4fv(loc(prog, "u_inv_view_proj"), 1, GL_FALSE, inv.data());
  gl->Uniform3f(loc(prog, "u_eye"), float(eye.x()), float(eye.y()), float(eye.z()));
  gl->Uniform1i(loc(prog, "u_env"), kEnvUnit);
  gl->BindVertexArray(empty_vao.id());
  gl->DrawArrays(GL_TRIANGLES, 0, 3);
  gl->DepthFunc(GL_LESS);
  return {};
}

}  // namespace reel
