// Renderer: draws a DrawList into its own multisampled framebuffer object and reads the pixels
// back as sRGB-encoded RGB8. Every GL call and all GL state of reel live in render/.
#pragma once

#include <memory>
#include <string>

#include "core/drawlist.h"
#include "core/error.h"
#include "core/image.h"
#include "render/gl/context.h"

namespace reel {

// Framebuffer memory an image may take (colour and depth per sample, and the resolved colour):
// 16384x16384 at one sample fits; past it a render is refused before anything is allocated.
inline constexpr std::size_t kMaxFramebufferBytes = std::size_t{3} << 30;

struct RenderSettings {
  int width = 1280, height = 720;
  int samples = 4;  // MSAA: 1, 2 or 4
  int shadow_map_size = 2048;
};

// Folder with reel's GLSL files: $REEL_SHADERS, the source tree's shaders/, or the installed
// share/reel/shaders next to the executable.
std::string findShaderDir();

class Renderer {
 public:
  // The context must be current on the calling thread for create() and draw().
  static Result<std::unique_ptr<Renderer>> create(gl::Context& ctx, const RenderSettings& s,
                                                  const std::string& shader_dir);
  // Deletes the renderer's GL objects: the context must outlive the renderer and be current.
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;
  Status draw(const DrawList& list, Image& out);
  // The rasteriser's own limit, for benchmarks: seconds per frame to clear and draw `mesh` with a
  // constant colour into the same multisampled framebuffer (no lighting, shadows or read-back),
  // averaged over `frames`, from the given camera.
  Result<double> bareDrawSeconds(const TriMesh& mesh, const DrawCamera& camera, int frames);
  const RenderSettings& settings() const;

  struct Impl;

 private:
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace reel
