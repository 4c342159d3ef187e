// EGL context provider through libglvnd's libEGL: on a hardware EGL device when there is one
// (EGL_EXT_device_enumeration, EGL_EXT_platform_device: the NVIDIA driver's device, or a Mesa
// driver's render node), else on Mesa's surfaceless platform (EGL_MESA_platform_surfaceless,
// libEGL_mesa) pinned to software: Mesa's swrast DRI driver, i.e. gallium llvmpipe, the same
// rasterizer OSMesa uses. docs/rendering.md, "GPU rendering".

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <strings.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "render/gl_context.h"
#include "render/software_rasterizer.h"

namespace corridorsim::render {
namespace {

std::string EglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    default:
      return "EGL error " + std::to_string(error);
  }
}

[[noreturn]] void ThrowEgl(const std::string& what) {
  throw RenderError("egl: " + what + " failed: " + EglErrorName(eglGetError()));
}

bool HasExtension(const char* extensions, const std::string& name) {
  if (extensions == nullptr) return false;
  const std::string list = std::string(" ") + extensions + " ";
  return list.find(" " + name + " ") != std::string::npos;
}

// Mesa's reading of a boolean environment variable (util/u_debug.c, env_var_as_boolean).
bool MesaBooleanTrue(const char* value) {
  if (value == nullptr) return false;
  for (const char* yes : {"1", "true", "yes", "y"}) {
    if (strcasecmp(value, yes) == 0) return true;
  }
  return false;
}

std::string CountOf(std::size_t n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

// The surfaceless display is one per process: eglGetPlatformDisplayEXT returns the same handle for
// every backend, and eglInitialize on an initialised display does nothing. It is never terminated:
// eglTerminate would end it for every other EGL backend, and unload the driver (with LLVM) only for
// the next backend to load it again. Mesa frees it at exit. The same holds for a device's display
// (one per EGLDeviceEXT), also when creating a context on it failed: another backend may use it.
EGLDisplay InitializeSurfacelessDisplay() {
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!HasExtension(client_extensions, "EGL_EXT_platform_base") ||
      !HasExtension(client_extensions, "EGL_MESA_platform_surfaceless")) {
    throw RenderError(
        "egl: eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA) failed: "
        "EGL_MESA_platform_surfaceless is not supported by this libEGL (needs Mesa's EGL vendor: "
        "libegl-mesa0, and libgl1-mesa-dri for swrast_dri.so)");
  }
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    throw RenderError("egl: eglGetProcAddress(eglGetPlatformDisplayEXT) returned null");
  }
  EGLDisplay display =
      get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY)
    ThrowEgl("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    ThrowEgl(
        "eglInitialize(surfaceless display) (no usable Mesa driver: is swrast_dri.so installed?)");
  }
  return display;
}

// The EGL devices libEGL lists (libglvnd: every vendor's, in vendor order) with their extension
// strings, and the entry points that query and open them.
struct EglDevices {
  std::string unavailable;  // why no device can be listed or opened; empty when they can
  std::vector<EGLDeviceEXT> handles;
  std::vector<std::optional<std::string>> extensions;  // per device; nullopt: query failed
  PFNEGLQUERYDEVICESTRINGEXTPROC query_string = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = nullptr;
};

EglDevices EnumerateDevices() {
  EglDevices devices;
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  // EGL_EXT_device_base is the older name of enumeration + query together.
  const bool base = HasExtension(client_extensions, "EGL_EXT_device_base");
  for (const char* needed : {"EGL_EXT_device_enumeration", "EGL_EXT_device_query",
                             "EGL_EXT_platform_base", "EGL_EXT_platform_device"}) {
    const bool in_base = std::string_view(needed).starts_with("EGL_EXT_device_") && base;
    if (!in_base && !HasExtension(client_extensions, needed)) {
      devices.unavailable = std::string(needed) + " is not supported by this libEGL";
      return devices;
    }
  }
  const auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  devices.query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  devices.get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (query_devices == nullptr || devices.query_string == nullptr ||
      devices.get_platform_display == nullptr) {
    devices.unavailable =
        "eglGetProcAddress returned null for eglQueryDevicesEXT, eglQueryDeviceStringEXT or "
        "eglGetPlatformDisplayEXT";
    return devices;
  }
  std::vector<EGLDeviceEXT> handles(kMaxEglDevices);
  EGLint count = 0;
  if (!query_devices(kMaxEglDevices, handles.data(), &count)) {
    devices.unavailable = "eglQueryDevicesEXT failed: " + EglErrorName(eglGetError());
    return devices;
  }
  handles.resize(std::size_t(std::clamp<EGLint>(count, 0, kMaxEglDevices)));
  devices.handles = std::move(handles);
  for (EGLDeviceEXT handle : devices.handles) {
    const char* extensions = devices.query_string(handle, EGL_EXTENSIONS);
    if (extensions == nullptr) {
      eglGetError();  // clears the query's error; the device is treated as unknown, never chosen
      devices.extensions.emplace_back(std::nullopt);
    } else {
      devices.extensions.emplace_back(extensions);
    }
  }
  return devices;
}

// "EGL device 1 (/dev/dri/renderD128, <renderer>)": the index CORRIDORSIM_EGL_DEVICE takes, and
// the DRM node and name where the device tells them (queried only where its extensions list them:
// another query sets EGL_BAD_PARAMETER).
std::string DeviceLabel(const EglDevices& devices, int index) {
  const EGLDeviceEXT handle = devices.handles[std::size_t(index)];
  const char* extensions =
      devices.extensions[std::size_t(index)] ? devices.extensions[std::size_t(index)]->c_str() : "";
  std::vector<std::string> names;
  auto query = [&](EGLint name) {
    const char* text = devices.query_string(handle, name);
    if (text == nullptr) {
      eglGetError();  // Mesa's software device lists EGL_EXT_device_drm_render_node but has none
      return false;
    }
    if (*text != '\0') names.emplace_back(text);
    return *text != '\0';
  };
  const bool render_node = HasExtension(extensions, "EGL_EXT_device_drm_render_node") &&
                           query(EGL_DRM_RENDER_NODE_FILE_EXT);
  if (!render_node && HasExtension(extensions, "EGL_EXT_device_drm")) {
    query(EGL_DRM_DEVICE_FILE_EXT);
  }
  if (HasExtension(extensions, "EGL_EXT_device_query_name")) query(EGL_RENDERER_EXT);
  std::string label = "EGL device " + std::to_string(index);
  for (std::size_t i = 0; i < names.size(); ++i) label += (i == 0 ? " (" : ", ") + names[i];
  return names.empty() ? label : label + ")";
}

EGLDisplay InitializeDeviceDisplay(const EglDevices& devices, int index, const std::string& label) {
  const EGLint attribs[] = {EGL_NONE};
  EGLDisplay display = devices.get_platform_display(EGL_PLATFORM_DEVICE_EXT,
                                                    devices.handles[std::size_t(index)], attribs);
  if (display == EGL_NO_DISPLAY) {
    ThrowEgl("eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, " + label + ")");
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) ThrowEgl("eglInitialize(" + label + ")");
  return display;
}

class EglContext final : public GlContext {
 public:
  EglContext() {
    using Kind = EglDeviceRequest::Kind;
    const EglDeviceRequest request = ParseEglDeviceRequest(std::getenv(kEglDeviceVariable),
                                                           std::getenv("LIBGL_ALWAYS_SOFTWARE"));
    // Why the surfaceless platform, when it comes to that: kept for BackendInfo::device rather
    // than logged, so that a run's provenance.json says it and the console stays quiet.
    std::string why_software = request.reason;
    if (request.kind != Kind::kSoftware) {
      const EglDevices devices = EnumerateDevices();
      if (!devices.unavailable.empty()) {
        if (request.kind == Kind::kIndex) {
          throw RenderError("egl: " + request.reason +
                            " names an EGL device, but none can be listed: " + devices.unavailable);
        }
        why_software = devices.unavailable;
      } else {
        const EglDeviceChoice choice = ChooseEglDevice(devices.extensions, request);
        if (choice.device) {
          const int index = *choice.device;
          const std::string label = DeviceLabel(devices, index);
          // A forced index may name Mesa's software device: llvmpipe then, pinned as elsewhere.
          const bool software =
              HasExtension(devices.extensions[std::size_t(index)].value_or("").c_str(),
                           kEglSoftwareDeviceExtension);
          try {
            if (software) RequireSoftwareRasterizerPinned("egl");
            display_ = InitializeDeviceDisplay(devices, index, label);
            CreateContext(label);
            device_ = std::string(software ? "software: " : "hardware: ") + label + " (" +
                      choice.reason + ")";
            return;
          } catch (const RenderError& e) {
            // The device the user named is used or is an error: a silent fallback would give
            // other images than asked for.
            if (choice.forced)
              throw RenderError(std::string(e.what()) + " (" + choice.reason + ")");
            why_software = label + " failed: " + e.what();
          }
        } else {
          why_software = choice.reason;
        }
      }
    }

    RequireSoftwareRasterizerPinned("egl");
    // Mesa's surfaceless platform would take a render node's hardware driver where there is one:
    // LIBGL_ALWAYS_SOFTWARE keeps it on swrast (llvmpipe). overwrite = 0: a value the user set
    // wins. The one variable a backend sets: set in main(), it would keep EGL off a GPU.
    setenv("LIBGL_ALWAYS_SOFTWARE", "1", 0);
    display_ = InitializeSurfacelessDisplay();
    CreateContext("the surfaceless display");
    device_ =
        "software: Mesa surfaceless platform, EGL_PLATFORM_SURFACELESS_MESA (" + why_software + ")";
  }

  ~EglContext() override {
    if (eglGetCurrentContext() == context_) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display_, context_);
  }

  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  BackendKind kind() const override { return BackendKind::kEgl; }

  void MakeCurrent() override {
    if (eglGetCurrentContext() == context_) return;  // rebinding is not free
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      ThrowEgl("eglMakeCurrent(EGL_NO_SURFACE)");
    }
  }

  GlProc GetProcAddress(const char* name) const override { return eglGetProcAddress(name); }

  std::string device() const override { return device_; }

 private:
  // A GL 3.3 core context on display_ (`where` names it in errors), current without a surface:
  // the renderer draws into its own FBOs.
  void CreateContext(const std::string& where) {
    const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
    if (!HasExtension(extensions, "EGL_KHR_surfaceless_context")) {
      throw RenderError("egl: EGL_KHR_surfaceless_context is not supported by " + where);
    }
    if (!eglBindAPI(EGL_OPENGL_API)) ThrowEgl("eglBindAPI(EGL_OPENGL_API)");

    // A context without a config where the display allows it; otherwise any desktop-GL config.
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!HasExtension(extensions, "EGL_KHR_no_config_context")) {
      const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                       EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(display_, config_attribs, &config, 1, &count) || count < 1) {
        throw RenderError("egl: no EGL config supports desktop OpenGL on " + where);
      }
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      3,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attribs);
    if (context_ == EGL_NO_CONTEXT) ThrowEgl("eglCreateContext(OpenGL 3.3 core, " + where + ")");
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      const std::string error = EglErrorName(eglGetError());
      eglDestroyContext(display_, context_);
      context_ = EGL_NO_CONTEXT;
      throw RenderError("egl: eglMakeCurrent(EGL_NO_SURFACE) failed: " + error);
    }
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string device_;  // BackendInfo::device
};

}  // namespace

EglDeviceRequest ParseEglDeviceRequest(const char* device, const char* always_software) {
  using Kind = EglDeviceRequest::Kind;
  const std::string_view value = device != nullptr ? device : "";
  if (value.empty()) {
    if (MesaBooleanTrue(always_software)) {
      return {Kind::kSoftware, -1, std::string("LIBGL_ALWAYS_SOFTWARE=") + always_software};
    }
    return {Kind::kAuto, -1, ""};
  }
  const std::string asked = std::string(kEglDeviceVariable) + "=" + std::string(value);
  if (value == "software") return {Kind::kSoftware, -1, asked};
  int index = -1;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), index);
  const bool digits_only =
      std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits_only || error != std::errc() || end != value.data() + value.size() ||
      index >= kMaxEglDevices) {
    throw RenderError("egl: environment variable " + asked +
                      " is not valid: use 'software' or an EGL device index from 0 to " +
                      std::to_string(kMaxEglDevices - 1) +
                      ", or leave it unset for the first hardware device");
  }
  return {Kind::kIndex, index, asked};
}

EglDeviceChoice ChooseEglDevice(std::span<const std::optional<std::string>> device_extensions,
                                const EglDeviceRequest& request) {
  using Kind = EglDeviceRequest::Kind;
  const std::size_t count = device_extensions.size();
  switch (request.kind) {
    case Kind::kSoftware:
      return {std::nullopt, false, request.reason};
    case Kind::kIndex:
      if (request.index < 0 || std::size_t(request.index) >= count) {
        throw RenderError("egl: environment variable " + request.reason + " names no EGL device: " +
                          (count == 0
                               ? std::string("this libEGL lists none (use 'software' or unset it)")
                               : "valid indices are 0 to " + std::to_string(count - 1) + " (" +
                                     CountOf(count, "EGL device") + " listed), or 'software'"));
      }
      return {request.index, true, request.reason};
    case Kind::kAuto:
      break;
  }
  std::size_t unknown = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!device_extensions[i]) {
      ++unknown;  // cannot tell what it is: never taken unasked
    } else if (!HasExtension(device_extensions[i]->c_str(), kEglSoftwareDeviceExtension)) {
      return {int(i), false,
              "the first EGL device without " + std::string(kEglSoftwareDeviceExtension) + ", of " +
                  std::to_string(count)};
    }
  }
  std::string reason = "no hardware EGL device: ";
  if (count == 0) return {std::nullopt, false, reason + "this libEGL lists none"};
  reason += CountOf(count, "EGL device") + ", " + std::to_string(count - unknown) + " with " +
            kEglSoftwareDeviceExtension;
  if (unknown > 0) reason += ", " + std::to_string(unknown) + " without an extension string";
  return {std::nullopt, false, reason};
}

std::unique_ptr<GlContext> CreateEglContext() { return std::make_unique<EglContext>(); }

}  // namespace corridorsim::render
