// A headless OpenGL context behind one small interface, two backends:
//  - OSMesa (Mesa's off-screen library; Mesa 25.1 removed it upstream, so it is loaded with
//    dlopen at run time and the binary runs without it);
//  - EGL without a display (surfaceless platform, or the device platform), llvmpipe here and a
//    real GPU where there is one.
// Drawing always goes to reel's own framebuffer object, so both give the same pixels.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "render/gl/api.h"

namespace reel::gl {

enum class Backend { Auto, OSMesa, Egl };

// "auto" | "osmesa" | "egl"; nullopt-like failure returns false.
bool parseBackend(const std::string& s, Backend& out);

class Context {
 public:
  virtual ~Context() = default;
  virtual const char* backend() const = 0;  // "osmesa" | "egl"
  // Makes the context current on the calling thread.
  virtual Status makeCurrent() = 0;
  const GlApi& api() const { return api_; }
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }

 protected:
  Status finishInit(ProcLoader load);  // loads GlApi, reads renderer and version
  GlApi api_;
  std::string renderer_, version_;
};

// Creates a context with OpenGL 3.3 core or newer. Auto tries OSMesa, then EGL; a backend that
// is named and fails is an error, never a silent fallback.
Result<std::unique_ptr<Context>> createContext(Backend b);

// Which backends can be loaded on this machine, with their renderer and version or the reason
// they cannot (for `reel info`).
struct BackendInfo {
  std::string name;
  bool ok = false;
  std::string detail;  // "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6" or why not
};
std::vector<BackendInfo> probeBackends();

}  // namespace reel::gl
