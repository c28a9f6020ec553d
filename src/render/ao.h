// Screen-space ambient occlusion (shaders/ao.frag, ao_blur.frag): the camera's depth drawn by
// the caller, then occlusion and its 4 x 4 average at full resolution, left bound to a texture
// unit for the surface shader's ambient and environment terms.
#pragma once

#include <functional>
#include <string>

#include "core/error.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/projection.h"

namespace reel {

class AmbientOcclusion {
 public:
  AmbientOcclusion(const gl::GlApi& gl, gl::UniformCache& uniforms) : gl_(&gl), uniforms_(&uniforms) {}
  // One frame: `draw_depth` draws the opaque geometry with the depth-only program bound to
  // `view_proj` (it gets the program to set it on); the result is bound to texture unit `unit`.
  // Its GL objects are made on first use (a film without occlusion pays nothing).
  Status run(const std::string& shader_dir, int width, int height, const Mat4f& proj, double radius, double strength,
             int unit, const std::function<Status()>& draw_depth, const gl::Framebuffer& restore);

 private:
  Status init(const std::string& shader_dir, int width, int height);
  void fullScreen(GLuint prog, const gl::Framebuffer& target);
  const gl::GlApi* gl_;
  gl::UniformCache* uniforms_;
  int width_ = 0, height_ = 0;
  gl::Texture depth_, ao_[2];
  gl::Framebuffer depth_fbo_, ao_fbo_[2];
  gl::Program ao_prog_, blur_prog_;
  gl::VertexArray vao_;
};

}  // namespace reel
