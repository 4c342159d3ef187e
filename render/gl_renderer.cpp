#include "render/gl_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <optional>
#include <stdexcept>
#include <string>

#include "render/gl_shaders.h"

namespace corridorsim::render {
namespace {

// Column-major 4x4 clip_from_camera for the OpenCV pinhole model. GL window pixel centres
// (i + 0.5, j + 0.5) map to (u, v) = (i, j), and window row j is image row j: the y axis is not
// flipped, so glReadPixels' bottom-up rows come back as top-down image rows with no copy.
std::array<float, 16> ClipFromCamera(const View& view) {
  const double w = view.width, h = view.height, n = view.near_m, f = view.far_m;
  std::array<float, 16> m{};
  m[0] = float(2.0 * view.fx / w);
  m[5] = float(2.0 * view.fy / h);
  m[8] = float(2.0 * (view.cx + 0.5) / w - 1.0);
  m[9] = float(2.0 * (view.cy + 0.5) / h - 1.0);
  m[10] = float((f + n) / (f - n));
  m[11] = 1.0f;
  m[14] = float(-2.0 * f * n / (f - n));
  return m;
}

std::array<float, 16> CameraFromWorld(const View& view) {
  const Eigen::Matrix4f m = view.world_from_camera.Inverse().ToMatrix().cast<float>();
  std::array<float, 16> out{};
  std::memcpy(out.data(), m.data(), sizeof(out));  // Eigen is column-major, like GL
  return out;
}

GLenum TextureFormat(int channels) {
  switch (channels) {
    case 1:
      return GL_RED;
    case 3:
      return GL_RGB;
    default:
      return GL_RGBA;
  }
}

// llvmpipe's draw module allocates and frees a vertex buffer on every draw call. With glibc's
// defaults each free at the top of the heap trims it and the next allocation faults its pages in
// again: with small images, where little else happens per draw, that was 90 % of a frame
// (64 x 48 front camera: 35 ms instead of 3.5 ms). Freed memory up to 64 MiB stays with the
// process, and buffers up to 32 MiB come from the heap instead of mmap. Process-wide, once.
void KeepHeapPages() {
#if defined(__GLIBC__)
  static const bool done = [] {
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    return true;
  }();
  (void)done;
#endif
}

}  // namespace

GlBackend::GlBackend(std::unique_ptr<GlContext> context) : context_(std::move(context)) {
  KeepHeapPages();
  context_->MakeCurrent();
  gl_ = LoadGlFunctions(*context_);

  const auto* version = reinterpret_cast<const char*>(gl_.GetString(GL_VERSION));
  const auto gl_string = [&](GLenum name) {
    const auto* text = reinterpret_cast<const char*>(gl_.GetString(name));
    return std::string(text != nullptr ? text : "");
  };
  info_ = BackendInfo{gl_string(GL_VENDOR), gl_string(GL_RENDERER), gl_string(GL_VERSION),
                      context_->device()};
  GLint major = 0, minor = 0;
  gl_.GetIntegerv(GL_MAJOR_VERSION, &major);
  gl_.GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    Fail(std::string("needs OpenGL 3.3 core, the context is ") +
         (version != nullptr ? version : "of unknown version"));
  }

  // Size limits, once: a pass must fit a renderbuffer and the viewport, a texture the texture
  // size.
  GLint renderbuffer_px = 0, texture_px = 0;
  GLint viewport_px[2] = {0, 0};
  gl_.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer_px);
  gl_.GetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport_px);
  gl_.GetIntegerv(GL_MAX_TEXTURE_SIZE, &texture_px);
  max_view_px_ = std::min({renderbuffer_px, viewport_px[0], viewport_px[1]});
  max_texture_px_ = texture_px;

  // The richest variant now, so that a shader that does not compile fails here; others on use.
  ProgramFor(kMaxLightsPerDraw);
  gl_.GenVertexArrays(1, &vao_);
  gl_.GenBuffers(1, &vbo_);
  gl_.GenBuffers(1, &ibo_);

  // Vertex layout: SceneVertex {position[3], normal[3], uv[2], irradiance}.
  gl_.BindVertexArray(vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
  constexpr auto kStride = GLsizei(sizeof(SceneVertex));
  struct Attribute {
    GLuint location;
    GLint floats;
    std::size_t offset;
  };
  for (const Attribute& a :
       {Attribute{0, 3, offsetof(SceneVertex, position)},
        Attribute{1, 3, offsetof(SceneVertex, normal)}, Attribute{2, 2, offsetof(SceneVertex, uv)},
        Attribute{3, 3, offsetof(SceneVertex, irradiance)}}) {
    gl_.EnableVertexAttribArray(a.location);
    gl_.VertexAttribPointer(a.location, a.floats, GL_FLOAT, GL_FALSE, kStride,
                            reinterpret_cast<const void*>(a.offset));
  }

  mask_program_ = LinkProgram(kMaskVertexShader, kMaskFragmentShader);
  gl_.GenVertexArrays(1, &mask_vao_);
  gl_.GenBuffers(1, &mask_vbo_);
  gl_.BindVertexArray(mask_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, mask_vbo_);
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);

  // Fixed state: depth test, back-face culling, no blending, no dither.
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LESS);
  // Back faces are culled: every surface winds counter-clockwise seen from where it can be seen
  // (boxes from outside, plates, posters and lamps from the corridor), and solids run past the
  // floor and ceiling so seams cross instead of touching (nothing can be seen through a seam). The
  // image y axis points down (see ClipFromCamera), so a face that is counter-clockwise in the world
  // is clockwise on the window. Culling halves the triangles llvmpipe rasterises, and a silhouette
  // edge pixel now always shows the facing side.
  gl_.Enable(GL_CULL_FACE);
  gl_.CullFace(GL_BACK);
  gl_.FrontFace(GL_CW);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_DITHER);
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  CheckGlError("context setup");
}

GlBackend::~GlBackend() {
  try {
    context_->MakeCurrent();
  } catch (const RenderError&) {
    return;  // the context goes with its objects
  }
  DeleteTextures();
  for (Target& t : targets_) {
    gl_.DeleteRenderbuffers(GLsizei(t.renderbuffers.size()), t.renderbuffers.data());
    gl_.DeleteFramebuffers(1, &t.fbo);
  }
  gl_.DeleteBuffers(1, &ibo_);
  gl_.DeleteBuffers(1, &vbo_);
  gl_.DeleteVertexArrays(1, &vao_);
  gl_.DeleteBuffers(1, &mask_vbo_);
  gl_.DeleteVertexArrays(1, &mask_vao_);
  if (mask_program_ != 0) gl_.DeleteProgram(mask_program_);
  for (const Program& program : programs_) {
    if (program.id != 0) gl_.DeleteProgram(program.id);
  }
}

void GlBackend::Fail(const std::string& what) const {
  throw RenderError(BackendName(context_->kind()) + ": " + what);
}

void GlBackend::CheckGlError(const char* where) {
  std::string errors;
  for (GLenum e = gl_.GetError(); e != GL_NO_ERROR; e = gl_.GetError()) {
    errors += std::string(errors.empty() ? "" : ", ") + GlErrorName(e);
  }
  if (!errors.empty()) Fail(std::string("GL error after ") + where + ": " + errors);
}

namespace {

// Nothing when a shader compiled or a program linked (`status`: GL_COMPILE_STATUS,
// GL_LINK_STATUS), else its info log (GL's glGet*iv and glGet*InfoLog of the same object).
template <class GetIv, class GetLog>
std::optional<std::string> FailureLog(GLuint id, GLenum status, GetIv get_iv, GetLog get_log) {
  GLint ok = GL_FALSE;
  get_iv(id, status, &ok);
  if (ok == GL_TRUE) return std::nullopt;
  GLint length = 0;
  get_iv(id, GL_INFO_LOG_LENGTH, &length);
  std::string log(std::size_t(std::max(length, 1)), '\0');
  get_log(id, GLsizei(log.size()), nullptr, log.data());
  return std::string(log.c_str());  // up to the terminating zero GL wrote
}

}  // namespace

GLuint GlBackend::LinkProgram(const std::string& vertex_source,
                              const std::string& fragment_source) {
  auto compile = [&](GLenum type, const std::string& source, const char* name) {
    const GLuint shader = gl_.CreateShader(type);
    const char* text = source.c_str();
    gl_.ShaderSource(shader, 1, &text, nullptr);
    gl_.CompileShader(shader);
    if (const auto log =
            FailureLog(shader, GL_COMPILE_STATUS, gl_.GetShaderiv, gl_.GetShaderInfoLog)) {
      gl_.DeleteShader(shader);
      Fail(std::string(name) + " shader does not compile: " + *log);
    }
    return shader;
  };
  const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source, "vertex");
  GLuint fragment = 0;
  try {
    fragment = compile(GL_FRAGMENT_SHADER, fragment_source, "fragment");
  } catch (...) {
    gl_.DeleteShader(vertex);
    throw;
  }
  const GLuint id = gl_.CreateProgram();
  gl_.AttachShader(id, vertex);
  gl_.AttachShader(id, fragment);
  gl_.LinkProgram(id);
  gl_.DeleteShader(vertex);  // flagged; freed with the program
  gl_.DeleteShader(fragment);
  if (const auto log = FailureLog(id, GL_LINK_STATUS, gl_.GetProgramiv, gl_.GetProgramInfoLog)) {
    gl_.DeleteProgram(id);
    Fail(std::string("shader program does not link: ") + *log);
  }
  return id;
}

const GlBackend::Program& GlBackend::ProgramFor(int light_count) {
  Program& program = programs_[std::size_t(light_count)];
  if (program.id != 0) return program;
  const GLuint id =
      LinkProgram(kVertexShader, "#version 330 core\n#define LIGHT_COUNT " +
                                     std::to_string(light_count) + "\n" + kFragmentShader);
  program.id = id;
  auto location = [&](const char* name) { return gl_.GetUniformLocation(id, name); };
  program.camera_from_world = location("u_camera_from_world");
  program.clip_from_camera = location("u_clip_from_camera");
  program.diffuse = location("u_diffuse");
  program.emission = location("u_emission");
  program.has_texture = location("u_has_texture");
  program.texture = location("u_texture");
  program.inv_falloff2 = location("u_inv_falloff2");
  program.exposure = location("u_exposure");
  program.light_position = location("u_light_position");
  program.light_intensity = location("u_light_intensity");
  program.instance = location("u_instance");
  program.semantic = location("u_semantic");
  gl_.UseProgram(id);
  gl_.Uniform1i(program.texture, 0);
  CheckGlError("shader setup");
  return program;
}

void GlBackend::DeleteTextures() {
  if (!textures_.empty()) gl_.DeleteTextures(GLsizei(textures_.size()), textures_.data());
  textures_.clear();
}

void GlBackend::Upload(const Scene& scene) {
  // Check the scene before touching GL: a bad scene leaves the earlier upload in place.
  const std::size_t vertex_count = scene.vertices.size();
  for (std::uint32_t index : scene.indices) {
    if (index >= vertex_count) {
      throw std::invalid_argument("render scene: index " + std::to_string(index) + " is past the " +
                                  std::to_string(vertex_count) + " vertices");
    }
  }
  for (std::size_t i = 0; i < scene.drawables.size(); ++i) {
    const Drawable& d = scene.drawables[i];
    if (std::size_t(d.first_index) + d.index_count > scene.indices.size() ||
        d.index_count % 3 != 0) {
      throw std::invalid_argument("render scene: drawable " + std::to_string(i) +
                                  " has an index range outside the index buffer or not whole "
                                  "triangles");
    }
    if (d.material < 0 || std::size_t(d.material) >= scene.materials.size()) {
      throw std::invalid_argument("render scene: drawable " + std::to_string(i) +
                                  " names material " + std::to_string(d.material) + " of " +
                                  std::to_string(scene.materials.size()));
    }
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const int t = scene.materials[i].texture;
    if (t < -1 || t >= int(scene.textures.size())) {
      throw std::invalid_argument("render scene: material " + std::to_string(i) +
                                  " names texture " + std::to_string(t) + " of " +
                                  std::to_string(scene.textures.size()));
    }
  }
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const Image8& t = scene.textures[i];
    if (t.width <= 0 || t.height <= 0 || (t.channels != 1 && t.channels != 3 && t.channels != 4) ||
        t.data.size() != std::size_t(t.width) * t.height * t.channels) {
      throw std::invalid_argument("render scene: texture " + std::to_string(i) +
                                  " is empty, not 1/3/4 channels, or its data size is wrong");
    }
    if (t.width > max_texture_px_ || t.height > max_texture_px_) {
      Fail("texture " + std::to_string(i) + " of " + std::to_string(t.width) + " x " +
           std::to_string(t.height) + " px exceeds GL_MAX_TEXTURE_SIZE " +
           std::to_string(max_texture_px_) + " (world.texture_px_per_m sets texture sizes)");
    }
  }
  if (!(scene.options.light_falloff_m > 0.0f)) {
    throw std::invalid_argument("render scene: options.light_falloff_m must be positive");
  }

  context_->MakeCurrent();
  gl_.BindVertexArray(vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertex_count * sizeof(SceneVertex)),
                 scene.vertices.data(), GL_STATIC_DRAW);
  gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(scene.indices.size() * sizeof(std::uint32_t)),
                 scene.indices.data(), GL_STATIC_DRAW);

  // Textures: Image8 row 0 is the top row, GL's first row is t = 0, and UV (0,0) is the
  // bottom-left of the image: upload the rows bottom-up.
  DeleteTextures();
  textures_.resize(scene.textures.size());
  if (!textures_.empty()) gl_.GenTextures(GLsizei(textures_.size()), textures_.data());
  gl_.ActiveTexture(GL_TEXTURE0);
  std::vector<std::uint8_t> flipped;
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const Image8& image = scene.textures[i];
    const std::size_t row_bytes = std::size_t(image.width) * image.channels;
    flipped.resize(image.data.size());
    for (int y = 0; y < image.height; ++y) {
      std::memcpy(&flipped[std::size_t(image.height - 1 - y) * row_bytes],
                  &image.data[std::size_t(y) * row_bytes], row_bytes);
    }
    const GLenum format = TextureFormat(image.channels);
    gl_.BindTexture(GL_TEXTURE_2D, textures_[i]);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, image.channels == 4 ? GL_RGBA8 : GLint(GL_RGB8), image.width,
                   image.height, 0, format, GL_UNSIGNED_BYTE, flipped.data());
    if (image.channels == 1) {  // grey: replicate red into green and blue
      gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_G, GL_RED);
      gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_B, GL_RED);
    }
    gl_.GenerateMipmap(GL_TEXTURE_2D);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                      scene.options.texture_filter == TextureFilter::kNearestMip
                          ? GL_LINEAR_MIPMAP_NEAREST
                          : GL_LINEAR_MIPMAP_LINEAR);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  }
  gl_.BindTexture(GL_TEXTURE_2D, 0);

  materials_ = scene.materials;
  drawables_.clear();
  drawables_.reserve(scene.drawables.size());
  for (const Drawable& d : scene.drawables) {
    drawables_.push_back(
        {d.first_index, d.index_count, d.material, d.instance_id, d.semantic_class, d.bounds});
  }
  lights_ = scene.lights;
  options_ = scene.options;
  uploaded_ = true;
  CheckGlError("scene upload");
}

GLuint GlBackend::EnsureFramebuffer(int width, int height, int slot) {
  for (const Target& t : targets_) {
    if (t.width == width && t.height == height && t.slot == slot) return t.fbo;
  }
  // colour, instance id, semantic class, view-space z, depth
  constexpr std::array<GLenum, 5> kFormats = {GL_RGBA8, GL_R32UI, GL_R8UI, GL_R32F,
                                              GL_DEPTH_COMPONENT32F};
  Target t;
  t.width = width;
  t.height = height;
  t.slot = slot;
  gl_.GenFramebuffers(1, &t.fbo);
  gl_.GenRenderbuffers(GLsizei(t.renderbuffers.size()), t.renderbuffers.data());
  gl_.BindFramebuffer(GL_FRAMEBUFFER, t.fbo);
  for (std::size_t i = 0; i < kFormats.size(); ++i) {
    gl_.BindRenderbuffer(GL_RENDERBUFFER, t.renderbuffers[i]);
    gl_.RenderbufferStorage(GL_RENDERBUFFER, kFormats[i], width, height);
    const GLenum attachment =
        i + 1 < kFormats.size() ? GLenum(GL_COLOR_ATTACHMENT0 + i) : GLenum(GL_DEPTH_ATTACHMENT);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, t.renderbuffers[i]);
  }
  constexpr std::array<GLenum, 4> kDrawBuffers = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
                                                  GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
  gl_.DrawBuffers(GLsizei(kDrawBuffers.size()), kDrawBuffers.data());
  const GLenum status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    gl_.DeleteRenderbuffers(GLsizei(t.renderbuffers.size()), t.renderbuffers.data());
    gl_.DeleteFramebuffers(1, &t.fbo);
    Fail("framebuffer (RGBA8, R32UI, R8UI, R32F, depth 32F) is incomplete: status 0x" + [&] {
      char hex[16];
      std::snprintf(hex, sizeof(hex), "%x", status);
      return std::string(hex);
    }());
  }
  targets_.push_back(t);
  CheckGlError("framebuffer setup");
  return t.fbo;
}

void GlBackend::Draw(const View& view, std::span<const int> drawables, std::span<const int> lights,
                     RenderedView* out) {
  const DrawRequest request{view, drawables, lights, out};
  DrawPasses(std::span<const DrawRequest>(&request, 1));
}

void GlBackend::DrawPasses(std::span<const DrawRequest> requests) {
  for (const DrawRequest& request : requests) Check(request);
  context_->MakeCurrent();
  const int max_size = max_view_px_;
  for (const DrawRequest& request : requests) {
    if (request.view.width > max_size || request.view.height > max_size) {
      throw std::invalid_argument("render: view size " + std::to_string(request.view.width) +
                                  " x " + std::to_string(request.view.height) +
                                  " exceeds the GL limit " + std::to_string(max_size));
    }
  }
  // Every pass into a framebuffer of its own, then the read-backs: llvmpipe rasterises a pass on
  // its threads while this thread transforms and bins the next one.
  for (std::size_t i = 0; i < requests.size(); ++i) Submit(requests[i], int(i));
  CheckGlError("draw");
  for (std::size_t i = 0; i < requests.size(); ++i) ReadBack(requests[i], int(i));
}

void GlBackend::Check(const DrawRequest& request) const {
  const View& view = request.view;
  const std::span<const int> drawables = request.drawables, lights = request.lights;
  if (request.out == nullptr) throw std::invalid_argument("render: Draw needs an output view");
  if (view.width <= 0 || view.height <= 0) {
    throw std::invalid_argument("render: view size must be positive, got " +
                                std::to_string(view.width) + " x " + std::to_string(view.height));
  }
  if (!(view.fx > 0) || !(view.fy > 0) || !std::isfinite(view.cx) || !std::isfinite(view.cy)) {
    throw std::invalid_argument("render: view focal lengths must be positive and finite");
  }
  if (!(view.near_m > 0) || !(view.far_m > view.near_m) || !std::isfinite(view.far_m)) {
    throw std::invalid_argument("render: view needs 0 < near_m < far_m");
  }
  if (lights.size() > std::size_t(kMaxLightsPerDraw)) {
    throw std::invalid_argument("render: at most 16 lights per draw, got " +
                                std::to_string(lights.size()));
  }
  if (!uploaded_) throw std::logic_error("render: Draw before Upload");
  for (int d : drawables) {
    if (d < 0 || std::size_t(d) >= drawables_.size()) {
      throw std::invalid_argument("render: drawable index " + std::to_string(d) + " out of range");
    }
  }
  for (int l : lights) {
    if (l < 0 || std::size_t(l) >= lights_.size()) {
      throw std::invalid_argument("render: light index " + std::to_string(l) + " out of range");
    }
  }
  for (const PixelRect& r : request.unused) {
    if (!(0 <= r.x0 && r.x0 < r.x1 && r.x1 <= view.width && 0 <= r.y0 && r.y0 < r.y1 &&
          r.y1 <= view.height)) {
      throw std::invalid_argument("render: unused rectangle [" + std::to_string(r.x0) + ", " +
                                  std::to_string(r.x1) + ") x [" + std::to_string(r.y0) + ", " +
                                  std::to_string(r.y1) + ") is empty or outside the view");
    }
  }
}

void GlBackend::Submit(const DrawRequest& request, int slot) {
  const View& view = request.view;
  const std::span<const int> drawables = request.drawables, lights = request.lights;
  gl_.BindFramebuffer(GL_FRAMEBUFFER, EnsureFramebuffer(view.width, view.height, slot));
  gl_.Viewport(0, 0, view.width, view.height);
  constexpr GLfloat kBlack[4] = {0, 0, 0, 0};
  constexpr GLuint kNoId[4] = {0, 0, 0, 0};
  constexpr GLfloat kFarDepth = 1.0f;
  gl_.ClearBufferfv(GL_COLOR, 0, kBlack);
  gl_.ClearBufferuiv(GL_COLOR, 1, kNoId);
  gl_.ClearBufferuiv(GL_COLOR, 2, kNoId);
  // The metric z attachment only where it is read: llvmpipe then neither clears nor writes it.
  const std::array<GLenum, 4> draw_buffers = {
      GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
      view.read_depth ? GLenum(GL_COLOR_ATTACHMENT3) : GLenum(GL_NONE)};
  gl_.DrawBuffers(GLsizei(draw_buffers.size()), draw_buffers.data());
  if (view.read_depth) gl_.ClearBufferfv(GL_COLOR, 3, kBlack);
  gl_.ClearBufferfv(GL_DEPTH, 0, &kFarDepth);
  if (!request.unused.empty()) DrawUnusedMask(request);

  const Program& program = ProgramFor(int(lights.size()));
  gl_.UseProgram(program.id);
  gl_.BindVertexArray(vao_);
  const std::array<float, 16> camera_from_world = CameraFromWorld(view);
  const std::array<float, 16> clip_from_camera = ClipFromCamera(view);
  gl_.UniformMatrix4fv(program.camera_from_world, 1, GL_FALSE, camera_from_world.data());
  gl_.UniformMatrix4fv(program.clip_from_camera, 1, GL_FALSE, clip_from_camera.data());
  gl_.Uniform1f(program.inv_falloff2, 1.0f / (options_.light_falloff_m * options_.light_falloff_m));
  gl_.Uniform1f(program.exposure, request.exposure);
  if (!lights.empty()) {
    std::array<float, 3 * kMaxLightsPerDraw> positions{}, intensities{};
    for (std::size_t i = 0; i < lights.size(); ++i) {
      const PointLight& light = lights_[std::size_t(lights[i])];
      for (int k = 0; k < 3; ++k) {
        positions[3 * i + k] = light.position[k];
        intensities[3 * i + k] = light.intensity[k];
      }
    }
    gl_.Uniform3fv(program.light_position, GLsizei(lights.size()), positions.data());
    gl_.Uniform3fv(program.light_intensity, GLsizei(lights.size()), intensities.data());
  }

  // Front to back (by the distance from the camera to each drawable's bounds, then by index):
  // llvmpipe tests depth before shading, so hidden surfaces drawn later cost little. The order is
  // a function of the view, so images stay deterministic.
  const Eigen::Vector3f eye = view.world_from_camera.translation().cast<float>();
  order_.clear();
  for (int index : drawables) {
    const DrawRange& d = drawables_[std::size_t(index)];
    if (d.index_count == 0) continue;
    const Eigen::Vector3f nearest = eye.cwiseMax(d.bounds.min()).cwiseMin(d.bounds.max());
    order_.emplace_back((nearest - eye).squaredNorm(), index);
  }
  std::sort(order_.begin(), order_.end());

  gl_.ActiveTexture(GL_TEXTURE0);
  int bound_material = -1;
  for (const auto& [distance2, index] : order_) {
    const DrawRange& d = drawables_[std::size_t(index)];
    if (d.material != bound_material) {
      const SceneMaterial& m = materials_[std::size_t(d.material)];
      gl_.Uniform3f(program.diffuse, m.diffuse.x(), m.diffuse.y(), m.diffuse.z());
      gl_.Uniform3f(program.emission, m.emission.x(), m.emission.y(), m.emission.z());
      gl_.Uniform1i(program.has_texture, m.texture >= 0 ? 1 : 0);
      gl_.BindTexture(GL_TEXTURE_2D, m.texture >= 0 ? textures_[std::size_t(m.texture)] : 0);
      bound_material = d.material;
    }
    gl_.Uniform1ui(program.instance, d.instance_id);
    gl_.Uniform1ui(program.semantic, d.semantic_class);
    gl_.DrawElements(
        GL_TRIANGLES, GLsizei(d.index_count), GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(std::uintptr_t(d.first_index) * sizeof(std::uint32_t)));
  }
}

void GlBackend::DrawUnusedMask(const DrawRequest& request) {
  // Two triangles per rectangle in normalised device coordinates: window row j is image row j
  // (see ClipFromCamera), so y needs no flip.
  const float sx = 2.0f / float(request.view.width), sy = 2.0f / float(request.view.height);
  mask_vertices_.clear();
  for (const PixelRect& r : request.unused) {
    const float x0 = float(r.x0) * sx - 1, x1 = float(r.x1) * sx - 1;
    const float y0 = float(r.y0) * sy - 1, y1 = float(r.y1) * sy - 1;
    mask_vertices_.insert(mask_vertices_.end(), {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1});
  }
  gl_.UseProgram(mask_program_);
  gl_.BindVertexArray(mask_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, mask_vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(mask_vertices_.size() * sizeof(float)),
                 mask_vertices_.data(), GL_STREAM_DRAW);
  gl_.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  gl_.Disable(GL_CULL_FACE);
  gl_.DepthFunc(GL_ALWAYS);
  gl_.DrawArrays(GL_TRIANGLES, 0, GLsizei(mask_vertices_.size() / 2));
  gl_.DepthFunc(GL_LESS);
  gl_.Enable(GL_CULL_FACE);
  gl_.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void GlBackend::ReadBack(const DrawRequest& request, int slot) {
  const View& view = request.view;
  RenderedView* out = request.out;
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, EnsureFramebuffer(view.width, view.height, slot));
  // Read back: GL rows come bottom-up, which is image row 0 first (see ClipFromCamera).
  const int w = view.width, h = view.height;
  const std::size_t pixels = std::size_t(w) * h;
  out->rgb.width = w;
  out->rgb.height = h;
  out->rgb.channels = 3;
  out->rgb.data.resize(pixels * 3);
  out->depth_m.width = view.read_depth ? w : 0;
  out->depth_m.height = view.read_depth ? h : 0;
  out->depth_m.data.resize(view.read_depth ? pixels : 0);
  out->instance.resize(pixels);
  out->semantic.resize(pixels);
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl_.ReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, out->rgb.data.data());
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT1);
  gl_.ReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, out->instance.data());
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT2);
  gl_.ReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_BYTE, out->semantic.data());
  if (view.read_depth) {
    gl_.ReadBuffer(GL_COLOR_ATTACHMENT3);
    gl_.ReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, out->depth_m.data.data());
  }
  CheckGlError("read-back");
}

}  // namespace corridorsim::render
