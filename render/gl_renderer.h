#pragma once
// The one GL renderer behind both backends (OSMesa and EGL provide only the context): GLSL 330
// core shaders (render/gl_shaders.h), the scene in one VBO + IBO, mip-mapped textures, and an FBO
// with colour, instance id, semantic class and view-space z attachments read back top-down.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "render/backend.h"
#include "render/gl_context.h"
#include "render/gl_functions.h"

namespace corridorsim::render {

inline constexpr int kMaxLightsPerDraw = 16;

class GlBackend final : public Backend {
 public:
  /// Takes a fresh context, loads GL through it and builds the shaders. Throws RenderError.
  explicit GlBackend(std::unique_ptr<GlContext> context);
  ~GlBackend() override;
  GlBackend(const GlBackend&) = delete;
  GlBackend& operator=(const GlBackend&) = delete;

  BackendKind kind() const override { return context_->kind(); }
  BackendInfo info() const override { return info_; }
  void Upload(const Scene& scene) override;
  void Draw(const View& view, std::span<const int> drawables, std::span<const int> lights,
            RenderedView* out) override;
  void DrawPasses(std::span<const DrawRequest> requests) override;
  int max_view_px() const override { return max_view_px_; }

 private:
  // What Draw needs of the uploaded scene.
  struct DrawRange {
    std::uint32_t first_index = 0;
    std::uint32_t index_count = 0;
    int material = 0;
    std::uint32_t instance_id = 0;
    std::uint8_t semantic_class = 0;
    Eigen::AlignedBox3f bounds;  // world frame, for drawing front to back
  };
  // One linked shader program (for one light count) and its uniform locations.
  struct Program {
    GLuint id = 0;
    GLint camera_from_world = -1, clip_from_camera = -1;
    GLint diffuse = -1, emission = -1, has_texture = -1, texture = -1;
    GLint inv_falloff2 = -1, exposure = -1, light_position = -1, light_intensity = -1;
    GLint instance = -1, semantic = -1;
  };

  /// Compiles and links a program; throws RenderError with the compiler's log.
  GLuint LinkProgram(const std::string& vertex_source, const std::string& fragment_source);
  /// The program for `light_count` lights, compiled on first use.
  const Program& ProgramFor(int light_count);
  /// The framebuffer for a pass of this size at position `slot` of a batch (created on first
  /// use; kept, so a rig's passes reuse theirs every frame).
  GLuint EnsureFramebuffer(int width, int height, int slot);
  /// Throws std::invalid_argument (std::logic_error before Upload) for a request it cannot draw.
  void Check(const DrawRequest& request) const;
  /// Clears the slot's framebuffer and issues the draw calls of one pass (no wait).
  void Submit(const DrawRequest& request, int slot);
  /// Sets depth 0 over request.unused, so that the scene is not shaded there.
  void DrawUnusedMask(const DrawRequest& request);
  /// Reads the slot's images into request.out (waits for the rasteriser).
  void ReadBack(const DrawRequest& request, int slot);
  void DeleteTextures();
  void CheckGlError(const char* where);
  [[noreturn]] void Fail(const std::string& what) const;

  std::unique_ptr<GlContext> context_;  // declared first: destroyed after the GL objects
  GlFunctions gl_;
  BackendInfo info_;
  std::array<Program, kMaxLightsPerDraw + 1> programs_{};  // by light count
  int max_view_px_ = 0;     // GL_MAX_RENDERBUFFER_SIZE and GL_MAX_VIEWPORT_DIMS
  int max_texture_px_ = 0;  // GL_MAX_TEXTURE_SIZE
  GLuint vao_ = 0, vbo_ = 0, ibo_ = 0;
  GLuint mask_program_ = 0, mask_vao_ = 0, mask_vbo_ = 0;  // DrawUnusedMask
  // Off-screen targets by size and batch slot: a rig alternates between pass sizes every frame,
  // so each keeps its own framebuffer instead of reallocating storage per draw.
  struct Target {
    int width = 0, height = 0;  // px
    int slot = 0;               // position in a DrawPasses batch
    GLuint fbo = 0;
    std::array<GLuint, 5> renderbuffers{};  // colour, instance, class, z, depth
  };
  std::vector<Target> targets_;

  bool uploaded_ = false;
  std::vector<GLuint> textures_;
  std::vector<SceneMaterial> materials_;
  std::vector<DrawRange> drawables_;
  std::vector<PointLight> lights_;
  SceneOptions options_;

  std::vector<std::pair<float, int>> order_;  // draw order of one Draw, reused across frames
  std::vector<float> mask_vertices_;          // DrawUnusedMask's triangles, reused
};

}  // namespace corridorsim::render
