#include "render/ao.h"

#include <Eigen/LU>

namespace reel {

Status AmbientOcclusion::init(const std::string& dir, int width, int height) {
  auto a = gl::buildProgram(*gl_, dir, "background.vert", "ao.frag", false);
  if (!a.ok()) return a.error();
  auto b = gl::buildProgram(*gl_, dir, "background.vert", "ao_blur.frag", false);
  if (!b.ok()) return b.error();
  ao_prog_ = std::move(a.value());
  blur_prog_ = std::move(b.value());
  vao_ = gl::makeVertexArray(*gl_);
  depth_ = gl::makeTargetTexture(*gl_, width, height, GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT, GL_NEAREST);
  auto df = gl::makeTargetFramebuffer(*gl_, 0, depth_.id(), "occlusion depth");
  if (!df.ok()) return df.error();
  depth_fbo_ = std::move(df.value());
  for (int i = 0; i < 2; ++i) {
    // The blurred result is read by the picture's pixels, twice as many a side: filtered.
    ao_[i] = gl::makeTargetTexture(*gl_, width, height, GL_R8, GL_RED, GL_UNSIGNED_BYTE, i == 1 ? GL_LINEAR : GL_NEAREST);
    auto f = gl::makeTargetFramebuffer(*gl_, ao_[i].id(), 0, "occlusion");
    if (!f.ok()) return f.error();
    ao_fbo_[i] = std::move(f.value());
  }
  width_ = width;
  height_ = height;
  return {};
}

void AmbientOcclusion::fullScreen(GLuint prog, const gl::Framebuffer& target) {
  gl_->BindFramebuffer(GL_FRAMEBUFFER, target.id());
  gl_->Uniform2f(uniforms_->get(*gl_, prog, "u_texel"), 1.0f / float(width_), 1.0f / float(height_));
  gl_->BindVertexArray(vao_.id());
  gl_->DrawArrays(GL_TRIANGLES, 0, 3);
}

Status AmbientOcclusion::run(const std::string& dir, int width, int height, const Mat4f& proj, double radius,
                             double strength, int unit, const std::function<Status()>& draw_depth,
                             const gl::Framebuffer& restore) {
  if (width != width_ || height != height_)
    if (Status st = init(dir, width, height); !st) return st;
  gl_->BindFramebuffer(GL_FRAMEBUFFER, depth_fbo_.id());
  gl_->Viewport(0, 0, width, height);
  gl_->Enable(GL_DEPTH_TEST);
  gl_->DepthFunc(GL_LESS);
  gl_->ClearDepth(1.0);
  gl_->Clear(GL_DEPTH_BUFFER_BIT);
  if (Status st = draw_depth(); !st) return st;
  gl_->Disable(GL_DEPTH_TEST);
  gl_->ActiveTexture(GL_TEXTURE0 + unit);
  gl_->BindTexture(GL_TEXTURE_2D, depth_.id());
  gl_->UseProgram(ao_prog_.id());
  auto loc = [&](GLuint p, const char* n) { return uniforms_->get(*gl_, p, n); };
  const Mat4f inv = proj.inverse();
  gl_->Uniform1i(loc(ao_prog_.id(), "u_depth"), unit);
  gl_->UniformMatrix4fv(loc(ao_prog_.id(), "u_proj"), 1, GL_FALSE, proj.data());
  gl_->UniformMatrix4fv(loc(ao_prog_.id(), "u_inv_proj"), 1, GL_FALSE, inv.data());
  gl_->Uniform1f(loc(ao_prog_.id(), "u_radius"), float(radius));
  gl_->Uniform1f(loc(ao_prog_.id(), "u_strength"), float(strength));
  fullScreen(ao_prog_.id(), ao_fbo_[0]);
  // The blur reads the occlusion from unit + 1 and the depth from unit.
  gl_->ActiveTexture(GL_TEXTURE0 + unit + 1);
  gl_->BindTexture(GL_TEXTURE_2D, ao_[0].id());
  gl_->UseProgram(blur_prog_.id());
  gl_->Uniform1i(loc(blur_prog_.id(), "u_depth"), unit);
  gl_->Uniform1i(loc(blur_prog_.id(), "u_ao"), unit + 1);
  fullScreen(blur_prog_.id(), ao_fbo_[1]);
  gl_->ActiveTexture(GL_TEXTURE0 + unit + 1);
  gl_->BindTexture(GL_TEXTURE_2D, 0);
  gl_->ActiveTexture(GL_TEXTURE0 + unit);
  gl_->BindTexture(GL_TEXTURE_2D, ao_[1].id());
  gl_->ActiveTexture(GL_TEXTURE0);
  gl_->Enable(GL_DEPTH_TEST);
  gl_->BindFramebuffer(GL_FRAMEBUFFER, restore.id());
  return {};
}

}  // namespace reel
