#pragma once
// A scenario file: the seed, the world, the sensors, the robot and its path, the SLAM pipelines
// that run on the sensor stream and the expectations on their metrics. Loading is strict: see
// docs/scenarios.md.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/io/options_yaml.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "harness/metrics/metrics.h"
#include "render/camera_rig.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"
#include "sim/robot.h"
#include "sim/robot_path.h"
#include "slam/registry.h"
#include "worlds/world.h"
#include "worlds/world_options.h"

namespace corridorsim {

struct Scenario {
  std::string file;  // the file given on the command line
  // Every file of the include chain LoadScenario read (`file` and the bases it includes): the
  // job's inputs, which no output folder may be, contain or lie inside (harness/run/job_inputs.h).
  std::vector<std::filesystem::path> chain_files;
  // `--set KEY=VALUE` as given, applied after the file's include chain (overrides.h); recorded
  // in provenance.json (the echo holds their values).
  std::vector<std::string> settings;
  std::string name;         // optional human-readable name
  std::string description;  // optional
  std::uint64_t seed = 1;   // seed of every random stream of the run
  worlds::WorldOptions world;
  render::RigOptions rig = render::RigOptions::Default();  // `sensors:` cameras and `render:`
  std::vector<sim::ImuOptions> imus;      // `sensors:` of `type: imu`, in the order first named
  std::vector<sim::LaserOptions> lasers;  // `sensors:` of `type: laser`
  sim::RobotOptions robot;                // `robot:` (odometry errors under `robot.odometry`)
  sim::RobotPathOptions robot_path;       // `path:`
  double duration_s = 0;  // `duration_s`: simulated time of a run; 0 = until the path is done
  // `plugins:`: the pipeline plugin libraries the scenario loads (harness/scenario/plugins.h),
  // canonical paths, base files' first; each is loaded when the scenario is (its types are then
  // known).
  std::vector<std::filesystem::path> plugins;
  // `pipelines:` in order of first appearance (base files first); `enabled: false` drops one.
  struct PipelineEntry {
    std::string name;  // unique in the scenario: names its files and its metrics
    std::string type;  // the pipeline type (slam/registry.h): `type:`, default the name
    std::shared_ptr<slam::PipelineOptions> options;
    bool enabled = true;
    // `baseline: true`: a reference the scenario compares against (dead reckoning, P1's Harris
    // EKF), not a system under test: a study reports and counts its diverged runs but never
    // fails on them (docs/studies.md, "Failures"). A harness key, not a pipeline option.
    bool baseline = false;
  };
  std::vector<PipelineEntry> pipelines;
  // `expectations:` as written (the last file that has the key wins), with where each was set.
  std::vector<std::string> expectations;
  std::vector<SourceLocation> expectation_locations;
  SourceMap sources;                  // where each key was set, for errors found after parsing
  SourceLocation world_location;      // the `world:` key of the last file that has one
  SourceLocation sensors_location;    // the `sensors:` key of the last file that has one
  SourceLocation robot_location;      // `robot:`
  SourceLocation path_location;       // `path:`
  SourceLocation pipelines_location;  // `pipelines:`

  /// The first problem of the `sensors:` section (key relative to `sensors`), or nothing.
  std::optional<OptionsProblem> CheckSensors() const;
};

/// The scenario file's keys: the top-level ones and every section through its table (parsing,
/// checks, the echo and docs/scenarios.md's key tables).
const OptionTable<Scenario>& ScenarioOptionsTable();

/// The `sensors:` section's keys: the named sensors of every kind, a new name made of its
/// `type:` (harness/scenario/scenario_sensors.cpp; docs/sensors.md).
const OptionTable<Scenario>& ScenarioSensorsTable();

/// docs/scenarios.md's generated key tables: every section of ScenarioOptionsTable() with the
/// defaults ("scenario", "world", "world.doors", ..., "sensors", "render", ...) and each shipped
/// pipeline's options ("pipelines.odometry").
std::vector<OptionsDocBlock> ScenarioDocBlocks();

/// Loads `path` and its `include:` chain (base first) onto code defaults, then checks the
/// result. Throws InputError naming file, line, column and key; a file of the chain with no key
/// at all (empty, only comments) is an error. A section written with nothing after it
/// (`world:`, YAML null) overrides nothing, as `world: {}`.
Scenario LoadScenario(const std::string& path);
/// As above, then `settings` (`--set KEY=VALUE`, harness/scenario/overrides.h) applied in order
/// on top of the chain, each checked as strictly as a file's keys (a problem is an InputError at
/// `command line: --set` naming the key).
Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings);
/// As above, then `overrides` applied in order on top of the settings (a study's sweep point: each
/// a map of scenario keys, checked as strictly as a file's).
Scenario LoadScenario(const std::string& path, const std::vector<std::string>& settings,
                      const std::vector<YamlDocument>& overrides);

/// Turns a problem found by a options's Check() or a generator into an InputError placed at the
/// line that set the offending key (`section` is "world", "sensors", "robot", "path" or
/// "pipelines").
InputError LocateProblem(const Scenario& scenario, const std::string& section,
                         const OptionsProblem& problem);

/// Generates the scenario's world with `seed`, reporting generator problems as InputError.
worlds::World GenerateWorld(const Scenario& scenario, std::uint64_t seed);

/// `scenario` (as loaded at the start of a job: the file is never read again) echoed through its
/// tables with `seed` set to `seed`: every key with its resolved value (defaults included), no
/// `include:`, a header line that names no file. A single file that repeats the run: loading it
/// gives the same options, and its own echo is these bytes.
std::string ResolvedScenarioYaml(const Scenario& scenario, std::uint64_t seed);

/// For `run` (without --export): throws InputError at `pipelines:` unless a pipeline is enabled,
/// since a run without one scores nothing. `drive`, `snapshot` and `world` need none.
void RequireScoredPipeline(const Scenario& scenario);

/// The scenario's expectations, parsed and checked against its pipelines and the metric names.
/// Throws InputError at the expectation's line for bad syntax, an unknown or disabled pipeline, an
/// unknown metric, or a `timing.*` metric (wall clock: it would pass or fail with the machine's
/// load).
std::vector<Expectation> ScenarioExpectations(const Scenario& scenario);

/// The scenario's path in `world`, reporting a path that does not fit as InputError at `path:`.
sim::RobotPath BuildScenarioRobotPath(const Scenario& scenario, const worlds::World& world);

}  // namespace corridorsim
