#pragma once
// provenance.json: what the bytes of a run folder depend on besides the scenario and the seed
// (docs/architecture.md, "Provenance"): the project's version (git describe at build time), the
// compiler, the GL renderer and its Mesa and LLVM releases and the device the backend chose
// (hardware or software, and why), or that nothing was rendered; the GALLIVM_PERF environment
// variable, the SHA-256 of the resolved scenario.yaml bytes, and each pipeline plugin's library
// (path, SHA-256, the version it reports).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/scenario/scenario.h"

#include "render/backend.h"

namespace corridorsim {

/// The project version: `git describe --always --dirty` of the source tree when it was built
/// ("unknown" outside git).
std::string ProjectVersion();

/// The release after `marker` in a GL string ("Mesa " in "4.5 (Core Profile) Mesa 22.3.6",
/// "LLVM " in "llvmpipe (LLVM 15.0.6, 256 bits)"): the characters up to a space, comma or
/// parenthesis; nothing when the marker is absent.
std::optional<std::string> ReleaseAfter(const std::string& gl_string, const std::string& marker);

/// The provenance of a run folder or drive folder. `scenario_yaml` is the resolved scenario.yaml
/// exactly as written (its SHA-256 is recorded), `scenario_file` the path given on the command
/// line; `backend` is the GL backend the job rendered with, or null when it rendered nothing;
/// `plugins` the canonical paths of the plugin libraries the scenario loaded (each recorded with
/// its SHA-256, name, version and types, harness/scenario/plugins.h); `settings` the `--set
/// KEY=VALUE` the scenario was loaded with (recorded only when there are some, so that the
/// provenance of a run without them keeps its bytes).
nlohmann::ordered_json ProvenanceJson(const std::string& scenario_file,
                                      const std::string& scenario_yaml, std::uint64_t seed,
                                      const render::Backend* backend,
                                      const std::vector<std::filesystem::path>& plugins = {},
                                      const nlohmann::ordered_json& external_programs = {},
                                      const std::vector<std::string>& settings = {});

/// The programs of `scenario`'s enabled external pipelines, by pipeline name, each as
/// external::ProgramFingerprint (its command and the SHA-256 of the files it names); null when
/// it has none. provenance.json records it as `external_programs`, a study's plan too (an edited
/// script makes another study).
nlohmann::ordered_json ExternalProgramsJson(const Scenario& scenario);

}  // namespace corridorsim
