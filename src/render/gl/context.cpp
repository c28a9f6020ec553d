#include "render/gl/context.h"

#include <dlfcn.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

namespace reel::gl {

bool parseBackend(const std::string& s, Backend& out) {
  if (s == "auto") out = Backend::Auto;
  else if (s == "osmesa") out = Backend::OSMesa;
  else if (s == "egl") out = Backend::Egl;
  else return false;
  return true;
}

Status Context::finishInit(ProcLoader load) {
  if (Status st = loadGlApi(load, api_); !st) return st;
  auto str = [&](GLenum e) {
    const auto* s = reinterpret_cast<const char*>(api_.GetString(e));
    return std::string(s ? s : "?");
  };
  renderer_ = str(GL_RENDERER);
  version_ = str(GL_VERSION);
  GLint major = 0, minor = 0;
  api_.GetIntegerv(GL_MAJOR_VERSION, &major);
  api_.GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33)
    return Error(ErrorKind::Internal, "OpenGL " + version_ + " is older than the 3.3 core reel needs");
  return {};
}

namespace {

// A shared library kept loaded for the life of the process (RTLD_NODELETE): GL drivers keep
// threads and caches that do not survive being unloaded.
struct Library {
  void* h = nullptr;
  explicit Library(std::initializer_list<const char*> names) {
    for (const char* n : names)
      if ((h = dlopen(n, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE))) break;
  }
  ~Library() {
    if (h) dlclose(h);  // drops the reference; the code stays mapped
  }
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;
  template <class F>
  F sym(const char* name) const {
    return reinterpret_cast<F>(dlsym(h, name));
  }
};

// --- OSMesa ------------------------------------------------------------------------------------
// The few OSMesa entry points and constants (GL/osmesa.h), declared here so that building needs
// no OSMesa header either.
using OSMesaContextH = void*;
using PfnCreateContextAttribs = OSMesaContextH (*)(const int*, OSMesaContextH);
using PfnMakeCurrent = unsigned char (*)(OSMesaContextH, void*, unsigned int, int, int);
using PfnDestroyContext = void (*)(OSMesaContextH);
using PfnGetProcAddress = void* (*)(const char*);
constexpr int kOSMesaFormat = 0x22, kOSMesaRgba = 0x1908, kOSMesaDepthBits = 0x30, kOSMesaProfile = 0x33,
              kOSMesaCoreProfile = 0x34, kOSMesaMajor = 0x36, kOSMesaMinor = 0x37;

PfnGetProcAddress g_osmesa_proc = nullptr;  // set before loading, used only by the loader below
void* osmesaLoader(const char* name) { return g_osmesa_proc(name); }

class OSMesaContext final : public Context {
 public:
  const char* backend() const override { return "osmesa"; }
  ~OSMesaContext() override {
    if (ctx_) destroy_(ctx_);
  }
  Status init() {
    if (!lib_.h) return Error(ErrorKind::Internal, "OSMesa is not installed (libOSMesa.so.8 not found)");
    auto create = lib_.sym<PfnCreateContextAttribs>("OSMesaCreateContextAttribs");
    make_ = lib_.sym<PfnMakeCurrent>("OSMesaMakeCurrent");
    destroy_ = lib_.sym<PfnDestroyContext>("OSMesaDestroyContext");
    auto proc = lib_.sym<PfnGetProcAddress>("OSMesaGetProcAddress");
    if (!create || !make_ || !destroy_ || !proc)
      return Error(ErrorKind::Internal, "OSMesa library lacks OSMesaCreateContextAttribs");
    for (int major : {4, 3}) {
      const int attribs[] = {kOSMesaFormat, kOSMesaRgba, kOSMesaDepthBits, 24, kOSMesaProfile, kOSMesaCoreProfile,
                             kOSMesaMajor, major, kOSMesaMinor, major == 4 ? 5 : 3, 0};
      if ((ctx_ = create(attribs, nullptr))) break;
    }
    if (!ctx_) return Error(ErrorKind::Internal, "OSMesa could not create an OpenGL 3.3 core context");
    if (Status st = makeCurrent(); !st) return st;
    g_osmesa_proc = proc;
    return finishInit(osmesaLoader);
  }
  Status makeCurrent() override {
    // OSMesa wants a colour buffer; reel draws into its own FBO, so a tiny one is enough.
    if (!make_(ctx_, dummy_, 0x1401 /*GL_UNSIGNED_BYTE*/, 4, 4))
      return Error(ErrorKind::Internal, "OSMesaMakeCurrent failed");
    return {};
  }

 private:
  Library lib_{"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};
  OSMesaContextH ctx_ = nullptr;
  PfnMakeCurrent make_ = nullptr;
  PfnDestroyContext destroy_ = nullptr;
  unsigned char dummy_[4 * 4 * 4] = {};
};

// --- EGL ---------------------------------------------------------------------------------------
PFNEGLGETPROCADDRESSPROC g_egl_proc = nullptr;
void* eglLoader(const char* name) { return reinterpret_cast<void*>(g_egl_proc(name)); }

class EglContext final : public Context {
 public:
  const char* backend() const override { return "egl"; }
  ~EglContext() override {
    if (dpy_) {
      if (ctx_) {
        make_(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        destroyCtx_(dpy_, ctx_);
      }
      // The display stays initialised: EGL displays are shared by the whole process, and
      // terminating one unloads the driver under any other context of it.
    }
  }
  Status init() {
    if (!lib_.h) return Error(ErrorKind::Internal, "EGL is not installed (libEGL.so.1 not found)");
    g_egl_proc = lib_.sym<PFNEGLGETPROCADDRESSPROC>("eglGetProcAddress");
    auto initialize = lib_.sym<PFNEGLINITIALIZEPROC>("eglInitialize");
    auto bind = lib_.sym<PFNEGLBINDAPIPROC>("eglBindAPI");
    auto choose = lib_.sym<PFNEGLCHOOSECONFIGPROC>("eglChooseConfig");
    auto create = lib_.sym<PFNEGLCREATECONTEXTPROC>("eglCreateContext");
    make_ = lib_.sym<PFNEGLMAKECURRENTPROC>("eglMakeCurrent");
    destroyCtx_ = lib_.sym<PFNEGLDESTROYCONTEXTPROC>("eglDestroyContext");
    terminate_ = lib_.sym<PFNEGLTERMINATEPROC>("eglTerminate");
    if (!g_egl_proc || !initialize || !bind || !choose || !create || !make_ || !destroyCtx_ || !terminate_)
      return Error(ErrorKind::Internal, "the EGL library lacks EGL 1.4 entry points");
    auto platformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(g_egl_proc("eglGetPlatformDisplayEXT"));
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(g_egl_proc("eglQueryDevicesEXT"));
    if (!platformDisplay) return Error(ErrorKind::Internal, "EGL lacks EGL_EXT_platform_base");
    // Surfaceless first (Mesa), then the first device (GPU drivers).
    std::string why;
    for (int attempt = 0; attempt < 2 && !ctx_; ++attempt) {
      if (attempt == 0) {
        dpy_ = platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      } else {
        EGLDeviceEXT dev[8];
        EGLint n = 0;
        if (!queryDevices || !queryDevices(8, dev, &n) || n < 1) break;
        dpy_ = platformDisplay(EGL_PLATFORM_DEVICE_EXT, dev[0], nullptr);
      }
      EGLint maj = 0, min = 0;
      if (!dpy_ || !initialize(dpy_, &maj, &min)) {
        dpy_ = nullptr;
        continue;
      }
      if (!bind(EGL_OPENGL_API)) continue;
      const EGLint cfg_attr[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLConfig cfg = nullptr;
      EGLint ncfg = 0;
      if (!choose(dpy_, cfg_attr, &cfg, 1, &ncfg) || ncfg < 1) cfg = nullptr;  // EGL_KHR_no_config_context
      for (int major : {4, 3}) {
        const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, major == 4 ? 5 : 3,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        if ((ctx_ = create(dpy_, cfg, EGL_NO_CONTEXT, ctx_attr))) break;
      }
      if (!ctx_) {
        terminate_(dpy_);
        dpy_ = nullptr;
      }
    }
    if (!ctx_) return Error(ErrorKind::Internal, "EGL could not create an OpenGL 3.3 core context without a display");
    if (Status st = makeCurrent(); !st) return st;
    return finishInit(eglLoader);
  }
  Status makeCurrent() override {
    if (!make_(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_))
      return Error(ErrorKind::Internal, "eglMakeCurrent without a surface failed");
    return {};
  }

 private:
  Library lib_{"libEGL.so.1", "libEGL.so"};
  EGLDisplay dpy_ = nullptr;
  EGLContext ctx_ = nullptr;
  PFNEGLMAKECURRENTPROC make_ = nullptr;
  PFNEGLDESTROYCONTEXTPROC destroyCtx_ = nullptr;
  PFNEGLTERMINATEPROC terminate_ = nullptr;
};

template <class C>
Result<std::unique_ptr<Context>> tryCreate() {
  auto c = std::make_unique<C>();
  if (Status st = c->init(); !st) return st.error();
  return std::unique_ptr<Context>(std::move(c));
}

}  // namespace

Result<std::unique_ptr<Context>> createContext(Backend b) {
  if (b == Backend::OSMesa) return tryCreate<OSMesaContext>();
  if (b == Backend::Egl) return tryCreate<EglContext>();
  auto os = tryCreate<OSMesaContext>();
  if (os.ok()) return os;
  auto egl = tryCreate<EglContext>();
  if (egl.ok()) return egl;
  return Error(ErrorKind::Internal, "no OpenGL backend: " + os.error().headline() + "; " + egl.error().headline());
}

std::vector<BackendInfo> probeBackends() {
  std::vector<BackendInfo> out;
  for (Backend b : {Backend::OSMesa, Backend::Egl}) {
    BackendInfo i;
    i.name = b == Backend::OSMesa ? "osmesa" : "egl";
    auto c = createContext(b);
    i.ok = c.ok();
    i.detail = c.ok() ? c.value()->renderer() + ", OpenGL " + c.value()->version() : c.error().headline();
    out.push_back(i);
  }
  return out;
}

}  // namespace reel::gl
