// OSMesa context provider (libOSMesa 22.x, gallium llvmpipe). OSMesa needs a client buffer to make
// a context current; a 16 x 16 one is bound and never drawn to: the renderer draws into its FBO.

#include <cstdint>
#include <string>
#include <vector>

#include <GL/osmesa.h>

#include "render/gl_context.h"
#include "render/software_rasterizer.h"

namespace corridorsim::render {

namespace {

constexpr int kBufferSize = 16;  // px, width and height of the bound client buffer

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext() : buffer_(std::size_t(kBufferSize) * kBufferSize * 4, 0) {
    RequireSoftwareRasterizerPinned("osmesa");  // llvmpipe as main() set it up
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           0,
                           OSMESA_STENCIL_BITS,
                           0,
                           OSMESA_ACCUM_BITS,
                           0,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    context_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (context_ == nullptr) {
      throw RenderError(
          "osmesa: OSMesaCreateContextAttribs(core profile 3.3) failed: this libOSMesa cannot "
          "create a GL 3.3 core context (needs Mesa's gallium OSMesa with llvmpipe)");
    }
    MakeCurrent();
  }

  ~OsMesaContext() override {
    if (OSMesaGetCurrentContext() == context_) {
      OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
    }
    OSMesaDestroyContext(context_);
  }

  OsMesaContext(const OsMesaContext&) = delete;
  OsMesaContext& operator=(const OsMesaContext&) = delete;

  BackendKind kind() const override { return BackendKind::kOsMesa; }

  void MakeCurrent() override {
    // Rebinding a current context is not free (Mesa revalidates the framebuffer): skip it.
    if (OSMesaGetCurrentContext() == context_) return;
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kBufferSize, kBufferSize)) {
      throw RenderError("osmesa: OSMesaMakeCurrent failed");
    }
  }

  GlProc GetProcAddress(const char* name) const override { return OSMesaGetProcAddress(name); }

  std::string device() const override { return "software: OSMesa"; }

 private:
  std::vector<std::uint8_t> buffer_;  // RGBA client buffer OSMesa binds the context to
  OSMesaContext context_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> CreateOsMesaContext() { return std::make_unique<OsMesaContext>(); }

}  // namespace corridorsim::render
