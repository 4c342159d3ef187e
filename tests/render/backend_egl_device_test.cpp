// Tests for the EGL backend (render/egl_context.cpp) on the device CORRIDORSIM_EGL_DEVICE names:
// the device it reports, software through Mesa's surfaceless platform, an EGL device through
// EGL_PLATFORM_DEVICE_EXT, a bad value, and a hardware device against llvmpipe; on the scene of
// tests/support/backend_test_scene.h (the choice itself, without EGL: egl_device_choice_test.cpp).

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include <catch2/catch.hpp>

#include "render/backend.h"
#include "tests/render/render_error_of.h"
#include "tests/support/backend_test_scene.h"
#include "tests/support/egl_environment.h"

namespace corridorsim::render {
namespace {

using namespace backend_tests;
using test::RenderErrorOf;

bool SoftwareRenderer(const BackendInfo& info) {
  return info.renderer.find("llvmpipe") != std::string::npos ||
         info.renderer.find("softpipe") != std::string::npos;
}

TEST_CASE("the EGL backend says which device it chose: software where llvmpipe renders",
          "[render][backend]") {
  const auto environment = EglDeviceEnvironment(nullptr);
  auto egl = TryEgl();
  if (!egl) return;
  const BackendInfo info = egl->info();
  INFO("device: " << info.device << "; GL_RENDERER: " << info.renderer);
  // On a machine without a GPU (where these tests were written) this is the software path.
  CHECK(info.device.starts_with(SoftwareRenderer(info) ? "software: " : "hardware: "));
  if (SoftwareRenderer(info) &&
      info.device.find("EGL_PLATFORM_SURFACELESS_MESA") != std::string::npos) {
    // Why not a device: none is hardware, or the hardware one failed (its error said).
    CHECK((info.device.find("no hardware EGL device") != std::string::npos ||
           info.device.find(" failed: ") != std::string::npos ||
           info.device.find("not supported") != std::string::npos));
  }
  egl->Upload(TestScene());
  CheckTestImage(Render(*egl));
}

TEST_CASE("CORRIDORSIM_EGL_DEVICE=software renders with llvmpipe on Mesa's surfaceless platform",
          "[render][backend]") {
  const auto environment = EglDeviceEnvironment("software");
  auto egl = TryEgl();
  if (!egl) return;
  const BackendInfo info = egl->info();
  CHECK(info.device ==
        "software: Mesa surfaceless platform, EGL_PLATFORM_SURFACELESS_MESA "
        "(CORRIDORSIM_EGL_DEVICE=software)");
  CHECK(info.renderer.find("llvmpipe") != std::string::npos);
  CHECK(CreateBackend(BackendKind::kOsMesa)->info().device == "software: OSMesa");
}

TEST_CASE("a bad CORRIDORSIM_EGL_DEVICE is a RenderError naming the variable and the valid values",
          "[render][backend]") {
  for (const char* bad : {"gpu", "-1", "64"}) {
    INFO("CORRIDORSIM_EGL_DEVICE=" << bad);
    const auto environment = EglDeviceEnvironment(bad);
    const std::string what = RenderErrorOf([] { CreateBackend(BackendKind::kEgl); });
    CHECK(what.find(std::string("egl: environment variable CORRIDORSIM_EGL_DEVICE=") + bad +
                    " is not valid: use 'software' or an EGL device index from 0 to 63") !=
          std::string::npos);
  }
  // An index past the devices this libEGL lists (fewer than 64 here): the valid range is theirs.
  const auto environment = EglDeviceEnvironment("63");
  const std::string what = RenderErrorOf([] { CreateBackend(BackendKind::kEgl); });
  INFO(what);
  CHECK(what.find("CORRIDORSIM_EGL_DEVICE=63") != std::string::npos);
  CHECK((what.find("valid indices are 0 to ") != std::string::npos ||
         what.find("lists none") != std::string::npos ||
         what.find("none can be listed") != std::string::npos));
}

TEST_CASE("CORRIDORSIM_EGL_DEVICE=0 renders on EGL device 0 through EGL_PLATFORM_DEVICE_EXT",
          "[render][backend]") {
  // Without a GPU, device 0 is Mesa's software device: the device platform's path on llvmpipe.
  std::unique_ptr<Backend> device0;
  {
    const auto environment = EglDeviceEnvironment("0");
    device0 = TryEgl();
  }
  if (!device0) return;
  const BackendInfo info = device0->info();
  INFO("device: " << info.device);
  CHECK(info.device.find(": EGL device 0") != std::string::npos);
  CHECK(info.device.ends_with("(CORRIDORSIM_EGL_DEVICE=0)"));
  CHECK(info.device.starts_with(SoftwareRenderer(info) ? "software: " : "hardware: "));
  const Scene scene = TestScene();
  device0->Upload(scene);
  const RenderedView image = Render(*device0);
  CheckTestImage(image);
  if (!SoftwareRenderer(info)) return;
  // llvmpipe either way: the surfaceless platform gives the same images.
  const auto environment = EglDeviceEnvironment("software");
  auto surfaceless = TryEgl();
  REQUIRE(surfaceless);
  surfaceless->Upload(scene);
  const RenderedView reference = Render(*surfaceless);
  int max_diff = 0;
  for (std::size_t i = 0; i < image.rgb.data.size(); ++i) {
    max_diff = std::max(max_diff, std::abs(int(image.rgb.data[i]) - int(reference.rgb.data[i])));
  }
  CHECK(max_diff <= kCrossBackendRgbTol);
  CHECK(image.instance == reference.instance);
  CHECK(image.depth_m.data == reference.depth_m.data);
}

TEST_CASE("a hardware EGL device gives llvmpipe's labels and depth", "[render][backend]") {
  const auto environment = EglDeviceEnvironment(nullptr);
  auto egl = TryEgl();
  if (!egl) return;
  if (!egl->info().device.starts_with("hardware: ")) {
    // No GPU here: nothing to compare (the software path is compared in the tests above).
    SUCCEED("no hardware EGL device: " << egl->info().device);
    return;
  }
  auto osmesa = CreateBackend(BackendKind::kOsMesa);
  const Scene scene = TestScene();
  osmesa->Upload(scene);
  egl->Upload(scene);
  const RenderedView a = Render(*osmesa);
  const RenderedView b = Render(*egl);
  // Ids and z come from the same fragments, so they agree but for coverage at triangle edges;
  // colour depends on the GPU's filtering and arithmetic and is reported, not bounded (no GPU
  // tolerance has been measured: docs/rendering.md, "GPU rendering").
  std::size_t same_ids = 0;
  double max_depth_diff = 0;
  int max_rgb_diff = 0;
  for (std::size_t i = 0; i < a.instance.size(); ++i) {
    const bool same = a.instance[i] == b.instance[i] && a.semantic[i] == b.semantic[i];
    same_ids += same;
    if (same) {
      max_depth_diff =
          std::max(max_depth_diff, double(std::abs(a.depth_m.data[i] - b.depth_m.data[i])));
    }
  }
  for (std::size_t i = 0; i < a.rgb.data.size(); ++i) {
    max_rgb_diff = std::max(max_rgb_diff, std::abs(int(a.rgb.data[i]) - int(b.rgb.data[i])));
  }
  WARN(egl->info().device << ", " << egl->info().renderer << ": largest RGB difference from "
                          << "llvmpipe " << max_rgb_diff << " DN");
  CHECK(double(same_ids) / double(a.instance.size()) >= kCrossBackendIdShare);
  CHECK(max_depth_diff <= kDepthTolM);
  CheckTestImage(b);
}

}  // namespace
}  // namespace corridorsim::render
