#include "render/gl/api.h"

namespace reel::gl {

Status loadGlApi(ProcLoader load, GlApi& api) {
#define REEL_GL_LOAD(name, type)                                                       \
  api.name = reinterpret_cast<type>(load("gl" #name));                                 \
  if (!api.name) return Error(ErrorKind::Internal, "OpenGL function gl" #name " is missing");
  REEL_GL_FUNCTIONS(REEL_GL_LOAD)
#undef REEL_GL_LOAD
  return {};
}

}  // namespace reel::gl
