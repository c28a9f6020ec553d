// reel still / reel render: simulate, draw each frame headlessly, write PNGs.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/commands.h"
#include "io/png.h"
#include "io/scene_loader.h"
#include "render/gl/context.h"
#include "render/renderer.h"
#include "sim/world.h"

namespace reel::app {

Result<gl::Backend> chooseBackend(const std::string& flag) {
  std::string name = flag;
  if (name.empty()) {
    const char* env = std::getenv("REEL_GL");
    name = env && *env ? env : "auto";
  }
  gl::Backend b;
  if (!gl::parseBackend(name, b))
    return Error(ErrorKind::BadInput, "unknown GL backend \"" + name + "\" (auto, osmesa or egl)");
  return b;
}

namespace {

struct Setup {
  SceneDesc scene;
  std::unique_ptr<World> world;
  std::unique_ptr<gl::Context> ctx;
  std::unique_ptr<Renderer> renderer;
};

Status setup(const RenderOptions& opt, Setup& s) {
  auto scene = io::loadScene(opt.scene);
  if (!scene.ok()) return scene.error();
  s.scene = std::move(scene.value());
  if (opt.width > 0) {
    s.scene.render.width = opt.width;
    s.scene.render.height = opt.height;
  }
  if (opt.samples > 0) s.scene.render.samples = opt.samples;
  auto world = World::create(s.scene);
  if (!world.ok()) return world.error();
  s.world = std::make_unique<World>(std::move(world.value()));
  auto backend = chooseBackend(opt.gl);
  if (!backend.ok()) return backend.error();
  auto ctx = gl::createContext(backend.value());
  if (!ctx.ok()) return ctx.error();
  s.ctx = std::move(ctx.value());
  RenderSettings rs;
  rs.width = s.scene.render.width;
  rs.height = s.scene.render.height;
  rs.samples = s.scene.render.samples;
  auto r = Renderer::create(*s.ctx, rs, findShaderDir());
  if (!r.ok()) return r.error();
  s.renderer = std::move(r.value());
  return {};
}

io::TextChunks pngText(const Setup& s, int frame) {
  return {{"Software", std::string("reel ") + REEL_VERSION},
          {"reel:scene", s.scene.name},
          {"reel:frame", std::to_string(frame)},
          {"reel:seed", std::to_string(s.scene.seed)},
          {"reel:gl", std::string(s.ctx->backend()) + ": " + s.ctx->renderer()}};
}

}  // namespace

int still(const RenderOptions& opt, double time, int frame) {
  Setup s;
  if (Status st = setup(opt, s); !st) return report(st.error());
  const int n = s.scene.frameCount();
  const int k = frame >= 0 ? frame : static_cast<int>(std::lround(time * s.scene.fps));
  if (k < 0 || k >= n)
    return report(Error(ErrorKind::BadInput, "frame " + std::to_string(k) + " is outside the film (frames 0.." +
                                                 std::to_string(n - 1) + ")"));
  while (s.world->frame() < k)
    if (Status st = s.world->advanceFrame(); !st) return report(st.error());
  DrawList list;
  s.world->emit(list);
  Image img;
  if (Status st = s.renderer->draw(list, img); !st) return report(st.error());
  if (Status st = io::writePng(opt.outputs.at(0), img, pngText(s, k)); !st) return report(st.error());
  return 0;
}

}  // namespace reel::app
