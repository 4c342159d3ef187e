// Tests harness/scenario/overrides.cpp (`--set KEY=VALUE`): keys into nested maps and lists,
// values read as YAML, the exact messages of bad settings, and the settings applied by
// LoadScenario and LoadStudy after the include chain, checked like a file's keys and echoed.
#include "harness/scenario/overrides.h"

#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/scenario/scenario.h"
#include "harness/study/study_file.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

using test::Contains;
using test::InputErrorOf;

// The one document of one setting, as flow YAML.
std::string DocumentOf(const std::string& text, const std::vector<YamlDocument>& chain = {}) {
  const std::vector<YamlDocument> docs = SettingDocuments(ParseSettings({text}), chain);
  REQUIRE(docs.size() == 1);
  CHECK(docs[0].file == "command line: --set");
  YAML::Emitter out;
  out << YAML::Flow << docs[0].root;
  return out.c_str();
}

// The message of the InputError that parsing `texts` throws, as main prints it.
std::string SettingError(const std::vector<std::string>& texts) {
  return InputErrorOf([&] { ParseSettings(texts); }).what();
}

std::string Write(const test::ScratchDir& dir, const std::string& name, const std::string& text) {
  const std::string path = (dir.path() / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST_CASE("A setting (--set) puts a dotted key into nested maps", "[scenarios][set]") {
  CHECK(DocumentOf("path.speed_mps=0.2") == "{path: {speed_mps: 0.2}}");
  CHECK(DocumentOf("world.doors.count=4") == "{world: {doors: {count: 4}}}");
  CHECK(DocumentOf("seed=7") == "{seed: 7}");
  CHECK(DocumentOf("pipelines.odometry.enabled=false") ==
        "{pipelines: {odometry: {enabled: false}}}");
}

TEST_CASE("A setting (--set) reads its value as YAML", "[scenarios][set]") {
  const auto value = [](const std::string& text) {
    return ParseSettings({"k=" + text}).front().value;
  };
  CHECK(value("20").as<int>() == 20);
  CHECK(value("2.5e-3").as<double>() == 2.5e-3);
  CHECK(value("true").as<bool>());
  CHECK(value("a text with = and spaces").as<std::string>() == "a text with = and spaces");
  CHECK(value("'0.10'").Tag() == "!");  // quoted: a string, as in a file
  CHECK(value("[]").IsSequence());
  CHECK(value("[]").size() == 0);
  CHECK(value("[a, 2]").size() == 2);
  CHECK(value("{count: 4, width_m: 1.1}")["width_m"].as<double>() == 1.1);
  CHECK(value("").IsNull());  // nothing: YAML null, which overrides nothing (like `world:`)
}

TEST_CASE("a bad --set is an error naming --set and the key", "[scenarios][set]") {
  const std::pair<const char*, const char*> bad[] = {
      {"duration_s",
       "command line: --set: expected KEY=VALUE, e.g. --set duration_s=20 (got "
       "'duration_s')"},
      {"world..count=3",
       "command line: --set: world..count: a key is dotted names of 1 to 64 letters, digits, "
       "'_' or '-' (e.g. world.doors.count; a part of digits is a list index)"},
      {"=3",
       "command line: --set: a key is dotted names of 1 to 64 letters, digits, '_' or '-' (e.g. "
       "world.doors.count; a part of digits is a list index)"},
      {"0.x=3", "command line: --set: 0.x: a key starts with a name, not an index"},
      {"include=other.yaml",
       "command line: --set: include: cannot be set on the command line (it names a file): give "
       "that file"},
      {"world.doors={count: 4",
       "command line: --set: world.doors: the value '{count: 4' is not YAML: invalid YAML: end "
       "of map flow not found"},
      {"world.doors={count: 4, count: 5}",
       "command line: --set: world.doors: the value '{count: 4, count: 5}' is not YAML: "
       "duplicate key"},
      {"name=a\nb",
       "command line: --set: name: a value is one line of YAML (a list as [a, b], a map as {k: "
       "v})"},
  };
  for (const auto& [setting, message] : bad) {
    INFO(setting);
    CHECK(SettingError({setting}) == message);
  }
}

TEST_CASE("A setting (--set) is bounded in count, key and value", "[scenarios][set]") {
  CHECK(SettingError(std::vector<std::string>(65, "seed=1")) ==
        "command line: --set: at most 64 --set options (got 65)");
  CHECK(Contains(SettingError({std::string(257, 'a') + "=1"}),
                 ": a key is at most 256 bytes (got 257)"));
  CHECK(Contains(SettingError({"name=" + std::string(4097, 'a')}),
                 "command line: --set: name: a value is at most 4096 bytes (got 4097)"));
  CHECK(Contains(SettingError({"a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q=1"}),
                 ": a key has at most 16 parts"));
  CHECK_NOTHROW(ParseSettings(std::vector<std::string>(64, "seed=1")));
}

TEST_CASE("A setting (--set) replaces or appends an item of a list the files write",
          "[scenarios][set]") {
  const std::vector<YamlDocument> chain = {
      YamlDocument::FromString("expectations: [a < 1]\npath: {commands: [[1, 0.3, 0]]}\n",
                               "b.yaml"),
      YamlDocument::FromString("expectations: [x < 1, y < 2]\n", "top.yaml")};
  // The last file that writes the list is the one a run uses.
  CHECK(DocumentOf("expectations.1=z < 3", chain) == "{expectations: [x < 1, z < 3]}");
  CHECK(DocumentOf("expectations.2=z < 3", chain) == "{expectations: [x < 1, y < 2, z < 3]}");
  CHECK(DocumentOf("path.commands.0.1=0.5", chain) == "{path: {commands: [[1, 0.5, 0]]}}");
  CHECK(DocumentOf("path.commands.1=[2, 0, 30]", chain) ==
        "{path: {commands: [[1, 0.3, 0], [2, 0, 30]]}}");
  // The files' own lists are left as they were.
  REQUIRE(chain[1].root["expectations"].size() == 2);
  CHECK(chain[1].root["expectations"][1].as<std::string>() == "y < 2");
  CHECK(chain[0].root["path"]["commands"][0][1].as<double>() == 0.3);
  // A later setting indexes the list as the earlier ones leave it.
  const std::vector<YamlDocument> docs =
      SettingDocuments(ParseSettings({"expectations=[p < 1]", "expectations.1=q < 2"}), chain);
  YAML::Emitter second;
  second << YAML::Flow << docs[1].root;
  CHECK(std::string(second.c_str()) == "{expectations: [p < 1, q < 2]}");

  const auto error = [&](const std::string& text) -> std::string {
    return InputErrorOf([&] { SettingDocuments(ParseSettings({text}), chain); }).what();
  };
  const std::pair<const char*, const char*> bad[] = {
      {"expectations.3=z < 3",
       "command line: --set: expectations.3: index 3 is beyond the list 'expectations' of 2 "
       "item(s) (0 to 1, or 2 to append as the last part)"},
      {"path.commands.0.4=1",
       "command line: --set: path.commands.0.4: index 4 is beyond the list 'path.commands.0' of 3 "
       "item(s) (0 to 2, or 3 to append as the last part)"},
      {"expectations.2.x=1",
       "command line: --set: expectations.2.x: index 2 is beyond the list 'expectations' of 2 "
       "item(s) (0 to 1, or 2 to append as the last part)"},
      {"sensors.front.distortion.0=0.1",
       "command line: --set: sensors.front.distortion.0: 'sensors.front.distortion' is not a "
       "list written in the scenario's files (its value is the code default): set it whole, "
       "e.g. --set 'sensors.front.distortion=[...]'"},
      {"path.commands.0.1.2=1",
       "command line: --set: path.commands.0.1.2: 'path.commands.0.1' is not a list: 2 is no "
       "key"},
      {"plugins.0=x.so",
       "command line: --set: plugins.0: the lists of `plugins` add up over the include chain: "
       "add a library with --set plugins=[path]"},
  };
  for (const auto& [setting, message] : bad) {
    INFO(setting);
    CHECK(error(setting) == message);
  }
}

TEST_CASE("LoadScenario applies --set after the include chain, a later one winning",
          "[scenarios][set]") {
  const test::ScratchDir dir("corridorsim_overrides_test");
  Write(dir, "base.yaml", "world: {doors: {count: 10}, plates: {count: 4}}\nduration_s: 30\n");
  const std::string top = Write(dir, "top.yaml",
                                "include: base.yaml\nseed: 3\npipelines:\n  odometry: {}\n"
                                "expectations: [odometry.ate_rmse_m < 9]\n");
  const Scenario plain = LoadScenario(top);
  const Scenario set = LoadScenario(
      top, {"duration_s=20", "world.doors.count=4", "seed=5", "seed=6", "expectations=[]",
            "pipelines.odometry.enabled=false", "world.length_m=40"});
  CHECK(plain.duration_s == 30);
  CHECK(set.duration_s == 20);
  CHECK(plain.world.doors.count == 10);
  CHECK(set.world.doors.count == 4);
  CHECK(set.world.length_m == 40);
  CHECK(set.seed == 6);
  CHECK(plain.expectations.size() == 1);
  CHECK(set.expectations.empty());
  CHECK_FALSE(set.pipelines.at(0).enabled);
  CHECK(set.settings.size() == 7);

  // The echo holds the set values: loaded again (without --set) it is the same scenario.
  const std::string echo = ResolvedScenarioYaml(set, set.seed);
  CHECK(Contains(echo, "duration_s: 20\n"));
  CHECK(echo != ResolvedScenarioYaml(plain, set.seed));
  const std::string saved = Write(dir, "saved.yaml", echo);
  CHECK(ResolvedScenarioYaml(LoadScenario(saved), set.seed) == echo);
}

TEST_CASE("a --set key is checked like a file's, the error naming --set and the key",
          "[scenarios][set]") {
  const test::ScratchDir dir("corridorsim_overrides_check_test");
  const std::string file = Write(dir, "s.yaml", "seed: 3\npipelines:\n  odometry: {}\n");
  const auto error = [&](const std::string& setting) -> std::string {
    return InputErrorOf([&] { LoadScenario(file, {setting}); }).what();
  };
  CHECK(error("wrld.length_m=30") ==
        "command line: --set: wrld: unknown key (known keys here: appearance, description, "
        "duration_s, expectations, include, name, path, pipelines, plugins, render, robot, seed, "
        "sensors, study, world)");
  // Each message names --set and the key; the rest is what a file's key gets.
  const std::pair<const char*, const char*> bad[] = {
      {"world.doors.cout=4",
       "command line: --set: world.doors.cout: unknown key (known keys here: "},
      {"world.doors.count=many", "command line: --set: world.doors.count: "},
      {"duration_s=-1", "command line: --set: duration_s: must lie in"},
      {"expectations=[odometry.nope < 1]", "command line: --set: expectations: "},
      {"pipelines.odometry.k_m=-1", "command line: --set: pipelines.odometry.k_m: "},
  };
  for (const auto& [setting, part] : bad) {
    INFO(setting);
    CHECK(Contains(error(setting), part));
  }
}

TEST_CASE("LoadStudy applies --set to the scenario of every point and to study keys",
          "[scenarios][set]") {
  const test::ScratchDir dir("corridorsim_overrides_study_test");
  const std::string file =
      Write(dir, "study.yaml",
            "duration_s: 30\nworld: {plates: {count: 2}}\npipelines:\n  odometry: {}\n"
            "study:\n  runs: 4\n  vary:\n"
            "    robot.odometry.random_k_m: [1.0e-5, 1.0e-3]\n"
            "  expectations: [odometry.ate_rmse_m.mean < 5]\n");
  const StudySpec plain = LoadStudy(file, std::nullopt, std::nullopt);
  const StudySpec set = LoadStudy(file, std::nullopt, std::nullopt,
                                  {"duration_s=8", "study.runs=2", "study.expectations=[]"});
  CHECK(plain.runs == 4);
  CHECK(set.runs == 2);
  CHECK(plain.expectations.size() == 1);
  CHECK(set.expectations.empty());
  REQUIRE(set.points.size() == 2);
  for (const StudyPoint& point : set.points) CHECK(point.scenario.duration_s == 8);
  CHECK(plain.points[0].scenario.duration_s == 30);

  CHECK(std::string(InputErrorOf([&] {
                      LoadStudy(file, std::nullopt, std::nullopt,
                                {"robot.odometry.random_k_m=0.01"});
                    }).what()) ==
        "command line: --set: robot.odometry.random_k_m: the study varies "
        "'robot.odometry.random_k_m' (study.vary), which every point sets: change the sweep's "
        "values instead (--set 'study.vary={...}')");
  CHECK(std::string(InputErrorOf([&] {
                      LoadStudy(file, std::nullopt, std::nullopt, {"study.runz=2"});
                    }).what()) ==
        "command line: --set: study.runz: unknown key (known keys here: divergence_nees, "
        "expectations, first_seed, may_diverge, metrics, run_timeout_s, runs, time_step_s, "
        "vary)");
  const StudySpec swept =
      LoadStudy(file, std::nullopt, std::nullopt, {"study.vary={world.doors.count: [4, 6, 8]}"});
  CHECK(swept.points.size() == 3);
  CHECK(swept.vary_keys == std::vector<std::string>{"world.doors.count"});
}

}  // namespace
}  // namespace corridorsim
