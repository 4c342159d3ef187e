#include "harness/scenario.h"

#include <algorithm>

#include <yaml-cpp/yaml.h>

#include "common/io/atomic_file.h"
#include "common/options_checker.h"

namespace corridorsim {

namespace {

// `pipelines:` maps pipeline names to their options; options accumulate over the include chain.
void ParsePipelines(YamlMap& pipelines, Scenario& scenario) {
  for (const std::string& name : pipelines.Keys()) {
    YamlMap options = pipelines.Map(name);
    auto entry = std::find_if(scenario.pipelines.begin(), scenario.pipelines.end(),
                              [&](const Scenario::PipelineEntry& e) { return e.name == name; });
    if (entry == scenario.pipelines.end()) {
      std::shared_ptr<slam::PipelineConfig> config = slam::NewPipelineConfig(name);
      if (!config) {
        std::string known;
        for (const std::string& n : slam::PipelineNames()) known += (known.empty() ? "" : ", ") + n;
        pipelines.Fail(name, "unknown pipeline (known: " + known + ")");
      }
      scenario.pipelines.push_back({name, std::move(config), true});
      entry = scenario.pipelines.end() - 1;
    }
    options.Read("enabled", entry->enabled);
    entry->config->Parse(options);
  }
}

}  // namespace

Scenario LoadScenario(const std::string& path) {
  Scenario scenario;
  scenario.file = path;
  scenario.world_location = SourceLocation{path, 0, 0};
  scenario.sensors_location = SourceLocation{path, 0, 0};
  scenario.robot_location = SourceLocation{path, 0, 0};
  scenario.path_location = SourceLocation{path, 0, 0};
  scenario.pipelines_location = SourceLocation{path, 0, 0};
  // Documents stay alive while their maps are read: YamlMap points into them.
  const std::vector<YamlDocument> chain = LoadWithIncludes(path);
  for (const YamlDocument& doc : chain) {
    YamlMap root(doc, doc.root, "", &scenario.sources);
    root.Accept("include");
    root.Read("name", scenario.name);
    root.Read("description", scenario.description);
    root.Read("seed", scenario.seed);
    if (root.Has("world")) scenario.world_location = root.LocationOfKey("world");
    YamlMap world = root.Map("world");
    worlds::ParseWorldOptions(world, scenario.world);
    if (root.Has("sensors")) scenario.sensors_location = root.LocationOfKey("sensors");
    YamlMap sensors = root.Map("sensors");
    render::ParseSensors(sensors, scenario.rig);
    YamlMap render = root.Map("render");
    render::ParseRenderOptions(render, scenario.rig);
    if (root.Has("robot")) scenario.robot_location = root.LocationOfKey("robot");
    YamlMap robot = root.Map("robot");
    sim::ParseRobotOptions(robot, scenario.robot);
    if (root.Has("path")) scenario.path_location = root.LocationOfKey("path");
    YamlMap path_map = root.Map("path");
    sim::ParseRobotPathOptions(path_map, scenario.robot_path);
    root.Read("duration_s", scenario.duration_s);
    if (root.Has("pipelines")) scenario.pipelines_location = root.LocationOfKey("pipelines");
    YamlMap pipelines = root.Map("pipelines");
    ParsePipelines(pipelines, scenario);
    root.Read("expectations", scenario.expectations, &scenario.expectation_locations);
    root.RejectUnknownKeys();
  }
  if (auto problem = scenario.world.Check()) throw LocateProblem(scenario, "world", *problem);
  if (auto problem = scenario.rig.Check()) throw LocateProblem(scenario, "sensors", *problem);
  if (auto problem = scenario.robot.Check()) throw LocateProblem(scenario, "robot", *problem);
  if (auto problem = scenario.robot_path.Check()) throw LocateProblem(scenario, "path", *problem);
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (auto problem = entry.config->Check()) {
      throw LocateProblem(scenario, "pipelines",
                          OptionsProblem{entry.name + "." + problem->key, problem->message});
    }
  }
  ScenarioExpectations(scenario);  // checked here so that every command rejects a bad one
  if (!(scenario.duration_s >= 0 && scenario.duration_s <= 1e6)) {
    throw InputError(scenario.sources.Find("duration_s", SourceLocation{path, 0, 0}), "duration_s",
                     "must lie in [0, 1e+06] s (got " + FormatNumber(scenario.duration_s) + ")");
  }
  return scenario;
}

InputError LocateProblem(const Scenario& scenario, const std::string& section,
                         const OptionsProblem& problem) {
  const std::string key = section + "." + problem.key;
  const SourceLocation& fallback = section == "sensors"     ? scenario.sensors_location
                                   : section == "robot"     ? scenario.robot_location
                                   : section == "path"      ? scenario.path_location
                                   : section == "pipelines" ? scenario.pipelines_location
                                                            : scenario.world_location;
  return InputError(scenario.sources.Find(key, fallback), key, problem.message);
}

worlds::World GenerateWorld(const Scenario& scenario, std::uint64_t seed) {
  try {
    return worlds::Generate(scenario.world, seed);
  } catch (const OptionsError& e) {
    throw LocateProblem(scenario, "world", e.problem());
  }
}

namespace {

// `over` on top of `base`: maps merge key by key, anything else replaces.
YAML::Node MergeNodes(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : base) {
    const std::string key = kv.first.Scalar();
    const YAML::Node& o = over;
    out[key] = o[key] ? MergeNodes(kv.second, o[key]) : YAML::Clone(kv.second);
  }
  for (const auto& kv : over) {
    const std::string key = kv.first.Scalar();
    const YAML::Node& b = base;
    if (!b[key]) out[key] = YAML::Clone(kv.second);
  }
  return out;
}

}  // namespace

std::string ResolvedScenarioYaml(const std::string& path, std::uint64_t seed) {
  YAML::Node merged(YAML::NodeType::Map);
  for (const YamlDocument& doc : LoadWithIncludes(path)) {
    if (doc.root.IsMap()) merged = MergeNodes(merged, doc.root);
  }
  merged.remove("include");
  merged["seed"] = seed;
  YAML::Emitter out;
  out << merged;
  return "# The scenario of this run: " + path +
         " with its include chain merged and the seed used.\n# Keys not written here keep "
         "corridorsim's defaults (docs/scenarios.md).\n" +
         std::string(out.c_str()) + "\n";
}

void EnsureOutputDirectory(const std::filesystem::path& dir, const std::string& option) {
  try {
    EnsureWritableDirectory(dir);
  } catch (const std::exception& e) {
    throw InputError(SourceLocation{"command line", 0, 0}, option, e.what());
  }
}

std::vector<Expectation> ScenarioExpectations(const Scenario& scenario) {
  std::vector<Expectation> parsed;
  const std::vector<std::string> metric_names = MetricNames();
  for (std::size_t i = 0; i < scenario.expectations.size(); ++i) {
    const SourceLocation& where = scenario.expectation_locations[i];
    Expectation e;
    if (auto error = ParseExpectation(scenario.expectations[i], &e)) {
      throw InputError(where, "expectations", *error);
    }
    const auto pipeline =
        std::find_if(scenario.pipelines.begin(), scenario.pipelines.end(),
                     [&](const Scenario::PipelineEntry& p) { return p.name == e.pipeline; });
    if (pipeline == scenario.pipelines.end() || !pipeline->enabled) {
      std::string known;
      for (const auto& p : scenario.pipelines) {
        if (p.enabled) known += (known.empty() ? "" : ", ") + p.name;
      }
      throw InputError(where, "expectations",
                       "'" + e.text + "': the pipeline '" + e.pipeline +
                           "' does not run in this scenario (running: " +
                           (known.empty() ? "none" : known) + ")");
    }
    if (std::find(metric_names.begin(), metric_names.end(), e.metric) == metric_names.end()) {
      std::string known;
      for (const std::string& m : metric_names) known += (known.empty() ? "" : ", ") + m;
      throw InputError(
          where, "expectations",
          "'" + e.text + "': unknown metric '" + e.metric + "' (known: " + known + ")");
    }
    parsed.push_back(std::move(e));
  }
  return parsed;
}

sim::RobotPath BuildScenarioRobotPath(const Scenario& scenario, const worlds::World& world) {
  try {
    return sim::BuildRobotPath(world, scenario.robot_path);
  } catch (const OptionsError& e) {
    throw LocateProblem(scenario, "path", e.problem());
  }
}

}  // namespace corridorsim
