// Tests slam/p3_upward_pipeline.cpp on the frames the issue names: a black frame is refused and
// counted; a frame of one flat colour and a frame of pure sensor noise give no lamp and leave the
// pose alone; a frame full of lamps starts a bounded number of landmarks; the three registered
// types carry their defaults; landmarks come out as world points in front of the camera. (Its
// accuracy on rendered runs: tests/harness/scenario_runs_test.py, case P3.)
#include "slam/p3_upward_pipeline.h"

#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "common/random.h"
#include "slam/features/image_conversion.h"
#include "slam/registry.h"
#include "tests/support/pioneer_calibration.h"

namespace corridorsim::slam {
namespace {

// The default rig's upward camera: Kannala-Brandt 640x480, 110 deg, at (-0.05, 0, 0.4) m looking
// up, image x along the robot's -y.
Calibration UpwardCalibration() {
  Calibration c = test::PioneerCalibration();
  Eigen::Matrix3d axes;  // columns: the optical x, y, z in the robot frame
  axes << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  CameraCalibration upward;
  upward.id = "upward";
  upward.model = KannalaBrandt::FromFov(640, 480, 110.0 * M_PI / 180.0);
  upward.robot_from_camera = SE3(axes, Eigen::Vector3d(-0.05, 0, 0.4));
  c.cameras = {upward};
  return c;
}

CameraInput Frame(TimeNs stamp, std::uint8_t level) {
  CameraInput input;
  input.image.stamp_ns = stamp;
  input.image.camera_id = "upward";
  input.image.image = Image8(640, 480, 3);
  std::fill(input.image.image.data.begin(), input.image.image.data.end(), level);
  return input;
}

void Disc(Image8* image, double cu, double cv, double radius) {
  for (int v = 0; v < image->height; ++v) {
    for (int u = 0; u < image->width; ++u) {
      if (std::hypot(u - cu, v - cv) < radius) {
        for (int c = 0; c < 3; ++c) image->Pixel(u, v)[c] = 255;
      }
    }
  }
}

// A ceiling of 44 px tiles with dark seams, blurred as a lens blurs (FAST finds no corner on
// perfectly sharp seams).
CameraInput TiledCeiling() {
  CameraInput tiles = Frame(0, 190);
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) {
      if ((u + 17) % 44 < 3 || (v + 9) % 44 < 3) {
        for (int c = 0; c < 3; ++c) tiles.image.image.Pixel(u, v)[c] = 70;
      }
    }
  }
  cv::Mat view = MatView(tiles.image.image);
  cv::GaussianBlur(view, view, cv::Size(5, 5), 1.0);
  return tiles;
}

struct Fixture {
  explicit Fixture(P3UpwardOptions options = P3UpwardDefaults())
      : pipeline(options, UpwardCalibration(), 3) {
    pipeline.Initialize(0, SE2(1.0, 0.0, 0.0));
  }
  P3UpwardPipeline pipeline;
};

TEST_CASE("P3: a black frame is refused and counted, the filter untouched", "[slam][p3]") {
  Fixture f;
  f.pipeline.OnCamera(Frame(1'000'000, 0));
  CHECK(f.pipeline.health().rejected_frames == 1);
  CHECK(f.pipeline.TakeDetections().empty());
  CHECK(f.pipeline.Landmarks().empty());
  CHECK(f.pipeline.Estimate().world_from_robot.x() == 1.0);
}

TEST_CASE("P3: a flat frame and a frame of noise give no lamp and no landmark of one",
          "[slam][p3]") {
  Fixture f;
  f.pipeline.OnCamera(Frame(1'000'000, 255));  // one flat colour, saturated
  CHECK(f.pipeline.TakeDetections().empty());
  CameraInput noise = Frame(2'000'000, 0);
  RandomStream rng(5, 0, "test.noise");
  for (std::uint8_t& p : noise.image.image.data) p = std::uint8_t(rng.UniformInt(0, 255));
  f.pipeline.OnCamera(noise);
  for (const Detection& d : f.pipeline.TakeDetections()) CHECK(d.type == LandmarkType::kCorner);
  for (const LandmarkEstimate& l : f.pipeline.Landmarks()) CHECK(l.type == LandmarkType::kCorner);
  CHECK(f.pipeline.health().rejected_frames == 0);
  CHECK(f.pipeline.health().non_positive_covariance == 0);
  const PoseEstimate e = f.pipeline.Estimate();
  CHECK(std::isfinite(e.world_from_robot.x()));
  CHECK(e.world_from_robot.x() == Approx(1.0).margin(1e-9));  // at a known pose, it stays there
}

TEST_CASE("P3: a frame full of lamps starts lamp landmarks above the camera, bounded",
          "[slam][p3]") {
  P3UpwardOptions options = P3UpwardDefaults();
  options.use_corners = false;
  options.max_landmarks = 20;
  Fixture f(options);
  CameraInput full = Frame(1'000'000, 140);
  int drawn = 0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 7; ++j) {
      Disc(&full.image.image, 40.0 + 70.0 * i, 35.0 + 68.0 * j, 12.0);
      ++drawn;
    }
  }
  f.pipeline.OnCamera(full);
  const std::vector<Detection> detections = f.pipeline.TakeDetections();
  // Discs drawn round in a fisheye's pixels are round on the ceiling only near the axis: those
  // are lamps, the outer ones are rejected as not circular (docs/detectors.md).
  CHECK(int(detections.size()) > 20);
  CHECK(int(detections.size()) < drawn);
  const std::vector<LandmarkEstimate> landmarks = f.pipeline.Landmarks();
  CHECK(landmarks.size() == 20);
  for (const LandmarkEstimate& l : landmarks) {
    CHECK(l.type == LandmarkType::kLamp);
    CHECK(l.status == LandmarkStatus::kInitializing);  // one sighting: its height is the prior's
    CHECK(l.position_in_world.z() > 0.4);
  }
}

// P3's pipeline with corners only.
P3UpwardOptions CornersOnly() {
  P3UpwardOptions options = P3UpwardDefaults();
  options.use_lamps = false;
  options.use_doors = false;
  return options;
}

// The landmarks in the state after `frames` frames of the tiled ceiling seen from a robot
// standing still (the same frame again and again, 5 Hz).
std::size_t LandmarksAfterStillFrames(const P3UpwardOptions& options, int frames) {
  CameraInput tiles = TiledCeiling();
  Fixture f(options);
  for (int k = 1; k <= frames; ++k) {
    tiles.image.stamp_ns = TimeNs(k) * 200'000'000;
    f.pipeline.OnCamera(tiles);
  }
  return f.pipeline.Landmarks().size();
}

TEST_CASE("P3: new corners start only while fewer than max_tracked_corners are matched",
          "[slam][p3]") {
  // A tiled ceiling seen from a robot standing still: the same frame again and again. Each frame
  // matches the corners already started; new ones start only while fewer than the target are
  // matched, so the state stops growing at the target instead of taking every corner.
  const auto corners_after = [](int max_tracked, int frames) {
    P3UpwardOptions options = CornersOnly();
    options.max_tracked_corners = max_tracked;
    return LandmarksAfterStillFrames(options, frames);
  };
  const std::size_t tracked = corners_after(20, 12);
  INFO("corners with the target: " << tracked << ", without: " << corners_after(1000, 12));
  // Every corner started is matched again in the next frame here, so a frame's new corners
  // only fill up to the target: the state holds exactly 20, and stays there.
  CHECK(tracked == 20);
  CHECK(corners_after(20, 24) == tracked);
  CHECK(corners_after(1000, 12) > tracked + 10);  // without the target, more corners start
}

TEST_CASE("P3: a frame that finds the map empty starts first_frame_corners corners", "[slam][p3]") {
  // The tiled ceiling's first frame: by default it starts max_new_corners_per_frame corners like
  // any frame; with first_frame_corners it starts that many (the ceiling has more than enough),
  // and the next frame, matching them all, starts none (max_tracked_corners is reached).
  const auto corners_after = [](int first_frame_corners, int frames) {
    P3UpwardOptions options = CornersOnly();
    options.first_frame_corners = first_frame_corners;
    return LandmarksAfterStillFrames(options, frames);
  };
  CHECK(corners_after(0, 1) == std::size_t(P3UpwardDefaults().max_new_corners_per_frame));
  CHECK(corners_after(20, 1) == 20);
  CHECK(corners_after(20, 2) == 20);
  CHECK(corners_after(3, 1) == std::size_t(P3UpwardDefaults().max_new_corners_per_frame));
}

TEST_CASE("P3: a full state retires the corner matched longest ago, out of view and stale",
          "[slam][p3]") {
  // The same tiled ceiling before and after a 10 m drive: the corners started at the start lie
  // 10 m behind the camera after it (out of view, unmatched since), and the state is full.
  CameraInput tiles = TiledCeiling();
  struct Outcome {
    std::size_t before = 0, after = 0;  // landmarks in the state
    int started_after = 0;              // of those after the drive, started after it
  };
  const auto drive = [&](double retire_after_s) {
    P3UpwardOptions options = P3UpwardDefaults();
    options.use_lamps = false;
    options.use_doors = false;
    options.max_tracked_corners = 1000;
    options.max_landmarks = 20;
    options.retire_after_s = retire_after_s;
    Fixture f(options);
    TimeNs t = 0;
    for (int k = 0; k < 12; ++k) {
      t += 200'000'000;
      tiles.image.stamp_ns = t;
      f.pipeline.OnCamera(tiles);
    }
    Outcome out;
    out.before = f.pipeline.Landmarks().size();
    int last_id_before = -1;
    for (const LandmarkEstimate& l : f.pipeline.Landmarks()) {
      last_id_before = std::max(last_id_before, l.id);
    }
    for (int k = 0; k < 200; ++k) {  // 10 m straight ahead in 10 s
      WheelOdometry odometry;
      odometry.interval_ns = 50'000'000;
      t += odometry.interval_ns;
      odometry.stamp_ns = t;
      odometry.left_distance_m = odometry.right_distance_m = 0.05;
      f.pipeline.OnOdometry(odometry);
    }
    for (int k = 0; k < 12; ++k) {
      t += 200'000'000;
      tiles.image.stamp_ns = t;
      f.pipeline.OnCamera(tiles);
    }
    const std::vector<LandmarkEstimate> after = f.pipeline.Landmarks();
    out.after = after.size();
    out.started_after = int(std::count_if(after.begin(), after.end(),
                                          [&](const auto& l) { return l.id > last_id_before; }));
    INFO("x after the drive: " << f.pipeline.Estimate().world_from_robot.x());
    CHECK(f.pipeline.Estimate().world_from_robot.x() == Approx(11.0).margin(0.5));
    return out;
  };
  const Outcome retiring = drive(5.0);
  CHECK(retiring.before == 20);
  CHECK(retiring.after == 20);          // never more than max_landmarks
  CHECK(retiring.started_after == 20);  // the new place mapped: every old corner retired
  const Outcome never = drive(1e6);     // nothing stale enough: the state stops growing
  CHECK(never.before == 20);
  CHECK(never.after == 20);
  CHECK(never.started_after == 0);
  // Only stale corners go: 10 s after their last match, a bound of 30 s retires none.
  CHECK(drive(30.0).started_after == 0);
}

TEST_CASE("P3: the three registered types and their defaults", "[slam][p3]") {
  for (const char* name : {"p3_upward", "p3_corners", "p2_upward"}) {
    INFO(name);
    const std::unique_ptr<PipelineOptions> options = NewPipelineOptions(name);
    REQUIRE(options);
    CHECK_FALSE(options->Check());
    const auto* o = static_cast<const P3UpwardOptions*>(options->options());
    CHECK(o->use_corners);
    CHECK(o->use_lamps == (std::string(name) == "p3_upward"));
    CHECK((o->corners.detector == CornerDetector::kHarris) == (std::string(name) == "p2_upward"));
    const std::unique_ptr<Pipeline> pipeline = options->Create(UpwardCalibration(), 1);
    CHECK(pipeline->cameras_used() == std::vector<std::string>{"upward"});
  }
}

}  // namespace
}  // namespace corridorsim::slam
