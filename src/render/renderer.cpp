#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <map>

#include "core/brdf.h"
#include "core/image.h"
#include "core/math.h"
#include "core/motion.h"
#include "render/ao.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/projection.h"
#include "render/surfaces.h"
#include "render/uploads.h"
#include "render/renderer_impl.h"

namespace reel {

std::string findShaderDir() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("REEL_SHADERS"); env && *env) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (const fs::path& p : {exe.parent_path() / "../share/reel/shaders", fs::path(REEL_SHADER_DIR)})
    if (fs::exists(p / "surface.frag", ec)) return fs::weakly_canonical(p, ec).string();
  return REEL_SHADER_DIR;
}


Status Renderer::Impl::init(const std::string& dir) {
  if (Status st = surfaces.compileRichest(); !st) return st;
  auto sh = gl::buildProgram(*gl, dir, "shadow.vert", "shadow.frag", true);
  if (!sh.ok()) return sh.error();
  shadow = std::move(sh.value());
  sh = gl::buildProgram(*gl, dir, "shadow.vert", "shadow.frag", true, "#define INSTANCED\n");
  if (!sh.ok()) return sh.error();
  shadow_instanced = std::move(sh.value());
  // The split-sum table: 32 x 32 (n·v, roughness), 256 samples each, a few milliseconds, once a
  // process (every renderer reads the same table).
  static const brdf::DfgTable dfg = brdf::integrateDfg(32, 256);
  dfg_tex = gl::makeTargetTexture(*gl, dfg.size, dfg.size, GL_RG32F, GL_RG, GL_FLOAT, GL_LINEAR, dfg.ab.data());
  // Pre-integrated skin: 64 x 64 (n·l, curvature), 7 ms, once a process.
  static const brdf::SkinTable skin = brdf::integrateSkin(64);
  skin_tex = gl::makeTargetTexture(*gl, skin.size, skin.size, GL_RGB16F, GL_RGB, GL_FLOAT, GL_LINEAR, skin.rgb.data());
  env_tex = gl::makeTexture(*gl);
  empty_vao = gl::makeVertexArray(*gl);
  inst.buffer = gl::makeBuffer(*gl);
  inst_color.buffer = gl::makeBuffer(*gl);
  // Spheres a few pixels wide need few triangles: llvmpipe's cost is per triangle.
  upload(*gl, sphere_lod[0], makeIcosphere(1.0, 0));
  upload(*gl, sphere_lod[1], makeIcosphere(1.0, 1));
  upload(*gl, sphere_lod[2], makeUvSphere(1.0, 14, 8));
  upload(*gl, sphere_lod[3], makeUvSphere(1.0, 28, 16));
  upload(*gl, tube_proto, makeTube(6));
  if (Status st = initTargets(); !st) return st;
  if (Status st = initShadowMaps(); !st) return st;
  if (GLenum e = gl->GetError(); e != GL_NO_ERROR)
    return Error(ErrorKind::Internal, "OpenGL error " + std::to_string(e) + " while setting up the renderer");
  return {};
}

// Multisampled colour + depth, resolved into a single-sample colour buffer.
Status Renderer::Impl::initTargets() {
  const GLsizei samples = set.samples > 1 ? set.samples : 0;
  // The image must fit this OpenGL's limits and reel's memory cap before anything is allocated
  // (past them the framebuffer is only "incomplete", which names no cause).
  GLint max_rb = 0, max_samples = 0, max_view[2] = {0, 0};
  gl->GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
  gl->GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  gl->GetIntegerv(GL_MAX_VIEWPORT_DIMS, max_view);
  const std::string size = std::to_string(set.width) + "x" + std::to_string(set.height);
  const GLint max_side = std::min({max_rb, max_view[0], max_view[1]});
  if (set.width > max_side || set.height > max_side)
    return Error(ErrorKind::BadInput, "an image of " + size + " is larger than this OpenGL allows (GL_MAX_RENDERBUFFER_SIZE " +
                                          std::to_string(max_rb) + ", GL_MAX_VIEWPORT_DIMS " + std::to_string(max_view[0]) + "x" +
                                          std::to_string(max_view[1]) + ")");
  if (samples > max_samples)
    return Error(ErrorKind::BadInput, std::to_string(samples) + " samples are more than this OpenGL allows (GL_MAX_SAMPLES " +
                                          std::to_string(max_samples) + ")");
  const double bytes = static_cast<double>(set.width) * set.height * (std::max(samples, 1) * 8.0 + 4.0);  // colour + depth, + resolve
  if (bytes > static_cast<double>(kMaxFramebufferBytes))
    return Error(ErrorKind::BadInput, "an image of " + size + " at " + std::to_string(std::max(samples, 1)) + " samples needs " +
                                          std::to_string(static_cast<long long>(bytes / (1 << 20))) + " MiB of framebuffer, more than the limit of " +
                                          std::to_string(kMaxFramebufferBytes >> 20) + " MiB: lower --size or --samples");
  msaa_color = gl::makeRenderbuffer(*gl);
  gl->BindRenderbuffer(GL_RENDERBUFFER, msaa_color.id());
  gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, set.width, set.height);
  msaa_depth = gl::makeRenderbuffer(*gl);
  gl->BindRenderbuffer(GL_RENDERBUFFER, msaa_depth.id());
  gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, set.width, set.height);
  msaa_fbo = gl::makeFramebuffer(*gl);
  gl->BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo.id());
  gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_color.id());
  gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_depth.id());
  if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return Error(ErrorKind::Internal, "the multisampled framebuffer is incomplete");
  resolve_color = gl::makeRenderbuffer(*gl);
  gl->BindRenderbuffer(GL_RENDERBUFFER, resolve_color.id());
  gl->RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_RGBA8, set.width, set.height);
  resolve_fbo = gl::makeFramebuffer(*gl);
  gl->BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo.id());
  gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color.id());
  if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return Error(ErrorKind::Internal, "the resolve framebuffer is incomplete");
  return {};
}

// Shadow maps: depth textures compared in the shader (hardware PCF where there is one).
Status Renderer::Impl::initShadowMaps() {
  raw_depth = gl::makeSampler(*gl);
  gl->SamplerParameteri(raw_depth.id(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  gl->SamplerParameteri(raw_depth.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl->SamplerParameteri(raw_depth.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl->SamplerParameteri(raw_depth.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl->SamplerParameteri(raw_depth.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  for (auto& t : shadow_tex) t = gl::makeTexture(*gl);
  for (std::size_t i = 0; i < 2; ++i) {
    gl->BindTexture(GL_TEXTURE_2D, shadow_tex[i].id());
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, set.shadow_map_size, set.shadow_map_size, 0,
                   GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    auto f = gl::makeTargetFramebuffer(*gl, 0, shadow_tex[i].id(), "shadow");
    if (!f.ok()) return f.error();
    shadow_fbo[i] = std::move(f.value());
  }
  return {};
}

// Whether a flat ground can hide anything the camera sees from the shadow map's light. An opaque
// ground hides what lies on its far side from the camera, and a ray from a point on the camera's
// side to a light on that side stays on it (a half-space is convex): with the light and the
// camera on one side, the ground shadows nothing in view. Left out of the map there, its fill,
// the largest in most films' maps, is saved; the picture is the same.
bool Renderer::Impl::shadowHides(const GroundPlane& g, const DrawMaterial& m, const LightDesc& light) const {
  if (!g.flat || m.opacity < 1.0 || m.transmission > 0.0) return true;
  const double camera_side = (eye - g.point).dot(g.normal);
  const double light_side = light.kind == LightKind::Directional ? -light.direction.dot(g.normal)
                                                                 : (light.position - g.point).dot(g.normal);
  return !(camera_side * light_side > 0);
}

Status Renderer::Impl::drawGeometry(const DrawList& list, Pass pass) {
  for (std::size_t i = 0; i < list.meshes.size(); ++i) {
    const DrawMesh& m = list.meshes[i];
    const GpuMesh* g = meshes.slot(i);
    if (!g || !pass.wants(m.material)) continue;
    if (pass.light && !shadowHides(g->ground, m.material, *pass.light)) continue;
    if (Status st = bind(m.material, pass); !st) return st;
    gl->Uniform1i(loc(program(pass), "u_mode"), 0);
    gl->BindVertexArray(g->vao.id());
    gl->DrawElements(GL_TRIANGLES, g->count, GL_UNSIGNED_INT, nullptr);
  }
  for (const auto& s : list.spheres)
    if (Status st = drawSpheres(s, pass); !st) return st;
  for (const auto& t : list.tubes)
    if (Status st = drawTubes(t, pass); !st) return st;
  for (const InstanceDraw& d : instance_draws)
    if (Status st = drawInstances(list.instances[d.item], d, pass); !st) return st;
  return {};
}

Status Renderer::Impl::drawSpheres(const DrawSpheres& s, Pass pass) {
  if (s.centers.empty() || !pass.wants(s.material)) return {};
  // Each sphere at the level of detail of its own on-screen radius (a set of thousands of
  // particles drawn at the level of its nearest one cost seconds a frame): below 3 pixels the
  // 20-triangle icosahedron (specks: foam, far particles), below 8 pixels the 80-triangle
  // icosphere, below 20 pixels 224 triangles, else 896; in the shadow pass at most the icosphere
  // (the shadow map's texels are coarser than that). Sets are split in order, so a frame's draw
  // is the same run to run.
  const bool coloured = pass.with_material && s.colors.size() == s.centers.size();
  for (int l = 0; l < 4; ++l) {
    lod_centers[static_cast<std::size_t>(l)].clear();
    lod_colors[static_cast<std::size_t>(l)].clear();
  }
  const double px_at_1m = s.radius * px_per_m_at_1m;
  for (std::size_t i = 0; i + 2 < s.centers.size(); i += 3) {
    const double d = (Vec3(s.centers[i], s.centers[i + 1], s.centers[i + 2]) - eye).norm();
    const double px = px_at_1m / std::max(d, 1e-3);
    const std::size_t l = px < 3 ? 0 : !pass.with_material || px < 8 ? 1 : px < 20 ? 2 : 3;
    lod_centers[l].insert(lod_centers[l].end(), &s.centers[i], &s.centers[i] + 3);
    if (coloured) lod_colors[l].insert(lod_colors[l].end(), &s.colors[i], &s.colors[i] + 3);
  }
  for (std::size_t l = 0; l < 4; ++l)
    if (!lod_centers[l].empty())
      if (Status st = drawSphereSet(s, sphere_lod[l], lod_centers[l], coloured ? &lod_colors[l] : nullptr, pass); !st)
        return st;
  return {};
}

Status Renderer::Impl::drawSphereSet(const DrawSpheres& s, const GpuMesh& proto, const std::vector<float>& centers,
                                     const std::vector<float>* colors, Pass pass) {
  bindInstances(*gl, proto, inst, centers, 3);
  // Per-sphere colours (a liquid's species blended): attribute 5 advances per instance.
  const bool coloured = colors != nullptr;
  if (coloured) {
    inst_color.fill(*gl, *colors);
    gl->EnableVertexAttribArray(5);
    gl->VertexAttribPointer(5, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl->VertexAttribDivisor(5, 1);
  }
  if (Status st = bind(s.material, pass); !st) return st;
  gl->Uniform1i(loc(program(pass), "u_mode"), 1);
  gl->Uniform1f(loc(program(pass), "u_radius"), s.radius);
  gl->DrawElementsInstanced(GL_TRIANGLES, proto.count, GL_UNSIGNED_INT, nullptr,
                            static_cast<GLsizei>(centers.size() / 3));
  if (coloured) {  // the prototype is shared: back to the constant white
    gl->BindVertexArray(proto.vao.id());
    gl->VertexAttribDivisor(5, 0);
    gl->DisableVertexAttribArray(5);
  }
  return {};
}

// Tubes are always tubes, never at least as thin as kMinTubePx on screen (a radius in pixels): a
// spring far away stays a thin, antialiased line of the same tubes instead of switching to GL
// lines and back as it nears, which popped. The shadow pass keeps the true radius.
Status Renderer::Impl::drawTubes(const DrawTubes& t, Pass pass) {
  if (t.ends.empty() || !pass.wants(t.material)) return {};
  constexpr double kMinTubePx = 0.6;
  bindInstances(*gl, tube_proto, inst, t.ends, 6);
  if (Status st = bind(t.material, pass); !st) return st;
  const GLuint prog = program(pass);
  gl->Uniform1i(loc(prog, "u_mode"), 2);
  gl->Uniform1f(loc(prog, "u_radius"), t.radius);
  gl->Uniform1f(loc(prog, "u_tube_min"), pass.fromCamera() ? static_cast<float>(kMinTubePx / px_per_m_at_1m) : 0.0f);
  gl->Uniform3f(loc(prog, "u_tube_eye"), static_cast<float>(eye.x()), static_cast<float>(eye.y()), static_cast<float>(eye.z()));
  gl->DrawElementsInstanced(GL_TRIANGLES, tube_proto.count, GL_UNSIGNED_INT, nullptr,
                            static_cast<GLsizei>(t.ends.size() / 6));
  return {};
}

// Splits each DrawInstances by level of detail and streams its copies to the GPU, once for all
// the frame's passes.
void Renderer::Impl::prepareInstances(const DrawList& list) {
  instance_draws.clear();
  std::size_t next = 0;  // the next stream buffer
  for (std::size_t i = 0; i < list.instances.size(); ++i) {
    const DrawInstances& d = list.instances[i];
    const GpuMesh* near = meshes.prototype(d.mesh);
    if (!near || d.count() == 0) continue;
    const GpuMesh* far = d.far_distance > 0 ? meshes.prototype(d.far_mesh) : nullptr;
    packInstances(d, eye, far ? d.far_distance : 0.0, packed);
    for (std::size_t lod = 0; lod < 2; ++lod) {
      if (packed[lod].empty()) continue;
      if (next >= instance_streams.size()) instance_streams.emplace_back().buffer = gl::makeBuffer(*gl);
      StreamBuffer& sb = instance_streams[next++];
      sb.fill(*gl, packed[lod]);
      instance_draws.push_back({i, lod == 0 ? near : far, &sb, static_cast<GLsizei>(packed[lod].size() / kInstanceFloats)});
    }
  }
}

Status Renderer::Impl::bindInstanced(const DrawMaterial& m, Pass pass) {
  if (pass.with_material) return surfaces.use(m, textures, true);
  gl->UseProgram(shadow_instanced.id());
  return {};
}

Status Renderer::Impl::drawInstances(const DrawInstances& d, const InstanceDraw& draw, Pass pass) {
  if (!pass.wants(d.material)) return {};
  bindMeshInstances(*gl, *draw.proto, *draw.copies);
  if (Status st = bindInstanced(d.material, pass); !st) return st;
  const GLuint prog = pass.with_material ? surfaces.current() : shadow_instanced.id();
  // No phases, or no span to bend over: no wave.
  const bool waving = d.phases.size() == d.count() && d.wave_start > d.wave_end;
  const float span = waving ? d.wave_start - d.wave_end : 1.0f;
  gl->Uniform4f(loc(prog, "u_wave"), waving ? d.wave_amplitude : 0.0f, d.wave_number, d.wave_start, 1.0f / span);
  // A closed mesh hides its back faces: culling them halves what the rasteriser fills.
  if (!d.material.double_sided) gl->Enable(GL_CULL_FACE);
  gl->DrawElementsInstanced(GL_TRIANGLES, draw.proto->count, GL_UNSIGNED_INT, nullptr, draw.count);
  gl->Disable(GL_CULL_FACE);
  return {};
}

Status Renderer::Impl::draw(const DrawList& list, Image& out) {
  Vec3 center;
  double radius;
  sceneBounds(list, center, radius);
  // Meshes to GPU once per frame; copies whose owners are gone are deleted first.
  meshes.forgetExpired();
  textures.forgetExpired();
  meshes.prepare(list);
  eye = list.camera.position;
  px_per_m_at_1m = 0.5 * set.height / std::tan(list.camera.fov_deg * kPi / 360.0);
  prepareInstances(list);
  std::vector<int> light_shadow(list.lights.size(), -1);
  ShadowFrame shadow_frame;
  if (Status st = shadowPasses(list, center, radius, light_shadow, shadow_frame); !st) return st;
  // The camera: near and far planes around the scene's bounds.
  const DrawCamera& cam = list.camera;
  const double dist = (cam.position - center).norm();
  const double far_plane = std::max(200.0, 2.0 * (dist + radius));
  const double near_plane = std::clamp((dist - radius) * 0.5, 0.01, 1.0);
  const Mat4f proj = perspective(cam.fov_deg, static_cast<double>(set.width) / set.height, near_plane, far_plane);
  const Mat4f view = lookAt(cam.position, cam.target, cam.up);
  const Mat4f view_proj = proj * view;
  surfaces.setView(view, static_cast<float>(near_plane), static_cast<float>(far_plane));
  // Ambient occlusion at half the picture's size a side (a quarter of the cost; occlusion is soft
  // and its blur spans 4 x 4 of its pixels anyway), read back filtered.
  if (list.ao_radius > 0)
    if (Status st = ao.run(shader_dir, (set.width + 1) / 2, (set.height + 1) / 2, proj, list.ao_radius, list.ao_strength, kAoUnit,
                           [&] { return depthOnly(list, view_proj); }, msaa_fbo);
        !st)
      return st;
  if (Status st = mainPass(list, view_proj, light_shadow, shadow_frame); !st) return st;
  return readBack(out);
}

// Shadow passes: an orthographic map along a directional light, a perspective map from a point
// light, each fitted to the scene's bounding sphere. light_shadow[i] becomes light i's map.
Status Renderer::Impl::shadowPasses(const DrawList& list, const Vec3& center, double radius,
                                    std::vector<int>& light_shadow, ShadowFrame& shadow_frame) {
  int shadows = 0;
  gl->Enable(GL_DEPTH_TEST);
  gl->DepthFunc(GL_LESS);
  gl->Disable(GL_CULL_FACE);
  for (std::size_t i = 0; i < list.lights.size() && shadows < 2; ++i) {
    const LightDesc& l = list.lights[i];
    if (!l.shadows || l.kind == LightKind::Ambient) continue;
    Mat4f vp;
    float* soft = &shadow_frame.soft[4 * static_cast<std::size_t>(shadows)];
    if (l.kind == LightKind::Directional) {
      const Vec3 d = l.direction.normalized();
      const Vec3 from = center - d * (radius * 2.0);
      vp = ortho(radius, radius * 0.5, radius * 3.5) * lookAt(from, center, Vec3::UnitY());
      // A penumbra of depth difference · 2 tan(θ/2) m, over a map 2·radius wide and 3·radius deep.
      if (l.size > 0) soft[0] = 1, soft[1] = float(3.0 * radius * 2.0 * std::tan(l.size * kPi / 360.0) / (2.0 * radius));
      shadow_frame.texel_world[static_cast<std::size_t>(shadows)] = float(2.0 * radius / set.shadow_map_size);
    } else {
      const double dist = std::max((l.position - center).norm(), radius * 1.01);
      const double half = std::asin(std::min(radius / dist, 0.99));
      const double near = std::max(dist - radius, 0.05), far = dist + radius;
      vp = perspective(2 * half * 180 / kPi, 1.0, near, far) * lookAt(l.position, center, Vec3::UnitY());
      if (l.size > 0) soft[0] = 2, soft[1] = float(near), soft[2] = float(far), soft[3] = float(2.0 * l.size / (2.0 * std::tan(half)));
      shadow_frame.texel_world[static_cast<std::size_t>(shadows)] = float(2.0 * dist * std::tan(half) / set.shadow_map_size);
    }
    gl->BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo[static_cast<std::size_t>(shadows)].id());
    gl->Viewport(0, 0, set.shadow_map_size, set.shadow_map_size);
    gl->ClearDepth(1.0);
    gl->Clear(GL_DEPTH_BUFFER_BIT);
    gl->UseProgram(shadow_instanced.id());
    gl->UniformMatrix4fv(loc(shadow_instanced.id(), "u_view_proj"), 1, GL_FALSE, vp.data());
    gl->UseProgram(shadow.id());
    gl->UniformMatrix4fv(loc(shadow.id(), "u_view_proj"), 1, GL_FALSE, vp.data());
    gl->Enable(GL_POLYGON_OFFSET_FILL);
    gl->PolygonOffset(1.5f, 2.0f);
    Status drawn = drawGeometry(list, Pass{false, Layer::All, &l});
    gl->Disable(GL_POLYGON_OFFSET_FILL);
    if (!drawn) return drawn;
    Mat4f bias = Mat4f::Identity();  // clip space [-1, 1] → texture space [0, 1]
    bias.block<3, 3>(0, 0) *= 0.5f;
    bias.block<3, 1>(0, 3) = Vec3f::Constant(0.5f);
    shadow_frame.mats[static_cast<std::size_t>(shadows)] = bias * vp;
    light_shadow[i] = shadows++;
  }
  return {};
}

// Main pass: opaque surfaces, the background where nothing covers, transparent surfaces.
// The camera's depth of the opaque geometry, for ambient occlusion: the shadow programs, which
// write depth only.
Status Renderer::Impl::depthOnly(const DrawList& list, const Mat4f& view_proj, Layer layer) {
  gl->UseProgram(shadow_instanced.id());
  gl->UniformMatrix4fv(loc(shadow_instanced.id(), "u_view_proj"), 1, GL_FALSE, view_proj.data());
  gl->UseProgram(shadow.id());
  gl->UniformMatrix4fv(loc(shadow.id(), "u_view_proj"), 1, GL_FALSE, view_proj.data());
  return drawGeometry(list, Pass{false, layer});
}

Status Renderer::Impl::mainPass(const DrawList& list, const Mat4f& view_proj, const std::vector<int>& light_shadow,
                                const ShadowFrame& shadow_frame) {
  const int W = set.width, H = set.height;
  gl->BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo.id());
  gl->Viewport(0, 0, W, H);
  gl->ClearDepth(1.0);
  gl->Clear(GL_DEPTH_BUFFER_BIT);
  gl->VertexAttrib3f(5, 1.0f, 1.0f, 1.0f);  // white where no per-vertex colour is given
  gl->VertexAttrib1f(11, 0.0f);              // no sheen where no per-vertex gloss is given
  gl->VertexAttrib1f(12, 1.0f);              // all of the transmission where no clarity is given
  gl->VertexAttrib1f(13, 0.0f);              // no wrinkles where no per-vertex weights are given
  // The frame's uniforms and the #defines of its surface variants.
  surfaces.beginFrame(list, light_shadow, view_proj, shadow_frame, W, H);
  for (std::size_t i = 0; i < 2; ++i) {
    gl->ActiveTexture(GL_TEXTURE1 + static_cast<GLenum>(i));
    gl->BindTexture(GL_TEXTURE_2D, shadow_tex[i].id());
    // Again on units 6 and 7 through a sampler that reads depths instead of comparing them.
    gl->ActiveTexture(GL_TEXTURE0 + kRawShadowUnit + static_cast<GLenum>(i));
    gl->BindTexture(GL_TEXTURE_2D, shadow_tex[i].id());
    gl->BindSampler(kRawShadowUnit + static_cast<GLuint>(i), raw_depth.id());
  }
  gl->ActiveTexture(GL_TEXTURE0 + kDfgUnit);
  gl->BindTexture(GL_TEXTURE_2D, dfg_tex.id());
  gl->ActiveTexture(GL_TEXTURE0 + kSkinUnit);
  gl->BindTexture(GL_TEXTURE_2D, skin_tex.id());
  uploadEnvironment(list);
  gl->ActiveTexture(GL_TEXTURE0);
  if (Status st = drawGeometry(list, Pass{true, Layer::Opaque}); !st) return st;
  if (Status st = drawBackground(list, view_proj); !st) return st;
  if (Status st = transmissionPass(list, view_proj); !st) return st;
  // Transparent surfaces after the opaque ones, blended, without writing depth: first those
  // blended whole, then those blended as one solid, which lay down their nearest surfaces' depth
  // before they are drawn (pushed a hair back, so those surfaces pass the test again and what lies
  // behind them does not).
  gl->DepthMask(GL_FALSE);
  gl->DepthFunc(GL_LESS);
  gl->Enable(GL_BLEND);
  gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  Status tr = drawGeometry(list, Pass{true, Layer::Transparent});
  if (tr && Pass{false, Layer::FrontOnly}.wantsAny(list)) {
    gl->Disable(GL_BLEND);
    gl->ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl->DepthMask(GL_TRUE);
    gl->Enable(GL_POLYGON_OFFSET_FILL);
    gl->PolygonOffset(1.0f, 2.0f);
    tr = depthOnly(list, view_proj, Layer::FrontOnly);
    gl->Disable(GL_POLYGON_OFFSET_FILL);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->DepthMask(GL_FALSE);
    gl->Enable(GL_BLEND);
    surfaces.programChanged();
    if (tr) tr = drawGeometry(list, Pass{true, Layer::FrontOnly});
  }
  gl->DepthMask(GL_TRUE);
  gl->Disable(GL_BLEND);
  return tr;
}

// Resolves the samples and reads the pixels back, top row first.
Status Renderer::Impl::readBack(Image& out) {
  const int W = set.width, H = set.height;
  gl->BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo.id());
  gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo.id());
  gl->BlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl->BindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo.id());
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

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;
const RenderSettings& Renderer::settings() const { return impl_->set; }

Result<std::unique_ptr<Renderer>> Renderer::create(gl::Context& ctx, const RenderSettings& s,
                                                   const std::string& shader_dir) {
  auto impl = std::make_unique<Impl>(ctx.api(), s, shader_dir);
  if (Status st = impl->init(shader_dir); !st) return st.error();
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

// With motion blur or depth of field, the mean of the pictures over the shutter and the lens
// (core/motion.h), taken in linear light: each picture's sRGB codes decoded, the mean encoded again.
Status Renderer::draw(const DrawList& list, Image& out) {
  const int n = picturesPerFrame(list);
  if (n == 1) return impl_->draw(list, out);
  static const std::array<double, 256> linear = [] {
    std::array<double, 256> t{};
    for (int c = 0; c < 256; ++c) t[static_cast<std::size_t>(c)] = srgbToLinear(c / 255.0);
    return t;
  }();
  std::vector<double> sum;
  Image one;
  for (int j = 0; j < n; ++j) {
    if (Status st = impl_->draw(picture(list, j, n), one); !st) return st;
    sum.resize(one.rgb.size(), 0.0);
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += linear[one.rgb[i]];
  }
  out = Image(one.width, one.height);
  for (std::size_t i = 0; i < sum.size(); ++i) out.rgb[i] = linearToSrgb8(sum[i] / n);
  return {};
}

Result<double> Renderer::bareDrawSeconds(const TriMesh& mesh, const DrawCamera& cam, int frames) {
  Impl& m = *impl_;
  const auto* gl = m.gl;
  // The shadow program is the plainest one there is: transform, constant output.
  double s = 0;
  {
    GpuMesh g;  // deleted at the end of this block
    upload(*gl, g, mesh);
    gl->BindFramebuffer(GL_FRAMEBUFFER, m.msaa_fbo.id());
    gl->Viewport(0, 0, m.set.width, m.set.height);
    gl->Enable(GL_DEPTH_TEST);
    gl->UseProgram(m.shadow.id());
    const Mat4f vp = perspective(cam.fov_deg, double(m.set.width) / m.set.height, 0.05, 200.0) *
                     lookAt(cam.position, cam.target, cam.up);
    gl->UniformMatrix4fv(m.loc(m.shadow.id(), "u_view_proj"), 1, GL_FALSE, vp.data());
    gl->Uniform1i(m.loc(m.shadow.id(), "u_mode"), 0);
    gl->BindVertexArray(g.vao.id());
    auto frame = [&] {
      gl->ClearColor(0.2f, 0.3f, 0.4f, 1.0f);
      gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      gl->DrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
      gl->Finish();
    };
    frame();  // untimed: the first draw of a program compiles its variant
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) frame();
    s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / frames;
  }
  if (GLenum e = gl->GetError(); e != GL_NO_ERROR)
    return Error(ErrorKind::Internal, "OpenGL error " + std::to_string(e) + " in the bare draw");
  return s;
}

}  // namespace reel
