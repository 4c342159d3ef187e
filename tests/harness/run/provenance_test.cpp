// Tests harness/run/provenance.cpp: provenance.json names the version, compiler, renderer (Mesa and
// LLVM read from its GL strings) and device, or that nothing was rendered, GALLIVM_PERF and the
// scenario's SHA-256.
#include "harness/run/provenance.h"

#include <cstdlib>
#include <string>

#include <catch2/catch.hpp>

#include "common/io/sha256.h"
#include "render/software_rasterizer.h"

namespace corridorsim {
namespace {

// A backend that only answers kind() and info(): provenance never draws.
class StringsOnlyBackend final : public render::Backend {
 public:
  explicit StringsOnlyBackend(render::BackendInfo info) : info_(std::move(info)) {}
  render::BackendKind kind() const override { return render::BackendKind::kEgl; }
  render::BackendInfo info() const override { return info_; }
  void Upload(const render::Scene&) override {}
  void Draw(const render::View&, std::span<const int>, std::span<const int>,
            render::RenderedView*) override {}
  void DrawPasses(std::span<const render::DrawRequest>) override {}
  int max_view_px() const override { return 8192; }

 private:
  render::BackendInfo info_;
};

TEST_CASE("the Mesa and LLVM releases are read from the GL strings", "[provenance]") {
  CHECK(ReleaseAfter("4.5 (Core Profile) Mesa 22.3.6", "Mesa ") == "22.3.6");
  CHECK(ReleaseAfter("4.5 (Core Profile) Mesa 23.2.1-1ubuntu3.1~22.04.2", "Mesa ") ==
        "23.2.1-1ubuntu3.1~22.04.2");
  CHECK(ReleaseAfter("llvmpipe (LLVM 15.0.6, 256 bits)", "LLVM ") == "15.0.6");
  CHECK(ReleaseAfter("softpipe", "LLVM ") == std::nullopt);
  CHECK(ReleaseAfter("Mesa ", "Mesa ") == std::nullopt);
}

TEST_CASE("provenance.json's GALLIVM_PERF is llvmpipe's; on a GPU or without a render the user's",
          "[provenance]") {
  // As main() left the process (here the test listener, tests/support): set unless the user had.
  const char* now = std::getenv("GALLIVM_PERF");
  const StringsOnlyBackend llvmpipe({"Mesa", "llvmpipe (LLVM 15.0.6, 256 bits)",
                                     "4.5 (Core Profile) Mesa 22.3.6", "software: OSMesa"});
  const StringsOnlyBackend gpu({"NVIDIA Corporation", "NVIDIA H100 80GB HBM3/PCIe/SSE2",
                                "4.6.0 NVIDIA 550.54.15",
                                "hardware: EGL device 0 (/dev/dri/renderD128) (the first EGL "
                                "device without EGL_MESA_device_software, of 2)"});
  auto reported = [](const render::Backend* backend) {
    return ProvenanceJson("s.yaml", "seed: 1\n", 1, backend)["environment"]["GALLIVM_PERF"];
  };
  CHECK(reported(&llvmpipe) == (now != nullptr ? nlohmann::ordered_json(now) : nullptr));
  // A GPU ignores it and nothing read it without a render: the user's value, else null.
  CHECK(reported(&gpu) == reported(nullptr));
  if (now == nullptr) {
    CHECK(reported(&gpu).is_null());
  } else if (std::string(now) != render::kDefaultGallivmPerf) {
    CHECK(reported(&gpu) == now);
  } else if (!reported(&gpu).is_null()) {
    WARN("GALLIVM_PERF=" << now << " was set before the tests started: the default is untested");
  }
}

TEST_CASE("provenance.json names the renderer used and hashes the scenario bytes", "[provenance]") {
  const std::string yaml = "# a scenario\nseed: 3\n";
  const StringsOnlyBackend backend(
      {"Mesa", "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core Profile) Mesa 22.3.6",
       "software: Mesa surfaceless platform (no hardware EGL device)"});
  ::setenv("GALLIVM_PERF", "brilinear", 1);
  const nlohmann::ordered_json j = ProvenanceJson("scenarios/x.yaml", yaml, 3, &backend);
  CHECK(j["project_version"] == ProjectVersion());
  CHECK_FALSE(ProjectVersion().empty());
  CHECK_FALSE(j["compiler"]["id"].get<std::string>().empty());
  CHECK_FALSE(j["compiler"]["version"].get<std::string>().empty());
  CHECK(j["scenario"]["file"] == "scenarios/x.yaml");
  CHECK(j["scenario"]["seed"] == 3);
  CHECK(j["scenario"]["sha256"] == Sha256Hex(yaml));
  CHECK(j["render"]["rendered"] == true);
  CHECK(j["render"]["backend"] == "egl");
  CHECK(j["render"]["gl_renderer"] == "llvmpipe (LLVM 15.0.6, 256 bits)");
  CHECK(j["render"]["device"] == "software: Mesa surfaceless platform (no hardware EGL device)");
  CHECK(j["render"]["mesa_version"] == "22.3.6");
  CHECK(j["render"]["llvm_version"] == "15.0.6");
  CHECK(j["environment"]["GALLIVM_PERF"] == "brilinear");
  ::unsetenv("GALLIVM_PERF");
}

TEST_CASE("provenance.json says so when nothing was rendered", "[provenance]") {
  ::unsetenv("GALLIVM_PERF");
  const nlohmann::ordered_json j = ProvenanceJson("s.yaml", "seed: 1\n", 1, nullptr);
  CHECK(j["render"]["rendered"] == false);
  CHECK_FALSE(j["render"].contains("gl_renderer"));
  CHECK(j["render"]["note"].get<std::string>().find("nothing was rendered") == 0);
  CHECK(j["environment"]["GALLIVM_PERF"].is_null());
}

}  // namespace
}  // namespace corridorsim
