// harness/run/export_yaml.h through the DatasetExporter: every exported camera's sensor.yaml
// (tum_rgbd/, euroc/mav0/cam<N>/) carries the camera's mount as T_BS and the body's start pose as
// T_WB_start, the first pose of the export's ground truth (docs/export.md); named cameras are
// numbered from cam2 in the rig's order (cameras.yaml); harness/run/export_imu.h's scanners and
// TUM accelerometer file. The frames are blank images of the right size: nothing is rendered.

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>

#include "harness/run/export.h"
#include "harness/run/export_imu.h"
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

// MovedRig() with named cameras after the three: `a` (depth), `off` (disabled) and `b`.
render::RigOptions NamedRig() {
  render::RigOptions rig = MovedRig();
  for (const char* id : {"a", "off", "b"}) {
    render::CameraOptions camera = render::NewCameraOptions(id);
    camera.model = PinholeRadTan::FromFov(16, 12, 60.0 * kDeg);
    camera.mount.y_m = id[0] == 'b' ? -0.06 : 0.06;
    camera.depth = id[0] == 'a';
    camera.enabled = id[0] != 'o';
    rig.cameras.push_back(camera);
  }
  REQUIRE_FALSE(rig.Check());
  return rig;
}

TEST_CASE("named cameras are numbered from cam2 in the rig's order, disabled ones counted",
          "[export]") {
  const render::RigOptions rig = NamedRig();
  CHECK(DatasetExporter::EurocCameraNumber(rig, "front") == -1);
  CHECK(DatasetExporter::EurocCameraNumber(rig, "upward") == 0);
  CHECK(DatasetExporter::EurocCameraNumber(rig, "lateral") == 1);
  CHECK(DatasetExporter::EurocCameraNumber(rig, "a") == 2);
  CHECK(DatasetExporter::EurocCameraNumber(rig, "off") == 3);
  CHECK(DatasetExporter::EurocCameraNumber(rig, "b") == 4);
  CHECK(DatasetExporter::EurocCameraNumber(rig, "nope") == -1);

  test::ScratchDir dir("export_named_test");
  std::vector<render::CameraOptions> enabled;
  for (const render::CameraOptions& c : rig.cameras) {
    if (c.enabled) enabled.push_back(c);
  }
  {
    DatasetExporter exporter(dir.path(), rig, 0.33);
    for (TimeNs t = 0; t <= 2 * kFramePeriodNs; t += kFramePeriodNs) {
      exporter.AddTruth(t, RobotPoseAt(t));
      for (const render::CameraOptions& options : enabled) {
        exporter.AddFrame(Frame(options, t), options.id);
      }
    }
    CHECK(exporter.has_tum());
    exporter.Finish();
  }
  const fs::path mav = dir.path() / "euroc" / "mav0";
  const YAML::Node cameras = YAML::LoadFile((mav / "cameras.yaml").string());
  CHECK(cameras.size() == 4);
  CHECK(cameras["cam0"].as<std::string>() == "upward");
  CHECK(cameras["cam1"].as<std::string>() == "lateral");
  CHECK(cameras["cam2"].as<std::string>() == "a");
  CHECK(cameras["cam4"].as<std::string>() == "b");
  CHECK_FALSE(fs::exists(mav / "cam3"));
  for (const auto& [cam, id] : {std::pair{"cam2", "a"}, std::pair{"cam4", "b"}}) {
    INFO(cam);
    const YAML::Node yaml = YAML::LoadFile((mav / cam / "sensor.yaml").string());
    CHECK(Matrix(yaml["T_BS"]) == MatrixOf(rig.Find(id)->mount.RobotFromCamera()));
    CHECK(yaml["comment"].as<std::string>() ==
          std::string("corridorsim ") + id + " camera as " + cam);
    const std::vector<std::vector<std::string>> rows = Rows(mav / cam / "data.csv", ',');
    REQUIRE(rows.size() == 3);
    CHECK(rows[1] == std::vector<std::string>{"300000000", "300000000.png"});
    CHECK(fs::exists(mav / cam / "data" / "600000000.png"));
  }
  // The depth camera's depth/ and its index; none for the other; COCO keeps front and lateral.
  CHECK(fs::exists(mav / "cam2" / "depth" / "600000000.png"));
  CHECK(ReadText(mav / "cam2" / "depth.csv") == ReadText(mav / "cam2" / "data.csv"));
  CHECK_FALSE(fs::exists(mav / "cam4" / "depth"));
  CHECK_FALSE(fs::exists(mav / "cam4" / "depth.csv"));
  CHECK(fs::exists(dir.path() / "labels" / "b" / "600000000.png"));
  CHECK(ReadText(dir.path() / "coco" / "plates.json").find("cam2") == std::string::npos);
}

TEST_CASE("an export of the three cameras alone has no cameras.yaml", "[export]") {
  test::ScratchDir dir("export_three_test");
  Export(dir.path(), MovedRig(), 0, true, 0);
  CHECK(fs::exists(dir.path() / "euroc" / "mav0" / "cam0" / "data.csv"));
  CHECK_FALSE(fs::exists(dir.path() / "euroc" / "mav0" / "cameras.yaml"));
}

LaserScan Sweep(TimeNs t, std::vector<float> ranges) {
  LaserScan scan;
  scan.stamp_ns = t;
  scan.angle_min_rad = -0.5;
  scan.angle_increment_rad = 0.25;
  scan.time_increment_ns = 1'000'000;
  scan.scan_time_ns = 100'000'000;
  scan.range_min_m = 0.1;
  scan.range_max_m = 30.0;
  scan.ranges_m = std::move(ranges);
  return scan;
}

TEST_CASE("laser scanners are exported as laser<k>/ with one row per sweep", "[export]") {
  test::ScratchDir dir("export_laser_test");
  std::vector<sim::LaserOptions> lasers(3);
  lasers[0].id = "s0";
  lasers[1].id = "off";
  lasers[1].enabled = false;
  lasers[2].id = "s1";
  LaserExport out(dir.path(), lasers);
  const float inf = std::numeric_limits<float>::infinity();
  out.Add(0, Sweep(0, {1.5f, inf, -inf, std::numeric_limits<float>::quiet_NaN(), 2.25f}));
  out.Add(0, Sweep(100'000'000, {1.0f, 1.0f, 1.0f, 1.0f, 1.0f}));
  // Out of order, or another beam count: refused.
  CHECK_THROWS_AS(out.Add(0, Sweep(100'000'000, {1, 1, 1, 1, 1})), std::invalid_argument);
  CHECK_THROWS_AS(out.Add(0, Sweep(200'000'000, {1, 1})), std::invalid_argument);
  out.Finish();
  const fs::path folder = dir.path() / "euroc" / "mav0" / "laser0";
  const std::vector<std::vector<std::string>> rows = Rows(folder / "data.csv", ',');
  REQUIRE(rows.size() == 2);
  CHECK(rows[0] == std::vector<std::string>{"0", "-0.5", "0.25", "0.001", "0.1", "30", "1.5", "inf",
                                            "-inf", "nan", "2.25"});
  CHECK(rows[1][0] == "100000000");
  const YAML::Node yaml = YAML::LoadFile((folder / "sensor.yaml").string());
  CHECK(yaml["sensor_type"].as<std::string>() == "laser");
  CHECK(yaml["beams"].as<int>() == 5);
  CHECK(Matrix(yaml["T_BS"]) == MatrixOf(lasers[0].mount.RobotFromBody()));
  // The second enabled scanner swept nothing: no folder.
  CHECK_FALSE(fs::exists(dir.path() / "euroc" / "mav0" / "laser1"));
}

ImuSample Sample(TimeNs t) {
  ImuSample s;
  s.stamp_ns = t;
  s.angular_velocity_rad_s = Eigen::Vector3d(0.1, 0.2, 0.3);
  s.linear_acceleration_m_s2 = Eigen::Vector3d(0.5, -0.25, 9.81);
  return s;
}

TEST_CASE("the first IMU's accelerometer is TUM RGB-D's accelerometer.txt beside a TUM sequence",
          "[export]") {
  std::vector<sim::ImuOptions> imus(2);
  imus[0].id = "first";
  imus[1].id = "second";
  for (const bool has_tum : {true, false}) {
    INFO("front frames: " << has_tum);
    test::ScratchDir dir("export_accelerometer_test");
    ImuExport out(dir.path(), imus, true);
    out.Add(0, Sample(0));
    out.Add(1, Sample(0));
    out.Add(0, Sample(5'000'000));
    out.Finish(has_tum);
    const fs::path file = dir.path() / "tum_rgbd" / "accelerometer.txt";
    if (!has_tum) {
      CHECK_FALSE(fs::exists(file));
      CHECK_FALSE(fs::exists(dir.path() / "tum_rgbd"));
      continue;
    }
    const std::string text = ReadText(file);
    CHECK(text.rfind("# accelerometer data\n# corridorsim IMU 'first'", 0) == 0);
    const std::vector<std::vector<std::string>> rows = Rows(file, ' ');
    REQUIRE(rows.size() == 2);
    CHECK(rows[0] == std::vector<std::string>{"0.000000000", "0.5", "-0.25", "9.81"});
    CHECK(rows[1][0] == "0.005000000");
  }
  // Without a front camera: no file at all.
  test::ScratchDir dir("export_no_tum_test");
  ImuExport out(dir.path(), imus, false);
  out.Add(0, Sample(0));
  out.Finish(false);
  CHECK_FALSE(fs::exists(dir.path() / "tum_rgbd"));
}

}  // namespace
}  // namespace corridorsim::export_tests
