#include "render/backend.h"

#include <cstdlib>
#include <stdexcept>

#include "common/enum_names.h"
#include "render/gl_context.h"
#include "render/gl_renderer.h"

namespace corridorsim::render {

std::string BackendName(BackendKind kind) { return NameOf(kBackendKindNames, kind); }

void PinSoftwareRasterizer() {
  // llvmpipe only: softpipe gives different images. overwrite = 0: a value the user set wins.
  // LIBGL_ALWAYS_SOFTWARE is the EGL backend's to set, only when it takes Mesa's surfaceless
  // platform (render/gl_context.h).
  setenv("GALLIUM_DRIVER", "llvmpipe", 0);
  // Texture LOD as GPUs compute it: the mip level from the largest derivative component instead
  // of the Euclidean length (an approximation the GL options allows), and two levels blended only
  // near a level change ("brilinear", what GPU drivers do for trilinear by default). 8 % less
  // time per noisy rig frame (median of eight alternated runs each way, 3-19 %); a front image
  // changes by 0.3 DN on average, labels and depth not at all. GALLIVM_PERF= (empty) gives
  // llvmpipe's exact trilinear filter. gallivm reads it once, when the first context is made.
  setenv("GALLIVM_PERF", kDefaultGallivmPerf, 0);
  // llvmpipe rasterises on the calling thread: its rasterizer threads race with the thread that
  // draws. In Mesa 22.3 (Debian 12) a rasterizer thread signals a scene's fence by count++ under
  // the fence's mutex, then broadcasts its condition variable and unlocks; the drawing thread
  // reads the count without the mutex (lp_fence_signalled, in lp_setup_get_empty_scene), recycles
  // the scene and, once the next scene replaces setup->last_fence, frees the fence while the
  // rasterizer thread can still be inside the broadcast. Freed memory written to: a rare heap
  // corruption or a hang (docs/rendering.md, "llvmpipe's rasterizer threads"). The images are the
  // same byte for byte with any thread count (test render.lp_threads_identical), and the rig's
  // SerialWorker and the pipelines' threads keep the other cores busy meanwhile.
  setenv("LP_NUM_THREADS", kDefaultLlvmpipeThreads, 0);
}

std::unique_ptr<Backend> CreateBackend(BackendKind kind) {
  switch (kind) {
    case BackendKind::kOsMesa:
      return std::make_unique<GlBackend>(CreateOsMesaContext());
    case BackendKind::kEgl:
      return std::make_unique<GlBackend>(CreateEglContext());
  }
  throw std::invalid_argument("render: unknown backend kind");
}

}  // namespace corridorsim::render
