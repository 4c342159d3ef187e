#include "harness/scenario/scenario.h"

#include <algorithm>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "common/io/atomic_file.h"
#include "common/io/input_text.h"
#include "common/io/options_yaml.h"
#include "harness/external/external_pipeline.h"
#include "harness/scenario/overrides.h"
#include "harness/scenario/plugins.h"

namespace corridorsim {

namespace {

// A YAML map none of whose keys a scenario has is some other file (`include: /etc/shadow`, a
// config of another program): reported by its position and kind only, never by its content,
// which an "unknown key" message would quote.
void RequireScenarioKey(const YamlDocument& doc) {
  const auto& fields = ScenarioOptionsTable().fields();
  for (const auto& kv : doc.root) {
    const bool known =
        kv.first.IsScalar() && std::any_of(fields.begin(), fields.end(), [&](const OptionField& f) {
          return f.key == kv.first.Scalar();
        });
    if (known) return;
  }
  throw InputError(SourceLocation{doc.file, 0, 0}, "",
                   "not a corridorsim scenario: a YAML map of " + std::to_string(doc.root.size()) +
                       " key(s), none of them a scenario key (docs/scenarios.md)");
}

// `pipelines:` maps pipeline names to their options; `type:` says which pipeline type the entry
// runs (default: its name), so that one scenario can compare variants of one type. Options
// accumulate over the include chain; a child file cannot change an entry's type.
void ParsePipelines(YamlMap& pipelines, Scenario& scenario) {
  for (const std::string& name : pipelines.Keys()) {
    YamlMap map = pipelines.Map(name);
    if (!slam::IsPipelineName(name)) {
      pipelines.Fail(name,
                     "a pipeline name is 1 to " + std::to_string(slam::kMaxPipelineNameLength) +
                         " lower-case letters, digits and '_', starting with a letter (got '" +
                         InputExcerpt(name) + "')");
    }
    auto entry = std::find_if(scenario.pipelines.begin(), scenario.pipelines.end(),
                              [&](const Scenario::PipelineEntry& e) { return e.name == name; });
    std::string type = entry == scenario.pipelines.end() ? name : entry->type;
    map.Read("type", type);
    if (entry == scenario.pipelines.end()) {
      std::shared_ptr<slam::PipelineOptions> options = slam::NewPipelineOptions(type);
      if (!options) {
        std::string known;
        for (const std::string& n : slam::PipelineNames()) known += (known.empty() ? "" : ", ") + n;
        map.Has("type") ? map.Fail("type", "unknown pipeline type '" + InputExcerpt(type) +
                                               "' (known: " + known + ")")
                        : pipelines.Fail(name, "unknown pipeline (known: " + known +
                                                   "; another name needs a `type:` key)");
      }
      scenario.pipelines.push_back({name, type, std::move(options), true, false});
      entry = scenario.pipelines.end() - 1;
    } else if (type != entry->type) {
      map.Fail("type", "the pipeline '" + name + "' is of type '" + entry->type +
                           "' in a base file; a child file cannot change it (got '" +
                           InputExcerpt(type) + "')");
    }
    map.Read("enabled", entry->enabled);
    map.Read("baseline", entry->baseline);
    ReadOptionFields(map, entry->options->table(), entry->options->options());
    map.RejectUnknownKeys();
  }
}

// `plugins:` lists libraries, relative to the file that names them (like `include:`); they load
// now, so that `pipelines:` below (read after this key) can name their types. The lists of an
// include chain add up, base first; a library named twice loads once.
void ParsePlugins(YamlMap& root, Scenario& scenario) {
  std::vector<std::string> paths;
  std::vector<SourceLocation> locations;
  if (!root.Read("plugins", paths, &locations)) return;
  constexpr std::size_t kMaxPlugins = 64;
  if (paths.size() + scenario.plugins.size() > kMaxPlugins) {
    root.Fail("plugins", "at most " + std::to_string(kMaxPlugins) + " plugin libraries");
  }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::string& name = paths[i];
    if (name.empty() || HasControlCharacter(name)) {
      throw InputError(locations[i], "plugins",
                       name.empty()
                           ? "expected the path of a plugin library"
                           : "the path '" + InputExcerpt(name) + "' contains a control character");
    }
    std::filesystem::path path(name);
    if (path.is_relative()) {
      path = std::filesystem::path(locations[i].file).parent_path() / path;
    }
    const LoadedPlugin plugin = LoadPlugin(path, locations[i]);
    if (std::find(scenario.plugins.begin(), scenario.plugins.end(), plugin.path) ==
        scenario.plugins.end()) {
      scenario.plugins.push_back(plugin.path);
    }
  }
}

// Absolute paths: the echo is read from the run folder, not from where the scenario was.
void EchoPlugins(const Scenario& scenario, OptionsYamlWriter& out) {
  if (scenario.plugins.empty()) return;  // the echo of a scenario without plugins stays as it was
  std::string list;
  for (const std::filesystem::path& p : scenario.plugins) {
    list += (list.empty() ? "" : ", ") + YamlString(p.string());
  }
  out.Scalar("plugins", "[" + list + "]");
}

void EchoPipelines(const Scenario& scenario, OptionsYamlWriter& out) {
  out.BeginMap("pipelines");
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    out.BeginMap(entry.name);
    out.Scalar("type", entry.type);
    out.Scalar("enabled", entry.enabled ? "true" : "false");
    // Only when set, so that the echo of a scenario without baselines stays what it was.
    if (entry.baseline) out.Scalar("baseline", "true");
    WriteOptions(out, entry.options->table(), entry.options->options());
    out.EndMap();
  }
  out.EndMap();
}

// The docs of a key that hooks read and echo: one row, without unit or bounds.
std::function<std::vector<OptionDocRow>(const Scenario&)> OneDocRow(std::string key,
                                                                    std::string default_value,
                                                                    std::string doc) {
  return [key, default_value, doc](const Scenario&) {
    return std::vector<OptionDocRow>{{key, "", default_value, "", doc}};
  };
}

void EchoExpectations(const Scenario& scenario, OptionsYamlWriter& out) {
  std::string list;
  for (const std::string& e : scenario.expectations) {
    list += (list.empty() ? "" : ", ") + YamlString(e);
  }
  out.Scalar("expectations", "[" + list + "]");
}

}  // namespace

const OptionTable<Scenario>& ScenarioOptionsTable() {
  return StaticOptionTable<Scenario>([](OptionTable<Scenario>& t) {
    using S = Scenario;
    t.AddCustom(
        "include", "", [](YamlMap& root, S&) { root.Accept("include"); },
        [](const S&, OptionsYamlWriter&) {},  // the echo has every key: it includes nothing
        OneDocRow("include", "",
                  "a base scenario (path relative to this file); this file overrides it"));
    t.AddCustom(
        "study", "", [](YamlMap& root, S&) { root.Accept("study"); },
        [](const S&, OptionsYamlWriter&) {},  // a run's echo is one run: no study
        OneDocRow("study", "",
                  "a study's settings (seeds, sweeps, expectations; docs/studies.md), read by "
                  "`corridorsim study` from the file it is given; `run` ignores it"));
    t.Add("name", &S::name, "", "free text");
    t.Add("description", &S::description, "", "free text");
    t.Add("seed", &S::seed, "",
          "seed of every random stream of the run (world layout, noise, ...)");
    t.AddSection("world", &S::world, worlds::WorldOptionsTable(), "the world",
                 &worlds::WorldOptions::Check);
    t.AddSection(
        "appearance", [](S& s) -> worlds::AppearanceOptions& { return s.world.appearance; },
        worlds::AppearanceOptionsTable(),
        "appearance randomisation: what varies from world to world (docs/rendering.md)",
        &worlds::AppearanceOptions::Check);
    auto rig = [](S& s) -> render::RigOptions& { return s.rig; };
    t.AddSection(
        "sensors", [](S& s) -> S& { return s; }, ScenarioSensorsTable(),
        "the named sensors: cameras, IMUs, laser scanners", &Scenario::CheckSensors);
    t.AddSection("render", rig, render::RenderOptionsTable(), "how the cameras are drawn",
                 &render::RigOptions::CheckRender);
    t.AddSection("robot", &S::robot, sim::RobotOptionsTable(), "the robot and its odometry errors",
                 &sim::RobotOptions::Check);
    t.AddSection("path", &S::robot_path, sim::RobotPathOptionsTable(), "what the robot drives",
                 &sim::RobotPathOptions::Check);
    t.Add("duration_s", &S::duration_s, "s", "simulated time of a run; 0 = until the path is done")
        .ZeroOr(1e-3, kMaxRunSeconds, "must lie in [0.001, 1e+06] s or be 0 (got {})");
    t.AddCustom(
        "plugins", "", [](YamlMap& root, S& s) { ParsePlugins(root, s); }, &EchoPlugins,
        OneDocRow("plugins", "`[]`",
                  "pipeline plugin libraries (paths relative to this file) whose pipeline types "
                  "`pipelines:` may name (docs/plugins.md)"));
    t.AddCustom(
        "pipelines", "",
        [](YamlMap& root, S& s) {
          YamlMap pipelines = root.Map("pipelines");
          ParsePipelines(pipelines, s);
        },
        &EchoPipelines,
        OneDocRow(
            "pipelines", "`{}`",
            "the SLAM pipelines that run on the sensor stream, by name, each with its options "
            "(below)"));
    t.AddCustom(
        "expectations", "",
        [](YamlMap& root, S& s) {
          root.Read("expectations", s.expectations, &s.expectation_locations);
        },
        &EchoExpectations,
        OneDocRow("expectations", "`[]`", "assertions on the run's metrics (below)"));
  });
}

Scenario LoadScenario(const std::string& path) {
  return LoadScenario(path, std::vector<std::string>{}, {});
}

Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings) {
  return LoadScenario(path, settings, {});
}

Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings,
                      const std::vector<YamlDocument>& overrides) {
  external::RegisterExternalPipelineType();  // `type: external` (docs/protocol.md)
  const std::vector<Setting> parsed_settings = ParseSettings(settings);
  Scenario scenario;
  scenario.file = path;
  scenario.settings = settings;
  scenario.world_location = SourceLocation{path, 0, 0};
  scenario.sensors_location = SourceLocation{path, 0, 0};
  scenario.robot_location = SourceLocation{path, 0, 0};
  scenario.path_location = SourceLocation{path, 0, 0};
  scenario.pipelines_location = SourceLocation{path, 0, 0};
  // Documents stay alive while their maps are read: YamlMap points into them.
  std::vector<YamlDocument> chain = LoadWithIncludes(path);
  for (const YamlDocument& doc : chain) scenario.chain_files.emplace_back(doc.file);
  const std::vector<YamlDocument> set = SettingDocuments(parsed_settings, chain);
  const std::size_t files = chain.size();
  chain.insert(chain.end(), set.begin(), set.end());
  chain.insert(chain.end(), overrides.begin(), overrides.end());
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const YamlDocument& doc = chain[i];
    const bool setting = i >= files && i < files + set.size();
    // A file without a key (0 bytes, only comments, `{}`) is a mistake, never "all defaults":
    // it would run the default simulation with nothing to score.
    if (doc.root.size() == 0) {
      throw InputError(SourceLocation{doc.file, 0, 0}, "",
                       "the scenario is empty (no keys: nothing but comments or blank lines)");
    }
    // A setting's unknown key is reported by name (RejectUnknownKeys) like a file's.
    if (!setting) RequireScenarioKey(doc);
    YamlMap root(doc, doc.root, "", &scenario.sources);
    for (auto [key, location] : {std::pair{"world", &scenario.world_location},
                                 {"sensors", &scenario.sensors_location},
                                 {"robot", &scenario.robot_location},
                                 {"path", &scenario.path_location},
                                 {"pipelines", &scenario.pipelines_location}}) {
      if (root.Has(key)) *location = root.LocationOfKey(key);
    }
    ReadOptions(root, ScenarioOptionsTable(), scenario);
  }
  // Bounds and each section's Check(), in table order: world, sensors, render, robot, path,
  // duration_s.
  if (auto problem = CheckOptionBounds(ScenarioOptionsTable(), scenario)) {
    const std::string& key = problem->key;
    const auto dot = key.find('.');
    if (dot == std::string::npos) {
      throw InputError(scenario.sources.Find(key, SourceLocation{path, 0, 0}), key,
                       problem->message);
    }
    throw LocateProblem(scenario, key.substr(0, dot),
                        OptionsProblem{key.substr(dot + 1), problem->message});
  }
  // Free text is printed to terminals and written into files: no control characters but tabs
  // (and newlines in `description`): an escape sequence in `name` would drive the user's
  // terminal. Bounded, like every text that is echoed.
  for (const auto& [key, text, newlines] :
       {std::tuple<const char*, const std::string*, bool>{"name", &scenario.name, false},
        {"description", &scenario.description, true}}) {
    constexpr std::size_t kMaxTextBytes = 1000;
    const bool lines = newlines;  // clang 14 (the fuzz build) cannot capture a binding
    const bool control = std::any_of(text->begin(), text->end(), [lines](char c) {
      const bool allowed = c == '\t' || (lines && c == '\n');
      return (static_cast<unsigned char>(c) < 0x20 && !allowed) || c == 0x7f;
    });
    if (control || text->size() > kMaxTextBytes) {
      throw InputError(
          scenario.sources.Find(key, SourceLocation{path, 0, 0}), key,
          control ? std::string("must not contain control characters (escapes") +
                        (newlines ? ")" : ", newlines)")
                  : "must be at most 1000 bytes (got " + std::to_string(text->size()) + ")");
    }
  }
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (auto problem = entry.options->Check()) {
      throw LocateProblem(scenario, "pipelines",
                          OptionsProblem{entry.name + "." + problem->key, problem->message});
    }
  }
  ScenarioExpectations(scenario);  // checked here so that every command rejects a bad one
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

std::string ResolvedScenarioYaml(const Scenario& scenario, std::uint64_t seed) {
  Scenario resolved = scenario;
  resolved.seed = seed;
  // The header names no file: the echo of this file's own load is these bytes again
  // (provenance.json records where the scenario came from).
  return "# The scenario of a run, resolved: its include chain merged, every key with the value "
         "the run used (defaults included) and the seed used.\n" +
         OptionsYaml(ScenarioOptionsTable(), resolved);
}

void RequireScoredPipeline(const Scenario& scenario) {
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (entry.enabled) return;
  }
  std::string disabled;
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    disabled += (disabled.empty() ? "" : ", ") + entry.name;
  }
  std::string known;
  for (const std::string& n : slam::PipelineNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError(scenario.pipelines_location, "pipelines",
                   "no pipeline is enabled, so the run would score nothing (" +
                       (disabled.empty() ? std::string("none given") : "disabled: " + disabled) +
                       "; known: " + known + "); enable one, or use `drive` or `run --export`");
}

std::vector<OptionsDocBlock> ScenarioDocBlocks() {
  const Scenario defaults;
  std::vector<OptionsDocBlock> blocks =
      OptionsDocBlocks(ScenarioOptionsTable(), &defaults, "scenario");
  // The kinds of sensor a scenario names itself (no default has one): their keys with the
  // kind's defaults, under `sensors.<imu>` and `sensors.<laser>`.
  const sim::ImuOptions imu;
  const sim::LaserOptions laser;
  for (const std::vector<OptionsDocBlock>& more :
       {OptionsDocBlocks(sim::ImuOptionsTable(), &imu, "sensors.<imu>", "sensors.<imu>"),
        OptionsDocBlocks(sim::LaserOptionsTable(), &laser, "sensors.<laser>", "sensors.<laser>")}) {
    blocks.insert(blocks.end(), more.begin(), more.end());
  }
  std::vector<slam::PipelineType> types = slam::ShippedPipelineTypes();
  types.push_back(external::ExternalPipelineType());
  for (const slam::PipelineType& type : types) {
    const std::unique_ptr<slam::PipelineOptions> options = type.new_options();
    const std::vector<OptionsDocBlock> more = OptionsDocBlocks(
        options->table(), options->options(), "pipelines." + type.name, "pipelines." + type.name);
    blocks.insert(blocks.end(), more.begin(), more.end());
  }
  return blocks;
}

std::vector<Expectation> ScenarioExpectations(const Scenario& scenario) {
  std::vector<Expectation> parsed;
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
                       "'" + InputExcerpt(e.text) + "': the pipeline '" + InputExcerpt(e.pipeline) +
                           "' does not run in this scenario (running: " +
                           (known.empty() ? "none" : known) + ")");
    }
    // timing.* are wall-clock figures (timing.json): a bound on them passes or fails with the
    // machine's load, never with the scenario.
    if (e.metric.rfind("timing.", 0) == 0) {
      throw InputError(where, "expectations",
                       "'" + e.text + "': timing metrics are machine-dependent; see timing.json");
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
