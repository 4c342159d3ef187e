#include "render/backend.h"

#include <stdexcept>

#include "common/enum_names.h"
#include "render/gl_context.h"
#include "render/gl_renderer.h"

namespace corridorsim::render {

std::string BackendName(BackendKind kind) { return NameOf(kBackendKindNames, kind); }

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
