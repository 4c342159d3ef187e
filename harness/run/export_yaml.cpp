#include "harness/run/export_yaml.h"

#include <charconv>
#include <sstream>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "harness/run/frame_io.h"

namespace corridorsim {
namespace {

// ORB-SLAM's RGB-D close/far threshold in baselines (TUM1.yaml's 40: 3 m with the default
// 7.5 cm projector-camera baseline of the depth noise model).
constexpr double kOrbSlamThDepth = 40.0;

// The model's intrinsics (CameraModel::intrinsics()) and whether it is the fisheye.
struct Intrinsics : CameraIntrinsics {
  bool fisheye = false;
};

Intrinsics IntrinsicsOf(const CameraModel& model) {
  return Intrinsics{{model.intrinsics()}, model.kannala_brandt() != nullptr};
}

}  // namespace

std::string Matrix4Yaml(const std::string& name, const SE3& pose) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = pose.rotation();
  m.topRightCorner<3, 1>() = pose.translation();
  std::ostringstream y;
  y << name << ":\n"
    << "  cols: 4\n"
    << "  rows: 4\n"
    << "  data: [";
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      y << (r == 0 && c == 0 ? "" : c == 0 ? ",\n         " : ", ") << YamlReal(m(r, c));
    }
  }
  y << "]\n";
  return y.str();
}

std::string YamlReal(double value) {
  char buf[64];
  const auto result = std::to_chars(buf, buf + sizeof(buf), value);
  std::string text(buf, result.ptr);
  if (text.find_first_of(".ni") != std::string::npos) return text;  // has a point, nan, inf
  const std::size_t e = text.find('e');
  if (e == std::string::npos) return text + ".0";
  return text.insert(e, ".0");
}

std::string YamlRealList(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + YamlReal(values[i]);
  return text + "]";
}

// The ORB and viewer parameters are TUM1.yaml's.
std::string OrbSlamYaml(const render::CameraOptions& options) {
  const Intrinsics in = IntrinsicsOf(options.model);
  std::ostringstream y;
  y << "%YAML:1.0\n"
    << "# ORB-SLAM2 / ORB-SLAM3 settings for the corridorsim front camera (tum_rgbd/), in the\n"
    << "# form of ORB-SLAM2's Examples/RGB-D/TUM1.yaml; Camera.type, Camera.width and\n"
    << "# Camera.height are ORB-SLAM3's additions. No File.version: ORB-SLAM3 1.0 reads this\n"
    << "# as its old settings form. Pixel (0, 0) is the centre of the top-left pixel.\n\n";
  y << "# Camera calibration and distortion parameters (OpenCV)\n";
  if (in.fisheye) {
    y << "Camera.type: \"KannalaBrandt8\"\n";
  } else {
    y << "Camera.type: \"PinHole\"\n";
  }
  y << "Camera.fx: " << YamlReal(in.fx) << "\n"
    << "Camera.fy: " << YamlReal(in.fy) << "\n"
    << "Camera.cx: " << YamlReal(in.cx) << "\n"
    << "Camera.cy: " << YamlReal(in.cy) << "\n\n";
  const char* const names[] = {"k1", "k2", "p1", "p2", "k3"};
  const char* const fisheye_names[] = {"k1", "k2", "k3", "k4"};
  for (std::size_t i = 0; i < in.distortion.size(); ++i) {
    y << "Camera." << (in.fisheye ? fisheye_names[i] : names[i]) << ": "
      << YamlReal(in.distortion[i]) << "\n";
  }
  y << "\nCamera.width: " << in.width << "\n"
    << "Camera.height: " << in.height << "\n\n"
    << "# Camera frames per second\n"
    << "Camera.fps: " << YamlReal(options.rate_hz) << "\n\n"
    << "# Color order of the images (0: BGR, 1: RGB. It is ignored if images are grayscale)\n"
    << "Camera.RGB: 1\n\n";
  if (options.depth) {
    const double baseline_m = options.depth_noise.baseline_m;
    y << "# IR projector baseline (" << YamlReal(baseline_m)
      << " m, the depth noise model's) times fx\n"
      << "Camera.bf: " << YamlReal(baseline_m * in.fx) << "\n\n"
      << "# Close/Far threshold. Baseline times.\n"
      << "ThDepth: " << YamlReal(kOrbSlamThDepth) << "\n\n"
      << "# Depth map values per metre (16-bit PNG)\n"
      << "DepthMapFactor: " << YamlReal(kDepthScale) << "\n\n";
  }
  y << "# ORB extractor (TUM1.yaml's values)\n"
    << "ORBextractor.nFeatures: 1000\n"
    << "ORBextractor.scaleFactor: 1.2\n"
    << "ORBextractor.nLevels: 8\n"
    << "ORBextractor.iniThFAST: 20\n"
    << "ORBextractor.minThFAST: 7\n\n"
    << "# Viewer (TUM1.yaml's values)\n"
    << "Viewer.KeyFrameSize: 0.05\n"
    << "Viewer.KeyFrameLineWidth: 1.0\n"
    << "Viewer.GraphLineWidth: 0.9\n"
    << "Viewer.PointSize: 2.0\n"
    << "Viewer.CameraSize: 0.08\n"
    << "Viewer.CameraLineWidth: 3.0\n"
    << "Viewer.ViewpointX: 0.0\n"
    << "Viewer.ViewpointY: -0.7\n"
    << "Viewer.ViewpointZ: -1.8\n"
    << "Viewer.ViewpointF: 500.0\n";
  return y.str();
}

// EuRoC / TUM-VI camera sensor.yaml: T_BS = robot_from_camera (body = robot frame R).
std::string CameraSensorYaml(const render::CameraOptions& options, const std::string& comment,
                             const BodyStart& start) {
  const Intrinsics in = IntrinsicsOf(options.model);
  std::ostringstream y;
  y << "# General sensor definitions.\n"
    << "sensor_type: camera\n"
    << "comment: " << comment << "\n\n"
    << "# Sensor extrinsics wrt. the body-frame (the robot frame R: x forward, z up).\n"
    << Matrix4Yaml("T_BS", options.mount.RobotFromCamera()) << "\n"
    << "# Camera specific definitions.\n"
    << "rate_hz: " << YamlReal(options.rate_hz) << "\n"
    << "resolution: [" << in.width << ", " << in.height << "]\n"
    << "camera_model: pinhole\n"
    << "intrinsics: " << YamlRealList({in.fx, in.fy, in.cx, in.cy}) << " #fu, fv, cu, cv\n";
  if (in.fisheye) {
    y << "distortion_model: equidistant\n"
      << "distortion_coefficients: " << YamlRealList(in.distortion) << " #k1, k2, k3, k4\n";
  } else {
    // Kalibr's radial-tangential has four coefficients; k3 follows only when it is used.
    std::vector<double> d(in.distortion.begin(), in.distortion.begin() + 4);
    if (in.distortion[4] != 0.0) d.push_back(in.distortion[4]);
    y << "distortion_model: radial-tangential\n"
      << "distortion_coefficients: " << YamlRealList(d)
      << (d.size() == 4 ? " #k1, k2, p1, p2\n" : " #k1, k2, p1, p2, k3\n");
  }
  y << "\n# The body's start pose: world_from_body (the robot frame R in the world frame W, z up)\n"
    << "# at start_timestamp_ns, the first pose of the export's ground truth.\n"
    << Matrix4Yaml("T_WB_start", start.world_from_robot) << "start_timestamp_ns: " << start.stamp_ns
    << "\n";
  return y.str();
}

std::string ImuSensorYaml(const sim::ImuOptions& o) {
  const double on = o.noise ? 1.0 : 0.0;  // noise off: the samples are exact
  std::ostringstream y;
  y << "# General sensor definitions.\n"
    << "sensor_type: imu\n"
    << "comment: corridorsim IMU '" << o.id << "' (docs/sensors.md)\n\n"
    << "# Sensor extrinsics wrt. the body-frame (the robot frame R: x forward, z up).\n"
    << Matrix4Yaml("T_BS", o.mount.RobotFromBody()) << "\n"
    << "rate_hz: " << YamlReal(o.rate_hz) << "\n\n"
    << "# Kalibr's imu.yaml: continuous-time noise densities and bias random walks.\n"
    << "accelerometer_noise_density: " << YamlReal(on * o.accelerometer_noise_density)
    << "  # [ m / s^2 / sqrt(Hz) ]\n"
    << "accelerometer_random_walk: " << YamlReal(on * o.accelerometer_random_walk)
    << "  # [ m / s^3 / sqrt(Hz) ]\n"
    << "gyroscope_noise_density: " << YamlReal(on * o.gyroscope_noise_density)
    << "  # [ rad / s / sqrt(Hz) ]\n"
    << "gyroscope_random_walk: " << YamlReal(on * o.gyroscope_random_walk)
    << "  # [ rad / s^2 / sqrt(Hz) ]\n"
    << "rostopic: /" << o.id << "\n"
    << "update_rate: " << YamlReal(o.rate_hz) << "  # Hz\n";
  return y.str();
}

std::string LaserSensorYaml(const sim::LaserOptions& o, const LaserScan& sweep) {
  const std::size_t beams = sweep.ranges_m.size();
  const double last = beams ? static_cast<double>(beams - 1) : 0.0;
  std::ostringstream y;
  y << "# General sensor definitions.\n"
    << "sensor_type: laser\n"
    << "comment: corridorsim planar laser scanner '" << o.id << "' (docs/sensors.md)\n\n"
    << "# Sensor extrinsics wrt. the body-frame (the robot frame R: x forward, z up); the scan\n"
    << "# plane is the sensor's x-y plane, beam 0 at angle_min about its z axis.\n"
    << Matrix4Yaml("T_BS", o.mount.RobotFromBody()) << "\n"
    << "rate_hz: " << YamlReal(o.rate_hz) << "\n"
    << "beams: " << beams << "\n"
    << "angle_min: " << YamlReal(sweep.angle_min_rad) << "  # rad\n"
    << "angle_max: " << YamlReal(sweep.angle_min_rad + last * sweep.angle_increment_rad)
    << "  # rad\n"
    << "angle_increment: " << YamlReal(sweep.angle_increment_rad) << "  # rad\n"
    << "time_increment: " << YamlReal(ToSeconds(sweep.time_increment_ns)) << "  # s\n"
    << "scan_time: " << YamlReal(ToSeconds(sweep.scan_time_ns)) << "  # s\n"
    << "range_min: " << YamlReal(sweep.range_min_m) << "  # m\n"
    << "range_max: " << YamlReal(sweep.range_max_m) << "  # m\n"
    << "range_sigma: " << YamlReal(o.noise ? o.range_sigma_m : 0.0) << "  # m\n";
  return y.str();
}

}  // namespace corridorsim
