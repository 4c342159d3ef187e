// Tests harness/metrics/map.cpp: landmarks matched one-to-one to ground truth; spurious, missed,
// errors. Each case is constructed so that its answer is known in closed form.
#include "harness/metrics/map.h"

#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

TEST_CASE("landmark matching counts a spurious and a missed landmark and wrong room numbers",
          "[metrics]") {
  const worlds::World world = PlateWorld();
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("map", truth, {"lateral"});
  record.landmarks = {
      Landmark(10, LandmarkType::kDoorPlate, {1.1, 1.0, 1.4}, "101"),   // plate 1, 0.1 m off
      Landmark(11, LandmarkType::kDoorPlate, {4.0, 1.2, 1.5}, "999"),   // plate 2, wrong number
      Landmark(12, LandmarkType::kDoorPlate, {20.0, 0.0, 1.5}, "120"),  // nothing near: spurious
      // Two lamps near the one lamp: one-to-one leaves the farther one spurious.
      Landmark(20, LandmarkType::kLamp, {2.05, 0.0, 2.5}),
      Landmark(21, LandmarkType::kLamp, {2.3, 0.0, 2.4}),
  };
  FrameTruthSample frame = Frame("lateral", 0);
  for (int id = 1; id <= 3; ++id) frame.truth.plates.push_back(PlateSeen(id, {100.0 * id, 50}));
  const Json m = RunOne(world, truth, record, {frame});
  REQUIRE(m.contains("map"));
  const Json& plates = m["map"]["door_plate"];
  CheckCounts(plates, {{"estimated", 3},
                       {"matched", 2},
                       {"spurious", 1},
                       {"observed", 3},
                       {"missed", 1}});  // missed: plate 3 was seen but never mapped
  CHECK(Num(plates["mean_error_m"]) == Approx(0.15).margin(test::kMetricsJsonM));
  CHECK(Num(plates["rmse_m"]) == Approx(std::sqrt(0.025)).margin(test::kMetricsJsonM));
  CHECK(Num(plates["max_error_m"]) == Approx(0.2).margin(test::kMetricsJsonM));
  CHECK(Num(plates["room_number_accuracy"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  const Json& lamps = m["map"]["lamp"];
  CHECK(lamps["matched"] == 1);
  CHECK(lamps["spurious"] == 1);
  CHECK(lamps["observed"] == 0);  // no frame saw the lamp: it cannot be missed
  CHECK(lamps["missed"] == 0);
  CHECK(Num(lamps["mean_error_m"]) == Approx(0.05).margin(test::kMetricsJsonM));
  CHECK(Num(lamps["z_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
}

}  // namespace
}  // namespace corridorsim::metrics_tests

namespace corridorsim::metrics_tests {
namespace {

// A corner detection that created landmark `landmark_id`.
slam::Detection NewCorner(const std::string& camera, int landmark_id) {
  slam::Detection d = DetectionAt(5, camera, LandmarkType::kCorner, Vector2d(100, 100));
  d.landmark_id = landmark_id;
  d.new_landmark = true;
  return d;
}

TEST_CASE(
    "a corner landmark is scored against the point its creating detection saw, not the "
    "nearest tile crossing",
    "[metrics]") {
  // A ceiling of tile crossings every 0.6 m: every estimate has one within the 1 m gate.
  worlds::World world;
  for (int i = 0; i < 20; ++i) {
    worlds::CornerPoint c;
    c.id = 100 + i;
    c.position = Eigen::Vector3d(0.6 * i, 0.0, 2.7);
    world.corner_points.push_back(c);
  }
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("harris", truth, {"front"});
  record.detections = {NewCorner("front", 1), NewCorner("front", 2)};
  // Landmark 1 saw a door-frame corner at (3.0, 1.1, 2.0) and is estimated 5 cm from it;
  // landmark 2 saw a point at (4.0, -1.1, 0.5) but is estimated 1.1 m away, on a tile
  // crossing (the old scheme would have matched it).
  record.seen_points[0] = SeenPoint{Eigen::Vector3d(3.0, 1.1, 2.0), 7};
  record.seen_points[1] = SeenPoint{Eigen::Vector3d(4.0, -1.1, 0.5), 8};
  record.landmarks = {Landmark(1, LandmarkType::kCorner, {3.05, 1.1, 2.0}),
                      Landmark(2, LandmarkType::kCorner, {4.2, 0.0, 2.7})};
  FrameTruthSample frame = Frame("front", 5);
  const Json m = RunOne(world, truth, record, {frame});
  const Json& corners = m["map"]["corner"];
  CHECK(corners["estimated"] == 2);
  CHECK(corners["matched"] == 1);
  CHECK(corners["spurious"] == 1);
  CHECK(Num(corners["mean_error_m"]) == Approx(0.05).margin(test::kMetricsJsonM));
  CHECK(Num(corners["z_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(corners["observed"].is_null());
}

TEST_CASE("map.area scores each landmark's area against the area its true position lies in",
          "[metrics]") {
  // Two open doorways, each with a room behind it: 20 in the left wall (room x 2-5, y 1.3-4.8),
  // 21 in the right wall (room x 8-11, y -4.8 to -1.3). A lamp hangs in room 20's ceiling.
  worlds::World world;
  const auto doorway = [&](int id, double x0, double y, double room_y0, double room_y1) {
    worlds::Doorway d;
    d.id = id;
    d.state = worlds::DoorState::kOpen;
    d.column_a = Vector2d(x0, y);
    d.column_b = Vector2d(x0 + 1.0, y);
    worlds::Room room;
    room.footprint = Eigen::AlignedBox2d(Vector2d(x0 - 1.0, room_y0), Vector2d(x0 + 2.0, room_y1));
    d.room = room;
    world.doors.push_back(d);
  };
  doorway(20, 3.0, 1.2, 1.3, 4.8);
  doorway(21, 9.0, -1.2, -4.8, -1.3);
  worlds::Lamp lamp;
  lamp.id = 30;
  lamp.center = Eigen::Vector3d(3.5, 3.0, 2.6);
  lamp.room_door_id = 20;
  world.lamps.push_back(lamp);
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("upward", truth, {"upward"});
  // Door landmark 50 is doorway 20 (its columns 2 cm off); doorway 21 was never registered.
  slam::LandmarkEstimate door = Landmark(50, LandmarkType::kDoor, {3.5, 1.2, 2.0});
  for (const auto& [role, x] : {std::pair("column_a", 3.02), std::pair("column_b", 3.98)}) {
    slam::LandmarkPoint p;
    p.role = role;
    p.position_in_world = Eigen::Vector3d(x, 1.2, 2.0);
    door.points.push_back(p);
  }
  record.detections = {NewCorner("upward", 1), NewCorner("upward", 3), NewCorner("upward", 4)};
  record.seen_points[0] = SeenPoint{Eigen::Vector3d(6.0, 0.0, 2.7), 7};   // the corridor
  record.seen_points[1] = SeenPoint{Eigen::Vector3d(9.5, -3.0, 2.6), 8};  // room 21's ceiling
  record.seen_points[2] = SeenPoint{Eigen::Vector3d(1.0, 0.5, 2.7), 9};   // the corridor
  record.landmarks = {Landmark(1, LandmarkType::kCorner, {6.0, 0.0, 2.7}),
                      Landmark(2, LandmarkType::kLamp, {3.55, 3.0, 2.6}),
                      Landmark(3, LandmarkType::kCorner, {9.5, -3.0, 2.6}),
                      Landmark(4, LandmarkType::kCorner, {1.0, 0.5, 2.7}), door};
  // The pipeline's division: landmark 4 wrongly in room 1, the rest where they truly are (3 in
  // the corridor: its room has no area).
  slam::MapArea corridor, room;
  corridor.landmark_ids = {1, 3};
  room.id = 1;
  room.kind = slam::AreaKind::kRoom;
  room.door_landmark_id = 50;
  room.polygon = {Vector2d(2, 1.2), Vector2d(5, 1.2), Vector2d(5, 5), Vector2d(2, 5)};
  room.landmark_ids = {2, 4};
  record.areas = {corridor, room};
  const Json m = RunOne(world, truth, record);
  REQUIRE(m["map"]["door"]["matched"] == 1);
  const Json& areas = m["map"]["area"];
  CHECK(areas["rooms"] == 1);
  CHECK(areas["rooms_behind_open_doors"] == 1);
  CHECK(areas["landmarks_scored"] == 4);
  CHECK(areas["in_unregistered_room"] == 1);  // landmark 3
  CHECK(areas["assigned_correctly"] == 2);    // landmarks 1 and 2
  CHECK(Num(areas["assignment_accuracy"]) == Approx(2.0 / 3.0).margin(1e-6));
  CHECK(areas["room_landmarks"] == 1);  // the lamp
  CHECK(areas["room_landmarks_found"] == 1);
  // A pipeline that divides nothing has no map.area.
  record.areas.clear();
  CHECK_FALSE(RunOne(world, truth, record)["map"].contains("area"));
}

}  // namespace
}  // namespace corridorsim::metrics_tests
