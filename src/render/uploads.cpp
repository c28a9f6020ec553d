#include "render/uploads.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace reel {

namespace {

// A new VAO with attributes 0..2 (positions, normals, uvs) and the indices bound to its buffers.
void makeMeshObjects(const gl::GlApi& gl, GpuMesh& m) {
  m.vao = gl::makeVertexArray(gl);
  for (auto& b : m.vbo) b = gl::makeBuffer(gl);
  m.ebo = gl::makeBuffer(gl);
  gl.BindVertexArray(m.vao.id());
  for (GLuint a = 0; a < 3; ++a) {
    gl.BindBuffer(GL_ARRAY_BUFFER, m.vbo[a].id());
    gl.EnableVertexAttribArray(a);
    gl.VertexAttribPointer(a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  }
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ebo.id());
}

// One float per vertex at `attribute` when `values` has one for each of the nv vertices, else
// the attribute is left to its constant.
void perVertexFloat(const gl::GlApi& gl, const gl::Buffer& vbo, std::size_t& capacity, GLuint attribute,
                    const std::vector<float>& values, std::size_t nv) {
  if (values.size() != nv || nv == 0) {
    gl.DisableVertexAttribArray(attribute);
    return;
  }
  gl.BindBuffer(GL_ARRAY_BUFFER, vbo.id());
  const auto bytes = static_cast<GLsizeiptr>(nv * sizeof(float));
  if (nv > capacity)
    gl.BufferData(GL_ARRAY_BUFFER, bytes, values.data(), GL_DYNAMIC_DRAW);
  else
    gl.BufferSubData(GL_ARRAY_BUFFER, 0, bytes, values.data());
  gl.EnableVertexAttribArray(attribute);
  gl.VertexAttribPointer(attribute, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
  capacity = std::max(capacity, nv);
}

}  // namespace

void upload(const gl::GlApi& gl, GpuMesh& m, const TriMesh& t) {
  if (!m.vao) makeMeshObjects(gl, m);
  m.ground = groundPlane(t);
  gl.BindVertexArray(m.vao.id());
  const std::size_t nv = t.vertexCount();
  std::vector<float> uv_fallback;
  const std::vector<float>* uvs = &t.uvs;
  if (t.uvs.size() != 2 * nv) {
    uv_fallback.assign(2 * nv, 0.0f);
    uvs = &uv_fallback;
  }
  const std::vector<float>* src[4] = {&t.positions, &t.normals, uvs, &t.colors};
  const bool coloured = t.colors.size() == 3 * nv;
  // Attribute 5: per-vertex colours when the mesh has them, else the constant white set per frame.
  if (coloured) {
    gl.BindBuffer(GL_ARRAY_BUFFER, m.vbo[3].id());
    gl.EnableVertexAttribArray(5);
    gl.VertexAttribPointer(5, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  } else {
    gl.DisableVertexAttribArray(5);
  }
  // Vertex data and indices: reallocated when larger than before, else overwritten in place.
  for (std::size_t a = 0; a < (coloured ? 4u : 3u); ++a) {
    gl.BindBuffer(GL_ARRAY_BUFFER, m.vbo[a].id());
    const auto bytes = static_cast<GLsizeiptr>(src[a]->size() * sizeof(float));
    if (nv > (a == 3 ? m.capacity_c : m.capacity_v))
      gl.BufferData(GL_ARRAY_BUFFER, bytes, src[a]->data(), GL_DYNAMIC_DRAW);
    else
      gl.BufferSubData(GL_ARRAY_BUFFER, 0, bytes, src[a]->data());
  }
  const auto ibytes = static_cast<GLsizeiptr>(t.indices.size() * sizeof(std::uint32_t));
  if (t.indices.size() > m.capacity_i)
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, ibytes, t.indices.data(), GL_DYNAMIC_DRAW);
  else
    gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, ibytes, t.indices.data());
  m.capacity_v = std::max(m.capacity_v, nv);
  if (coloured) m.capacity_c = std::max(m.capacity_c, nv);
  // Attribute 11: per-vertex gloss, else the constant 0 set per frame; attribute 12: per-vertex
  // clarity, else the constant 1; attribute 13: per-vertex wrinkle weights, else 0.
  perVertexFloat(gl, m.vbo[4], m.capacity_g, 11, t.gloss, nv);
  perVertexFloat(gl, m.vbo[5], m.capacity_k, 12, t.clarity, nv);
  perVertexFloat(gl, m.vbo[6], m.capacity_w, 13, t.wrinkle, nv);
  m.capacity_i = std::max(m.capacity_i, t.indices.size());
  m.count = static_cast<GLsizei>(t.indices.size());
}

void StreamBuffer::fill(const gl::GlApi& gl, const std::vector<float>& data) {
  gl.BindBuffer(GL_ARRAY_BUFFER, buffer.id());
  const auto bytes = static_cast<GLsizeiptr>(data.size() * sizeof(float));
  if (data.size() > capacity) {
    gl.BufferData(GL_ARRAY_BUFFER, bytes, data.data(), GL_STREAM_DRAW);
    capacity = data.size();
  } else {
    gl.BufferSubData(GL_ARRAY_BUFFER, 0, bytes, data.data());
  }
}

void bindInstances(const gl::GlApi& gl, const GpuMesh& proto, StreamBuffer& inst, const std::vector<float>& data,
                   int floats_per_instance) {
  gl.BindVertexArray(proto.vao.id());
  inst.fill(gl, data);
  const GLsizei stride = floats_per_instance * static_cast<GLsizei>(sizeof(float));
  gl.EnableVertexAttribArray(3);
  gl.VertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  gl.VertexAttribDivisor(3, 1);
  if (floats_per_instance == 6) {
    gl.EnableVertexAttribArray(4);
    gl.VertexAttribPointer(4, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
    gl.VertexAttribDivisor(4, 1);
  }
}

void packInstances(const DrawInstances& d, const Vec3& eye, double far_distance,
                   std::array<std::vector<float>, 2>& out) {
  const std::size_t n = d.count();
  const bool tinted = d.colors.size() == 3 * n, waving = d.phases.size() == n;
  const bool lod = far_distance > 0;
  const double far2 = far_distance * far_distance;
  out[0].clear();
  out[1].clear();
  for (std::size_t i = 0; i < n; ++i) {
    const float* t = &d.transforms[12 * i];
    const Vec3 origin(t[9], t[10], t[11]);
    std::vector<float>& o = out[lod && (origin - eye).squaredNorm() > far2 ? 1 : 0];
    o.insert(o.end(), t, t + 12);
    if (tinted)
      o.insert(o.end(), &d.colors[3 * i], &d.colors[3 * i] + 3);
    else
      o.insert(o.end(), {1.0f, 1.0f, 1.0f});
    o.push_back(waving ? d.phases[i] : 0.0f);
  }
}

void bindMeshInstances(const gl::GlApi& gl, const GpuMesh& proto, const StreamBuffer& inst) {
  gl.BindVertexArray(proto.vao.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, inst.buffer.id());
  const GLsizei stride = kInstanceFloats * static_cast<GLsizei>(sizeof(float));
  for (GLuint a = 6; a <= 10; ++a) {
    const std::size_t offset = (a - 6) * 3 * sizeof(float);
    gl.EnableVertexAttribArray(a);
    gl.VertexAttribPointer(a, a == 10 ? 4 : 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(offset));
    gl.VertexAttribDivisor(a, 1);
  }
}

void MeshCache::forgetExpired() {
  std::erase_if(static_, [](const auto& kv) { return kv.second.first.expired(); });
  std::erase_if(prototypes_, [](const auto& kv) { return kv.second.first.expired(); });
}

GpuMesh& MeshCache::keep(StaticMeshes& cache, const std::shared_ptr<const TriMesh>& mesh) {
  auto& entry = cache[mesh.get()];
  if (entry.first.lock() != mesh) {  // new, or an old address reused by another mesh
    entry.first = mesh;
    upload(*gl_, entry.second, *mesh);
  }
  return entry.second;
}

const GpuMesh* MeshCache::prototype(const std::shared_ptr<const TriMesh>& mesh) {
  if (!mesh || mesh->indices.empty()) return nullptr;
  return &keep(prototypes_, mesh);
}

void MeshCache::prepare(const DrawList& list) {
  slots_.assign(list.meshes.size(), nullptr);
  std::size_t next = 0;  // the next per-frame slot
  for (std::size_t i = 0; i < list.meshes.size(); ++i) {
    const DrawMesh& m = list.meshes[i];
    if (!m.mesh || m.mesh->indices.empty()) continue;
    if (m.per_frame) {
      if (next >= per_frame_.size()) per_frame_.emplace_back();
      slots_[i] = &per_frame_[next++];
      upload(*gl_, *slots_[i], *m.mesh);
      continue;
    }
    slots_[i] = &keep(static_, m.mesh);
  }
}

void TextureCache::forgetExpired() {
  std::erase_if(textures_, [](const auto& kv) { return kv.second.first.expired(); });
}

void TextureCache::bind(const std::shared_ptr<const Image>& img, int unit, bool srgb) {
  auto& entry = textures_[{img.get(), srgb}];
  const GLenum texture_unit = GL_TEXTURE0 + static_cast<GLenum>(unit);
  if (entry.first.lock() != img) {
    entry.second.reset();  // an old image's texture at a reused address
    entry.first = img;
    entry.second = gl::makeTexture(*gl_);
    gl_->ActiveTexture(texture_unit);
    gl_->BindTexture(GL_TEXTURE_2D, entry.second.id());
    gl_->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // Rows from the top: v = 0 is the image's first row.
    if (srgb) {
      gl_->TexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, img->width, img->height, 0, GL_RGB, GL_UNSIGNED_BYTE, img->rgb.data());
    } else {
      // Data: the luminance as one float channel, so that filtering keeps its fractions (a bump
      // map's slopes are differences of filtered heights; in 8 bits they came out 15% short).
      std::vector<float> lum(static_cast<std::size_t>(img->width) * static_cast<std::size_t>(img->height));
      for (std::size_t k = 0; k < lum.size(); ++k) {
        const std::uint8_t* px = img->rgb.data() + 3 * k;
        lum[k] = (0.2126f * px[0] + 0.7152f * px[1] + 0.0722f * px[2]) / 255.0f;
      }
      gl_->TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, img->width, img->height, 0, GL_RED, GL_FLOAT, lum.data());
    }
    gl_->GenerateMipmap(GL_TEXTURE_2D);
    gl_->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl_->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl_->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl_->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  }
  gl_->ActiveTexture(texture_unit);
  gl_->BindTexture(GL_TEXTURE_2D, entry.second.id());
  gl_->ActiveTexture(GL_TEXTURE0);
}

}  // namespace reel
