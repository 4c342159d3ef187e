#include "render/software_rasterizer.h"

#include <atomic>
#include <cstdlib>
#include <cstring>

namespace corridorsim::render {

namespace {

// Written by the first PinSoftwareRasterizer, before any thread exists; read afterwards.
std::atomic<bool> pinned{false};
// GALLIVM_PERF was unset when the first PinSoftwareRasterizer ran, so the value is ours.
std::atomic<bool> gallivm_perf_ours{false};

}  // namespace

// Set beside GALLIVM_PERF when PinSoftwareRasterizer chose its value, so that a corridorsim child
// (a study's run, a test's job) that inherits the variable knows it as corridorsim's, not the
// user's: its provenance then says what a run started on its own says.
constexpr const char* kPinnedMarker = "CORRIDORSIM_PINNED_GALLIVM_PERF";

void PinSoftwareRasterizer() {
  if (!pinned.load()) {
    const char* value = std::getenv("GALLIVM_PERF");
    const char* marker = std::getenv(kPinnedMarker);
    gallivm_perf_ours.store(value == nullptr ||
                            (marker != nullptr && std::strcmp(marker, value) == 0));
  }
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
  if (gallivm_perf_ours.load()) setenv(kPinnedMarker, std::getenv("GALLIVM_PERF"), 1);
  pinned.store(true);
}

bool SoftwareRasterizerPinned() { return pinned.load(); }

void RequireSoftwareRasterizerPinned(const std::string& backend) {
  if (pinned.load()) return;
  throw RenderError(backend +
                    ": Mesa's software rasterizer is not pinned: call "
                    "corridorsim::render::PinSoftwareRasterizer() first thing in main(), before "
                    "any thread exists (render/software_rasterizer.h)");
}

std::optional<std::string> GallivmPerfInEffect(const Backend* backend) {
  const bool software = backend != nullptr && backend->info().device.rfind("software", 0) == 0;
  if (!software && pinned.load() && gallivm_perf_ours.load()) return std::nullopt;
  const char* value = std::getenv("GALLIVM_PERF");
  return value != nullptr ? std::optional<std::string>(value) : std::nullopt;
}

}  // namespace corridorsim::render
