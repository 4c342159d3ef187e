#pragma once
// GL backends behind one interface (MuJoCo's mjr_ side): they only draw a render::Scene.
// OSMesa (libosmesa6, llvmpipe) and EGL (a hardware EGL device when there is one, else Mesa
// surfaceless with llvmpipe); on llvmpipe the same scene and view give the same images within a
// small tolerance (docs/rendering.md, "GPU rendering").

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/enum_names.h"
#include "common/image.h"
#include "render/scene.h"

namespace corridorsim::render {

/// What one pinhole pass produces. Rows are top-down (row 0 = top of the image).
struct RenderedView {
  Image8 rgb;                           // RGB, 8 bit, lit and shaded
  ImageF depth_m;                       // z along the optical axis (m), 0 where nothing was hit
  std::vector<std::uint32_t> instance;  // width * height instance ids, 0 = nothing
  std::vector<std::uint8_t> semantic;   // width * height worlds::SemanticClass values
};

enum class BackendKind { kOsMesa, kEgl };
inline constexpr EnumName<BackendKind> kBackendKindNames[] = {{BackendKind::kOsMesa, "osmesa"},
                                                              {BackendKind::kEgl, "egl"}};
std::string BackendName(BackendKind kind);  // "osmesa", "egl"

/// A context or GL resource that cannot be created: names the backend and what is missing.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Pixels [x0, x1) x [y0, y1) of a pass image (rows top-down).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// One pass of a batch: what to draw from where, and where its images go.
struct DrawRequest {
  View view;
  std::span<const int> drawables;  // indices into the uploaded scene's drawables
  std::span<const int> lights;     // indices into scene.lights, at most 16
  RenderedView* out = nullptr;
  /// Pixels of the pass that nobody reads (a fisheye's remap samples only part of its cropped
  /// cube faces): the backend may leave them unshaded, so their values are unspecified. Every
  /// other pixel is exactly what it would be without them.
  std::span<const PixelRect> unused = {};
  /// The camera's exposure gain: colour = clamp(exposure * (albedo * light + emission)).
  float exposure = 1.0f;
};

/// The context's GL strings (glGetString), which the images depend on besides the scene: the
/// renderer names llvmpipe and its LLVM (or the GPU), the version the Mesa release or the GPU
/// driver's (provenance.json); and which device the backend chose, and why.
struct BackendInfo {
  std::string vendor;    // GL_VENDOR
  std::string renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;   // GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6"
  /// "hardware: EGL device 1 (/dev/dri/renderD128) (why)" or "software: ... (why)", e.g.
  /// "software: Mesa surfaceless platform, EGL_PLATFORM_SURFACELESS_MESA (no hardware EGL
  /// device: ...)" or "software: OSMesa". Defaulted, so that a backend naming only the GL
  /// strings stays valid.
  std::string device = {};
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual BackendKind kind() const = 0;
  virtual BackendInfo info() const = 0;
  /// Uploads geometry, materials, textures (once per scene; replaces an earlier scene).
  virtual void Upload(const Scene& scene) = 0;
  /// Draws `drawables` (indices into the uploaded scene's drawables) from `view` into `out`,
  /// lit by the lights listed in `lights` (indices into scene.lights, at most 16).
  virtual void Draw(const View& view, std::span<const int> drawables, std::span<const int> lights,
                    RenderedView* out) = 0;
  /// Draws several passes, each as Draw would (the same images), then reads them back: a
  /// backend may overlap one pass's drawing with the next one's submission. Every request is
  /// checked before anything is drawn.
  virtual void DrawPasses(std::span<const DrawRequest> requests) = 0;
  /// The largest pass side (px) it draws: GL_MAX_RENDERBUFFER_SIZE and GL_MAX_VIEWPORT_DIMS,
  /// queried once. The Rig refuses a camera that needs more when it is made, before any frame.
  virtual int max_view_px() const = 0;
};

/// Creates a backend with its own off-screen context. Throws RenderError naming the backend and
/// what is missing when the context cannot be created.
std::unique_ptr<Backend> CreateBackend(BackendKind kind);

}  // namespace corridorsim::render
