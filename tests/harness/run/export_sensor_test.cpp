// harness/run/export_yaml.h through the DatasetExporter: every exported camera's sensor.yaml
// (tum_rgbd/, euroc/mav0/cam0/ and cam1/) carries the camera's mount as T_BS and the body's start
// pose as T_WB_start, the first pose of the export's ground truth (docs/export.md). The frames are
// blank images of the right size: nothing is rendered.

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>

#include "harness/run/export.h"
#include "tests/support/exported_dataset.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim::export_tests {
namespace {

// The default rig with small images and mounts moved off their defaults on every axis, so that
// T_BS can only be the scenario's mount.
render::RigOptions MovedRig() {
  render::RigOptions rig = render::RigOptions::Default();
  for (render::CameraOptions& camera : rig.cameras) {
    camera.enabled = true;
    if (camera.id == "upward") {
      camera.model = KannalaBrandt::FromFov(16, 12, 110.0 * kDeg);
    } else {
      camera.model = PinholeRadTan::FromFov(16, 12, 60.0 * kDeg);
    }
    camera.mount.x_m += 0.031;
    camera.mount.y_m -= 0.017;
    camera.mount.z_m += 0.043;
    camera.mount.yaw_deg += 3.5;
    camera.mount.pitch_deg -= 4.25;
    camera.mount.roll_deg += 1.75;
  }
  REQUIRE_FALSE(rig.Check());
  return rig;
}

// The robot drives along a curve: no pose is the identity or another's.
SE3 RobotPoseAt(TimeNs t) {
  const double s = ToSeconds(t);
  return SE3::FromSE2(SE2(1.5 + 0.4 * s, -2.0 + 0.1 * s * s, 0.7 + 0.2 * s));
}

sim::CameraMessage Frame(const render::CameraOptions& options, TimeNs t) {
  const CameraIntrinsics in = options.model.intrinsics();
  const std::size_t n = static_cast<std::size_t>(in.width) * in.height;
  sim::CameraMessage m;
  m.stamp_ns = t;
  m.world_from_robot = RobotPoseAt(t);
  m.frame.camera_id = options.id;
  m.frame.world_from_camera = m.world_from_robot * options.mount.RobotFromCamera();
  m.frame.rgb = Image8(in.width, in.height, 3);
  m.frame.instance.assign(n, 0);
  m.frame.semantic.assign(n, 0);
  if (options.depth) m.frame.noisy_depth_m = ImageF(in.width, in.height, 2.0f);
  return m;
}

// Frames of every camera from `first_frame_ns`, and with `truth` the robot's truth at 100 Hz from
// `first_truth_ns`.
void Export(const fs::path& dir, const render::RigOptions& rig, TimeNs first_frame_ns, bool truth,
            TimeNs first_truth_ns) {
  DatasetExporter exporter(dir, rig, 0.33);
  const TimeNs end = first_frame_ns + 2 * kFramePeriodNs;
  for (TimeNs t = 0; t <= end; t += kTruthPeriodNs) {
    if (truth && t >= first_truth_ns) exporter.AddTruth(t, RobotPoseAt(t));
    if (t >= first_frame_ns && (t - first_frame_ns) % kFramePeriodNs == 0) {
      for (const render::CameraOptions& options : rig.cameras) {
        exporter.AddFrame(Frame(options, t), options.id);
      }
    }
  }
  exporter.Finish();
}

// A 4x4 matrix as EuRoC writes one: rows, cols, data row-major.
Eigen::Matrix4d Matrix(const YAML::Node& node) {
  REQUIRE(node["rows"].as<int>() == 4);
  REQUIRE(node["cols"].as<int>() == 4);
  const std::vector<double> d = node["data"].as<std::vector<double>>();
  REQUIRE(d.size() == 16);
  return Eigen::Matrix<double, 4, 4, Eigen::RowMajor>(d.data());
}

Eigen::Matrix4d MatrixOf(const SE3& pose) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = pose.rotation();
  m.topRightCorner<3, 1>() = pose.translation();
  return m;
}

// The first data line of a text file, split at `separator`.
std::vector<std::string> FirstRow(const fs::path& path, char separator) {
  const std::vector<std::vector<std::string>> rows = Rows(path, separator);
  REQUIRE_FALSE(rows.empty());
  return rows.front();
}

double RotationError(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

struct Sensor {
  const char* folder;  // under the export root
  const char* camera_id;
};
constexpr Sensor kSensors[] = {
    {"tum_rgbd", "front"}, {"euroc/mav0/cam0", "upward"}, {"euroc/mav0/cam1", "lateral"}};

TEST_CASE("every exported camera's sensor.yaml holds its mount and the ground truth's first pose",
          "[export]") {
  test::ScratchDir dir("export_sensor_test");
  const render::RigOptions rig = MovedRig();
  // Truth from 0, the first frames at 0.1 s: the start is the first truth sample.
  Export(dir.path(), rig, 100'000'000, true, 0);
  for (const Sensor& sensor : kSensors) {
    INFO(sensor.folder);
    const render::CameraOptions& options = *rig.Find(sensor.camera_id);
    const YAML::Node yaml = YAML::LoadFile((dir.path() / sensor.folder / "sensor.yaml").string());
    CHECK(yaml["sensor_type"].as<std::string>() == "camera");
    // Exactly the numbers (the file's reals read back as the doubles written).
    const Eigen::Matrix4d t_bs = Matrix(yaml["T_BS"]);
    CHECK(t_bs == MatrixOf(options.mount.RobotFromCamera()));
    CHECK(t_bs.topRightCorner<3, 1>() ==
          Eigen::Vector3d(options.mount.x_m, options.mount.y_m, options.mount.z_m));
    CHECK(Matrix(yaml["T_WB_start"]) == MatrixOf(RobotPoseAt(0)));
    CHECK(yaml["start_timestamp_ns"].as<TimeNs>() == 0);
  }
  // The start pose is the first line of each layout's ground truth: EuRoC's robot truth, and the
  // TUM front camera's through T_BS.
  const YAML::Node tum = YAML::LoadFile((dir.path() / "tum_rgbd" / "sensor.yaml").string());
  const Eigen::Matrix4d start = Matrix(tum["T_WB_start"]);
  const std::vector<std::string> euroc =
      FirstRow(dir.path() / "euroc/mav0/state_groundtruth_estimate0/data.csv", ',');
  REQUIRE(euroc.size() == 17);
  CHECK(std::stoll(euroc[0]) == 0);
  const Eigen::Vector3d p_euroc(std::stod(euroc[1]), std::stod(euroc[2]), std::stod(euroc[3]));
  const Eigen::Quaterniond q_euroc(std::stod(euroc[4]), std::stod(euroc[5]), std::stod(euroc[6]),
                                   std::stod(euroc[7]));
  CHECK((p_euroc - start.topRightCorner<3, 1>()).cwiseAbs().maxCoeff() < kEurocPoseTol);
  CHECK(RotationError(q_euroc.toRotationMatrix(), start.topLeftCorner<3, 3>()) < kEurocPoseTol);
  const std::vector<std::string> first = FirstRow(dir.path() / "tum_rgbd" / "groundtruth.txt", ' ');
  REQUIRE(first.size() == 8);
  CHECK(first[0] == "0.000000000");
  const Eigen::Matrix4d camera = start * Matrix(tum["T_BS"]);
  const Eigen::Vector3d p_tum(std::stod(first[1]), std::stod(first[2]), std::stod(first[3]));
  const Eigen::Quaterniond q_tum(std::stod(first[7]), std::stod(first[4]), std::stod(first[5]),
                                 std::stod(first[6]));
  CHECK((p_tum - camera.topRightCorner<3, 1>()).cwiseAbs().maxCoeff() < kTumTranslationTolM);
  CHECK(RotationError(q_tum.toRotationMatrix(), camera.topLeftCorner<3, 3>()) < kTumRotationTol);
}

TEST_CASE("without truth before the first frame, the start pose is the robot's at that frame",
          "[export]") {
  for (const bool truth : {false, true}) {
    INFO("truth from 0.2 s: " << truth);
    test::ScratchDir dir("export_sensor_start_test");
    const render::RigOptions rig = MovedRig();
    Export(dir.path(), rig, 50'000'000, truth, 200'000'000);
    for (const Sensor& sensor : kSensors) {
      INFO(sensor.folder);
      const YAML::Node yaml = YAML::LoadFile((dir.path() / sensor.folder / "sensor.yaml").string());
      CHECK(Matrix(yaml["T_WB_start"]) == MatrixOf(RobotPoseAt(50'000'000)));
      CHECK(yaml["start_timestamp_ns"].as<TimeNs>() == 50'000'000);
    }
    // TUM's groundtruth.txt starts at that frame, with the frame's camera pose.
    const std::vector<std::string> first =
        FirstRow(dir.path() / "tum_rgbd" / "groundtruth.txt", ' ');
    REQUIRE(first.size() == 8);
    CHECK(first[0] == "0.050000000");
  }
}

}  // namespace
}  // namespace corridorsim::export_tests
