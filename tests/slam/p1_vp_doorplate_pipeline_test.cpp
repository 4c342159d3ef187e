// Tests slam/p1_vp_doorplate_pipeline.cpp on bad data: a black frame, a frame without lines, a
// depth image of zeros, odometry with a NaN, frames out of time order or of the wrong size are
// refused and counted in the pipeline's health, and never move or poison the filter. (Its
// accuracy on rendered runs: tests/harness/scenario_runs_test.py, case P1.)
#include "slam/p1_vp_doorplate_pipeline.h"

#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "tests/support/odometry_message.h"
#include "tests/support/pioneer_calibration.h"
#include "tests/support/synthetic_corridor.h"

namespace corridorsim::slam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The rig of default.yaml as a robot's calibration: the front RGB-D sensor and the lateral
// camera facing left on its mast.
Calibration P1Calibration() {
  Calibration c = test::PioneerCalibration();
  Eigen::Matrix3d front_axes;  // columns: the optical x, y, z in the robot frame
  front_axes << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  CameraCalibration front;
  front.id = "front";
  front.model = PinholeRadTan::FromFov(640, 480, 58.0 * kDeg);
  front.robot_from_camera = SE3(front_axes, Eigen::Vector3d(0.18, 0, 0.45));
  front.depth = DepthRange{0.5, 8.0};
  Eigen::Matrix3d lateral_axes;
  lateral_axes << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  CameraCalibration lateral;
  lateral.id = "lateral";
  lateral.model = PinholeRadTan::FromFov(640, 480, 60.0 * kDeg);
  lateral.robot_from_camera = SE3(lateral_axes, Eigen::Vector3d(0, 0.12, 1.5));
  c.cameras = {front, lateral};
  return c;
}

CameraInput Frame(const std::string& camera, TimeNs stamp, int width, int height,
                  std::uint8_t level) {
  CameraInput input;
  input.image.stamp_ns = stamp;
  input.image.camera_id = camera;
  input.image.image = Image8(width, height, 3);
  std::fill(input.image.image.data.begin(), input.image.image.data.end(), level);
  return input;
}

struct Fixture {
  Fixture() : pipeline(Options(), P1Calibration(), 7) {
    pipeline.Initialize(0, SE2(0, 0, 0));
    pipeline.OnOdometry(test::OdometryMessage(10'000'000, 0.01, 0.01));
    before = pipeline.Estimate();
  }
  static P1VpDoorplateOptions Options() {
    P1VpDoorplateOptions o;
    o.octomap_map.keyframe_distance_m = 0.01;  // every frame is a keyframe
    return o;
  }
  void CheckUntouched() const {
    const PoseEstimate now = pipeline.Estimate();
    CHECK(now.world_from_robot.x() == before.world_from_robot.x());
    CHECK(now.world_from_robot.y() == before.world_from_robot.y());
    CHECK(now.world_from_robot.yaw() == before.world_from_robot.yaw());
    CHECK(now.covariance == before.covariance);
    CHECK(now.covariance.allFinite());
  }
  P1VpDoorplatePipeline pipeline;
  PoseEstimate before;
};

TEST_CASE("P1: a black frame is refused and counted, the filter untouched", "[slam][p1]") {
  Fixture f;
  f.pipeline.OnCamera(Frame("front", 20'000'000, 640, 480, 0));
  f.pipeline.OnCamera(Frame("lateral", 20'000'000, 640, 480, 0));
  CHECK(f.pipeline.health().rejected_frames == 2);
  CHECK(f.pipeline.TakeDetections().empty());
  CHECK(f.pipeline.Landmarks().empty());
  f.CheckUntouched();
}

TEST_CASE("P1: a frame without lines gives no vanishing point and no update", "[slam][p1]") {
  Fixture f;
  f.pipeline.OnCamera(Frame("front", 20'000'000, 640, 480, 128));
  CHECK(f.pipeline.health().rejected_frames == 0);  // a valid frame that shows nothing
  CHECK(f.pipeline.TakeDetections().empty());
  CHECK(f.pipeline.TakeInnovations().empty());
  CHECK(f.pipeline.Landmarks().empty());
  f.CheckUntouched();
}

TEST_CASE("P1: a depth image of zeros is refused and counted, nothing enters the map",
          "[slam][p1]") {
  Fixture f;
  CameraInput input = Frame("front", 20'000'000, 640, 480, 128);
  input.depth = StampedDepth{20'000'000, "front", ImageF(640, 480, 0.0f)};
  f.pipeline.OnCamera(input);
  CHECK(f.pipeline.health().rejected_frames == 1);
  REQUIRE(f.pipeline.occupancy_map() != nullptr);
  CHECK(f.pipeline.occupancy_map()->size() == 0);
  f.CheckUntouched();
}

TEST_CASE("P1: odometry with a NaN or out of time order is refused and counted", "[slam][p1]") {
  Fixture f;
  f.pipeline.OnOdometry(
      test::OdometryMessage(20'000'000, std::numeric_limits<double>::quiet_NaN(), 0.01));
  f.pipeline.OnOdometry(test::OdometryMessage(5'000'000, 0.01, 0.01));
  CHECK(f.pipeline.health().rejected_odometry == 2);
  f.CheckUntouched();
  f.pipeline.OnOdometry(
      test::OdometryMessage(30'000'000, 0.01, 0.01));  // good data afterwards is used
  CHECK(f.pipeline.Estimate().world_from_robot.x() > f.before.world_from_robot.x());
}

TEST_CASE("P1: frames out of time order or of the wrong size are refused and counted",
          "[slam][p1]") {
  Fixture f;
  f.pipeline.OnCamera(Frame("front", 20'000'000, 640, 480, 128));
  f.pipeline.OnCamera(Frame("front", 15'000'000, 640, 480, 128));    // older
  f.pipeline.OnCamera(Frame("front", 20'000'000, 640, 480, 128));    // the same stamp again
  f.pipeline.OnCamera(Frame("lateral", 20'000'000, 320, 240, 128));  // not the calibration's
  f.pipeline.OnCamera(Frame("lateral", 20'000'000, 0, 0, 128));      // empty
  CHECK(f.pipeline.health().rejected_frames == 4);
  f.CheckUntouched();
}

TEST_CASE("P1: a vanishing point outside the image never starts a VP landmark; one inside does",
          "[slam][p1]") {
  P1VpDoorplateOptions options;
  options.use_door_plates = false;
  options.octomap = false;
  // The corridor seen 40 degrees off its axis: the detector places its point right of the image
  // (within max_outside_image_px), as it does for frames taken while the robot turns.
  test::CorridorView aside;
  aside.yaw_rad = 40.0 * kDeg;
  aside.camera_in_world.y() = -0.6;
  const Image8 aside_image = test::DrawCorridor(aside);
  const std::optional<VanishingPoint> seen =
      DetectVanishingPoint(aside_image, options.vanishing_point);
  REQUIRE(seen);
  REQUIRE(seen->pixel_px.x() > test::kCorridorImageWidth);

  const auto vp_landmarks = [](const P1VpDoorplatePipeline& p) {
    int count = 0;
    for (const LandmarkEstimate& l : p.Landmarks())
      count += l.type == LandmarkType::kVanishingPoint;
    return count;
  };
  P1VpDoorplatePipeline pipeline(options, P1Calibration(), 7);
  pipeline.Initialize(0, SE2(0, 0, 0));
  CameraInput frame = Frame("front", 1'000'000, 640, 480, 0);
  frame.image.image = aside_image;
  pipeline.OnCamera(frame);
  CHECK(vp_landmarks(pipeline) == 0);
  const std::vector<Detection> detections = pipeline.TakeDetections();
  REQUIRE(detections.size() == 1);  // reported, but associated with nothing
  CHECK(detections[0].landmark_id < 0);

  // Looking down the corridor, the point lies inside the image and starts the landmark.
  frame.image.stamp_ns = 2'000'000;
  frame.image.image = test::DrawCorridor(test::CorridorView{});
  pipeline.OnCamera(frame);
  CHECK(vp_landmarks(pipeline) == 1);
}

}  // namespace
}  // namespace corridorsim::slam
