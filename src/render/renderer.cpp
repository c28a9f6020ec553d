#include "render/renderer.h"

#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <array>
#include <deque>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/math.h"

namespace reel {

using Mat4f = Eigen::Matrix4f;
using Vec3f = Eigen::Vector3f;

namespace {

Mat4f lookAt(const Vec3& eye, const Vec3& target, const Vec3& up_hint) {
  const Vec3 f = (target - eye).normalized();
  Vec3 s = f.cross(up_hint);
  if (s.norm() < 1e-9) s = f.cross(std::abs(f.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitZ());
  s.normalize();
  const Vec3 u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m.cast<float>();
}

Mat4f perspective(double fovy_deg, double aspect, double n, double f) {
  const double t = 1.0 / std::tan(fovy_deg * kPi / 360.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2 * f * n / (n - f);
  m(3, 2) = -1;
  return m.cast<float>();
}

Mat4f ortho(double r, double n, double f) {  // symmetric box of half-size r
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 1 / r;
  m(1, 1) = 1 / r;
  m(2, 2) = -2 / (f - n);
  m(2, 3) = -(f + n) / (f - n);
  return m.cast<float>();
}

bool readText(const std::string& path, std::string& out) {
  std::ifstream in(path);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

struct GpuMesh {
  GLuint vao = 0, vbo[4] = {0, 0, 0, 0}, ebo = 0;  // positions, normals, uvs, colours
  GLsizei count = 0;
  std::size_t capacity_v = 0, capacity_i = 0, capacity_c = 0;  // vertices, indices, coloured vertices
};

}  // namespace

std::string findShaderDir() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("REEL_SHADERS"); env && *env) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path& p : {exe.parent_path() / "../share/reel/shaders", fs::path(REEL_SHADER_DIR)})
    if (fs::exists(p / "surface.frag", ec)) return fs::weakly_canonical(p, ec).string();
  return REEL_SHADER_DIR;
}

struct Renderer::Impl {
  gl::Context* ctx = nullptr;
  const gl::GlApi* gl = nullptr;
  RenderSettings set;
  GLuint shadow = 0, background = 0, empty_vao = 0;
  std::string shader_dir;
  // Surface shader variants by their #define header; `frame` marks the frame whose uniforms a
  // variant holds.
  struct Variant {
    GLuint id = 0;
    long long frame = -1;
  };
  std::map<std::string, Variant> variants;
  long long frame_no = 0;
  std::string frame_defines;  // LIGHTS, FOG, ACES of the current frame
  struct FrameUniforms {
    Mat4f view_proj;
    Vec3f eye;
    std::array<float, 24> light_vec{}, light_rad{};
    std::array<Mat4f, 2> shadow_mats{};
    Vec3f fog_color;
    float fog_density = 0;
  } fu;
  GLuint current = 0;  // the surface variant in use
  GLuint msaa_fbo = 0, msaa_color = 0, msaa_depth = 0, resolve_fbo = 0, resolve_color = 0;
  std::array<GLuint, 2> shadow_fbo{}, shadow_tex{};
  std::array<GpuMesh, 3> sphere_lod;  // coarse, medium, fine prototypes
  GpuMesh tube_proto;
  GLuint line_vao = 0, line_vbo = 0;
  double px_per_m_at_1m = 1.0;  // pixels per metre at 1 m from the camera (LOD choice)
  Vec3 eye{0, 0, 0};
  GLuint inst_vbo = 0, inst_color_vbo = 0;
  std::size_t inst_capacity = 0, inst_color_capacity = 0;
  std::map<const TriMesh*, std::pair<std::weak_ptr<const TriMesh>, GpuMesh>> static_meshes;
  std::deque<GpuMesh> dynamic_meshes;
  std::map<const Image*, std::pair<std::weak_ptr<const Image>, GLuint>> textures;  // deque: slots stay valid as it grows
  std::map<std::string, GLint> uniform_cache;
  std::vector<std::uint8_t> readback;

  ~Impl() { release(); }

  void release() {
    if (!gl) return;
    auto delMesh = [&](GpuMesh& m) {
      if (m.vao) gl->DeleteVertexArrays(1, &m.vao);
      gl->DeleteBuffers(4, m.vbo);
      if (m.ebo) gl->DeleteBuffers(1, &m.ebo);
      m = GpuMesh{};
    };
    for (auto& [k, v] : static_meshes) delMesh(v.second);
    for (auto& [k, v] : textures) gl->DeleteTextures(1, &v.second);
    for (auto& m : dynamic_meshes) delMesh(m);
    for (auto& m : sphere_lod) delMesh(m);
    delMesh(tube_proto);
    if (inst_vbo) gl->DeleteBuffers(1, &inst_vbo);
    if (inst_color_vbo) gl->DeleteBuffers(1, &inst_color_vbo);
    if (line_vbo) gl->DeleteBuffers(1, &line_vbo);
    if (line_vao) gl->DeleteVertexArrays(1, &line_vao);
    for (GLuint p : {shadow, background})
      if (p) gl->DeleteProgram(p);
    for (auto& [k, v] : variants) gl->DeleteProgram(v.id);
    if (empty_vao) gl->DeleteVertexArrays(1, &empty_vao);
    GLuint fbos[] = {msaa_fbo, resolve_fbo, shadow_fbo[0], shadow_fbo[1]};
    gl->DeleteFramebuffers(4, fbos);
    GLuint rbs[] = {msaa_color, msaa_depth, resolve_color};
    gl->DeleteRenderbuffers(3, rbs);
    gl->DeleteTextures(2, shadow_tex.data());
    gl = nullptr;
  }

  Result<GLuint> compile(GLenum type, const std::string& src, const std::string& name) {
    GLuint sh = gl->CreateShader(type);
    const char* p = src.c_str();
    gl->ShaderSource(sh, 1, &p, nullptr);
    gl->CompileShader(sh);
    GLint ok = 0;
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[4096];
      gl->GetShaderInfoLog(sh, sizeof log, nullptr, log);
      gl->DeleteShader(sh);
      return Error(ErrorKind::Internal, "shader " + name + " does not compile: " + log);
    }
    return sh;
  }

  Result<GLuint> program(const std::string& dir, const std::string& vs, const std::string& fs,
                         bool with_geometry, const std::string& defines = "") {
    std::string vsrc, fsrc, geo;
    if (!readText(dir + "/" + vs, vsrc) || !readText(dir + "/" + fs, fsrc) ||
        (with_geometry && !readText(dir + "/geometry.glsl", geo)))
      return Error(ErrorKind::Internal, "shaders not found in " + dir + " (set REEL_SHADERS)");
    const std::string head = "#version 330 core\n";
    auto v = compile(GL_VERTEX_SHADER, head + geo + vsrc, vs);
    if (!v.ok()) return v.error();
    auto f = compile(GL_FRAGMENT_SHADER, head + defines + fsrc, fs);
    if (!f.ok()) return f.error();
    GLuint p = gl->CreateProgram();
    gl->AttachShader(p, v.value());
    gl->AttachShader(p, f.value());
    gl->LinkProgram(p);
    gl->DeleteShader(v.value());
    gl->DeleteShader(f.value());
    GLint ok = 0;
    gl->GetProgramiv(p, GL_LINK_STATUS, &ok);  // (attribute 5 is a_color in every program)
    if (!ok) {
      char log[4096];
      gl->GetProgramInfoLog(p, sizeof log, nullptr, log);
      return Error(ErrorKind::Internal, "shaders " + vs + " + " + fs + " do not link: " + log);
    }
    return p;
  }

  GLint loc(GLuint prog, const char* name) {
    const std::string key = std::to_string(prog) + ":" + name;
    auto it = uniform_cache.find(key);
    if (it != uniform_cache.end()) return it->second;
    const GLint l = gl->GetUniformLocation(prog, name);
    uniform_cache[key] = l;
    return l;
  }

  void upload(GpuMesh& m, const TriMesh& t) {
    if (!m.vao) {
      gl->GenVertexArrays(1, &m.vao);
      gl->GenBuffers(4, m.vbo);
      gl->GenBuffers(1, &m.ebo);
      gl->BindVertexArray(m.vao);
      for (GLuint a = 0; a < 3; ++a) {
        gl->BindBuffer(GL_ARRAY_BUFFER, m.vbo[a]);
        gl->EnableVertexAttribArray(a);
        gl->VertexAttribPointer(a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      }
      gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ebo);
    }
    gl->BindVertexArray(m.vao);
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
      gl->BindBuffer(GL_ARRAY_BUFFER, m.vbo[3]);
      gl->EnableVertexAttribArray(5);
      gl->VertexAttribPointer(5, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    } else {
      gl->DisableVertexAttribArray(5);
    }
    for (int a = 0; a < (coloured ? 4 : 3); ++a) {
      gl->BindBuffer(GL_ARRAY_BUFFER, m.vbo[a]);
      const auto bytes = static_cast<GLsizeiptr>(src[a]->size() * sizeof(float));
      if (nv > (a == 3 ? m.capacity_c : m.capacity_v))
        gl->BufferData(GL_ARRAY_BUFFER, bytes, src[a]->data(), GL_DYNAMIC_DRAW);
      else
        gl->BufferSubData(GL_ARRAY_BUFFER, 0, bytes, src[a]->data());
    }
    const auto ibytes = static_cast<GLsizeiptr>(t.indices.size() * sizeof(std::uint32_t));
    if (t.indices.size() > m.capacity_i)
      gl->BufferData(GL_ELEMENT_ARRAY_BUFFER, ibytes, t.indices.data(), GL_DYNAMIC_DRAW);
    else
      gl->BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, ibytes, t.indices.data());
    m.capacity_v = std::max(m.capacity_v, nv);
    if (coloured) m.capacity_c = std::max(m.capacity_c, nv);
    m.capacity_i = std::max(m.capacity_i, t.indices.size());
    m.count = static_cast<GLsizei>(t.indices.size());
  }

  // Binds the instance buffer to attributes 3 (and 4) of a prototype's VAO.
  void instances(GpuMesh& proto, const std::vector<float>& data, int floats_per_instance) {
    gl->BindVertexArray(proto.vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, inst_vbo);
    const auto bytes = static_cast<GLsizeiptr>(data.size() * sizeof(float));
    if (data.size() > inst_capacity) {
      gl->BufferData(GL_ARRAY_BUFFER, bytes, data.data(), GL_STREAM_DRAW);
      inst_capacity = data.size();
    } else {
      gl->BufferSubData(GL_ARRAY_BUFFER, 0, bytes, data.data());
    }
    const GLsizei stride = floats_per_instance * static_cast<GLsizei>(sizeof(float));
    gl->EnableVertexAttribArray(3);
    gl->VertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    gl->VertexAttribDivisor(3, 1);
    if (floats_per_instance == 6) {
      gl->EnableVertexAttribArray(4);
      gl->VertexAttribPointer(4, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
      gl->VertexAttribDivisor(4, 1);
    }
  }

  Status init(const std::string& dir) {
    shader_dir = dir;
    // Compile the richest surface variant now, so a broken shader fails here, not mid-film.
    frame_defines = "#define LIGHTS c += DIRECTIONAL_SHADOW(0, 0); c += POINT_SHADOW(1, 1); c += AMBIENT(2);\n"
                    "#define FOG\n#define ACES\n";
    DrawMaterial probe;
    probe.specular = 1;
    probe.double_sided = probe.checker = true;
    if (Status st = useSurface(probe); !st) return st;
    auto sh = program(dir, "shadow.vert", "shadow.frag", true);
    if (!sh.ok()) return sh.error();
    shadow = sh.value();
    auto bg = program(dir, "background.vert", "background.frag", false);
    if (!bg.ok()) return bg.error();
    background = bg.value();
    gl->GenVertexArrays(1, &empty_vao);
    gl->GenBuffers(1, &inst_vbo);
    gl->GenBuffers(1, &inst_color_vbo);
    // Spheres a few pixels wide need few triangles: llvmpipe's cost is per triangle.
    upload(sphere_lod[0], makeUvSphere(1.0, 8, 5));
    upload(sphere_lod[1], makeUvSphere(1.0, 14, 8));
    upload(sphere_lod[2], makeUvSphere(1.0, 28, 16));
    upload(tube_proto, makeTube(6));
    gl->GenVertexArrays(1, &line_vao);
    gl->GenBuffers(1, &line_vbo);
    gl->BindVertexArray(line_vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, line_vbo);
    gl->EnableVertexAttribArray(0);
    gl->VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);

    // Multisampled colour + depth, resolved into a single-sample colour buffer.
    const GLsizei samples = set.samples > 1 ? set.samples : 0;
    gl->GenRenderbuffers(1, &msaa_color);
    gl->BindRenderbuffer(GL_RENDERBUFFER, msaa_color);
    gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, set.width, set.height);
    gl->GenRenderbuffers(1, &msaa_depth);
    gl->BindRenderbuffer(GL_RENDERBUFFER, msaa_depth);
    gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, set.width, set.height);
    gl->GenFramebuffers(1, &msaa_fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_color);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_depth);
    if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      return Error(ErrorKind::Internal, "the multisampled framebuffer is incomplete");
    gl->GenRenderbuffers(1, &resolve_color);
    gl->BindRenderbuffer(GL_RENDERBUFFER, resolve_color);
    gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_RGBA8, set.width, set.height);
    gl->GenFramebuffers(1, &resolve_fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
    gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color);
    if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      return Error(ErrorKind::Internal, "the resolve framebuffer is incomplete");

    // Shadow maps: depth textures compared in the shader (hardware PCF where there is one).
    gl->GenTextures(2, shadow_tex.data());
    gl->GenFramebuffers(2, shadow_fbo.data());
    for (int i = 0; i < 2; ++i) {
      gl->BindTexture(GL_TEXTURE_2D, shadow_tex[i]);
      gl->TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, set.shadow_map_size, set.shadow_map_size, 0,
                     GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
      gl->BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo[i]);
      gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_tex[i], 0);
      gl->DrawBuffer(GL_NONE);
      gl->ReadBuffer(GL_NONE);
      if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return Error(ErrorKind::Internal, "the shadow framebuffer is incomplete");
    }
    if (GLenum e = gl->GetError(); e != GL_NO_ERROR)
      return Error(ErrorKind::Internal, "OpenGL error " + std::to_string(e) + " while setting up the renderer");
    return {};
  }

  // The scene's bounding sphere from everything but unbounded planes.
  void bounds(const DrawList& list, Vec3& center, double& radius) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    auto add = [&](const float* p) {
      const Vec3 q(p[0], p[1], p[2]);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    };
    for (const auto& m : list.meshes) {
      if (!m.mesh || m.mesh->vertexCount() == 0) continue;
      const auto& pos = m.mesh->positions;
      Vec3 mlo = Vec3::Constant(1e300), mhi = Vec3::Constant(-1e300);
      for (std::size_t i = 0; i + 2 < pos.size(); i += 3) {
        const Vec3 q(pos[i], pos[i + 1], pos[i + 2]);
        mlo = mlo.cwiseMin(q);
        mhi = mhi.cwiseMax(q);
      }
      if ((mhi - mlo).norm() > 100.0) continue;  // a ground plane: it receives, it does not bound
      lo = lo.cwiseMin(mlo);
      hi = hi.cwiseMax(mhi);
    }
    for (const auto& s : list.spheres)
      for (std::size_t i = 0; i + 2 < s.centers.size(); i += 3) add(&s.centers[i]);
    for (const auto& t : list.tubes)
      for (std::size_t i = 0; i + 2 < t.ends.size(); i += 3) add(&t.ends[i]);
    if (lo.x() > hi.x()) {
      center = list.camera.target;
      radius = 5.0;
      return;
    }
    center = (lo + hi) / 2;
    radius = std::max(0.5 * (hi - lo).norm(), 0.1) * 1.05;
  }

  // A texture to GPU once while its owner lives; sRGB-encoded pixels are decoded to linear by
  // the sampler (GL_SRGB8), mipmapped.
  void bindTexture(const std::shared_ptr<const Image>& img) {
    auto& entry = textures[img.get()];
    if (entry.first.lock() != img) {
      if (entry.second) gl->DeleteTextures(1, &entry.second);
      entry.first = img;
      gl->GenTextures(1, &entry.second);
      gl->ActiveTexture(GL_TEXTURE0);
      gl->BindTexture(GL_TEXTURE_2D, entry.second);
      gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
      // Rows from the top: v = 0 is the image's first row.
      gl->TexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, img->width, img->height, 0, GL_RGB, GL_UNSIGNED_BYTE, img->rgb.data());
      gl->GenerateMipmap(GL_TEXTURE_2D);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
      gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    }
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, entry.second);
  }

  // Binds the surface variant for a material (compiling it on first use), uploads the frame's
  // uniforms to it once per frame, then the material's.
  Status useSurface(const DrawMaterial& m) {
    std::string key = frame_defines;
    if (m.specular > 0) key += "#define SPECULAR\n";
    if (m.double_sided) key += "#define DOUBLE_SIDED\n";
    if (m.checker) key += "#define CHECKER\n";
    if (m.texture) key += "#define TEXTURED\n";
    auto it = variants.find(key);
    if (it == variants.end()) {
      auto p = program(shader_dir, "surface.vert", "surface.frag", true, key);
      if (!p.ok()) return p.error();
      it = variants.emplace(key, Variant{p.value(), -1}).first;
    }
    const GLuint prog = it->second.id;
    if (current != prog) {
      gl->UseProgram(prog);
      current = prog;
    }
    if (it->second.frame != frame_no) {
      it->second.frame = frame_no;
      gl->UniformMatrix4fv(loc(prog, "u_view_proj"), 1, GL_FALSE, fu.view_proj.data());
      gl->Uniform3f(loc(prog, "u_eye"), fu.eye.x(), fu.eye.y(), fu.eye.z());
      gl->Uniform3fv(loc(prog, "u_light_vec"), 8, fu.light_vec.data());
      gl->Uniform3fv(loc(prog, "u_light_radiance"), 8, fu.light_rad.data());
      gl->Uniform1i(loc(prog, "u_shadow_map0"), 1);
      gl->Uniform1i(loc(prog, "u_shadow_map1"), 2);
      gl->UniformMatrix4fv(loc(prog, "u_shadow_matrix"), 2, GL_FALSE, fu.shadow_mats[0].data());
      gl->Uniform1f(loc(prog, "u_shadow_texel"), 1.0f / float(set.shadow_map_size));
      gl->Uniform1i(loc(prog, "u_texture"), 0);
      gl->Uniform3f(loc(prog, "u_fog_color"), fu.fog_color.x(), fu.fog_color.y(), fu.fog_color.z());
      gl->Uniform1f(loc(prog, "u_fog_density"), fu.fog_density);
    }
    if (m.texture) bindTexture(m.texture);
    gl->Uniform3f(loc(prog, "u_color"), float(m.color.x()), float(m.color.y()), float(m.color.z()));
    gl->Uniform1f(loc(prog, "u_specular"), float(m.specular));
    gl->Uniform1f(loc(prog, "u_shininess"), float(m.shininess));
    gl->Uniform1f(loc(prog, "u_opacity"), float(m.opacity));
    return {};
  }

  // Meshes to GPU once per frame: static ones keep their copy while their owner lives, dynamic
  // ones are uploaded into per-slot buffers every frame. slots[i] is list.meshes[i]'s copy.
  std::vector<GpuMesh*> slots;
  void prepare(const DrawList& list) {
    // Forget static meshes whose owners are gone.
    for (auto it = static_meshes.begin(); it != static_meshes.end();) {
      if (it->second.first.expired()) {
        GpuMesh& g = it->second.second;
        if (g.vao) gl->DeleteVertexArrays(1, &g.vao);
        gl->DeleteBuffers(4, g.vbo);
        if (g.ebo) gl->DeleteBuffers(1, &g.ebo);
        it = static_meshes.erase(it);
      } else {
        ++it;
      }
    }
    for (auto it = textures.begin(); it != textures.end();) {
      if (it->second.first.expired()) {
        gl->DeleteTextures(1, &it->second.second);
        it = textures.erase(it);
      } else {
        ++it;
      }
    }
    slots.assign(list.meshes.size(), nullptr);
    std::size_t dyn = 0;
    for (std::size_t i = 0; i < list.meshes.size(); ++i) {
      const DrawMesh& m = list.meshes[i];
      if (!m.mesh || m.mesh->indices.empty()) continue;
      if (m.per_frame) {
        if (dyn >= dynamic_meshes.size()) dynamic_meshes.emplace_back();
        slots[i] = &dynamic_meshes[dyn++];
        upload(*slots[i], *m.mesh);
        continue;
      }
      auto& entry = static_meshes[m.mesh.get()];
      slots[i] = &entry.second;
      if (entry.first.lock() != m.mesh) {  // new, or an old address reused by another mesh
        entry.first = m.mesh;
        upload(entry.second, *m.mesh);
      }
    }
  }

  // Draws all geometry: with the shadow program bound (with_material false), or each item with
  // its material's surface variant.
  Status drawGeometry(const DrawList& list, bool with_material, bool transparent) {
    auto bind = [&](const DrawMaterial& m) -> Status {
      if (!with_material) return {};
      return useSurface(m);
    };
    auto prog = [&] { return with_material ? current : shadow; };
    auto want = [&](const DrawMaterial& m) { return !with_material || (m.opacity < 1.0) == transparent; };
    for (std::size_t i = 0; i < list.meshes.size(); ++i) {
      const DrawMesh& m = list.meshes[i];
      if (!slots[i] || !want(m.material)) continue;
      if (Status st = bind(m.material); !st) return st;
      gl->Uniform1i(loc(prog(), "u_mode"), 0);
      gl->BindVertexArray(slots[i]->vao);
      gl->DrawElements(GL_TRIANGLES, slots[i]->count, GL_UNSIGNED_INT, nullptr);
    }
    for (const auto& s : list.spheres) {
      if (s.centers.empty() || !want(s.material)) continue;
      // Level of detail from the largest on-screen radius of the set.
      double nearest = 1e300;
      for (std::size_t i = 0; i + 2 < s.centers.size(); i += 3)
        nearest = std::min(nearest, (Vec3(s.centers[i], s.centers[i + 1], s.centers[i + 2]) - eye).norm());
      const double px = s.radius * px_per_m_at_1m / std::max(nearest, 1e-3);
      GpuMesh& proto = sphere_lod[px < 5 ? 0 : px < 20 ? 1 : 2];
      instances(proto, s.centers, 3);
      // Per-sphere colours (a liquid's species blended): attribute 5 advances per instance.
      const bool coloured = with_material && s.colors.size() == s.centers.size();
      if (coloured) {
        gl->BindBuffer(GL_ARRAY_BUFFER, inst_color_vbo);
        const auto bytes = static_cast<GLsizeiptr>(s.colors.size() * sizeof(float));
        if (s.colors.size() > inst_color_capacity) {
          gl->BufferData(GL_ARRAY_BUFFER, bytes, s.colors.data(), GL_STREAM_DRAW);
          inst_color_capacity = s.colors.size();
        } else {
          gl->BufferSubData(GL_ARRAY_BUFFER, 0, bytes, s.colors.data());
        }
        gl->EnableVertexAttribArray(5);
        gl->VertexAttribPointer(5, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        gl->VertexAttribDivisor(5, 1);
      }
      if (Status st = bind(s.material); !st) return st;
      gl->Uniform1i(loc(prog(), "u_mode"), 1);
      gl->Uniform1f(loc(prog(), "u_radius"), s.radius);
      gl->DrawElementsInstanced(GL_TRIANGLES, proto.count, GL_UNSIGNED_INT, nullptr,
                                static_cast<GLsizei>(s.centers.size() / 3));
      if (coloured) {  // the prototype is shared: back to the constant white
        gl->BindVertexArray(proto.vao);
        gl->VertexAttribDivisor(5, 0);
        gl->DisableVertexAttribArray(5);
      }
    }
    for (const auto& t : list.tubes) {
      if (t.ends.empty() || !want(t.material)) continue;
      double nearest = 1e300;
      for (std::size_t i = 0; i + 2 < t.ends.size(); i += 3)
        nearest = std::min(nearest, (Vec3(t.ends[i], t.ends[i + 1], t.ends[i + 2]) - eye).norm());
      if (t.radius * px_per_m_at_1m / std::max(nearest, 1e-3) < 1.5) {
        if (!with_material) continue;  // a one-pixel line casts no shadow worth its stripes
        // Tubes about a pixel wide: one-pixel lines look the same, and long thin triangles are
        // llvmpipe's slowest case.
        gl->BindVertexArray(line_vao);
        gl->BindBuffer(GL_ARRAY_BUFFER, line_vbo);
        gl->BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(t.ends.size() * sizeof(float)), t.ends.data(),
                       GL_STREAM_DRAW);
        gl->VertexAttrib3f(1, 0.0f, 1.0f, 0.0f);  // lit as facing up
        gl->VertexAttrib2f(2, 0.0f, 0.0f);
        if (Status st = bind(t.material); !st) return st;
        gl->Uniform1i(loc(prog(), "u_mode"), 0);
        gl->BindVertexArray(line_vao);
        gl->DrawArrays(GL_LINES, 0, static_cast<GLsizei>(t.ends.size() / 3));
        continue;
      }
      instances(tube_proto, t.ends, 6);
      if (Status st = bind(t.material); !st) return st;
      gl->Uniform1i(loc(prog(), "u_mode"), 2);
      gl->Uniform1f(loc(prog(), "u_radius"), t.radius);
      gl->DrawElementsInstanced(GL_TRIANGLES, tube_proto.count, GL_UNSIGNED_INT, nullptr,
                                static_cast<GLsizei>(t.ends.size() / 6));
    }
    return {};
  }

  Status draw(const DrawList& list, Image& out) {
    const int W = set.width, H = set.height;
    Vec3 center;
    double radius;
    bounds(list, center, radius);
    prepare(list);
    this->eye = list.camera.position;
    px_per_m_at_1m = 0.5 * H / std::tan(list.camera.fov_deg * kPi / 360.0);

    // Shadow passes: an orthographic map along a directional light, a perspective map from a
    // point light, each fitted to the scene's bounding sphere.
    std::vector<int> light_shadow(list.lights.size(), -1);
    std::array<Mat4f, 2> shadow_mats{};
    int shadows = 0;
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LESS);
    gl->Disable(GL_CULL_FACE);
    for (std::size_t i = 0; i < list.lights.size() && shadows < 2; ++i) {
      const LightDesc& l = list.lights[i];
      if (!l.shadows || l.kind == LightKind::Ambient) continue;
      Mat4f vp;
      if (l.kind == LightKind::Directional) {
        const Vec3 d = l.direction.normalized();
        const Vec3 from = center - d * (radius * 2.0);
        vp = ortho(radius, radius * 0.5, radius * 3.5) * lookAt(from, center, Vec3::UnitY());
      } else {
        const double dist = std::max((l.position - center).norm(), radius * 1.01);
        const double half = std::asin(std::min(radius / dist, 0.99));
        vp = perspective(2 * half * 180 / kPi, 1.0, std::max(dist - radius, 0.05), dist + radius) *
             lookAt(l.position, center, Vec3::UnitY());
      }
      gl->BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo[shadows]);
      gl->Viewport(0, 0, set.shadow_map_size, set.shadow_map_size);
      gl->ClearDepth(1.0);
      gl->Clear(GL_DEPTH_BUFFER_BIT);
      gl->UseProgram(shadow);
      gl->UniformMatrix4fv(loc(shadow, "u_view_proj"), 1, GL_FALSE, vp.data());
      gl->Enable(GL_POLYGON_OFFSET_FILL);
      gl->PolygonOffset(1.5f, 2.0f);
      if (Status st = drawGeometry(list, false, false); !st) return st;
      gl->Disable(GL_POLYGON_OFFSET_FILL);
      Mat4f bias = Mat4f::Identity();  // clip space [-1, 1] → texture space [0, 1]
      bias.block<3, 3>(0, 0) *= 0.5f;
      bias.block<3, 1>(0, 3) = Vec3f::Constant(0.5f);
      shadow_mats[static_cast<std::size_t>(shadows)] = bias * vp;
      light_shadow[i] = shadows++;
    }

    // Main pass.
    gl->BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo);
    gl->Viewport(0, 0, W, H);
    gl->ClearDepth(1.0);
    gl->Clear(GL_DEPTH_BUFFER_BIT);
    gl->VertexAttrib3f(5, 1.0f, 1.0f, 1.0f);  // white where no per-vertex colour is given
    // The frame's uniforms and the #defines of its surface variants: the light list unrolled.
    const DrawCamera& cam = list.camera;
    const double dist = (cam.position - center).norm();
    const double far_plane = std::max(200.0, 2.0 * (dist + radius));
    const double near_plane = std::clamp((dist - radius) * 0.5, 0.01, 1.0);
    fu.view_proj = perspective(cam.fov_deg, static_cast<double>(W) / H, near_plane, far_plane) *
                   lookAt(cam.position, cam.target, cam.up);
    fu.eye = cam.position.cast<float>();
    fu.shadow_mats = shadow_mats;
    fu.fog_color = list.fog_color.cast<float>();
    fu.fog_density = float(list.fog_density);
    std::string lights;
    const std::size_t nl = std::min<std::size_t>(list.lights.size(), 8);
    for (std::size_t i = 0; i < nl; ++i) {
      const LightDesc& l = list.lights[i];
      const Vec3 v = l.kind == LightKind::Point ? l.position : l.direction;
      const Vec3 r = l.color * l.intensity;
      for (int k = 0; k < 3; ++k) {
        fu.light_vec[3 * i + static_cast<std::size_t>(k)] = float(v[k]);
        fu.light_rad[3 * i + static_cast<std::size_t>(k)] = float(r[k]);
      }
      const std::string I = std::to_string(i), S = std::to_string(light_shadow[i]);
      if (l.kind == LightKind::Ambient) lights += " c += AMBIENT(" + I + ");";
      else if (l.kind == LightKind::Directional)
        lights += light_shadow[i] >= 0 ? " c += DIRECTIONAL_SHADOW(" + I + ", " + S + ");" : " c += DIRECTIONAL(" + I + ");";
      else
        lights += light_shadow[i] >= 0 ? " c += POINT_SHADOW(" + I + ", " + S + ");" : " c += POINT(" + I + ");";
    }
    frame_defines = "#define LIGHTS" + lights + "\n";
    if (list.fog_density > 0) frame_defines += "#define FOG\n";
    if (list.tonemap == "aces") frame_defines += "#define ACES\n";
    ++frame_no;
    current = 0;
    for (int i = 0; i < 2; ++i) {
      gl->ActiveTexture(GL_TEXTURE1 + static_cast<GLenum>(i));
      gl->BindTexture(GL_TEXTURE_2D, shadow_tex[static_cast<std::size_t>(i)]);
    }
    gl->ActiveTexture(GL_TEXTURE0);
    if (Status st = drawGeometry(list, true, false); !st) return st;
    // Background gradient after the opaque geometry, at the far plane with depth testing on: it
    // only shades the pixels nothing covers.
    gl->DepthFunc(GL_LEQUAL);
    gl->DepthMask(GL_FALSE);
    gl->UseProgram(background);
    current = 0;
    const Vec3& bt = list.background_top;
    const Vec3& bb = list.background_bottom;
    gl->Uniform3f(loc(background, "u_top"), float(bt.x()), float(bt.y()), float(bt.z()));
    gl->Uniform3f(loc(background, "u_bottom"), float(bb.x()), float(bb.y()), float(bb.z()));
    gl->BindVertexArray(empty_vao);
    gl->DrawArrays(GL_TRIANGLES, 0, 3);
    gl->DepthFunc(GL_LESS);
    // Transparent surfaces after the opaque ones, blended, without writing depth.
    gl->Enable(GL_BLEND);
    gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    Status tr = drawGeometry(list, true, true);
    gl->DepthMask(GL_TRUE);
    gl->Disable(GL_BLEND);
    if (!tr) return tr;

    // Resolve the samples and read the pixels back, top row first.
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo);
    gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
    gl->BlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    readback.resize(static_cast<std::size_t>(W) * H * 3);
    gl->ReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, readback.data());
    if (GLenum e = gl->GetError(); e != GL_NO_ERROR)
      return Error(ErrorKind::Internal, "OpenGL error " + std::to_string(e) + " while drawing");
    if (out.width != W || out.height != H) out = Image(W, H);
    for (int y = 0; y < H; ++y)  // GL's rows run from the bottom
      std::copy_n(&readback[static_cast<std::size_t>(H - 1 - y) * W * 3], static_cast<std::size_t>(W) * 3, out.pixel(0, y));
    return {};
  }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;
const RenderSettings& Renderer::settings() const { return impl_->set; }

Result<std::unique_ptr<Renderer>> Renderer::create(gl::Context& ctx, const RenderSettings& s,
                                                   const std::string& shader_dir) {
  auto impl = std::make_unique<Impl>();
  impl->ctx = &ctx;
  impl->gl = &ctx.api();
  impl->set = s;
  if (Status st = impl->init(shader_dir); !st) return st.error();
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

Status Renderer::draw(const DrawList& list, Image& out) { return impl_->draw(list, out); }

Result<double> Renderer::bareDrawSeconds(const TriMesh& mesh, const DrawCamera& cam, int frames) {
  Impl& m = *impl_;
  const auto* gl = m.gl;
  // The shadow program is the plainest one there is: transform, constant output.
  GpuMesh g;
  m.upload(g, mesh);
  gl->BindFramebuffer(GL_FRAMEBUFFER, m.msaa_fbo);
  gl->Viewport(0, 0, m.set.width, m.set.height);
  gl->Enable(GL_DEPTH_TEST);
  gl->UseProgram(m.shadow);
  const Mat4f vp = perspective(cam.fov_deg, double(m.set.width) / m.set.height, 0.05, 200.0) *
                   lookAt(cam.position, cam.target, cam.up);
  gl->UniformMatrix4fv(m.loc(m.shadow, "u_view_proj"), 1, GL_FALSE, vp.data());
  gl->Uniform1i(m.loc(m.shadow, "u_mode"), 0);
  gl->BindVertexArray(g.vao);
  gl->Finish();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < frames; ++i) {
    gl->ClearColor(0.2f, 0.3f, 0.4f, 1.0f);
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->DrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
    gl->Finish();
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / frames;
  gl->DeleteVertexArrays(1, &g.vao);
  gl->DeleteBuffers(4, g.vbo);
  gl->DeleteBuffers(1, &g.ebo);
  if (GLenum e = gl->GetError(); e != GL_NO_ERROR)
    return Error(ErrorKind::Internal, "OpenGL error " + std::to_string(e) + " in the bare draw");
  return s;
}

}  // namespace reel
