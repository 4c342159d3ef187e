#pragma once
// Off-screen GL context providers for the GL backends: each creates a core-profile context of its
// own (OSMesa or EGL surfaceless, both Mesa llvmpipe) and hands out GL entry points through its own
// GetProcAddress. Internal to render/; users go through render::CreateBackend.

#include <memory>

#include "render/backend.h"

namespace corridorsim::render {

/// A GL entry point as the context's GetProcAddress returns it (cast to the PFNGL...PROC type).
using GlProc = void (*)();

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual BackendKind kind() const = 0;
  /// Makes this context current on the calling thread; throws RenderError when that fails.
  virtual void MakeCurrent() = 0;
  /// The entry point `name` ("glDrawElements"), or nullptr when the context has none.
  virtual GlProc GetProcAddress(const char* name) const = 0;
};

/// OSMesa core 3.3+ context bound to a small client buffer (the backend draws into its own FBO).
/// Throws RenderError ("osmesa: ...") when it cannot be created.
std::unique_ptr<GlContext> CreateOsMesaContext();

/// EGL surfaceless (EGL_MESA_platform_surfaceless) core 3.3+ desktop GL context, made current
/// without a surface. Throws RenderError ("egl: ...") when it cannot be created.
std::unique_ptr<GlContext> CreateEglContext();

/// llvmpipe's texture-sampling shortcuts corridorsim asks for unless GALLIVM_PERF is set.
inline constexpr const char* kDefaultGallivmPerf = "brilinear,rho_approx";

/// Pins Mesa to llvmpipe (softpipe and hardware drivers give different images) unless the user
/// set GALLIUM_DRIVER / LIBGL_ALWAYS_SOFTWARE already, and sets GALLIVM_PERF to
/// kDefaultGallivmPerf unless it is set (empty: llvmpipe's exact trilinear LOD and filter).
/// Called before any context is created.
void PinSoftwareRasterizer();

}  // namespace corridorsim::render
