// The surface shader in its variants: one program per #define header, made of the frame's part
// (its lights unrolled, fog, tone mapping) and the material's (specular, double-sided, checker,
// textured, bumped, wrinkled), each compiled on first use and kept for the renderer's life.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/drawlist.h"
#include "core/error.h"
#include "render/gl/program.h"
#include "render/projection.h"
#include "render/uploads.h"

namespace reel {

// Texture units: 0 the material's texture, 1 and 2 the shadow maps, then these.
// 6 and 7: the shadow maps again, read as depths (soft shadows' blocker search).
inline constexpr int kDfgUnit = 3, kEnvUnit = 4, kAoUnit = 5, kRawShadowUnit = 6;
// 8, 9, 10: the picture, its depth and the see-through bodies' far depth (transmission).
inline constexpr int kSceneColorUnit = 8, kSceneDepthUnit = 9, kBackDepthUnit = 10;
// 11 and 12: the material's bump map and wrinkle map.
inline constexpr int kBumpUnit = 11, kWrinkleUnit = 12;
// 13: the pre-integrated skin table (brdf::integrateSkin).
inline constexpr int kSkinUnit = 13;
// ACES's input gain: middle grey 0.18 comes out 0.18 (shaders/surface.frag's aces()).
inline constexpr double kAcesGreyGain = 1.4617;
// What the frame's linear colours are multiplied by before tone mapping: 2^exposure, with ACES's gain.
inline double exposureScale(const DrawList& list) {
  return std::exp2(list.exposure) * (list.tonemap == "aces" ? kAcesGreyGain : 1.0);
}

// The frame's shadow maps as the surface shader reads them.
struct ShadowFrame {
  std::array<Mat4f, 2> mats{Mat4f::Zero(), Mat4f::Zero()};  // world → map texture space
  // Per map: 0 (a fixed filter) or its light's penumbra: 1 and (depth span · 2 tan(θ/2) / map
  // width) for an orthographic map; 2, near, far and (light diameter / (2 tan(fov/2))) for a
  // perspective one.
  std::array<float, 8> soft{};
  // Per map: the width of one of its texels on the scene, m (at the scene's centre for a
  // perspective map): how far a point looked up is moved off its surface (the normal offset).
  std::array<float, 2> texel_world{};
};

class SurfaceShaders {
 public:
  // `uniforms` must outlive this object.
  SurfaceShaders(const gl::GlApi& gl, gl::UniformCache& uniforms, std::string shader_dir, int shadow_map_size);

  // Compiles the richest variant (every light kind with shadows, fog, ACES, all material
  // features), so that a broken shader fails at start-up, not mid-film.
  Status compileRichest();
  // Starts a frame: its uniforms, and its lights unrolled into the variants' #defines (at most 8;
  // light_shadow[i] is light i's shadow map or -1).
  void beginFrame(const DrawList& list, const std::vector<int>& light_shadow, const Mat4f& view_proj,
                  const ShadowFrame& shadows, int width, int height);
  // The camera's view matrix and depth range, for the frame that begins next.
  void setView(const Mat4f& view, float near, float far) {
    fu_.view = view;
    fu_.near_far[0] = near;
    fu_.near_far[1] = far;
  }
  // Binds the variant for a material (compiling it on first use), uploads the frame's uniforms to
  // it once per frame, then binds the material's texture and sets its uniforms. `instanced`: the
  // variant for instanced meshes (geometry.glsl's INSTANCED).
  Status use(const DrawMaterial& m, TextureCache& textures, bool instanced = false);
  // The variant bound by the last use(), 0 after programChanged().
  GLuint current() const { return current_; }
  // Another program was bound: the next use() binds its variant again.
  void programChanged() { current_ = 0; }

 private:
  struct Variant {
    gl::Program program;
    long long frame = -1;  // the frame whose uniforms the program holds
  };
  // Uniforms shared by every variant in one frame.
  struct FrameUniforms {
    Mat4f view_proj = Mat4f::Zero();
    Vec3f eye = Vec3f::Zero();
    std::array<float, 24> light_vec{}, light_rad{};  // xyz per light: position or direction; radiance
    ShadowFrame shadows;
    Vec3f fog_color = Vec3f::Zero();
    float fog_density = 0;
    float exposure = 1;  // 2^EV times ACES's grey gain
    std::array<float, 27> sh{};  // the environment's irradiance harmonics
    float env_lod = 0;           // its last level
    float screen_texel[2] = {0, 0};
    Mat4f view = Mat4f::Identity();
    float near_far[2] = {0.1f, 100.0f};
  };
  void setFrameUniforms(GLuint prog);

  const gl::GlApi* gl_;
  gl::UniformCache* uniforms_;
  std::string shader_dir_;
  int shadow_map_size_;
  std::map<std::string, Variant> variants_;  // by #define header
  long long frame_no_ = 0;
  std::string frame_defines_;  // LIGHTS, FOG, ACES of the current frame
  FrameUniforms fu_;
  GLuint current_ = 0;  // the variant in use
};

}  // namespace reel
