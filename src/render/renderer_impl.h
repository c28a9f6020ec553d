// Renderer::Impl: the renderer's GL objects and passes, shared by renderer.cpp (set-up, geometry,
// shadows, the main pass, read-back) and renderer_passes.cpp (transmission, the environment,
// the background). Private to render/.
#pragma once

#include <algorithm>

#include <array>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/ao.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/projection.h"
#include "render/renderer.h"
#include "render/surfaces.h"
#include "render/uploads.h"

namespace reel {

// Every GL object is an RAII member: destroying the Impl deletes them all, through the GlApi of
// the context, which must outlive the renderer and be current (see Renderer::~Renderer).
struct Renderer::Impl {
  const gl::GlApi* gl;
  RenderSettings set;
  gl::UniformCache uniforms;  // of every program below
  SurfaceShaders surfaces;
  gl::Program shadow, shadow_instanced;
  std::map<std::string, gl::Program> backgrounds;  // by #defines: ACES, ENVIRONMENT
  // The split-sum table (core/brdf.h) and the scene's environment, uploaded once.
  gl::Texture dfg_tex, skin_tex, env_tex;
  std::weak_ptr<const Environment> env_owner;
  const Environment* env_uploaded = nullptr;
  gl::VertexArray empty_vao;  // the background's full-screen triangle needs no attributes
  // Multisampled colour + depth, resolved into a single-sample colour buffer; two shadow maps.
  gl::Renderbuffer msaa_color, msaa_depth, resolve_color;
  gl::Framebuffer msaa_fbo, resolve_fbo;
  std::array<gl::Texture, 2> shadow_tex;
  std::array<gl::Framebuffer, 2> shadow_fbo;
  gl::Sampler raw_depth;  // the shadow maps read as depths, nearest texel
  // Instancing prototypes and their per-draw data.
  std::array<GpuMesh, 4> sphere_lod;  // specks, coarse, medium, fine
  GpuMesh tube_proto;
  StreamBuffer inst, inst_color;  // centres or ends (attributes 3, 4); per-sphere colours (5)
  std::array<std::vector<float>, 4> lod_centers, lod_colors;  // a set of spheres by level of detail
  // The DrawList's meshes and textures.
  MeshCache meshes;
  TextureCache textures;
  AmbientOcclusion ao;
  // The frame's instanced meshes: one draw per DrawInstances and level of detail, its copies
  // streamed once per frame into a buffer of its own and drawn by every pass.
  struct InstanceDraw {
    std::size_t item;  // into list.instances
    const GpuMesh* proto;
    const StreamBuffer* copies;
    GLsizei count;
  };
  std::vector<InstanceDraw> instance_draws;
  std::deque<StreamBuffer> instance_streams;  // reused frame to frame; deque: stable addresses
  std::array<std::vector<float>, 2> packed;    // near and far copies of one DrawInstances
  // The frame's camera, for the level of detail.
  double px_per_m_at_1m = 1.0;  // pixels per metre at 1 m from the camera
  Vec3 eye{0, 0, 0};
  std::vector<std::uint8_t> readback;  // RGB8, bottom row first

  std::string shader_dir;

  Impl(const gl::GlApi& api, const RenderSettings& s, const std::string& dir)
      : gl(&api), set(s), surfaces(api, uniforms, dir, s.shadow_map_size), meshes(api), textures(api), ao(api, uniforms), shader_dir(dir) {}

  GLint loc(GLuint prog, const char* name) { return uniforms.get(*gl, prog, name); }

  Status init(const std::string& dir);
  Status initTargets();
  Status initShadowMaps();
  Status draw(const DrawList& list, Image& out);
  Status shadowPasses(const DrawList& list, const Vec3& center, double radius, std::vector<int>& light_shadow,
                      ShadowFrame& shadow_frame);
  Status mainPass(const DrawList& list, const Mat4f& view_proj, const std::vector<int>& light_shadow,
                  const ShadowFrame& shadow_frame);
  Status readBack(Image& out);
  void uploadEnvironment(const DrawList& list);
  Status drawBackground(const DrawList& list, const Mat4f& view_proj);

  // One geometry pass: the shadow program for every item (with_material false), or each item's
  // surface variant for the opaque or the transparent items.
  // The items of a pass: all that cast shadows (shadow maps), the opaque ones, the see-through ones (transmission) or
  // the blended ones (opacity below 1).
  // Transparent: blended, every surface; FrontOnly: blended as one solid (DrawMaterial::front_only).
  enum class Layer { All, Opaque, Transmissive, Transparent, FrontOnly };
  struct Pass {
    bool with_material;
    Layer layer;
    const LightDesc* light = nullptr;  // a shadow map's (grounds that hide nothing from it are left out)
    bool wants(const DrawMaterial& m) const {
      switch (layer) {
        case Layer::All: return m.casts_shadow;
        case Layer::Opaque: return m.opacity >= 1.0 && m.transmission <= 0.0;
        case Layer::Transmissive: return m.opacity >= 1.0 && m.transmission > 0.0;
        case Layer::Transparent: return m.opacity < 1.0 && !m.front_only;
        case Layer::FrontOnly: return m.opacity < 1.0 && m.front_only;
      }
      return false;
    }
    bool fromCamera() const { return with_material || layer != Layer::All; }  // not a shadow map
    // Whether anything in the list is drawn in this pass.
    bool wantsAny(const DrawList& list) const {
      auto some = [&](const auto& items) {
        return std::any_of(items.begin(), items.end(), [&](const auto& item) { return wants(item.material); });
      };
      return some(list.meshes) || some(list.spheres) || some(list.tubes) || some(list.instances);
    }
  };
  Status depthOnly(const DrawList& list, const Mat4f& view_proj, Layer layer = Layer::Opaque);
  Status transmissionPass(const DrawList& list, const Mat4f& view_proj);
  // Transmission's targets, made on first use: the picture so far and its depth, and the
  // see-through bodies' far depth.
  gl::Texture scene_color_tex, scene_depth_tex, back_depth_tex;
  gl::Framebuffer copy_fbo, back_fbo;
  Status initTransmission();
  bool shadowHides(const GroundPlane& g, const DrawMaterial& m, const LightDesc& light) const;
  Status drawGeometry(const DrawList& list, Pass pass);
  Status drawSpheres(const DrawSpheres& s, Pass pass);
  Status drawSphereSet(const DrawSpheres& s, const GpuMesh& proto, const std::vector<float>& centers,
                       const std::vector<float>* colors, Pass pass);
  Status drawTubes(const DrawTubes& t, Pass pass);
  void prepareInstances(const DrawList& list);
  Status drawInstances(const DrawInstances& d, const InstanceDraw& draw, Pass pass);
  Status bind(const DrawMaterial& m, Pass pass) { return pass.with_material ? surfaces.use(m, textures) : Status{}; }
  GLuint program(Pass pass) const { return pass.with_material ? surfaces.current() : shadow.id(); }
  // The same for instanced meshes: their own variants, which leave the shadow program bound.
  Status bindInstanced(const DrawMaterial& m, Pass pass);
};

}  // namespace reel
