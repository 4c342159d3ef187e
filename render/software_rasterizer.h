#pragma once
// Mesa's software rasterizer as corridorsim renders with it: llvmpipe (softpipe gives different
// images), GPU-like texture LOD, and no rasterizer threads. Mesa reads these from environment
// variables, and setenv beside a getenv on another thread is undefined behaviour, so a program
// that renders sets them once, first thing in main(), before any thread exists: the corridorsim
// program (harness/cli/main.cpp), the test binaries that render (a Catch2 listener,
// tests/support/software_rasterizer_listener.cpp), bench_* and render_probe. The backends never
// set them; a software context made before PinSoftwareRasterizer is a RenderError
// (docs/rendering.md, "Mesa's environment").

#include <optional>
#include <string>

#include "render/backend.h"

namespace corridorsim::render {

/// llvmpipe's texture-sampling shortcuts corridorsim asks for unless GALLIVM_PERF is set.
inline constexpr const char* kDefaultGallivmPerf = "brilinear,rho_approx";

/// llvmpipe's rasterizer threads unless LP_NUM_THREADS is set: none (it draws on the calling
/// thread). Mesa 22.3's llvmpipe can free a fence its rasterizer thread is still signalling.
inline constexpr const char* kDefaultLlvmpipeThreads = "0";

/// Pins Mesa's software rasterizer to llvmpipe (softpipe gives different images) unless the user
/// set GALLIUM_DRIVER already, sets GALLIVM_PERF to kDefaultGallivmPerf unless it is set
/// (empty: llvmpipe's exact trilinear LOD and filter) and LP_NUM_THREADS to
/// kDefaultLlvmpipeThreads unless it is set. Call it first thing in main(), before any thread
/// exists and before any backend is created. It leaves LIBGL_ALWAYS_SOFTWARE alone: only Mesa's
/// EGL platforms read it (the EGL backend sets it before it opens the surfaceless display), and
/// the EGL backend reads it as a request for software, so setting it here would keep the EGL
/// backend off the GPU.
void PinSoftwareRasterizer();

/// Whether PinSoftwareRasterizer has run in this process.
bool SoftwareRasterizerPinned();

/// What the backends call before they create a software context: throws RenderError, naming
/// `backend` ("osmesa", "egl"), when PinSoftwareRasterizer has not run (the context would render
/// with Mesa's defaults: other images, and llvmpipe's racing rasterizer threads).
void RequireSoftwareRasterizerPinned(const std::string& backend);

/// GALLIVM_PERF as it applies to the images of `backend` (provenance.json, bench_render): with
/// Mesa's software rasterizer (a device "software: ..."), the variable as set now; on a GPU or
/// when nothing was rendered (`backend` null), the value the user set, or nothing when only
/// PinSoftwareRasterizer set it (gallivm is llvmpipe's: a GPU ignores it).
std::optional<std::string> GallivmPerfInEffect(const Backend* backend);

}  // namespace corridorsim::render
