// What the renderer copies to the GPU: meshes (the DrawList's and the instancing prototypes),
// per-draw instance data, and textures. Each copy lives in RAII GL objects, deleted with it.
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "core/drawlist.h"
#include "render/gl/objects.h"
#include "render/projection.h"

namespace reel {

// A triangle mesh on the GPU: attributes 0..2 (and 5 when coloured) and the indices, in one VAO.
struct GpuMesh {
  gl::VertexArray vao;
  std::array<gl::Buffer, 7> vbo;  // positions, normals, uvs, colours, gloss, clarity, wrinkle
  gl::Buffer ebo;
  GLsizei count = 0;  // indices
  // vertices, indices, coloured, glossy, clarity, wrinkle
  std::size_t capacity_v = 0, capacity_i = 0, capacity_c = 0, capacity_g = 0, capacity_k = 0, capacity_w = 0;
  GroundPlane ground;  // the mesh as a flat ground, found at upload (the shadow maps leave it out where it hides nothing)
};

// Copies `t` into `m`: makes the VAO and buffers on first use, grows them when `t` is larger,
// else overwrites in place.
void upload(const gl::GlApi& gl, GpuMesh& m, const TriMesh& t);

// An array buffer refilled for every draw (instance data), grown when the data is larger.
struct StreamBuffer {
  gl::Buffer buffer;
  std::size_t capacity = 0;  // floats
  // Binds the buffer to GL_ARRAY_BUFFER and fills it with `data`.
  void fill(const gl::GlApi& gl, const std::vector<float>& data);
};

// Streams `data` into `inst` and binds it to attributes 3 (and 4 with 6 floats per instance) of
// a prototype's VAO, one step per instance.
void bindInstances(const gl::GlApi& gl, const GpuMesh& proto, StreamBuffer& inst, const std::vector<float>& data,
                   int floats_per_instance);

// The copies of one DrawInstances for one level of detail, packed for attributes 6..10: per copy
// 16 floats, the transform's X, Y, Z and origin (12), the tint (3, white without `colors`) and the
// wave phase (1, 0 without `phases`).
inline constexpr int kInstanceFloats = 16;

// Splits d's copies by level of detail, each part in the DrawList's order: out[1] has the copies
// whose origin is farther than `far_distance` from `eye` (none when far_distance <= 0), out[0]
// the others.
void packInstances(const DrawInstances& d, const Vec3& eye, double far_distance,
                   std::array<std::vector<float>, 2>& out);

// Binds `inst` (packed as above) to attributes 6..10 of a prototype's VAO, one step per instance.
void bindMeshInstances(const gl::GlApi& gl, const GpuMesh& proto, const StreamBuffer& inst);

// The DrawList's meshes on the GPU: static ones keep their copy while their owner lives,
// per-frame ones are uploaded into reused slots every frame; the prototypes of instanced meshes
// likewise, in their own VAOs (which carry the instance attributes).
class MeshCache {
 public:
  explicit MeshCache(const gl::GlApi& gl) : gl_(&gl) {}
  // Deletes the copies of static meshes whose owners are gone.
  void forgetExpired();
  // Uploads what the frame needs; afterwards slot(i) is list.meshes[i]'s copy (null: nothing to draw).
  void prepare(const DrawList& list);
  const GpuMesh* slot(std::size_t i) const { return slots_[i]; }
  // The copy of an instancing prototype, uploaded on first use; null for an empty mesh.
  const GpuMesh* prototype(const std::shared_ptr<const TriMesh>& mesh);

 private:
  const gl::GlApi* gl_;
  // Static meshes and prototypes by address; the weak pointer tells a live owner from a reused address.
  using StaticMeshes = std::map<const TriMesh*, std::pair<std::weak_ptr<const TriMesh>, GpuMesh>>;
  StaticMeshes static_, prototypes_;
  GpuMesh& keep(StaticMeshes& cache, const std::shared_ptr<const TriMesh>& mesh);
  std::deque<GpuMesh> per_frame_;  // deque: slots stay valid as it grows
  std::vector<GpuMesh*> slots_;    // list.meshes[i]'s copy, into static_ or per_frame_
};

// Textures on the GPU once while their image lives, mipmapped: colours sRGB-encoded, decoded to
// linear by the sampler (GL_SRGB8); data (a bump map's heights): the luminance as stored, 0..1,
// one float channel (GL_R32F).
class TextureCache {
 public:
  explicit TextureCache(const gl::GlApi& gl) : gl_(&gl) {}
  // Deletes the textures whose images are gone.
  void forgetExpired();
  // Binds the image's texture to `unit`, uploading it first if needed; srgb: colours (decoded),
  // else data. One image may be bound both ways (a texture that is also its own bump map).
  void bind(const std::shared_ptr<const Image>& img, int unit = 0, bool srgb = true);

 private:
  const gl::GlApi* gl_;
  // By image address and encoding; the weak pointer tells a live owner from a reused address.
  std::map<std::pair<const Image*, bool>, std::pair<std::weak_ptr<const Image>, gl::Texture>> textures_;
};

}  // namespace reel
