// Tests scenarios/scenario.cpp: every shipped scenario loads and generates; bad input gives an
// InputError with the exact `file:line:column: key: message`; include chains override key by key
// and report problems in the file that set the key.
#include "harness/scenario/scenario.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/scenario/scenario_files.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/test_cameras.h"
#include "worlds/world_io.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using test::Contains;
using test::FixtureDir;
using test::InputErrorOf;
using test::LoadError;

// ---- shipped scenarios
// ---------------------------------------------------------------------------

// The .yaml files of `folder`, sorted.
std::vector<fs::path> YamlFilesIn(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file() && entry.path().extension() == ".yaml")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<fs::path> ShippedScenarios() {
  return YamlFilesIn(CORRIDORSIM_SOURCE_DIR "/scenarios");
}

TEST_CASE("every shipped scenario loads and generates its world", "[scenarios]") {
  const std::vector<fs::path> files = ShippedScenarios();
  // The seven of docs/scenarios.md at least; new files are covered automatically.
  CHECK(files.size() >= 7);
  for (const fs::path& file : files) {
    INFO(file.string());
    const Scenario scenario = LoadScenario(file.string());
    CHECK_FALSE(scenario.name.empty());
    const worlds::World world = GenerateWorld(scenario, scenario.seed);
    CHECK(static_cast<int>(world.doors.size()) == scenario.world.doors.count);
    CHECK(static_cast<int>(world.plates.size()) == scenario.world.plates.count);
    CHECK_FALSE(world.meshes.empty());
  }
}

// The echo of a loaded scenario through its tables, without the comment line.
std::string EchoOf(const std::string& path, std::uint64_t seed) {
  const std::string resolved = ResolvedScenarioYaml(LoadScenario(path), seed);
  REQUIRE(resolved.rfind("# ", 0) == 0);
  return resolved.substr(resolved.find('\n') + 1);
}

TEST_CASE("every shipped scenario's resolved echo is a fixed point with the same options",
          "[scenarios]") {
  const FixtureDir dir;
  for (const fs::path& file : ShippedScenarios()) {
    INFO(file.string());
    const Scenario original = LoadScenario(file.string());
    const std::string echo = EchoOf(file.string(), original.seed);
    CHECK(echo == OptionsYaml(ScenarioOptionsTable(), original));
    CHECK_FALSE(Contains(echo, "include:"));
    const std::string copy = dir.Write(file.filename().string(), "# echo\n" + echo);
    const Scenario again = LoadScenario(copy);
    CHECK(OptionsYaml(ScenarioOptionsTable(), again) == echo);
    CHECK(EchoOf(copy, again.seed) == echo);
    // A few options directly, models included (the echo could hide a key it does not write).
    CHECK(again.seed == original.seed);
    CHECK(again.world.length_m == original.world.length_m);
    CHECK(again.robot.odometry.random_k_m == original.robot.odometry.random_k_m);
    REQUIRE(again.rig.cameras.size() == original.rig.cameras.size());
    for (std::size_t i = 0; i < again.rig.cameras.size(); ++i) {
      const render::CameraOptions& a = again.rig.cameras[i];
      const render::CameraOptions& b = original.rig.cameras[i];
      test::CheckIntrinsics(a.model.intrinsics(), b.model.intrinsics());
      CHECK(a.enabled == b.enabled);
      CHECK(a.rate_hz == b.rate_hz);
    }
    REQUIRE(again.pipelines.size() == original.pipelines.size());
    CHECK(again.expectations == original.expectations);
  }
}

TEST_CASE("the resolved scenario sets the run's seed and merges the include chain", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml",
            "seed: 4\nworld:\n  length_m: 50\n  doors: {count: 15}\nsensors:\n  upward:\n"
            "    model: pinhole\n    fov_deg: 100\npipelines:\n  odometry: {k_m: 0.0002}\n");
  const std::string child = dir.Write(
      "child.yaml", "include: base.yaml\nname: \"a: child\"\nworld:\n  doors: {width_m: 1.0}\n");
  const std::string resolved = ResolvedScenarioYaml(LoadScenario(child), 77);
  const std::string copy = dir.Write("resolved.yaml", resolved);
  const Scenario s = LoadScenario(copy);
  CHECK(s.seed == 77);
  CHECK(s.name == "a: child");
  CHECK(s.world.length_m == 50);
  CHECK(s.world.doors.count == 15);
  CHECK(s.world.doors.width_m == 1.0);
  CHECK(s.rig.Find("upward")->model.pinhole() != nullptr);
  REQUIRE(s.pipelines.size() == 1);
  CHECK(
      Contains(resolved, "  odometry:\n    type: odometry\n    enabled: true\n    k_m: 0.0002\n"));
  CHECK(EchoOf(copy, 77) == resolved.substr(resolved.find('\n') + 1));
}

TEST_CASE("the default scenario is P1's corridor", "[scenarios]") {
  const Scenario s = LoadScenario(CORRIDORSIM_SOURCE_DIR "/scenarios/default.yaml");
  CHECK(s.seed == 1);
  CHECK(s.world.layout == worlds::Layout::kStraight);
  CHECK(s.world.length_m == 55.0);
  CHECK(s.world.width_m == 2.4);
  CHECK(s.world.height_m == 2.7);
  CHECK(s.world.plates.count == 14);
}

// ---- bad input: the exact location, key and message ---------------------------------------------

// Bad scenarios and the message each gives after its file name: the whole message, or how it
// starts.
enum class Match { kWhole, kStart };
struct BadScenario {
  const char* what;  // the behaviour
  const char* yaml;
  const char* message;
  Match match;
};
const BadScenario kBadScenarios[] = {
    {"an unknown top-level key is an error at that key",
     "seed: 3\n"
     "wrld:\n"
     "  length_m: 30\n",
     ":2:1: wrld: unknown key (known keys here: appearance, description, duration_s, "
     "expectations, include, name, path, pipelines, plugins, render, robot, seed, sensors, "
     "study, world)",
     Match::kWhole},
    {"a duplicate key is an error at its second occurrence",
     "world:\n"
     "  length_m: 30\n"
     "  width_m: 2.4\n"
     "  length_m: 40\n",
     ":4:3: world.length_m: duplicate key", Match::kWhole},
    {"a negative size is an error at its line",
     "name: negative\n"
     "world:\n"
     "  width_m: -2.4\n",
     ":3:3: world.width_m: must be greater than 0 (got -2.4)", Match::kWhole},
    {"a zero size is an error at its line",
     "world:\n"
     "  plates:\n"
     "    count: 4\n"
     "    height_m: 0\n",
     ":4:5: world.plates.height_m: must be greater than 0 (got 0)", Match::kWhole},
    {"a door wider than its wall is an error at doors.width_m",
     "world:\n"
     "  length_m: 5\n"
     "  doors: {width_m: 3}\n",
     ":3:11: world.doors.width_m: a doorway of 3.16 m with its frame is wider than every wall "
     "segment (longest usable wall: 2.60 m)",
     Match::kWhole},
    {"more plates than doors is an error at plates.count",
     "world:\n"
     "  doors:\n"
     "    count: 16\n"
     "  plates:\n"
     "    count: 17\n",
     ":5:5: world.plates.count: 17 plates need a door each, but there are only 16 doors "
     "(doors.count)",
     Match::kWhole},
    {"more doors than fit is an error at doors.count",
     "world:\n"
     "  length_m: 20\n"
     "  doors:\n"
     "    count: 30\n",
     ":4:5: world.doors.count: 30 doorways do not fit on the side walls", Match::kStart},
    {"a ceiling lower than a door is an error at height_m",
     "world:\n"
     "  height_m: 2.0\n",
     ":2:3: world.height_m: the ceiling (2 m) is lower than the doors with their top bar "
     "(2.18 m)",
     Match::kWhole},
    // plates.count keeps its default 14, but only 10 doors are asked for.
    {"a problem with a key nobody set is reported at the world section",
     "seed: 2\n"
     "world:\n"
     "  doors:\n"
     "    count: 10\n",
     ":2:1: world.plates.count: 14 plates need a door each", Match::kStart},
    // yaml-cpp finds the unclosed list where the next key starts; its wording is its own.
    {"a file that is not valid YAML is an error at the syntax error",
     "world:\n"
     "  doors: [1, 2\n"
     "  length_m: 3\n",
     ":3:11: invalid YAML: ", Match::kStart},
};

TEST_CASE("bad input is an error at its exact location, key and message", "[scenarios]") {
  for (const BadScenario& bad : kBadScenarios) {
    DYNAMIC_SECTION(bad.what) {
      const std::string msg = LoadError(bad.yaml);
      if (bad.match == Match::kWhole) {
        CHECK(msg == bad.message);
      } else {
        CHECK_THAT(msg, Catch::StartsWith(bad.message));
      }
    }
  }
}

TEST_CASE("an unknown nested key is an error naming its full key", "[scenarios]") {
  const std::string msg = LoadError(
      "world:\n"
      "  doors:\n"
      "    count: 10\n"
      "    colour: red\n");
  CHECK(msg.rfind(":4:5: world.doors.colour: unknown key (known keys here: ", 0) == 0);
  CHECK(Contains(msg, "width_m"));
}

TEST_CASE("a value of the wrong type is an error at its key", "[scenarios]") {
  CHECK(LoadError("world:\n  length_m: long\n") ==
        ":2:3: world.length_m: expected a finite number, got 'long'");
  CHECK(LoadError("seed: -4\n") == ":1:1: seed: expected a non-negative integer, got '-4'");
  CHECK(LoadError("world:\n  layout: spiral\n") ==
        ":2:3: world.layout: unknown value 'spiral' (expected one of: straight, l_turn, "
        "t_junction, loop)");
  CHECK(LoadError("world: [1, 2]\n") == ":1:1: world: expected a map of keys");
}

TEST_CASE("render.texture_filter picks the mip filter; other values are errors", "[scenarios]") {
  const FixtureDir dir;
  CHECK(LoadScenario(dir.Write("a.yaml", "name: a\n")).rig.scene.texture_filter ==
        render::TextureFilter::kTrilinear);
  CHECK(LoadScenario(dir.Write("b.yaml", "render:\n  texture_filter: nearest_mip\n"))
            .rig.scene.texture_filter == render::TextureFilter::kNearestMip);
  CHECK(LoadError("render:\n  texture_filter: anisotropic\n") ==
        ":2:3: render.texture_filter: unknown value 'anisotropic' (expected one of: trilinear, "
        "nearest_mip)");
}

TEST_CASE("a missing included file is an error at the include line", "[scenarios]") {
  const FixtureDir dir;
  const std::string path = dir.Write("child.yaml",
                                     "name: child\n"
                                     "include: nowhere.yaml\n");
  const InputError e = InputErrorOf([&] { LoadScenario(path); });
  CHECK(std::string(e.what()) ==
        path + ":2:10: include: included file '" + dir.Path("nowhere.yaml") + "' does not exist");
}

TEST_CASE("an include cycle is an error at the include that closes it", "[scenarios]") {
  const FixtureDir dir;
  const std::string a = dir.Write("a.yaml", "include: b.yaml\n");
  dir.Write("b.yaml",
            "seed: 4\n"
            "include: a.yaml\n");
  const InputError e = InputErrorOf([&] { LoadScenario(a); });
  CHECK(std::string(e.what()) ==
        dir.Path("b.yaml") + ":2:10: include: include cycle through '" + a + "'");
}

TEST_CASE("a file that includes itself is a cycle", "[scenarios]") {
  const FixtureDir dir;
  const std::string self = dir.Write("self.yaml", "include: self.yaml\n");
  const InputError e = InputErrorOf([&] { LoadScenario(self); });
  CHECK(e.key() == "include");
  CHECK(e.location().line == 1);
  CHECK(Contains(e.message(), "include cycle"));
}

TEST_CASE("a YAML document that is not a map is an error", "[scenarios]") {
  CHECK(LoadError("- seed\n- 3\n") == ":1:1: the document must be a map of keys");
}

TEST_CASE("an empty scenario file is an error naming it, not a run of the defaults",
          "[scenarios]") {
  const FixtureDir dir;
  for (const char* text : {"", "# only a comment\n", "\n\n", "{}\n", "---\n# nothing\n"}) {
    INFO("'" << text << "'");
    const std::string path = dir.Write("empty.yaml", text);
    CHECK(std::string(InputErrorOf([&] { LoadScenario(path); }).what()) ==
          path + ": the scenario is empty (no keys: nothing but comments or blank lines)");
  }
  // An empty file in the include chain too (a base that was meant to hold something).
  const std::string base = dir.Write("base.yaml", "# nothing yet\n");
  const std::string child = dir.Write("child.yaml", "include: base.yaml\nseed: 3\n");
  CHECK(std::string(InputErrorOf([&] { LoadScenario(child); }).what()) ==
        base + ": the scenario is empty (no keys: nothing but comments or blank lines)");
}

TEST_CASE("name and description are text without control characters", "[scenarios]") {
  // An escape sequence in `name` would be printed to the user's terminal by `run`.
  CHECK(LoadError("name: \"x\\e]0;owned\\a\"\n") ==
        ":1:1: name: must not contain control characters (escapes, newlines)");
  CHECK(LoadError("name: \"two\\nlines\"\n") ==
        ":1:1: name: must not contain control characters (escapes, newlines)");
  CHECK(LoadError("seed: 2\ndescription: \"bell\\a\"\n") ==
        ":2:1: description: must not contain control characters (escapes)");
  CHECK(LoadError("name: " + std::string(1001, 'n') + "\n") ==
        ":1:1: name: must be at most 1000 bytes (got 1001)");
  const FixtureDir dir;
  const Scenario ok = LoadScenario(dir.Write(
      "ok.yaml", "name: \"P1 corridor:\\t55 m, \u00fc\"\ndescription: \"two\\nlines\"\n"));
  CHECK(ok.name == "P1 corridor:\t55 m, \u00fc");
  CHECK(ok.description == "two\nlines");
}

TEST_CASE("a file with one key is not empty", "[scenarios]") {
  const FixtureDir dir;
  CHECK(LoadScenario(dir.Write("seed.yaml", "seed: 4\n")).seed == 4);
}

TEST_CASE("a scenario path that does not exist is an error naming it", "[scenarios]") {
  const FixtureDir dir;
  const std::string path = dir.Path("absent.yaml");
  CHECK(std::string(InputErrorOf([&] { LoadScenario(path); }).what()) ==
        path + ": cannot open the file");
}

TEST_CASE("a scenario path that is a folder is an input error naming it", "[scenarios]") {
  const FixtureDir dir;
  const std::string folder = dir.Path("sub.yaml");
  fs::create_directories(folder);
  const InputError e = InputErrorOf([&] { LoadScenario(folder); });
  CHECK(e.location().file == folder);
}

TEST_CASE("an include naming a folder is an input error at the include line", "[scenarios]") {
  const FixtureDir dir;
  fs::create_directories(dir.Path("base"));
  const std::string child = dir.Write("child.yaml",
                                      "seed: 2\n"
                                      "include: base\n");
  const InputError e = InputErrorOf([&] { LoadScenario(child); });
  CHECK(e.key() == "include");
  CHECK(e.location().file == child);
  CHECK(e.location().line == 2);
  CHECK(e.location().column == 10);
}

TEST_CASE("distractors that do not fit are an error at their key when the world is generated",
          "[scenarios]") {
  const FixtureDir dir;
  const std::string path = dir.Write("crowded.yaml",
                                     "world:\n"
                                     "  length_m: 20\n"
                                     "  doors: {count: 6}\n"
                                     "  plates: {count: 4}\n"
                                     "  distractors:\n"
                                     "    posters: 100\n");
  const Scenario s = LoadScenario(path);  // valid as a spec; the generated walls are too short
  const InputError e = InputErrorOf([&] { GenerateWorld(s, 1); });
  CHECK(std::string(e.what()).rfind(path + ":6:5: world.distractors.posters: only ", 0) == 0);
  CHECK(Contains(e.message(), "of 100 fit"));
}

// ---- include chains
// ------------------------------------------------------------------------------

TEST_CASE("a child overriding one nested key keeps the base's other keys", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml",
            "name: base\n"
            "seed: 9\n"
            "world:\n"
            "  length_m: 40\n"
            "  doors:\n"
            "    count: 12\n"
            "    width_m: 1.0\n"
            "  plates:\n"
            "    count: 10\n");
  const std::string child = dir.Write("child.yaml",
                                      "include: base.yaml\n"
                                      "name: child\n"
                                      "world:\n"
                                      "  doors:\n"
                                      "    count: 14\n");
  const Scenario s = LoadScenario(child);
  CHECK(s.name == "child");
  CHECK(s.seed == 9);
  CHECK(s.world.length_m == 40);
  CHECK(s.world.doors.count == 14);
  CHECK(s.world.doors.width_m == 1.0);
  CHECK(s.world.plates.count == 10);
  CHECK(s.file == child);
  // Where each key was set: the child for what it overrides, the base for the rest.
  const SourceLocation count = s.sources.Find("world.doors.count", SourceLocation{});
  CHECK(count.file == child);
  CHECK(count.line == 5);
  const SourceLocation width = s.sources.Find("world.doors.width_m", SourceLocation{});
  CHECK(width.file == dir.Path("base.yaml"));
  CHECK(width.line == 7);
}

TEST_CASE("an error in the base file is reported with the base file's name", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml",
            "world:\n"
            "  length_m: 40\n"
            "  lamps:\n"
            "    brightness: 3\n");
  const std::string child = dir.Write("child.yaml",
                                      "include: base.yaml\n"
                                      "world:\n"
                                      "  length_m: 30\n");
  const InputError e = InputErrorOf([&] { LoadScenario(child); });
  CHECK(std::string(e.what()).rfind(
            dir.Path("base.yaml") + ":4:5: world.lamps.brightness: unknown key", 0) == 0);
}

TEST_CASE("a problem caused by a key set in the base is reported at the base file's line",
          "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml",
            "seed: 3\n"
            "world:\n"
            "  height_m: 2.0\n");
  const std::string child = dir.Write("child.yaml",
                                      "include: base.yaml\n"
                                      "world:\n"
                                      "  length_m: 30\n");
  const InputError e = InputErrorOf([&] { LoadScenario(child); });
  CHECK(e.location().file == dir.Path("base.yaml"));
  CHECK(e.location().line == 3);
  CHECK(e.location().column == 3);
  CHECK(e.key() == "world.height_m");
}

TEST_CASE("a problem between keys of two files is reported where the offending key was set",
          "[scenarios]") {
  // The base asks for 12 plates; the child lowers the doors to 10: plates.count is wrong, set
  // in the base.
  const FixtureDir dir;
  dir.Write("base.yaml",
            "world:\n"
            "  doors:\n"
            "    count: 14\n"
            "  plates:\n"
            "    count: 12\n");
  const std::string child = dir.Write("child.yaml",
                                      "include: base.yaml\n"
                                      "world:\n"
                                      "  doors:\n"
                                      "    count: 10\n");
  const InputError e = InputErrorOf([&] { LoadScenario(child); });
  CHECK(std::string(e.what()) ==
        dir.Path("base.yaml") +
            ":5:5: world.plates.count: 12 plates need a door each, but there are only 10 doors "
            "(doors.count)");
}

TEST_CASE("a child may fix a problem of its base", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml", "world:\n  height_m: 2.0\n");
  const std::string child = dir.Write("child.yaml",
                                      "include: base.yaml\n"
                                      "world:\n"
                                      "  height_m: 2.8\n");
  CHECK(LoadScenario(child).world.height_m == 2.8);
}

TEST_CASE("includes chain through several files, base first", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("a.yaml", "seed: 1\nworld:\n  length_m: 30\n  width_m: 2.2\n");
  dir.Write("b.yaml", "include: a.yaml\nseed: 2\nworld:\n  length_m: 35\n");
  const std::string c = dir.Write("c.yaml", "include: b.yaml\nseed: 3\n");
  const Scenario s = LoadScenario(c);
  CHECK(s.seed == 3);
  CHECK(s.world.length_m == 35);
  CHECK(s.world.width_m == 2.2);
}

// ---- the saved scenario repeats the run -------------------------------------------------------

std::vector<fs::path> RepeatChains() { return YamlFilesIn(CORRIDORSIM_TEST_DATA_DIR "/repeat"); }

TEST_CASE(
    "the echo of every shipped scenario and repeat chain loads as the same scenario and is "
    "its own echo byte for byte",
    "[scenarios]") {
  std::vector<fs::path> files = ShippedScenarios();
  const std::vector<fs::path> chains = RepeatChains();
  CHECK(chains.size() >= 10);
  files.insert(files.end(), chains.begin(), chains.end());
  const FixtureDir dir;
  for (const fs::path& file : files) {
    INFO(file.string());
    const Scenario loaded = LoadScenario(file.string());
    const std::string echo = ResolvedScenarioYaml(loaded, loaded.seed);
    // A different name and folder: the echo depends on neither.
    const std::string copy = dir.Write("saved_" + file.filename().string(), echo);
    const Scenario again = LoadScenario(copy);
    CHECK(ResolvedScenarioYaml(again, again.seed) == echo);
    // The same options, compared directly where the echo could hide a difference.
    CHECK(again.seed == loaded.seed);
    CHECK(again.name == loaded.name);
    CHECK(again.description == loaded.description);
    CHECK(again.duration_s == loaded.duration_s);
    CHECK(OptionsYaml(worlds::WorldOptionsTable(), again.world) ==
          OptionsYaml(worlds::WorldOptionsTable(), loaded.world));
    REQUIRE(again.rig.cameras.size() == loaded.rig.cameras.size());
    for (std::size_t i = 0; i < again.rig.cameras.size(); ++i) {
      const render::CameraOptions& a = again.rig.cameras[i];
      const render::CameraOptions& b = loaded.rig.cameras[i];
      INFO(a.id);
      CHECK((a.model.pinhole() != nullptr) == (b.model.pinhole() != nullptr));
      const CameraIntrinsics ia = a.model.intrinsics(), ib = b.model.intrinsics();
      CHECK(ia.width == ib.width);
      CHECK(ia.height == ib.height);
      CHECK(ia.fx == ib.fx);  // exactly: the echo writes round-trip digits
      CHECK(ia.fy == ib.fy);
      CHECK(ia.cx == ib.cx);
      CHECK(ia.cy == ib.cy);
      CHECK(ia.distortion == ib.distortion);
      CHECK(a.enabled == b.enabled);
    }
    REQUIRE(again.pipelines.size() == loaded.pipelines.size());
    for (std::size_t i = 0; i < again.pipelines.size(); ++i) {
      CHECK(again.pipelines[i].name == loaded.pipelines[i].name);
      CHECK(again.pipelines[i].enabled == loaded.pipelines[i].enabled);
    }
    CHECK(again.expectations == loaded.expectations);
    // The same world, to the byte.
    CHECK(worlds::GroundTruthJson(GenerateWorld(again, again.seed)).dump() ==
          worlds::GroundTruthJson(GenerateWorld(loaded, loaded.seed)).dump());
  }
}

TEST_CASE("the echo is of the scenario as loaded: files edited afterwards change nothing",
          "[scenarios]") {
  const FixtureDir dir;
  const std::string base = dir.Write("base.yaml", "seed: 4\nworld:\n  length_m: 30\n");
  const std::string child = dir.Write("child.yaml", "include: base.yaml\nname: child\n");
  const Scenario loaded = LoadScenario(child);
  const std::string before = ResolvedScenarioYaml(loaded, 4);
  // The include is edited (and the child removed) while the run goes on.
  dir.Write("base.yaml", "seed: 4\nworld:\n  length_m: 45\n");
  fs::remove(child);
  const std::string after = ResolvedScenarioYaml(loaded, 4);
  CHECK(after == before);
  CHECK(Contains(after, "  length_m: 30\n"));
  CHECK_FALSE(Contains(after, child));  // the header names no file
}

TEST_CASE("a section with nothing after it overrides nothing, as an empty map", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml",
            "seed: 6\nworld:\n  length_m: 30\n  doors: {count: 6}\n  plates: {count: 4}\n"
            "sensors:\n  front: {fx: 300}\npipelines:\n  odometry: {k_m: 0.0003}\n");
  const Scenario base = LoadScenario(dir.Path("base.yaml"));
  const std::string null_child =
      dir.Write("null.yaml", "include: base.yaml\nworld:\nsensors:\n  front:\npipelines:\n");
  const std::string empty_child = dir.Write(
      "empty.yaml", "include: base.yaml\nworld: {}\nsensors:\n  front: {}\npipelines: {}\n");
  for (const std::string& child : {null_child, empty_child}) {
    INFO(child);
    const Scenario s = LoadScenario(child);
    CHECK(ResolvedScenarioYaml(s, 6) == ResolvedScenarioYaml(base, 6));
    CHECK(s.world.length_m == 30);
    CHECK(s.rig.Find("front")->model.intrinsics().fx == 300);
  }
  // A null value of a key that is not a section stays an error.
  CHECK(LoadError("seed:\n") == ":1:1: seed: expected a non-negative integer, got nothing");
}

TEST_CASE("an expectation on a timing metric is refused at its line", "[scenarios]") {
  const std::string msg = LoadError(
      "pipelines:\n"
      "  odometry: {}\n"
      "expectations:\n"
      "  - odometry.ate_rmse_m < 5\n"
      "  - odometry.timing.total_ms_per_step < 1\n");
  CHECK(msg ==
        ":5:5: expectations: 'odometry.timing.total_ms_per_step < 1': timing metrics are "
        "machine-dependent; see timing.json");
  // Every timing.* name, counts included: they live in timing.json, not metrics.json.
  for (const std::string& metric : MetricNames()) {
    if (metric.rfind("timing.", 0) != 0) continue;
    INFO(metric);
    CHECK(Contains(
        LoadError("pipelines:\n  odometry: {}\nexpectations:\n  - odometry." + metric + " < 1\n"),
        "timing metrics are machine-dependent"));
  }
  // ... and an unknown metric's message does not offer them.
  const std::string unknown =
      LoadError("pipelines:\n  odometry: {}\nexpectations:\n  - odometry.speed_of_light < 1\n");
  CHECK(Contains(unknown, "unknown metric 'speed_of_light'"));
  CHECK(Contains(unknown, "ate_rmse_m"));
  CHECK_FALSE(Contains(unknown, "timing."));
}

TEST_CASE("a run needs an enabled pipeline, at the pipelines key", "[scenarios]") {
  const FixtureDir dir;
  const Scenario none = LoadScenario(dir.Write("none.yaml", "seed: 2\n"));
  const InputError e = InputErrorOf([&] { RequireScoredPipeline(none); });
  CHECK(e.key() == "pipelines");
  CHECK(e.location().file == dir.Path("none.yaml"));
  CHECK(
      Contains(e.message(), "no pipeline is enabled, so the run would score nothing (none given"));
  const Scenario disabled = LoadScenario(
      dir.Write("disabled.yaml", "seed: 2\npipelines:\n  odometry: {enabled: false}\n"));
  const InputError d = InputErrorOf([&] { RequireScoredPipeline(disabled); });
  CHECK(d.location().line == 2);
  CHECK(Contains(d.message(), "disabled: odometry"));
  const Scenario one = LoadScenario(dir.Write("one.yaml", "seed: 2\npipelines:\n  odometry: {}\n"));
  RequireScoredPipeline(one);  // no throw
}

}  // namespace
}  // namespace corridorsim
