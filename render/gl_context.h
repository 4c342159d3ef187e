#pragma once
// Off-screen GL context providers for the GL backends: each creates a core-profile context of its
// own (OSMesa, llvmpipe; EGL on a hardware device when there is one, else Mesa surfaceless with
// llvmpipe) and hands out GL entry points through its own GetProcAddress. Internal to render/;
// users go through render::CreateBackend.

#include <memory>
#include <optional>
#include <span>
#include <string>

#include "render/backend.h"

namespace corridorsim::render {

/// A GL entry point as the context's GetProcAddress returns it (cast to the PFNGL...PROC type).
using GlProc = void (*)();

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual BackendKind kind() const = 0;
  /// Makes this context current on the calling thread; throws RenderError when that fails.
  virtual void MakeCurrent() = 0;
  /// The entry point `name` ("glDrawElements"), or nullptr when the context has none.
  virtual GlProc GetProcAddress(const char* name) const = 0;
  /// Which device renders and why (BackendInfo::device): "hardware: ..." or "software: ...".
  virtual std::string device() const = 0;
};

/// OSMesa core 3.3+ context bound to a small client buffer (the backend draws into its own FBO).
/// Throws RenderError ("osmesa: ...") when it cannot be created.
std::unique_ptr<GlContext> CreateOsMesaContext();

/// EGL core 3.3+ desktop GL context, made current without a surface: on the EGL device
/// ChooseEglDevice picks (EGL_EXT_platform_device), else, or when that device fails, on Mesa's
/// surfaceless platform (EGL_MESA_platform_surfaceless, llvmpipe). Throws RenderError
/// ("egl: ...") when no context can be created, when CORRIDORSIM_EGL_DEVICE is bad, or when the
/// device it names cannot be used.
std::unique_ptr<GlContext> CreateEglContext();

/// The environment variable that chooses the EGL backend's device: unset or empty, the first
/// hardware device; "software", Mesa surfaceless (llvmpipe); a decimal index, that device.
inline constexpr const char* kEglDeviceVariable = "CORRIDORSIM_EGL_DEVICE";
/// At most this many EGL devices are enumerated (eglQueryDevicesEXT's max_devices).
inline constexpr int kMaxEglDevices = 64;
/// The device extension with which Mesa marks its software device (llvmpipe or softpipe).
inline constexpr const char* kEglSoftwareDeviceExtension = "EGL_MESA_device_software";

/// What the environment asks of the EGL backend's device.
struct EglDeviceRequest {
  enum class Kind { kAuto, kSoftware, kIndex };
  Kind kind = Kind::kAuto;
  int index = -1;      // kIndex only: 0 <= index < kMaxEglDevices
  std::string reason;  // kSoftware and kIndex: the variable that asked, as "NAME=value"
};

/// Reads CORRIDORSIM_EGL_DEVICE's value `device` and LIBGL_ALWAYS_SOFTWARE's value
/// `always_software` (nullptr: unset). Unset or empty `device` is kAuto, unless
/// `always_software` is true as Mesa reads it ("1", "true", "yes", "y", any case): Mesa's own
/// request for software, which Mesa refuses on a device the application selects. Throws
/// RenderError naming the variable, the value and the valid values when `device` is none of them.
EglDeviceRequest ParseEglDeviceRequest(const char* device, const char* always_software);

/// The EGL backend's choice of device.
struct EglDeviceChoice {
  std::optional<int> device;  // index in enumeration order; nullopt: Mesa surfaceless (llvmpipe)
  bool forced = false;        // named by CORRIDORSIM_EGL_DEVICE: used, or an error, no fallback
  std::string reason;         // why this choice, for BackendInfo::device
};

/// The choice, without EGL: `device_extensions` holds each enumerated device's EGL_EXTENSIONS
/// string in enumeration order (nullopt where it could not be read). kAuto takes the first device
/// known not to be software (its string lacks EGL_MESA_device_software), else none; kSoftware
/// none; kIndex that device, whatever it is. Throws RenderError naming the variable and the valid
/// range when the index is past the list.
EglDeviceChoice ChooseEglDevice(std::span<const std::optional<std::string>> device_extensions,
                                const EglDeviceRequest& request);

}  // namespace corridorsim::render
