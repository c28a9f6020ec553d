#include "render/gl/objects.h"

namespace reel::gl {

void deleteBuffer(const GlApi& gl, GLuint id) { gl.DeleteBuffers(1, &id); }
void deleteVertexArray(const GlApi& gl, GLuint id) { gl.DeleteVertexArrays(1, &id); }
void deleteFramebuffer(const GlApi& gl, GLuint id) { gl.DeleteFramebuffers(1, &id); }
void deleteRenderbuffer(const GlApi& gl, GLuint id) { gl.DeleteRenderbuffers(1, &id); }
void deleteTexture(const GlApi& gl, GLuint id) { gl.DeleteTextures(1, &id); }
void deleteSampler(const GlApi& gl, GLuint id) { gl.DeleteSamplers(1, &id); }
void deleteShader(const GlApi& gl, GLuint id) { gl.DeleteShader(id); }
void deleteProgram(const GlApi& gl, GLuint id) { gl.DeleteProgram(id); }

namespace {

// An object from a glGen* function: one name, owned by the returned object.
template <class Object, class Gen>
Object generated(const GlApi& gl, Gen gen) {
  GLuint id = 0;
  gen(1, &id);
  return {gl, id};
}

}  // namespace

Buffer makeBuffer(const GlApi& gl) { return generated<Buffer>(gl, gl.GenBuffers); }
VertexArray makeVertexArray(const GlApi& gl) { return generated<VertexArray>(gl, gl.GenVertexArrays); }
Framebuffer makeFramebuffer(const GlApi& gl) { return generated<Framebuffer>(gl, gl.GenFramebuffers); }
Renderbuffer makeRenderbuffer(const GlApi& gl) { return generated<Renderbuffer>(gl, gl.GenRenderbuffers); }
Texture makeTexture(const GlApi& gl) { return generated<Texture>(gl, gl.GenTextures); }
Sampler makeSampler(const GlApi& gl) { return generated<Sampler>(gl, gl.GenSamplers); }

Texture makeTargetTexture(const GlApi& gl, int w, int h, GLint internal, GLenum format, GLenum type, GLint filter,
                          const void* data) {
  Texture t = makeTexture(gl);
  gl.BindTexture(GL_TEXTURE_2D, t.id());
  gl.TexImage2D(GL_TEXTURE_2D, 0, internal, w, h, 0, format, type, data);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

Result<Framebuffer> makeTargetFramebuffer(const GlApi& gl, GLuint color, GLuint depth, const std::string& what) {
  Framebuffer f = makeFramebuffer(gl);
  gl.BindFramebuffer(GL_FRAMEBUFFER, f.id());
  if (color) gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
  if (depth) gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
  if (!color) {
    gl.DrawBuffer(GL_NONE);
    gl.ReadBuffer(GL_NONE);
  }
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return Error(ErrorKind::Internal, "the " + what + " framebuffer is incomplete");
  return f;
}

Shader makeShader(const GlApi& gl, GLenum type) { return {gl, gl.CreateShader(type)}; }

Program makeProgram(const GlApi& gl) { return {gl, gl.CreateProgram()}; }

}  // namespace reel::gl
