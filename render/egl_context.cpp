// EGL surfaceless context provider (EGL_MESA_platform_surfaceless through libglvnd's libEGL and
// libEGL_mesa). Without a /dev/dri render node Mesa falls back to its swrast DRI driver, i.e.
// gallium llvmpipe, the same rasterizer OSMesa uses.

#include <string>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "render/gl_context.h"

namespace corridorsim::render {
namespace {

std::string EglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    default:
      return "EGL error " + std::to_string(error);
  }
}

[[noreturn]] void ThrowEgl(const std::string& what) {
  throw RenderError("egl: " + what + " failed: " + EglErrorName(eglGetError()));
}

bool HasExtension(const char* extensions, const std::string& name) {
  if (extensions == nullptr) return false;
  const std::string list = std::string(" ") + extensions + " ";
  return list.find(" " + name + " ") != std::string::npos;
}

// The surfaceless display is one per process: eglGetPlatformDisplayEXT returns the same handle for
// every backend, and eglInitialize on an initialised display does nothing. It is never terminated:
// eglTerminate would end it for every other EGL backend, and unload the driver (with LLVM) only for
// the next backend to load it again. Mesa frees it at exit.
EGLDisplay InitializeDisplay() {
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!HasExtension(client_extensions, "EGL_EXT_platform_base") ||
      !HasExtension(client_extensions, "EGL_MESA_platform_surfaceless")) {
    throw RenderError(
        "egl: eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA) failed: "
        "EGL_MESA_platform_surfaceless is not supported by this libEGL (needs Mesa's EGL vendor: "
        "libegl-mesa0, and libgl1-mesa-dri for swrast_dri.so)");
  }
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    throw RenderError("egl: eglGetProcAddress(eglGetPlatformDisplayEXT) returned null");
  }
  EGLDisplay display =
      get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY)
    ThrowEgl("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    ThrowEgl(
        "eglInitialize(surfaceless display) (no usable Mesa driver: is swrast_dri.so installed?)");
  }
  return display;
}

class EglContext final : public GlContext {
 public:
  EglContext() {
    PinSoftwareRasterizer();
    display_ = InitializeDisplay();
    CreateContext();
  }

  ~EglContext() override {
    if (eglGetCurrentContext() == context_) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display_, context_);
  }

  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  BackendKind kind() const override { return BackendKind::kEgl; }

  void MakeCurrent() override {
    if (eglGetCurrentContext() == context_) return;  // rebinding is not free
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      ThrowEgl("eglMakeCurrent(EGL_NO_SURFACE)");
    }
  }

  GlProc GetProcAddress(const char* name) const override { return eglGetProcAddress(name); }

 private:
  void CreateContext() {
    const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
    if (!HasExtension(extensions, "EGL_KHR_surfaceless_context")) {
      throw RenderError(
          "egl: EGL_KHR_surfaceless_context is not supported by the surfaceless display");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) ThrowEgl("eglBindAPI(EGL_OPENGL_API)");

    // A context without a config where the display allows it; otherwise any desktop-GL config.
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!HasExtension(extensions, "EGL_KHR_no_config_context")) {
      const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                       EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(display_, config_attribs, &config, 1, &count) || count < 1) {
        throw RenderError("egl: no EGL config supports desktop OpenGL on the surfaceless display");
      }
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      3,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attribs);
    if (context_ == EGL_NO_CONTEXT) ThrowEgl("eglCreateContext(OpenGL 3.3 core)");
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      const std::string error = EglErrorName(eglGetError());
      eglDestroyContext(display_, context_);
      throw RenderError("egl: eglMakeCurrent(EGL_NO_SURFACE) failed: " + error);
    }
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<GlContext> CreateEglContext() { return std::make_unique<EglContext>(); }

}  // namespace corridorsim::render
