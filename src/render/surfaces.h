// The surface shader in its variants: one program per #define header, made of the frame's part
// (its lights unrolled, fog, tone mapping) and the material's (specular, double-sided, checker,
// textured), each compiled on first use and kept for the renderer's life.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/drawlist.h"
#include "core/error.h"
#include "render/gl/program.h"
#include "render/projection.h"
#include "render/uploads.h"

namespace reel {

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
                  const std::array<Mat4f, 2>& shadow_mats);
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
    std::array<Mat4f, 2> shadow_mats{Mat4f::Zero(), Mat4f::Zero()};  // world → shadow-map texture space
    Vec3f fog_color = Vec3f::Zero();
    float fog_density = 0;
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
