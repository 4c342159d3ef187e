// Tests scenarios/scenario.cpp's pipelines: read by name with their options and type, names that
// make file names, types a plugin or the shipped registry knows, and a type fixed by the file that
// first names a pipeline.
#include <string>

#include <catch2/catch.hpp>

#include "harness/scenario/scenario.h"
#include "slam/odometry_pipeline.h"
#include "slam/registry.h"
#include "tests/harness/scenario/scenario_files.h"
#include "tests/support/expect_input_error.h"

namespace corridorsim {
namespace {

using test::Contains;
using test::FixtureDir;
using test::InputErrorOf;
using test::LoadError;

TEST_CASE("pipelines are read by name with their options, and an unknown one is an error",
          "[scenarios]") {
  const std::string msg = LoadError(
      "pipelines:\n"
      "  odometry: {k_m: 0.0002}\n"
      "  orb_slam9: {}\n");
  // The shipped types in their order, with any a plugin test earlier in this process registered
  // before `external` (ctest runs each case alone; a whole-binary run shares the registry).
  std::string plugin_types;
  for (const std::string& name : slam::PipelineNames()) {
    if (name.rfind("test_", 0) == 0) plugin_types += ", " + name;
  }
  CHECK(msg ==
        ":3:3: pipelines.orb_slam9: unknown pipeline (known: odometry, p1_harris, p1_vp_doorplate, "
        "p3_upward, p3_corners, p2_upward, imu_odometry, laser_slam" +
            plugin_types + ", external; another name needs a `type:` key)");
  const std::string bad = LoadError(
      "pipelines:\n"
      "  odometry:\n"
      "    k_m: -1\n");
  CHECK(bad.rfind(":3:5: pipelines.odometry.k_m: must lie in", 0) == 0);
}

TEST_CASE("two pipelines of one type with different options run under their own names",
          "[scenarios]") {
  const FixtureDir dir;
  const std::string path = dir.Write("s.yaml",
                                     "pipelines:\n"
                                     "  odometry:\n"
                                     "    k_m: 0.0001\n"
                                     "  odometry_loose:\n"
                                     "    type: odometry\n"
                                     "    k_m: 0.001\n");
  const Scenario scenario = LoadScenario(path);
  REQUIRE(scenario.pipelines.size() == 2);
  CHECK(scenario.pipelines[0].name == "odometry");
  CHECK(scenario.pipelines[0].type == "odometry");
  CHECK(scenario.pipelines[1].name == "odometry_loose");
  CHECK(scenario.pipelines[1].type == "odometry");
  const auto* tight =
      static_cast<const slam::OdometryPipelineOptions*>(scenario.pipelines[0].options->options());
  const auto* loose =
      static_cast<const slam::OdometryPipelineOptions*>(scenario.pipelines[1].options->options());
  CHECK(tight->k_m == 0.0001);
  CHECK(loose->k_m == 0.001);
  // The echo names the type, so a saved scenario repeats the run.
  const std::string echo = ResolvedScenarioYaml(scenario, 1);
  CHECK(Contains(echo, "odometry_loose:\n    type: odometry\n"));
}

TEST_CASE("a pipeline of an unknown type is an error at its type key", "[scenarios]") {
  // Loaded first: loading registers `external` (the list below then names it).
  const std::string error = LoadError("pipelines:\n  mine:\n    type: orbslam\n");
  CHECK(error == ":3:5: pipelines.mine.type: unknown pipeline type 'orbslam' (known: " + [] {
    std::string known;
    for (const std::string& n : slam::PipelineNames()) {
      known += (known.empty() ? "" : ", ") + n;
    }
    return known;
  }() + ")");
}

TEST_CASE("a pipeline name that is not a file-name identifier is an error at it", "[scenarios]") {
  const std::string msg = LoadError("pipelines:\n  \"../evil\":\n    type: odometry\n");
  CHECK(msg.rfind(":2:3: pipelines.../evil: a pipeline name is 1 to 64 lower-case letters", 0) ==
        0);
  CHECK(Contains(LoadError("pipelines:\n  Odometry:\n    type: odometry\n"), "(got 'Odometry')"));
}

TEST_CASE("a child file cannot change the type of a base file's pipeline", "[scenarios]") {
  const FixtureDir dir;
  dir.Write("base.yaml", "pipelines:\n  mine:\n    type: odometry\n");
  const std::string child =
      dir.Write("child.yaml", "include: base.yaml\npipelines:\n  mine:\n    type: p1_harris\n");
  const InputError e = InputErrorOf([&] { LoadScenario(child); });
  CHECK(Contains(e.what(), "pipelines.mine.type: the pipeline 'mine' is of type 'odometry'"));
}

}  // namespace
}  // namespace corridorsim
