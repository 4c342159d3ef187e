// A test plugin: the pipeline type `test_echo` (dead reckoning through the SDK's odometry model,
// scaled by an option), and with `-DTEST_PLUGIN_VARIANT=...` the broken variants that the loader
// must refuse (tests/harness/scenario/plugins_test.cpp, tests/CMakeLists.txt) and the two that end
// the process with exit code 0 (7, 8: tests/harness/cli_supervision_test.py).

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/options_table.h"
#include "common/wheel_odometry_model.h"
#include "slam/pipeline.h"
#include "slam/plugin.h"

namespace test_echo {

struct EchoOptions {
  double scale = 1.0;  // multiplies the wheel distances
  // > 0: OnOdometry throws at the first message after this time (a plugin's bug, for the
  // runner's failure semantics: tests/harness/cli_plugin_test.py).
  double throw_after_s = 0.0;
  // Reads the upward camera; then OnCamera (not OnOdometry) is the call that throws.
  bool read_upward = false;
  // With read_upward: every frame's detections hold a lamp without a radius (malformed).
  bool bad_detection = false;
  // The exception's message ends in a byte that is not UTF-8 and markup (Latin-1 "caf\xE9",
  // "<!--<script>"): text from outside (tests/harness/cli_outside_text_test.py).
  bool latin1_message = false;
  // > 0: OnImu (OnScan) throws at the first IMU sample (laser sweep) after this time: the SDK
  // hands a plugin the scenario's IMUs and scanners (docs/sensors.md).
  double imu_throw_after_s = 0.0;
  double scan_throw_after_s = 0.0;
  // Measurement types of its own (slam::MeasurementType): declares `wheel_yaw` (1 dof) and
  // reports one innovation of it per odometry message, of `reported_dof` degrees of freedom;
  // with `undeclared_after_s` > 0, an innovation of `wall_line` (never declared) at the first
  // odometry message after that time.
  bool own_measurement = false;
  int reported_dof = 1;
  double undeclared_after_s = 0.0;
  // Finish() leaves a detection of the undeclared type wall_line (the runner checks those too).
  bool finish_detection = false;
  std::optional<corridorsim::OptionsProblem> Check() const;
};

const corridorsim::OptionTable<EchoOptions>& EchoOptionsTable() {
  return corridorsim::StaticOptionTable<EchoOptions>([](corridorsim::OptionTable<EchoOptions>& t) {
    t.Add("scale", &EchoOptions::scale, "", "multiplies the wheel distances").Range(0.5, 2.0);
    t.Add("throw_after_s", &EchoOptions::throw_after_s, "s",
          "> 0: OnOdometry throws at the first message after this time")
        .Range(0, 1e6);
    t.Add("read_upward", &EchoOptions::read_upward, "",
          "read the upward camera; throw_after_s then applies to OnCamera");
    t.Add("bad_detection", &EchoOptions::bad_detection, "",
          "report a malformed lamp detection (no radius) in every frame");
    t.Add("latin1_message", &EchoOptions::latin1_message, "",
          "the exception's message ends in a Latin-1 byte and markup");
    t.Add("imu_throw_after_s", &EchoOptions::imu_throw_after_s, "s",
          "> 0: OnImu throws at the first IMU sample after this time")
        .Range(0, 1e6);
    t.Add("scan_throw_after_s", &EchoOptions::scan_throw_after_s, "s",
          "> 0: OnScan throws at the first laser sweep after this time")
        .Range(0, 1e6);
    t.Add("own_measurement", &EchoOptions::own_measurement, "",
          "declare the measurement type wheel_yaw and report an innovation of it per odometry");
    t.Add("reported_dof", &EchoOptions::reported_dof, "",
          "the degrees of freedom of the wheel_yaw innovations it reports (declared: 1)")
        .Range(1, 3);
    t.Add("undeclared_after_s", &EchoOptions::undeclared_after_s, "s",
          "> 0: report an innovation of the undeclared type wall_line after this time")
        .Range(0, 1e6);
    t.Add("finish_detection", &EchoOptions::finish_detection, "",
          "Finish() leaves a detection of the undeclared type wall_line");
  });
}

std::optional<corridorsim::OptionsProblem> EchoOptions::Check() const {
  return corridorsim::CheckOptionBounds(EchoOptionsTable(), *this);
}

class EchoPipeline : public corridorsim::slam::Pipeline {
 public:
  EchoPipeline(const EchoOptions& options, const corridorsim::slam::Calibration& calibration,
               std::uint64_t /*seed*/)
      : options_(options), wheelbase_m_(calibration.wheelbase_m) {}
  void Initialize(corridorsim::TimeNs stamp_ns, const corridorsim::SE2& pose) override {
    estimate_.stamp_ns = stamp_ns;
    estimate_.world_from_robot = pose;
  }
  std::vector<std::string> cameras_used() const override {
    return options_.read_upward ? std::vector<std::string>{"upward"} : std::vector<std::string>{};
  }
  void OnCamera(const corridorsim::slam::CameraInput& input) override {
    if (options_.throw_after_s > 0 &&
        static_cast<double>(input.image.stamp_ns) * 1e-9 > options_.throw_after_s) {
      throw std::runtime_error("test_echo: the camera went dark");
    }
    if (options_.bad_detection) {
      corridorsim::slam::Detection d;
      d.stamp_ns = input.image.stamp_ns;
      d.camera_id = input.image.camera_id;
      d.type = corridorsim::slam::LandmarkType::kLamp;
      d.pixel = Eigen::Vector2d(10, 10);
      d.radius_px = 0.0;  // a lamp needs a positive radius
      detections_.push_back(d);
    }
  }
  void OnImu(const corridorsim::ImuSample& sample) override {
    if (options_.imu_throw_after_s > 0 &&
        static_cast<double>(sample.stamp_ns) * 1e-9 > options_.imu_throw_after_s) {
      throw std::runtime_error("test_echo: IMU " + sample.sensor_id + " read " +
                               std::to_string(sample.linear_acceleration_m_s2.z()));
    }
  }
  void OnScan(const corridorsim::LaserScan& scan) override {
    if (options_.scan_throw_after_s > 0 &&
        static_cast<double>(scan.stamp_ns) * 1e-9 > options_.scan_throw_after_s) {
      throw std::runtime_error("test_echo: scanner " + scan.sensor_id + " swept " +
                               std::to_string(scan.ranges_m.size()) + " beams");
    }
  }
  std::vector<corridorsim::slam::Detection> TakeDetections() override {
    return std::move(detections_);
  }
  std::vector<corridorsim::slam::MeasurementType> measurement_types() const override {
    if (!options_.own_measurement) return {};
    return {{"wheel_yaw", 1}};
  }
  void Finish() override {
    if (!options_.finish_detection) return;
    corridorsim::slam::Detection d;
    d.stamp_ns = estimate_.stamp_ns;
    d.camera_id = "front";
    d.measurement = "wall_line";
    detections_.push_back(d);
  }
  std::vector<corridorsim::slam::Innovation> TakeInnovations() override {
    return std::move(innovations_);
  }
  void OnOdometry(const corridorsim::WheelOdometry& odometry) override {
    if (!options_.read_upward && options_.throw_after_s > 0 &&
        static_cast<double>(odometry.stamp_ns) * 1e-9 > options_.throw_after_s) {
#if defined(TEST_PLUGIN_VARIANT) && TEST_PLUGIN_VARIANT == 8
      std::_Exit(0);  // ends the whole process, reporting success (harness/cli/supervisor.h)
#endif
      throw std::runtime_error(std::string("test_echo: the wheels went out of sync") +
                               (options_.latin1_message ? " (caf\xE9 <!--<script>)" : ""));
    }
    estimate_.world_from_robot = corridorsim::ApplyWheelOdometry(
        estimate_.world_from_robot, options_.scale * odometry.left_distance_m,
        options_.scale * odometry.right_distance_m, wheelbase_m_);
    estimate_.stamp_ns = odometry.stamp_ns;
    estimate_.covariance = 1e-4 * Eigen::Matrix3d::Identity();
    if (options_.own_measurement) {
      // NIS 0, 0.5, 1, 0, ...
      corridorsim::slam::Innovation n;
      n.stamp_ns = odometry.stamp_ns;
      n.measurement = "wheel_yaw";
      n.dof = options_.reported_dof;
      n.nis = 0.5 * static_cast<double>(odometry_count_++ % 3);
      innovations_.push_back(n);
    }
    if (options_.undeclared_after_s > 0 &&
        static_cast<double>(odometry.stamp_ns) * 1e-9 > options_.undeclared_after_s) {
      corridorsim::slam::Innovation n;
      n.stamp_ns = odometry.stamp_ns;
      n.measurement = "wall_line";
      n.dof = 2;
      n.nis = 1.0;
      innovations_.push_back(n);
    }
  }
  corridorsim::slam::PoseEstimate Estimate() const override { return estimate_; }

 private:
  EchoOptions options_;
  std::vector<corridorsim::slam::Detection> detections_;
  std::vector<corridorsim::slam::Innovation> innovations_;
  long odometry_count_ = 0;
  double wheelbase_m_;
  corridorsim::slam::PoseEstimate estimate_;
};

}  // namespace test_echo

#if !defined(TEST_PLUGIN_VARIANT)
CORRIDORSIM_PLUGIN("test_echo_plugin", "2.5.0", registrar) {
  registrar.Add<test_echo::EchoOptions, test_echo::EchoPipeline>("test_echo",
                                                                 &test_echo::EchoOptionsTable);
}
#elif TEST_PLUGIN_VARIANT == 1  // no entry point at all
CORRIDORSIM_PLUGIN_EXPORT int not_a_corridorsim_plugin() { return 1; }
#elif TEST_PLUGIN_VARIANT == 2  // built against another SDK ABI version
CORRIDORSIM_PLUGIN_EXPORT const CorridorsimPluginInfo* corridorsim_plugin_info() {
  static CorridorsimPluginInfo info = corridorsim::slam::ThisBuildPluginInfo("old", "0.0.1");
  info.sdk_abi_version = CORRIDORSIM_SDK_ABI_VERSION + 98;
  return &info;
}
CORRIDORSIM_PLUGIN_EXPORT void corridorsim_plugin_register(corridorsim::slam::PluginRegistrar*) {
  std::abort();  // never called: the ABI check comes first
}
#elif TEST_PLUGIN_VARIANT == 3  // a type name corridorsim ships
CORRIDORSIM_PLUGIN("taken", "1", registrar) {
  registrar.Add<test_echo::EchoOptions, test_echo::EchoPipeline>("odometry",
                                                                 &test_echo::EchoOptionsTable);
}
#elif TEST_PLUGIN_VARIANT == 4  // not a pipeline name
CORRIDORSIM_PLUGIN("bad_name", "1", registrar) {
  registrar.Add<test_echo::EchoOptions, test_echo::EchoPipeline>("Echo-Pipeline",
                                                                 &test_echo::EchoOptionsTable);
}
#elif TEST_PLUGIN_VARIANT == 5  // throws while registering
CORRIDORSIM_PLUGIN("throws", "1", registrar) {
  (void)registrar;
  throw std::runtime_error("cannot find my configuration");
}
#elif TEST_PLUGIN_VARIANT == 6  // another std::string ABI
CORRIDORSIM_PLUGIN_EXPORT const CorridorsimPluginInfo* corridorsim_plugin_info() {
  static CorridorsimPluginInfo info = corridorsim::slam::ThisBuildPluginInfo("abi", "1");
  info.cxx11_string_abi = 1 - info.cxx11_string_abi;
  return &info;
}
CORRIDORSIM_PLUGIN_EXPORT void corridorsim_plugin_register(corridorsim::slam::PluginRegistrar*) {
  std::abort();
}
#elif TEST_PLUGIN_VARIANT == 7  // a static initializer calls exit(0) as the library loads
namespace {
[[maybe_unused]] const int kExitsAsItLoads = (std::exit(0), 0);
}  // namespace
CORRIDORSIM_PLUGIN("exits_as_it_loads", "1", registrar) {
  registrar.Add<test_echo::EchoOptions, test_echo::EchoPipeline>("test_echo",
                                                                 &test_echo::EchoOptionsTable);
}
#elif TEST_PLUGIN_VARIANT == 8  // throw_after_s ends the process with _Exit(0) instead
CORRIDORSIM_PLUGIN("exits_mid_run", "1", registrar) {
  registrar.Add<test_echo::EchoOptions, test_echo::EchoPipeline>("test_echo",
                                                                 &test_echo::EchoOptionsTable);
}
#endif
