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

Shader makeShader(const GlApi& gl, GLenum type) { return {gl, gl.CreateShader(type)}; }

Program makeProgram(const GlApi& gl) { return {gl, gl.CreateProgram()}; }

}  // namespace reel::gl
