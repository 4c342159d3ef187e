// Tests for render/backend.cpp and the GL renderer behind it (render/gl_renderer.cpp,
// render/osmesa_context.cpp, render/egl_context.cpp) on a scene built by hand
// (tests/support/backend_test_scene.h): a tilted textured wall and a small emissive quad, seen by
// a camera whose pose is not the identity. The EGL backend on the device CORRIDORSIM_EGL_DEVICE
// names: backend_egl_device_test.cpp (the choice itself, without EGL:
// egl_device_choice_test.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "render/backend.h"
#include "render/software_rasterizer.h"
#include "tests/support/backend_test_scene.h"
#include "tests/support/egl_environment.h"

namespace corridorsim::render {
namespace {

using namespace backend_tests;

TEST_CASE("backend names are osmesa and egl", "[render]") {
  CHECK(BackendName(BackendKind::kOsMesa) == "osmesa");
  CHECK(BackendName(BackendKind::kEgl) == "egl");
}

TEST_CASE("Mesa is pinned to llvmpipe and its fast texture LOD unless the user chose otherwise",
          "[render][backend]") {
  // The variables as the process had them, restored on the way out (gallivm read them when this
  // process made its first context, so changing them here changes no image).
  struct SavedEnvironment {
    std::vector<std::pair<std::string, std::optional<std::string>>> values;
    SavedEnvironment() {
      for (const char* name :
           {"GALLIUM_DRIVER", "LIBGL_ALWAYS_SOFTWARE", "GALLIVM_PERF", "LP_NUM_THREADS"}) {
        const char* value = std::getenv(name);
        values.emplace_back(name,
                            value != nullptr ? std::optional<std::string>(value) : std::nullopt);
      }
    }
    ~SavedEnvironment() {
      for (const auto& [name, value] : values) {
        if (value) {
          setenv(name.c_str(), value->c_str(), 1);
        } else {
          unsetenv(name.c_str());
        }
      }
    }
  } saved;
  auto get = [](const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr ? std::string(value) : std::string("(unset)");
  };

  for (const auto& [name, value] : saved.values) unsetenv(name.c_str());
  PinSoftwareRasterizer();
  CHECK(get("GALLIUM_DRIVER") == "llvmpipe");
  CHECK(get("GALLIVM_PERF") == "brilinear,rho_approx");
  CHECK(get("LP_NUM_THREADS") == "0");
  // Left to the EGL backend's surfaceless path: set here, it would keep EGL off a GPU.
  CHECK(get("LIBGL_ALWAYS_SOFTWARE") == "(unset)");

  // A value the user set wins, an empty GALLIVM_PERF (exact trilinear) included.
  setenv("GALLIUM_DRIVER", "softpipe", 1);
  setenv("GALLIVM_PERF", "", 1);
  setenv("LP_NUM_THREADS", "2", 1);
  PinSoftwareRasterizer();
  CHECK(get("GALLIUM_DRIVER") == "softpipe");
  CHECK(get("GALLIVM_PERF").empty());
  CHECK(get("LP_NUM_THREADS") == "2");
}

// The names of this process's threads whose name starts with `prefix` (/proc/self/task/*/comm).
std::vector<std::string> ThreadsNamed(const std::string& prefix) {
  std::vector<std::string> names;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (std::getline(comm, name) && name.rfind(prefix, 0) == 0) names.push_back(name);
  }
  return names;
}

TEST_CASE("the software backends draw on the calling thread: no llvmpipe rasterizer thread runs",
          "[render][backend]") {
  // Mesa 22.3's llvmpipe frees a fence that its rasterizer thread can still be signalling
  // (render/software_rasterizer.cpp, PinSoftwareRasterizer), so corridorsim asks for none. ctest
  // runs this case in a process of its own: the first context below is the one that reads
  // LP_NUM_THREADS.
  const char* user_value = std::getenv("LP_NUM_THREADS");
  if (user_value != nullptr && std::string(user_value) != "0") {
    WARN("LP_NUM_THREADS=" << user_value << " is set: the default is not what this run tests");
    return;
  }
  auto osmesa = CreateBackend(BackendKind::kOsMesa);
  osmesa->Upload(TestScene());
  CheckTestImage(Render(*osmesa));
  CHECK(ThreadsNamed("llvmpipe").empty());

  const auto environment = EglDeviceEnvironment("software");
  if (auto egl = TryEgl()) {
    egl->Upload(TestScene());
    CheckTestImage(Render(*egl));
    CHECK(ThreadsNamed("llvmpipe").empty());
  }
}

TEST_CASE("osmesa renders depth, ids and edges where the pinhole model puts them", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  REQUIRE(backend->kind() == BackendKind::kOsMesa);
  backend->Upload(TestScene());
  CheckTestImage(Render(*backend));
}

TEST_CASE("egl renders depth, ids and edges where the pinhole model puts them", "[render]") {
  auto backend = TryEgl();
  if (!backend) return;
  REQUIRE(backend->kind() == BackendKind::kEgl);
  backend->Upload(TestScene());
  CheckTestImage(Render(*backend));
}

TEST_CASE("rendered rows are top-down and texture v runs up the image", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  backend->Upload(TestScene());
  const RenderedView image = Render(*backend);
  // The lamp is only in the top half of the image.
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (image.instance[Index(x, y)] == kLampId) REQUIRE(y < kHeight / 2);
    }
  }
  // The texture's top half (red) is on the wall's upper part, its bottom half (green) below.
  const std::uint8_t* upper = image.rgb.Pixel(320, 130);
  const std::uint8_t* lower = image.rgb.Pixel(320, 350);
  CHECK(upper[0] > 2 * upper[1]);
  CHECK(lower[1] > 2 * lower[0]);
}

TEST_CASE("the emissive lamp is the brightest region and saturates to white", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  backend->Upload(TestScene());
  const RenderedView image = Render(*backend);
  int brightest_wall = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t* p = image.rgb.Pixel(x, y);
      const int sum = p[0] + p[1] + p[2];
      if (image.instance[Index(x, y)] == kLampId) {
        REQUIRE(sum == 3 * 255);
      } else if (image.instance[Index(x, y)] == kWallId) {
        brightest_wall = std::max(brightest_wall, sum);
      } else {
        REQUIRE(sum == 0);  // cleared to black
      }
    }
  }
  CHECK(brightest_wall > 0);
  CHECK(brightest_wall < 3 * 255);
}

TEST_CASE("two draws of the same view give identical bytes", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  backend->Upload(TestScene());
  const RenderedView first = Render(*backend);
  RenderedView second = Render(*backend);
  // Drawing into a used output, after a draw of another size, keeps the result identical.
  View small = TestView();
  small.width = 320;
  small.height = 240;
  small.cx = 160;
  small.cy = 120;
  backend->Draw(small, kAllDrawables, kAllLights, &second);
  CHECK(second.rgb.width == 320);
  CHECK(second.instance.size() == 320u * 240u);
  backend->Draw(TestView(), kAllDrawables, kAllLights, &second);
  CHECK(first.rgb.data == second.rgb.data);
  CHECK(first.depth_m.data == second.depth_m.data);
  CHECK(first.instance == second.instance);
  CHECK(first.semantic == second.semantic);
}

TEST_CASE("drawing only some drawables and no lights leaves the others out", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  backend->Upload(TestScene());
  RenderedView out;
  const std::vector<int> lamp_only = {1};
  backend->Draw(TestView(), lamp_only, {}, &out);
  CHECK(out.instance[Index(320, 240)] == 0);
  CHECK(out.depth_m.at(320, 240) == 0.0f);
  CHECK(out.instance[Index(320, 50)] == kLampId);
  // Unlit wall: ambient only, darker than the lit wall.
  const RenderedView lit = Render(*backend);
  RenderedView unlit;
  backend->Draw(TestView(), kAllDrawables, {}, &unlit);
  CHECK(int(unlit.rgb.Pixel(320, 350)[1]) < int(lit.rgb.Pixel(320, 350)[1]));
}

TEST_CASE("osmesa and egl give the same images within a small tolerance", "[render]") {
  // Both on llvmpipe: a GPU's images differ more ("a hardware EGL device ..." below).
  const auto environment = EglDeviceEnvironment("software");
  auto osmesa = CreateBackend(BackendKind::kOsMesa);
  auto egl = TryEgl();  // both alive at once
  if (!egl) return;
  REQUIRE(egl->info().device.starts_with("software: "));
  const Scene scene = TestScene();
  osmesa->Upload(scene);
  egl->Upload(scene);
  // Interleave the draws: each makes its own context current.
  const RenderedView a = Render(*osmesa);
  const RenderedView b = Render(*egl);
  const RenderedView a2 = Render(*osmesa);
  CHECK(a.rgb.data == a2.rgb.data);
  int max_diff = 0;
  for (std::size_t i = 0; i < a.rgb.data.size(); ++i) {
    max_diff = std::max(max_diff, std::abs(int(a.rgb.data[i]) - int(b.rgb.data[i])));
  }
  CHECK(max_diff <= kCrossBackendRgbTol);
  std::size_t same_ids = 0;
  for (std::size_t i = 0; i < a.instance.size(); ++i) {
    same_ids += a.instance[i] == b.instance[i] && a.semantic[i] == b.semantic[i];
  }
  CHECK(double(same_ids) / double(a.instance.size()) >= kCrossBackendIdShare);
  double max_depth_diff = 0;
  for (std::size_t i = 0; i < a.depth_m.data.size(); ++i) {
    if (a.instance[i] == b.instance[i]) {
      max_depth_diff =
          std::max(max_depth_diff, double(std::abs(a.depth_m.data[i] - b.depth_m.data[i])));
    }
  }
  CHECK(max_depth_diff <= kDepthTolM);
}

TEST_CASE("backends can be created and destroyed one after the other in any order", "[render]") {
  const Scene scene = TestScene();
  auto render_once = [&](BackendKind kind) -> std::optional<RenderedView> {
    std::unique_ptr<Backend> backend;
    if (kind == BackendKind::kEgl) {
      backend = TryEgl();
      if (!backend) return std::nullopt;
    } else {
      backend = CreateBackend(kind);
    }
    backend->Upload(scene);
    return Render(*backend);
  };
  const auto first = render_once(BackendKind::kOsMesa);
  const auto egl = render_once(BackendKind::kEgl);
  const auto second = render_once(BackendKind::kOsMesa);
  const auto egl_again = render_once(BackendKind::kEgl);
  REQUIRE(first);
  REQUIRE(second);
  CHECK(first->rgb.data == second->rgb.data);
  CHECK(first->instance == second->instance);
  if (egl && egl_again) {
    CHECK(egl->rgb.data == egl_again->rgb.data);
    CHECK(egl->depth_m.data == egl_again->depth_m.data);
  }
}

TEST_CASE("a bad draw request throws invalid_argument and the backend still works", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  RenderedView out;
  CHECK_THROWS_AS(backend->Draw(TestView(), kAllDrawables, kAllLights, &out), std::logic_error);
  backend->Upload(TestScene());
  View zero_width = TestView();
  zero_width.width = 0;
  CHECK_THROWS_AS(backend->Draw(zero_width, kAllDrawables, kAllLights, &out),
                  std::invalid_argument);
  View bad_depth_range = TestView();
  bad_depth_range.far_m = bad_depth_range.near_m;
  CHECK_THROWS_AS(backend->Draw(bad_depth_range, kAllDrawables, kAllLights, &out),
                  std::invalid_argument);
  const std::vector<int> missing_drawable = {0, 5};
  CHECK_THROWS_AS(backend->Draw(TestView(), missing_drawable, kAllLights, &out),
                  std::invalid_argument);
  const std::vector<int> too_many_lights(17, 0);
  CHECK_THROWS_AS(backend->Draw(TestView(), kAllDrawables, too_many_lights, &out),
                  std::invalid_argument);
  CHECK_THROWS_AS(backend->Draw(TestView(), kAllDrawables, kAllLights, nullptr),
                  std::invalid_argument);
  CheckTestImage(Render(*backend));
}

TEST_CASE("a batch of passes gives each pass the images a single draw gives", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  backend->Upload(TestScene());
  // Three passes, two of one size (each keeps a framebuffer of its own within the batch).
  View smaller = TestView();
  smaller.width = kWidth / 2;
  smaller.cx = smaller.cx / 2;
  View turned = TestView();
  turned.world_from_camera =
      turned.world_from_camera *
      SE3(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()).matrix(), Eigen::Vector3d::Zero());
  const std::vector<View> views = {TestView(), smaller, turned};
  std::vector<RenderedView> batch(views.size());
  std::vector<DrawRequest> requests;
  for (std::size_t k = 0; k < views.size(); ++k) {
    requests.push_back({views[k], kAllDrawables, kAllLights, &batch[k]});
  }
  backend->DrawPasses(requests);
  for (std::size_t k = 0; k < views.size(); ++k) {
    const RenderedView alone = Render(*backend, views[k]);
    INFO("pass " << k);
    CHECK(batch[k].rgb.width == views[k].width);
    CHECK(batch[k].rgb.data == alone.rgb.data);
    CHECK(batch[k].depth_m.data == alone.depth_m.data);
    CHECK(batch[k].instance == alone.instance);
    CHECK(batch[k].semantic == alone.semantic);
  }
  CHECK(batch[0].rgb.data != batch[2].rgb.data);  // the turned view sees something else
  CheckTestImage(batch[0]);

  // A bad request anywhere in the batch: nothing is drawn, the outputs stay as they were.
  std::vector<RenderedView> untouched(2);
  View zero_height = TestView();
  zero_height.height = 0;
  const std::vector<DrawRequest> bad = {{TestView(), kAllDrawables, kAllLights, &untouched[0]},
                                        {zero_height, kAllDrawables, kAllLights, &untouched[1]}};
  CHECK_THROWS_AS(backend->DrawPasses(bad), std::invalid_argument);
  CHECK(untouched[0].rgb.data.empty());
  CheckTestImage(Render(*backend));
}

TEST_CASE("a scene with an index past the vertices is rejected before upload", "[render]") {
  auto backend = CreateBackend(BackendKind::kOsMesa);
  Scene scene = TestScene();
  scene.indices.push_back(std::uint32_t(scene.vertices.size()));
  CHECK_THROWS_AS(backend->Upload(scene), std::invalid_argument);
  Scene bad_material = TestScene();
  bad_material.drawables[0].material = 4;
  CHECK_THROWS_AS(backend->Upload(bad_material), std::invalid_argument);
}

// True when GL_RENDERER names one of Mesa's software rasterizers.

}  // namespace
}  // namespace corridorsim::render
