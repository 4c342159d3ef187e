// Tests harness/external/reply_keys.cpp and the replies' readers (protocol.cpp) on unknown keys:
// the message names the reply, the key, the key it likely misspells and every valid key; with
// `problems` what the reply holds under its valid keys is kept, a misspelling of a key that
// carries no result is a warning, any other unknown key an error; without it, anything throws.
#include "harness/external/reply_keys.h"

#include <string>

#include <catch2/catch.hpp>

#include "harness/external/protocol.h"

namespace corridorsim::external {
namespace {

using Catch::Matchers::Contains;

const char* kFinishedKeys =
    "the valid keys are type, landmarks, detections, innovations, maps, health, stage_seconds";

TEST_CASE("the nearest valid key is found for a misspelling, not for another word",
          "[external][protocol]") {
  const std::vector<std::string> keys = {"type", "landmarks", "maps", "health", "stage_seconds"};
  CHECK(NearestKey("landmark", keys) == std::optional<std::string>("landmarks"));
  CHECK(NearestKey("Landmarks", keys) == std::optional<std::string>("landmarks"));
  CHECK(NearestKey("stage_secs", keys) == std::optional<std::string>("stage_seconds"));
  CHECK(NearestKey("heatlh", keys) == std::optional<std::string>("health"));  // a swap
  CHECK(NearestKey("trajectory", keys) == std::nullopt);
  CHECK(NearestKey("", keys) == std::nullopt);
  CHECK(NearestKey(std::string(1000, 'a'), keys) == std::nullopt);
  CHECK(UnknownKeyText("finished reply", "mapz", keys) ==
        "finished reply: unknown key 'mapz' (did you mean 'maps'?); the valid keys are type, "
        "landmarks, maps, health, stage_seconds");
}

TEST_CASE("a finished reply with a misspelt result key keeps its other parts and reports an error",
          "[external][protocol]") {
  const nlohmann::json reply = nlohmann::json::parse(R"({"type": "finished",
      "landmark": [{"id": 1, "type": "lamp", "position": [1, 2, 3]}],
      "innovations": [{"type": "lamp", "nis": 1.5, "dof": 2}],
      "health": {"rejected_updates": 2}, "stage_seconds": {"detect": 0.5}})");
  ReplyProblems problems;
  const Finished finished = ParseFinished(reply, "", 100, {"upward"}, &problems);
  CHECK(finished.landmarks.empty());
  CHECK(finished.extras.innovations.size() == 1);
  CHECK(finished.health.rejected_updates == 2);
  CHECK(finished.stage_seconds.at("detect") == 0.5);
  REQUIRE(problems.errors.size() == 1);
  CHECK(problems.errors[0] == std::string("finished reply: unknown key 'landmark' (did you mean "
                                          "'landmarks'?); ") +
                                  kFinishedKeys);
  CHECK(problems.warnings.empty());
  // Without `problems`: it throws, with the same words.
  CHECK_THROWS_WITH(ParseFinished(reply, "", 100, {"upward"}),
                    Contains("unknown key 'landmark'") && Contains(kFinishedKeys));
}

TEST_CASE("a misspelt key that carries no result is a warning; the results are whole",
          "[external][protocol]") {
  ReplyProblems problems;
  const Finished finished =
      ParseFinished(nlohmann::json::parse(R"({"type": "finished", "stage_second": {"detect": 0.5},
                                "landmarks": [{"id": 1, "type": "lamp", "position": [1, 2, 3]}]})"),
                    "", 100, {}, &problems);
  CHECK(finished.landmarks.size() == 1);
  CHECK(problems.errors.empty());
  REQUIRE(problems.warnings.size() == 1);
  CHECK_THAT(problems.warnings[0], Contains("unknown key 'stage_second' (did you mean "
                                            "'stage_seconds'?)") &&
                                       Contains(kFinishedKeys));
  ReplyProblems ready_problems;
  const Ready ready =
      ParseReady(nlohmann::json::parse(R"({"type": "ready", "name": "mine", "verison": "1"})"),
                 &ready_problems);
  CHECK(ready.name == "mine");
  CHECK(ready_problems.errors.empty());
  CHECK(ready_problems.warnings.size() == 1);
}

TEST_CASE("a bad part of a finished reply costs only itself", "[external][protocol]") {
  ReplyProblems problems;
  const Finished finished = ParseFinished(nlohmann::json::parse(R"({"type": "finished",
          "landmarks": [{"id": 1, "type": "lamp", "position": [1, 2, 3]},
                        {"id": 2, "type": "lamp", "positon": [1, 2, 3]}],
          "health": {"rejected_updates": 4}})"),
                                          "", 100, {}, &problems);
  CHECK(finished.landmarks.size() == 1);
  CHECK(finished.health.rejected_updates == 4);
  REQUIRE(problems.errors.size() == 1);
  CHECK_THAT(problems.errors[0], Contains("finished.landmarks[1]: unknown key 'positon' (did you "
                                          "mean 'position'?); the valid keys are id, type, "
                                          "status, position, covariance, points, label"));
}

TEST_CASE("an estimate with an unknown key is read; a misspelt required key is named",
          "[external][protocol]") {
  ReplyProblems problems;
  ReplyExtras extras;
  const slam::PoseEstimate estimate = ParseEstimate(
      nlohmann::json::parse(R"({"type": "estimate", "stamp_ns": 20, "pose": [1, 2, 0.5],
                                "covariance": [1, 0, 0, 0, 1, 0, 0, 0, 1], "innovation": []})"),
      20, &extras, &problems);
  CHECK(estimate.stamp_ns == 20);
  CHECK(estimate.world_from_robot.x() == 1.0);
  REQUIRE(problems.errors.size() == 1);
  CHECK_THAT(problems.errors[0], Contains("estimate reply: unknown key 'innovation' (did you mean "
                                          "'innovations'?); the valid keys are type, stamp_ns, "
                                          "pose, covariance, detections, innovations"));
  // The key it needs, misspelt: it throws, saying what is missing and what the typo was.
  CHECK_THROWS_WITH(
      ParseEstimate(nlohmann::json::parse(R"({"type": "estimate", "stamp_ns": 20,
                                              "pose": [1, 2, 0.5], "covarience": []})"),
                    20, &extras, &problems),
      Contains("needs pose and covariance") && Contains("unknown key 'covarience' (did you mean "
                                                        "'covariance'?)"));
}

TEST_CASE("a processed reply's unknown key keeps its detections", "[external][protocol]") {
  ReplyProblems problems;
  ReplyExtras extras;
  ParseProcessed(nlohmann::json::parse(R"({"type": "processed", "stamp_ns": 20, "score": 1,
      "detections": [{"camera": "upward", "type": "lamp", "pixel": [3, 4], "radius_px": 2}]})"),
                 20, {"upward"}, &extras, &problems);
  CHECK(extras.detections.size() == 1);
  REQUIRE(problems.errors.size() == 1);
  CHECK_THAT(problems.errors[0], Contains("processed reply: unknown key 'score'; the valid keys "
                                          "are type, stamp_ns, detections, innovations"));
}

}  // namespace
}  // namespace corridorsim::external
