// The environment of the EGL backend tests (tests/render/backend_test.cpp,
// backend_egl_device_test.cpp): variables set for a scope and put back after it, the EGL device
// asked for through CORRIDORSIM_EGL_DEVICE, and the EGL backend where this machine can create one.
#pragma once

#include <cstdlib>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "render/backend.h"
#include "render/gl_context.h"

namespace corridorsim::render::backend_tests {

// Sets (or with nullptr unsets) environment variables for a scope and puts back what the process
// had: tests that choose the EGL device leave no trace for the next test case. The EGL backend's
// software path sets LIBGL_ALWAYS_SOFTWARE (which then reads as a request for software), so it is
// saved wherever CORRIDORSIM_EGL_DEVICE is.
class ScopedEnvironment {
 public:
  ScopedEnvironment(std::initializer_list<std::pair<const char*, const char*>> values) {
    for (const auto& [name, value] : values) {
      const char* old = std::getenv(name);
      saved_.emplace_back(name, old != nullptr ? std::optional<std::string>(old) : std::nullopt);
    }
    for (const auto& [name, value] : values) Set(name, value);
  }
  ~ScopedEnvironment() {
    for (auto it = saved_.rbegin(); it != saved_.rend(); ++it) {
      Set(it->first.c_str(), it->second ? it->second->c_str() : nullptr);
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  static void Set(const char* name, const char* value) {
    if (value != nullptr) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

// The EGL device choice as the environment `device` (CORRIDORSIM_EGL_DEVICE) asks, with
// LIBGL_ALWAYS_SOFTWARE unset.
inline ScopedEnvironment EglDeviceEnvironment(const char* device) {
  return ScopedEnvironment{{kEglDeviceVariable, device}, {"LIBGL_ALWAYS_SOFTWARE", nullptr}};
}

// The EGL backend, or nothing (with a WARN) where this machine cannot create one; the error must
// then be a RenderError that names "egl".
inline std::unique_ptr<Backend> TryEgl() {
  try {
    return CreateBackend(BackendKind::kEgl);
  } catch (const RenderError& e) {
    const std::string what = e.what();
    WARN("EGL backend not available here: " << what);
    CHECK(what.find("egl") != std::string::npos);
    return nullptr;
  }
}

}  // namespace corridorsim::render::backend_tests
