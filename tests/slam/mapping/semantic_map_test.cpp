// Tests slam/mapping/semantic_map.cpp: the room-number map as JSON, written and parsed back.
#include "slam/mapping/semantic_map.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace corridorsim::slam {
namespace {

SemanticMapEntry Entry(const std::string& room, int id, double x, double y, bool planar) {
  SemanticMapEntry e;
  e.room = room;
  e.landmark_id = id;
  e.position_in_world = Eigen::Vector3d(x, y, 1.6);
  e.planar = planar;
  if (planar) {
    e.covariance.topLeftCorner<2, 2>() << 0.01, 0.002, 0.002, 0.04;
  } else {
    e.covariance << 0.01, 0.001, -0.003, 0.001, 0.02, 0.0, -0.003, 0.0, 0.0025;
  }
  return e;
}

// The message ParseSemanticMap throws for `text` ("" when it parses).
std::string ProblemOf(const std::string& text) {
  try {
    ParseSemanticMap(text);
  } catch (const SemanticMapError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("the semantic map's JSON is sorted by room number and parses back to the same entries",
          "[slam][mapping]") {
  const std::vector<SemanticMapEntry> entries = {
      Entry("110", 4, 12.5, -1.2, false), Entry("9", 2, 1.0 / 3.0, 1.2, true),
      Entry("A2", 7, 30.0, 1.2, false), Entry("101", 3, 2.0, -1.2, false)};
  const std::string text = SemanticMapToJson(entries);
  CHECK(text.back() == '\n');
  CHECK_THAT(text, Catch::StartsWith("{\n  \"format\": \"corridorsim.semantic_map\""));
  const std::vector<SemanticMapEntry> parsed = ParseSemanticMap(text);
  REQUIRE(parsed.size() == 4u);
  const std::vector<std::string> order = {"9", "101", "110", "A2"};
  for (std::size_t i = 0; i < parsed.size(); ++i) {
    CHECK(parsed[i].room == order[i]);
    const SemanticMapEntry& original =
        *std::find_if(entries.begin(), entries.end(),
                      [&](const SemanticMapEntry& e) { return e.room == order[i]; });
    CHECK(parsed[i].landmark_id == original.landmark_id);
    CHECK(parsed[i].position_in_world == original.position_in_world);  // exact: shortest repr
    CHECK(parsed[i].covariance == original.covariance);
    CHECK(parsed[i].planar == original.planar);
  }
  // The same entries in any order give the same bytes.
  CHECK(SemanticMapToJson(parsed) == text);
  CHECK(SemanticMapToJson({}) ==
        "{\n  \"format\": \"corridorsim.semantic_map\",\n  \"version\": 1,\n  \"frame\": "
        "\"world\",\n  \"rooms\": []\n}\n");
}

TEST_CASE("room numbers sort by value, other labels after them", "[slam][mapping]") {
  CHECK(RoomNumberLess("9", "10"));
  CHECK(RoomNumberLess("010", "11"));
  CHECK(RoomNumberLess("010", "10"));  // equal value: by bytes, never equivalent
  CHECK_FALSE(RoomNumberLess("10", "010"));
  CHECK(RoomNumberLess("999", "A1"));
  CHECK_FALSE(RoomNumberLess("101", "101"));
}

TEST_CASE("the semantic map of landmarks keeps labelled door plates, the better of duplicates",
          "[slam][mapping]") {
  const auto landmark = [](int id, LandmarkType type, const Eigen::Vector3d& p,
                           const Eigen::Matrix3d& covariance, const std::string& label) {
    LandmarkEstimate l;
    l.id = id;
    l.type = type;
    l.position_in_world = p;
    l.covariance = covariance;
    l.label = label;
    return l;
  };
  std::vector<LandmarkEstimate> landmarks(4);
  landmarks[0] =
      landmark(1, LandmarkType::kDoorPlate, {1, 2, 1.6}, Eigen::Matrix3d::Identity() * 0.04, "102");
  landmarks[1] =
      landmark(2, LandmarkType::kDoorPlate, {5, 2, 1.6}, Eigen::Matrix3d::Identity() * 0.01, "102");
  landmarks[2] =
      landmark(3, LandmarkType::kDoorPlate, {7, 2, 1.6}, Eigen::Matrix3d::Identity(), "");
  landmarks[3] = landmark(4, LandmarkType::kLamp, {8, 0, 2.7}, Eigen::Matrix3d::Identity(), "103");
  const std::vector<SemanticMapEntry> map = SemanticMapFromLandmarks(landmarks);
  REQUIRE(map.size() == 1u);
  CHECK(map[0].room == "102");
  CHECK(map[0].landmark_id == 2);
  CHECK(map[0].position_in_world.x() == 5.0);
}

TEST_CASE("the semantic map parser names what is wrong", "[slam][mapping]") {
  const std::string head =
      R"({"format": "corridorsim.semantic_map", "version": 1, "frame": "world", )";
  const std::string room =
      R"({"room": "101", "landmark_id": 3, "position_m": [1, 2, 3], "covariance_m2": [[1, 0], [0, 1]]})";
  CHECK(ProblemOf(head + R"("rooms": [)" + room + "]}") == "");
  CHECK_THAT(ProblemOf("{\n  \"format\": 1,\n  oops"), Catch::StartsWith("not JSON"));
  try {
    ParseSemanticMap("{\n  \"format\": 1,\n  oops");
  } catch (const SemanticMapError& e) {
    CHECK(e.line() == 3);
    CHECK(e.column() == 3);
  }
  CHECK(ProblemOf(head + R"("rooms": [], "extra": 1})") ==
        "extra: unknown key (known: format, version, frame, rooms)");
  CHECK(ProblemOf(R"({"format": "corridorsim.semantic_map", "version": 1, "frame": "world"})") ==
        "missing key 'rooms'");
  CHECK(ProblemOf(head + R"("rooms": [], "rooms": []})") == "rooms: duplicate key");
  CHECK(ProblemOf(R"({"format": "x", "version": 1, "frame": "world", "rooms": []})") ==
        "format: expected \"corridorsim.semantic_map\"");
  CHECK(ProblemOf(head + R"("rooms": {}})") == "rooms: expected an array (got object)");
  CHECK(ProblemOf(head + R"("rooms": [)" + room + ", " + room + "]}") ==
        "rooms[1].room: room '101' appears twice");
  // The problem of a map of the one room with its first `part` replaced by `replacement`.
  const auto edited = [&](const std::string& part, const std::string& replacement) {
    std::string bad = room;
    bad.replace(bad.find(part), part.size(), replacement);
    return ProblemOf(head + R"("rooms": [)" + bad + "]}");
  };
  CHECK(edited("[1, 2, 3]", "[1, 2]") == "rooms[0].position_m: expected [x, y, z] in metres");
  CHECK(edited("[1, 2, 3]", "[1, \"2\", 3]") ==
        "rooms[0].position_m[1]: expected a number (got string)");
  CHECK(edited("[[1, 0], [0, 1]]", "[[1, 0.5], [0, 1]]") ==
        "rooms[0].covariance_m2: not symmetric");
  CHECK(edited("[[1, 0], [0, 1]]", "[[-1, 0], [0, 1]]") ==
        "rooms[0].covariance_m2: a variance is negative");
  CHECK_THAT(edited("\"101\"", "\"1 01\""), Catch::StartsWith("rooms[0].room: "));
  CHECK_THAT(edited("3, \"pos", "3.5, \"pos"),
             Catch::StartsWith("rooms[0].landmark_id: expected an integer"));
  CHECK(edited("[1, 2, 3]", "[1, 2, 1e400]") == "not JSON: number overflow parsing '1e400'");
  CHECK_THAT(ProblemOf(std::string(kSemanticMapMaxBytes + 1, ' ')),
             Catch::StartsWith("longer than"));
}

}  // namespace
}  // namespace corridorsim::slam
