// Tests for the EGL backend's choice of device, without EGL (render/egl_context.cpp):
// CORRIDORSIM_EGL_DEVICE and LIBGL_ALWAYS_SOFTWARE as ParseEglDeviceRequest reads them, and
// ChooseEglDevice over the devices' extension strings. tests/render/backend_egl_device_test.cpp
// creates the EGL backend on the device chosen.

#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "render/gl_context.h"
#include "tests/render/render_error_of.h"

namespace corridorsim::render {
namespace {

using test::RenderErrorOf;

TEST_CASE("CORRIDORSIM_EGL_DEVICE is read as the first hardware device, software or an index",
          "[render][backend]") {
  using Kind = EglDeviceRequest::Kind;
  CHECK(ParseEglDeviceRequest(nullptr, nullptr).kind == Kind::kAuto);
  CHECK(ParseEglDeviceRequest("", nullptr).kind == Kind::kAuto);  // set but empty: as unset
  const EglDeviceRequest software = ParseEglDeviceRequest("software", nullptr);
  CHECK(software.kind == Kind::kSoftware);
  CHECK(software.reason == "CORRIDORSIM_EGL_DEVICE=software");
  const EglDeviceRequest three = ParseEglDeviceRequest("3", nullptr);
  CHECK(three.kind == Kind::kIndex);
  CHECK(three.index == 3);
  CHECK(three.reason == "CORRIDORSIM_EGL_DEVICE=3");
  CHECK(ParseEglDeviceRequest("007", nullptr).index == 7);
  CHECK(ParseEglDeviceRequest("63", nullptr).index == kMaxEglDevices - 1);

  // LIBGL_ALWAYS_SOFTWARE, true as Mesa reads it, asks for software unless a device is named.
  for (const char* yes : {"1", "true", "TRUE", "yes", "y"}) {
    INFO("LIBGL_ALWAYS_SOFTWARE=" << yes);
    const EglDeviceRequest request = ParseEglDeviceRequest(nullptr, yes);
    CHECK(request.kind == Kind::kSoftware);
    CHECK(request.reason == std::string("LIBGL_ALWAYS_SOFTWARE=") + yes);
  }
  for (const char* no : {"0", "false", "no", ""}) {
    INFO("LIBGL_ALWAYS_SOFTWARE=" << no);
    CHECK(ParseEglDeviceRequest(nullptr, no).kind == Kind::kAuto);
  }
  CHECK(ParseEglDeviceRequest("2", "1").kind == Kind::kIndex);

  for (const char* bad :
       {"Software", "gpu", "-1", "+1", "1.5", " 1", "1 ", "0x1", "64", "99999999999999999999"}) {
    INFO("CORRIDORSIM_EGL_DEVICE='" << bad << "'");
    const std::string what = RenderErrorOf([&] { ParseEglDeviceRequest(bad, nullptr); });
    CHECK(what.find(std::string("CORRIDORSIM_EGL_DEVICE=") + bad) != std::string::npos);
    CHECK(what.find("'software' or an EGL device index from 0 to 63") != std::string::npos);
  }
}

TEST_CASE(
    "the EGL device choice takes the first hardware device, else software, or the index "
    "asked for",
    "[render][backend]") {
  using Devices = std::vector<std::optional<std::string>>;
  const std::string software = "EGL_MESA_device_software EGL_EXT_device_drm_render_node";
  const std::string mesa_gpu = "EGL_EXT_device_drm EGL_EXT_device_drm_render_node";
  const std::string nvidia = "EGL_NV_device_cuda EGL_EXT_device_drm EGL_EXT_device_query_name";
  const EglDeviceRequest automatic = ParseEglDeviceRequest(nullptr, nullptr);

  // Each case: the devices' extension strings in enumeration order, the request, and the
  // choice it must make.
  struct Case {
    const char* what;
    Devices devices;
    EglDeviceRequest request;
    std::optional<int> device;
    bool forced;
    std::string reason;
  };
  const std::string first_of_3 = "the first EGL device without EGL_MESA_device_software, of 3";
  const Case cases[] = {
      // What Mesa lists on a machine without a GPU: its software device only.
      {"software only", Devices{software}, automatic, std::nullopt, false,
       "no hardware EGL device: 1 EGL device, 1 with EGL_MESA_device_software"},
      {"no devices", Devices{}, automatic, std::nullopt, false,
       "no hardware EGL device: this libEGL lists none"},
      // The first device without the software mark, in enumeration order.
      {"hardware first", Devices{nvidia, software, mesa_gpu}, automatic, 0, false, first_of_3},
      {"software first", Devices{software, mesa_gpu, nvidia}, automatic, 1, false, first_of_3},
      // A whole extension name only: a longer name that starts with the mark is not the mark.
      {"a longer name", Devices{"EGL_MESA_device_software_x EGL_EXT_device_drm"}, automatic, 0,
       false, "the first EGL device without EGL_MESA_device_software, of 1"},
      // A device whose extensions could not be read is never taken unasked.
      {"unknown first", Devices{std::nullopt, software, mesa_gpu}, automatic, 2, false, first_of_3},
      {"only unknown and software", Devices{software, std::nullopt}, automatic, std::nullopt, false,
       "no hardware EGL device: 2 EGL devices, 1 with EGL_MESA_device_software, 1 without an "
       "extension string"},
      // Software when asked, whatever is there.
      {"software asked", Devices{nvidia}, ParseEglDeviceRequest("software", nullptr), std::nullopt,
       false, "CORRIDORSIM_EGL_DEVICE=software"},
      {"Mesa's software asked", Devices{nvidia}, ParseEglDeviceRequest(nullptr, "1"), std::nullopt,
       false, "LIBGL_ALWAYS_SOFTWARE=1"},
      // An index is taken as it is, Mesa's software device included, and forced (no fallback).
      {"index 1", Devices{nvidia, mesa_gpu}, ParseEglDeviceRequest("1", nullptr), 1, true,
       "CORRIDORSIM_EGL_DEVICE=1"},
      {"index 0 on software", Devices{software, nvidia}, ParseEglDeviceRequest("0", nullptr), 0,
       true, "CORRIDORSIM_EGL_DEVICE=0"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const EglDeviceChoice choice = ChooseEglDevice(c.devices, c.request);
    CHECK(choice.device == c.device);
    CHECK(choice.forced == c.forced);
    CHECK(choice.reason == c.reason);
  }
  // An index past the devices listed is an error.
  const std::string past = RenderErrorOf([&] {
    ChooseEglDevice(Devices{software, nvidia}, ParseEglDeviceRequest("2", nullptr));
  });
  CHECK(past.find("CORRIDORSIM_EGL_DEVICE=2 names no EGL device") != std::string::npos);
  CHECK(past.find("valid indices are 0 to 1 (2 EGL devices listed)") != std::string::npos);
  const std::string no_devices =
      RenderErrorOf([&] { ChooseEglDevice(Devices{}, ParseEglDeviceRequest("0", nullptr)); });
  CHECK(no_devices.find("CORRIDORSIM_EGL_DEVICE=0 names no EGL device: this libEGL lists none") !=
        std::string::npos);
}

}  // namespace
}  // namespace corridorsim::render
