#include "harness/run/provenance.h"

#include <optional>
#include <string>

#include "common/io/sha256.h"
#include "corridorsim_version.h"  // generated at build time (cmake/version.cmake)
#include "harness/external/external_pipeline.h"
#include "harness/scenario/plugins.h"
#include "render/software_rasterizer.h"
#include "slam/sdk_version.h"

namespace corridorsim {

using Json = nlohmann::ordered_json;

std::string ProjectVersion() { return CORRIDORSIM_GIT_DESCRIBE; }

std::optional<std::string> ReleaseAfter(const std::string& gl_string, const std::string& marker) {
  const auto at = gl_string.find(marker);
  if (at == std::string::npos) return std::nullopt;
  const auto begin = at + marker.size();
  const auto end = gl_string.find_first_of(" ,()", begin);
  std::string release = gl_string.substr(begin, end == std::string::npos ? end : end - begin);
  if (release.empty()) return std::nullopt;
  return release;
}

Json ExternalProgramsJson(const Scenario& scenario) {
  Json out;
  for (const Scenario::PipelineEntry& p : scenario.pipelines) {
    if (!p.enabled || !p.options ||
        &p.options->table() != &external::ExternalPipelineOptionsTable()) {
      continue;
    }
    const auto* options =
        static_cast<const external::ExternalPipelineOptions*>(p.options->options());
    out[p.name] = external::ProgramFingerprint(*options);
  }
  return out;
}

Json ProvenanceJson(const std::string& scenario_file, const std::string& scenario_yaml,
                    std::uint64_t seed, const render::Backend* backend,
                    const std::vector<std::filesystem::path>& plugins,
                    const nlohmann::ordered_json& external_programs,
                    const std::vector<std::string>& settings) {
  const auto or_null = [](const std::optional<std::string>& s) {
    return s ? Json(*s) : Json(nullptr);
  };
  Json j;
  j["project_version"] = ProjectVersion();
  j["version"] = CORRIDORSIM_VERSION;
  j["sdk_abi_version"] = CORRIDORSIM_SDK_ABI_VERSION;
  j["compiler"] = {{"id", CORRIDORSIM_CXX_COMPILER_ID},
                   {"version", CORRIDORSIM_CXX_COMPILER_VERSION}};
  j["scenario"] = {{"file", scenario_file},
                   {"seed", seed},
                   {"sha256", Sha256Hex(scenario_yaml)},
                   {"sha256_of", "the resolved scenario (a run's scenario.yaml)"}};
  if (!settings.empty()) j["scenario"]["settings"] = settings;  // --set, in order
  Json plugin_list = Json::array();
  for (const std::filesystem::path& path : plugins) {
    const LoadedPlugin* plugin = FindLoadedPlugin(path);
    if (!plugin) continue;  // cannot happen: a scenario's plugins are loaded with it
    plugin_list.push_back({{"path", plugin->path.string()},
                           {"sha256", plugin->sha256},
                           {"name", plugin->name},
                           {"version", plugin->version},
                           {"sdk_version", plugin->sdk_version},
                           {"types", plugin->types}});
  }
  j["plugins"] = std::move(plugin_list);
  // Only with external pipelines: the provenance of every other run keeps its bytes.
  if (!external_programs.is_null()) j["external_programs"] = external_programs;
  Json render;
  if (backend == nullptr) {
    render["rendered"] = false;
    render["note"] = "nothing was rendered: no GL context, so no renderer, Mesa or LLVM";
  } else {
    const render::BackendInfo info = backend->info();
    render["rendered"] = true;
    render["backend"] = render::BackendName(backend->kind());
    render["gl_vendor"] = info.vendor;
    render["gl_renderer"] = info.renderer;
    // Which device rendered and why (a GPU's images differ from llvmpipe's within a tolerance).
    render["device"] = info.device;
    render["gl_version"] = info.version;
    render["mesa_version"] = or_null(ReleaseAfter(info.version, "Mesa "));
    render["llvm_version"] = or_null(ReleaseAfter(info.renderer, "LLVM "));
  }
  j["render"] = std::move(render);
  // As in effect for llvmpipe: main() sets it unless the user did; null on a GPU or without a
  // render unless the user set it (render/software_rasterizer.h).
  const std::optional<std::string> gallivm_perf = render::GallivmPerfInEffect(backend);
  j["environment"] = {{"GALLIVM_PERF", gallivm_perf ? Json(*gallivm_perf) : Json(nullptr)}};
  return j;
}

}  // namespace corridorsim
