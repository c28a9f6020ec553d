#include "render/gl/objects.h"

namespace reel::gl {

void deleteBuffer(const GlApi& gl, GLuint id) { gl.DeleteBuffers(1, &id); }
void deleteVertexArray(const GlApi& gl, GLuint id) { gl.DeleteVertexArrays(1, &id); }
void deleteFramebuffer(const GlApi& gl, GLuint id) { gl.DeleteFramebuffers(1, &id); }
void deleteRenderbuffer(const GlApi& gl, GLuint id) { gl.DeleteRenderbuffers(1, &id); }
void deleteTexture(const GlApi& gl, GLuint id) { gl.DeleteTextures(1, &id); }
void deleteShader(const GlApi& gl, GLuint id) { gl.DeleteShader(id); }
void deleteProgram(const GlApi& gl, GLuint id) { gl.DeleteProgram(id); }

Buffer makeBuffer(const GlApi& gl) {
  GLuint id = 0;
  gl.GenBuffers(1, &id);
  return {gl, id};
}

VertexArray makeVertexArray(const GlApi& gl) {
  GLuint id = 0;
  gl.GenVertexArrays(1, &id);
  return {gl, id};
}

Framebuffer makeFramebuffer(const GlApi& gl) {
  GLuint id = 0;
  gl.GenFramebuffers(1, &id);
  return {gl, id};
}

Renderbuffer makeRenderbuffer(const GlApi& gl) {
  GLuint id = 0;
  gl.GenRenderbuffers(1, &id);
  return {gl, id};
}

Texture makeTexture(const GlApi& gl) {
  GLuint id = 0;
  gl.GenTextures(1, &id);
  return {gl, id};
}

Shader makeShader(const GlApi& gl, GLenum type) { return {gl, gl.CreateShader(type)}; }

Program makeProgram(const GlApi& gl) { return {gl, gl.CreateProgram()}; }

}  // namespace reel::gl
