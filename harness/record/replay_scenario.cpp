#include "harness/record/replay_scenario.h"

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <set>

#include <yaml-cpp/yaml.h>

#include "common/error.h"
#include "common/io/input_text.h"

namespace corridorsim::record {
namespace {

// Keys a replay may change: they do not shape the sensor stream.
const std::set<std::string> kReplayKeys = {"name",    "description", "seed",
                                           "plugins", "pipelines",   "expectations"};

std::string Text(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "(not set)";
  if (node.IsScalar()) return "'" + InputExcerpt(node.Scalar(), 60) + "'";
  YAML::Emitter out;
  out << YAML::Flow << node;
  return InputExcerpt(out.c_str(), 80);
}

std::string Join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// The first key under `path` where a and b differ, "" when they are equal.
std::string Compare(const YAML::Node& a, const YAML::Node& b, const std::string& path, bool top) {
  const auto differ = [&](const std::string& key) {
    return key + ": the recording has " + Text(a) + ", the scenario " + Text(b);
  };
  if (a.Type() != b.Type()) return differ(path);
  if (a.IsScalar()) return a.Scalar() == b.Scalar() ? "" : differ(path);
  if (a.IsSequence()) {
    if (a.size() != b.size()) {
      return path + ": the recording has " + std::to_string(a.size()) + " entries, the scenario " +
             std::to_string(b.size());
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string d = Compare(a[i], b[i], path + "[" + std::to_string(i) + "]", false);
      if (!d.empty()) return d;
    }
    return "";
  }
  if (a.IsMap()) {
    for (const auto& entry : a) {
      const std::string key = entry.first.as<std::string>();
      if (top && kReplayKeys.count(key)) continue;
      const std::string d = Compare(entry.second, b[key], Join(path, key), false);
      if (!d.empty()) return d;
    }
    for (const auto& entry : b) {
      const std::string key = entry.first.as<std::string>();
      if (top && kReplayKeys.count(key)) continue;
      if (!a[key].IsDefined()) {
        return Join(path, key) + ": the scenario sets it and the recording does not";
      }
    }
  }
  return "";
}

}  // namespace

std::string FirstStreamDifference(const std::string& recorded_yaml, const std::string& yaml) {
  return Compare(YAML::Load(recorded_yaml), YAML::Load(yaml), "", true);
}

Scenario ReplayScenario(const RecordingInfo& recording, const std::string& recording_file,
                        const std::string& scenario_file, const std::vector<std::string>& settings,
                        const std::optional<std::uint64_t>& seed) {
  if (seed && *seed != recording.seed) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--seed",
                     std::to_string(*seed) + " is not the recording's seed (" +
                         std::to_string(recording.seed) +
                         "): a replay runs the recorded stream, seed included");
  }
  Scenario scenario;
  if (scenario_file.empty()) {
    // The recording's own scenario, resolved as the run used it: loaded from a private copy.
    const std::filesystem::path copy =
        std::filesystem::temp_directory_path() /
        ("corridorsim-replay-" + std::to_string(::getpid()) + ".yaml");
    {
      std::ofstream out(copy, std::ios::binary);
      out << recording.scenario_yaml;
      if (!out) throw std::runtime_error("cannot write " + copy.string());
    }
    try {
      scenario = LoadScenario(copy.string(), settings);
    } catch (...) {
      std::filesystem::remove(copy);
      throw;
    }
    std::filesystem::remove(copy);
    scenario.file = recording.scenario_file.empty() ? recording_file : recording.scenario_file;
    scenario.chain_files.clear();
  } else {
    scenario = LoadScenario(scenario_file, settings);
  }
  std::string difference;
  try {
    difference = FirstStreamDifference(recording.scenario_yaml,
                                       ResolvedScenarioYaml(scenario, recording.seed));
  } catch (const YAML::Exception& e) {
    throw InputError(SourceLocation{recording_file, 0, 0}, "scenario.yaml",
                     std::string("the recording's scenario is not YAML: ") + e.what());
  }
  if (!difference.empty()) {
    throw InputError(SourceLocation{scenario_file.empty() ? recording_file : scenario_file, 0, 0},
                     "scenario",
                     "its sensor stream differs from the recording's at " + difference +
                         " (a replay may change only the pipelines and the expectations)");
  }
  return scenario;
}

}  // namespace corridorsim::record
