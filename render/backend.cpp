#include "render/backend.h"

#include <cstdlib>
#include <stdexcept>

#include "render/gl_context.h"
#include "render/gl_renderer.h"

namespace corridorsim::render {

std::string BackendName(BackendKind kind) {
  switch (kind) {
    case BackendKind::kOsMesa:
      return "osmesa";
    case BackendKind::kEgl:
      return "egl";
  }
  return "unknown";
}

void PinSoftwareRasterizer() {
  // llvmpipe only: softpipe gives different images, and so would a hardware driver picked up
  // through a render node. overwrite = 0: a value the user set wins.
  setenv("GALLIUM_DRIVER", "llvmpipe", 0);
  setenv("LIBGL_ALWAYS_SOFTWARE", "1", 0);
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
