#include "render/surfaces.h"

#include "core/brdf.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace reel {

SurfaceShaders::SurfaceShaders(const gl::GlApi& gl, gl::UniformCache& uniforms, std::string shader_dir,
                               int shadow_map_size)
    : gl_(&gl), uniforms_(&uniforms), shader_dir_(std::move(shader_dir)), shadow_map_size_(shadow_map_size) {}

Status SurfaceShaders::compileRichest() {
  frame_defines_ = "#define LIGHTS c += DIRECTIONAL_SHADOW(0, 0); c += POINT_SHADOW(1, 1); c += AMBIENT(2); "
                   "c += DIRECTIONAL_SHADOW_SOFT(0, 0); c += POINT_SHADOW_SOFT(1, 1);\n"
                   "#define FOG\n#define ACES\n#define ENVIRONMENT\n#define AO\n";
  DrawMaterial probe;
  probe.specular = 1;
  probe.sheen = 1;
  probe.transmission = 0.5;
  probe.double_sided = probe.checker = true;
  probe.texture = probe.bump = probe.wrinkles = std::make_shared<const Image>(2, 2);
  probe.bump_depth = probe.wrinkle_depth = 1e-3;
  probe.scatter = 1;
  probe.translucency = 0.5;
  TextureCache textures(*gl_);  // the probe's texture, gone with it
  return use(probe, textures);
}

void SurfaceShaders::beginFrame(const DrawList& list, const std::vector<int>& light_shadow, const Mat4f& view_proj,
                                const ShadowFrame& shadows, int width, int height) {
  fu_.screen_texel[0] = 1.0f / float(width);
  fu_.screen_texel[1] = 1.0f / float(height);
  fu_.view_proj = view_proj;
  fu_.eye = list.camera.position.cast<float>();
  fu_.shadows = shadows;
  fu_.fog_color = list.fog_color.cast<float>();
  fu_.fog_density = float(list.fog_density);
  fu_.exposure = float(exposureScale(list));
  if (list.environment) {
    for (std::size_t i = 0; i < 9; ++i)
      for (int k = 0; k < 3; ++k) fu_.sh[3 * i + static_cast<std::size_t>(k)] = float(list.environment->sh[i][k]);
    fu_.env_lod = float(list.environment->levels.size() - 1);
  }
  // The light list unrolled: one shading call per light, with its shadow map if it has one.
  std::string lights;
  const std::size_t nl = std::min<std::size_t>(list.lights.size(), 8);
  for (std::size_t i = 0; i < nl; ++i) {
    const LightDesc& l = list.lights[i];
    const Vec3 v = l.kind == LightKind::Point ? l.position : l.direction;
    const Vec3 r = l.color * l.intensity;
    for (int k = 0; k < 3; ++k) {
      fu_.light_vec[3 * i + static_cast<std::size_t>(k)] = float(v[k]);
      fu_.light_rad[3 * i + static_cast<std::size_t>(k)] = float(r[k]);
    }
    const std::string I = std::to_string(i), S = std::to_string(light_shadow[i]);
    const std::string soft = l.size > 0 ? "_SOFT(" : "(";  // percentage-closer soft shadows
    if (l.kind == LightKind::Ambient) lights += " c += AMBIENT(" + I + ");";
    else if (l.kind == LightKind::Directional)
      lights += light_shadow[i] >= 0 ? " c += DIRECTIONAL_SHADOW" + soft + I + ", " + S + ");" : " c += DIRECTIONAL(" + I + ");";
    else
      lights += light_shadow[i] >= 0 ? " c += POINT_SHADOW" + soft + I + ", " + S + ");" : " c += POINT(" + I + ");";
  }
  frame_defines_ = "#define LIGHTS" + lights + "\n";
  if (list.fog_density > 0) frame_defines_ += "#define FOG\n";
  if (list.tonemap == "aces") frame_defines_ += "#define ACES\n";
  if (list.environment) frame_defines_ += "#define ENVIRONMENT\n";
  if (list.ao_radius > 0) frame_defines_ += "#define AO\n";
  ++frame_no_;
  current_ = 0;
}

Status SurfaceShaders::use(const DrawMaterial& m, TextureCache& textures, bool instanced) {
  // The variant: the frame's #defines and the material's.
  std::string key = frame_defines_;
  if (instanced) key += "#define INSTANCED\n";
  if (m.specular > 0 || m.metallic > 0) key += "#define SPECULAR\n";
  if (m.sheen > 0) key += "#define SHEEN\n";
  if (m.transmission > 0) key += "#define TRANSMISSIVE\n";
  if (m.double_sided) key += "#define DOUBLE_SIDED\n";
  if (m.checker) key += "#define CHECKER\n";
  if (m.texture) key += "#define TEXTURED\n";
  const bool bumped = m.bump && m.bump_depth != 0;
  if (bumped) key += "#define BUMPED\n";
  const bool wrinkled = m.wrinkles && m.wrinkle_depth != 0;
  if (wrinkled) key += "#define WRINKLED\n";
  if (m.scatter > 0) key += "#define SCATTER\n";
  const bool translucent = m.translucency > 0 && m.double_sided && m.scatter > 0;
  if (translucent) key += "#define TRANSLUCENT\n";
  auto it = variants_.find(key);
  if (it == variants_.end()) {
    auto p = gl::buildProgram(*gl_, shader_dir_, "surface.vert", "surface.frag", true, key);
    if (!p.ok()) return p.error();
    it = variants_.emplace(key, Variant{std::move(p.value()), -1}).first;
  }
  const GLuint prog = it->second.program.id();
  if (current_ != prog) {
    gl_->UseProgram(prog);
    current_ = prog;
  }
  if (it->second.frame != frame_no_) {
    it->second.frame = frame_no_;
    setFrameUniforms(prog);
  }
  // The material's texture and uniforms.
  if (m.texture) textures.bind(m.texture);
  if (bumped) textures.bind(m.bump, kBumpUnit, false);
  if (wrinkled) textures.bind(m.wrinkles, kWrinkleUnit, false);
  auto loc = [&](const char* name) { return uniforms_->get(*gl_, prog, name); };
  gl_->Uniform3f(loc("u_color"), float(m.color.x()), float(m.color.y()), float(m.color.z()));
  gl_->Uniform1f(loc("u_f0"), float(0.08 * m.specular));
  gl_->Uniform1f(loc("u_roughness"), float(m.roughnessValue()));
  gl_->Uniform1f(loc("u_metallic"), float(m.metallic));
  if (m.sheen > 0) gl_->Uniform1f(loc("u_sheen"), float(m.sheen));
  if (m.transmission > 0) {
    gl_->Uniform1f(loc("u_transmission"), float(m.transmission));
    gl_->Uniform1f(loc("u_absorption_depth"), float(m.absorption_depth));
  }
  gl_->Uniform1f(loc("u_opacity"), float(m.opacity));
  if (m.scatter > 0) gl_->Uniform1f(loc("u_scatter"), float(m.scatter));
  if (translucent) gl_->Uniform1f(loc("u_translucency"), float(m.translucency));
  if (m.checker) gl_->Uniform1f(loc("u_checker_size"), float(m.checker_size));
  if (bumped) gl_->Uniform1f(loc("u_bump_depth"), float(m.bump_depth));
  if (wrinkled) {
    gl_->Uniform1f(loc("u_wrinkle_depth"), float(m.wrinkle_depth));
    gl_->Uniform1f(loc("u_wrinkle_shade"), float(m.wrinkle_shade));
  }
  if (m.double_sided) {
    const Vec3 back = m.back_color.value_or(m.color);
    gl_->Uniform3f(loc("u_back_color"), float(back.x()), float(back.y()), float(back.z()));
    gl_->Uniform1i(loc("u_plain_back"), m.back_color ? 1 : 0);
  }
  return {};
}

void SurfaceShaders::setFrameUniforms(GLuint prog) {
  auto loc = [&](const char* name) { return uniforms_->get(*gl_, prog, name); };
  gl_->UniformMatrix4fv(loc("u_view_proj"), 1, GL_FALSE, fu_.view_proj.data());
  gl_->Uniform3f(loc("u_eye"), fu_.eye.x(), fu_.eye.y(), fu_.eye.z());
  gl_->Uniform3fv(loc("u_light_vec"), 8, fu_.light_vec.data());
  gl_->Uniform3fv(loc("u_light_radiance"), 8, fu_.light_rad.data());
  gl_->Uniform1i(loc("u_shadow_map0"), 1);
  gl_->Uniform1i(loc("u_shadow_map1"), 2);
  gl_->UniformMatrix4fv(loc("u_shadow_matrix"), 2, GL_FALSE, fu_.shadows.mats[0].data());
  gl_->Uniform4fv(loc("u_shadow_soft"), 2, fu_.shadows.soft.data());
  gl_->Uniform1i(loc("u_shadow_raw0"), kRawShadowUnit);
  gl_->Uniform1i(loc("u_shadow_raw1"), kRawShadowUnit + 1);
  gl_->Uniform1f(loc("u_shadow_texel"), 1.0f / float(shadow_map_size_));
  gl_->Uniform1fv(loc("u_shadow_offset"), 2, fu_.shadows.texel_world.data());
  gl_->Uniform1i(loc("u_texture"), 0);
  gl_->Uniform1i(loc("u_bump"), kBumpUnit);
  gl_->Uniform1i(loc("u_wrinkles"), kWrinkleUnit);
  gl_->Uniform3f(loc("u_fog_color"), fu_.fog_color.x(), fu_.fog_color.y(), fu_.fog_color.z());
  gl_->Uniform1f(loc("u_fog_density"), fu_.fog_density);
  gl_->Uniform1f(loc("u_exposure"), fu_.exposure);
  gl_->Uniform1i(loc("u_dfg"), kDfgUnit);
  gl_->Uniform1i(loc("u_skin"), kSkinUnit);
  gl_->Uniform1f(loc("u_skin_max_curvature"), float(1000.0 * brdf::kSkinMaxCurvature));  // mm⁻¹ → m⁻¹
  gl_->Uniform1i(loc("u_env"), kEnvUnit);
  gl_->Uniform1f(loc("u_env_lod"), fu_.env_lod);
  gl_->Uniform3fv(loc("u_sh"), 9, fu_.sh.data());
  gl_->Uniform1i(loc("u_ao"), kAoUnit);
  gl_->Uniform2f(loc("u_screen_texel"), fu_.screen_texel[0], fu_.screen_texel[1]);
  gl_->UniformMatrix4fv(loc("u_view"), 1, GL_FALSE, fu_.view.data());
  gl_->Uniform2f(loc("u_near_far"), fu_.near_far[0], fu_.near_far[1]);
  gl_->Uniform1i(loc("u_scene_color"), kSceneColorUnit);
  gl_->Uniform1i(loc("u_scene_depth"), kSceneDepthUnit);
  gl_->Uniform1i(loc("u_back_depth"), kBackDepthUnit);
}

}  // namespace reel
