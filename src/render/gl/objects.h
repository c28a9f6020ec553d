// RAII GL objects: each owns one GL name and deletes it through the GlApi it was made with.
// Move-only; a default-constructed or moved-from object holds 0 and deletes nothing.
// Deleting needs the owning context alive and current, so whoever holds these objects must be
// destroyed before its gl::Context (the Renderer's contract).
#pragma once

#include <string>
#include <utility>

#include "core/error.h"
#include "render/gl/api.h"

namespace reel::gl {

// One GL name and the function that deletes it.
template <void (*Delete)(const GlApi&, GLuint)>
class Object {
 public:
  Object() = default;
  Object(const GlApi& api, GLuint id) : api_(&api), id_(id) {}  // takes ownership of `id`
  ~Object() { reset(); }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  Object(Object&& o) noexcept : api_(o.api_), id_(std::exchange(o.id_, 0)) {}
  Object& operator=(Object&& o) noexcept {
    if (this != &o) {
      reset();
      api_ = o.api_;
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  // Deletes the object now; it then holds 0.
  void reset() {
    if (id_) Delete(*api_, std::exchange(id_, 0));
  }

 private:
  const GlApi* api_ = nullptr;
  GLuint id_ = 0;
};

void deleteBuffer(const GlApi& gl, GLuint id);
void deleteVertexArray(const GlApi& gl, GLuint id);
void deleteFramebuffer(const GlApi& gl, GLuint id);
void deleteRenderbuffer(const GlApi& gl, GLuint id);
void deleteTexture(const GlApi& gl, GLuint id);
void deleteSampler(const GlApi& gl, GLuint id);
void deleteShader(const GlApi& gl, GLuint id);
void deleteProgram(const GlApi& gl, GLuint id);

using Buffer = Object<deleteBuffer>;
using VertexArray = Object<deleteVertexArray>;
using Framebuffer = Object<deleteFramebuffer>;
using Renderbuffer = Object<deleteRenderbuffer>;
using Texture = Object<deleteTexture>;
using Sampler = Object<deleteSampler>;
using Shader = Object<deleteShader>;
using Program = Object<deleteProgram>;

// New, unbound objects (glGen*, glCreate*).
Buffer makeBuffer(const GlApi& gl);
VertexArray makeVertexArray(const GlApi& gl);
Framebuffer makeFramebuffer(const GlApi& gl);
Renderbuffer makeRenderbuffer(const GlApi& gl);
Texture makeTexture(const GlApi& gl);
Sampler makeSampler(const GlApi& gl);
// A w x h texture of one level, `internal` format, `filter` both ways, clamped at the edges:
// without `data` a render target (depths, occlusion, copies of the picture), with it a table the
// shaders read (`data` in `format` and `type`). Left bound to GL_TEXTURE_2D.
Texture makeTargetTexture(const GlApi& gl, int w, int h, GLint internal, GLenum format, GLenum type, GLint filter,
                          const void* data = nullptr);
// A framebuffer drawing into these textures (0: none; without colour it draws depth only),
// checked complete; the error names `what`. Left bound.
Result<Framebuffer> makeTargetFramebuffer(const GlApi& gl, GLuint color, GLuint depth, const std::string& what);
Shader makeShader(const GlApi& gl, GLenum type);
Program makeProgram(const GlApi& gl);

}  // namespace reel::gl
