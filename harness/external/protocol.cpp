#include "harness/external/protocol.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "common/io/camera_json.h"
#include "common/io/json_input.h"
#include "common/io/stable_json.h"
#include "common/io/yaml_reader.h"
#include "harness/external/reply_values.h"

namespace corridorsim::external {
namespace {

nlohmann::ordered_json MatrixJson(const Eigen::Matrix3d& m) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.push_back(m(r, c));
  }
  return out;
}

// A mount as the start message carries it: a translation in m and a rotation matrix, row-major.
nlohmann::ordered_json MountJson(const SE3& mount) {
  const Eigen::Vector3d t = mount.translation();
  return {{"translation", {t.x(), t.y(), t.z()}}, {"rotation", MatrixJson(mount.rotation())}};
}

// The head of a version-2 sweep or IMU sample: its type (none for a sample in an imu message),
// stamp and sensor id.
nlohmann::ordered_json SensorMessageHead(const char* type, TimeNs stamp_ns,
                                         const std::string& sensor) {
  nlohmann::ordered_json head = nlohmann::ordered_json::object();
  if (type) head["type"] = type;
  head["stamp_ns"] = stamp_ns;
  head["sensor"] = sensor;
  return head;
}

}  // namespace

std::string EncodeHeader(std::size_t json_bytes, std::size_t blob_bytes) {
  std::string header(kHeaderBytes, '\0');
  std::memcpy(header.data(), kMagic, 4);
  const auto put = [&header](std::size_t at, std::size_t v) {
    for (int i = 0; i < 4; ++i) header[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
  };
  put(4, json_bytes);
  put(8, blob_bytes);
  return header;
}

Header DecodeHeader(const char (&bytes)[kHeaderBytes]) {
  if (std::memcmp(bytes, kMagic, 4) != 0) {
    throw ProtocolError("malformed message: it does not start with \"CSIM\" (got " +
                        InputExcerpt(std::string(bytes, 4), 20) + ")");
  }
  const auto get = [&bytes](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    }
    return v;
  };
  Header h{get(4), get(8)};
  if (h.json_bytes == 0 || h.json_bytes > kMaxJsonBytes) {
    throw ProtocolError("oversized message: its JSON length " + std::to_string(h.json_bytes) +
                        " is not in [1, " + std::to_string(kMaxJsonBytes) + "]");
  }
  if (h.blob_bytes > kMaxBlobBytes) {
    throw ProtocolError("oversized message: its blob length " + std::to_string(h.blob_bytes) +
                        " is over " + std::to_string(kMaxBlobBytes));
  }
  return h;
}

nlohmann::json ParseMessage(std::string_view json) {
  // Nesting and the count of values are bounded before the (recursive) parser sees the text,
  // as for every JSON a user hands in (common/io/json_input.h).
  try {
    CheckJsonInputBounds(json, "message", kMaxJsonValues);
  } catch (const InputError& e) {
    throw ProtocolError(std::string("malformed message: ") + e.what());
  }
  nlohmann::json message;
  try {
    message = nlohmann::json::parse(json.begin(), json.end());
  } catch (const nlohmann::json::exception& e) {
    std::string why = e.what();
    if (why.find("number overflow") != std::string::npos) {
      why += " (a non-finite number)";
    } else if (json.find("NaN") != std::string_view::npos ||
               json.find("Infinity") != std::string_view::npos) {
      why += " (NaN and Infinity are not JSON: a non-finite number?)";
    }
    throw ProtocolError("malformed message: " + InputExcerpt(why, 300));
  }
  if (!message.is_object()) throw ProtocolError("malformed message: not a JSON object");
  const nlohmann::json* type = reply_values::Find(message, "type");
  if (!type || !type->is_string()) {
    throw ProtocolError("malformed message: no \"type\" string");
  }
  return message;
}

std::string MessageType(const nlohmann::json& message) {
  return message.at("type").get<std::string>();
}

std::string MessageType(const nlohmann::ordered_json& message) {
  return message.at("type").get<std::string>();
}

nlohmann::ordered_json CalibrationJson(const slam::Calibration& calibration) {
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (const slam::CameraCalibration& c : calibration.cameras) {
    nlohmann::ordered_json camera;
    camera["id"] = c.id;
    camera["model"] = CameraModelToJson(c.model);
    camera["robot_from_camera"] = MountJson(c.robot_from_camera);
    if (c.depth) {
      camera["depth"] = {
          {"min_m", c.depth->min_m}, {"max_m", c.depth->max_m}, {"encoding", "depth_f32"}};
    } else {
      camera["depth"] = nullptr;
    }
    cameras.push_back(std::move(camera));
  }
  // Version 2 (a version-1 client ignores these keys): the IMUs and scanners, as
  // slam::Calibration::imus and lasers hold them: id, mount and rate, then each kind's own.
  const auto sensor = [](const std::string& id, const char* mount_key, const SE3& mount,
                         double rate_hz, nlohmann::ordered_json own) {
    nlohmann::ordered_json out = {{"id", id}, {mount_key, MountJson(mount)}, {"rate_hz", rate_hz}};
    for (auto& [key, value] : own.items()) out[key] = std::move(value);
    return out;
  };
  nlohmann::ordered_json imus = nlohmann::ordered_json::array();
  for (const slam::ImuCalibration& c : calibration.imus) {
    imus.push_back(sensor(c.id, "robot_from_imu", c.robot_from_imu, c.rate_hz,
                          {{"gyroscope_noise_density", c.gyroscope_noise_density},
                           {"gyroscope_random_walk", c.gyroscope_random_walk},
                           {"accelerometer_noise_density", c.accelerometer_noise_density},
                           {"accelerometer_random_walk", c.accelerometer_random_walk}}));
  }
  nlohmann::ordered_json lasers = nlohmann::ordered_json::array();
  for (const slam::LaserCalibration& c : calibration.lasers) {
    lasers.push_back(sensor(c.id, "robot_from_laser", c.robot_from_laser, c.rate_hz,
                            {{"beams", c.beams}, {"range_sigma_m", c.range_sigma_m}}));
  }
  return {{"wheelbase_m", calibration.wheelbase_m},
          {"wheel_diameter_m", calibration.wheel_diameter_m},
          {"ticks_per_revolution", calibration.ticks_per_revolution},
          {"cameras", std::move(cameras)},
          {"imus", std::move(imus)},
          {"lasers", std::move(lasers)}};
}

OfferedSensors Offered(const slam::Calibration& calibration) {
  OfferedSensors offered;
  for (const slam::ImuCalibration& c : calibration.imus) offered.imus.push_back(c.id);
  for (const slam::LaserCalibration& c : calibration.lasers) offered.lasers.push_back(c.id);
  return offered;
}

nlohmann::ordered_json StartMessage(const std::string& pipeline,
                                    const slam::Calibration& calibration,
                                    const std::vector<std::string>& cameras, TimeNs stamp_ns,
                                    const SE2& world_from_robot,
                                    const nlohmann::ordered_json& options, std::uint64_t seed,
                                    std::size_t shared_memory_bytes) {
  return {{"type", "start"},
          {"protocol", kProtocolVersion},
          {"protocol_max", kProtocolMaxVersion},
          {"pipeline", pipeline},
          {"seed", seed},
          {"stamp_ns", stamp_ns},
          {"pose", {world_from_robot.x(), world_from_robot.y(), world_from_robot.yaw()}},
          {"calibration", CalibrationJson(calibration)},
          {"cameras", cameras},
          {"options", options},
          {"shared_memory_bytes", shared_memory_bytes}};
}

nlohmann::ordered_json OdometryMessage(const WheelOdometry& o) {
  return {{"type", "odometry"},
          {"stamp_ns", o.stamp_ns},
          {"interval_ns", o.interval_ns},
          {"left_m", o.left_distance_m},
          {"right_m", o.right_distance_m},
          {"left_ticks", o.left_ticks},
          {"right_ticks", o.right_ticks}};
}

nlohmann::ordered_json CamerasMessage(TimeNs stamp_ns, const std::vector<CameraSlice>& cameras,
                                      const std::string& transport) {
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  const auto image = [](const ImageSlice& s) {
    return nlohmann::ordered_json{{"encoding", s.encoding},
                                  {"width", s.width},
                                  {"height", s.height},
                                  {"offset", s.offset},
                                  {"bytes", s.bytes}};
  };
  for (const CameraSlice& c : cameras) {
    nlohmann::ordered_json f = {{"camera", c.camera}, {"dropped", c.dropped}};
    if (!c.dropped) {
      f["stamp_ns"] = c.stamp_ns;
      f["rgb"] = c.rgb ? image(*c.rgb) : nlohmann::ordered_json(nullptr);
      f["depth"] = c.depth ? image(*c.depth) : nlohmann::ordered_json(nullptr);
    }
    frames.push_back(std::move(f));
  }
  return {{"type", "cameras"},
          {"stamp_ns", stamp_ns},
          {"transport", transport},
          {"frames", std::move(frames)}};
}

nlohmann::ordered_json FinishMessage(TimeNs stamp_ns) {
  return {{"type", "finish"}, {"stamp_ns", stamp_ns}};
}

nlohmann::ordered_json ImuMessage(const std::vector<ImuSample>& samples) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const ImuSample& sample : samples) {
    const Eigen::Vector3d& w = sample.angular_velocity_rad_s;
    const Eigen::Vector3d& a = sample.linear_acceleration_m_s2;
    nlohmann::ordered_json one = SensorMessageHead(nullptr, sample.stamp_ns, sample.sensor_id);
    one["angular_velocity_rad_s"] = {w.x(), w.y(), w.z()};
    one["linear_acceleration_m_s2"] = {a.x(), a.y(), a.z()};
    list.push_back(std::move(one));
  }
  return {{"type", "imu"},
          {"stamp_ns", samples.empty() ? TimeNs{0} : samples.back().stamp_ns},
          {"samples", std::move(list)}};
}

nlohmann::ordered_json ScanMessage(const LaserScan& scan, std::size_t ranges_offset) {
  nlohmann::ordered_json message = SensorMessageHead("scan", scan.stamp_ns, scan.sensor_id);
  // sensor_msgs/LaserScan's fields in its order: the beams' directions, their times (in ns like
  // every stamp), the valid ranges.
  message["angle_min_rad"] = scan.angle_min_rad;
  message["angle_increment_rad"] = scan.angle_increment_rad;
  for (const auto& [key, ns] :
       {std::pair<const char*, TimeNs>{"time_increment_ns", scan.time_increment_ns},
        {"scan_time_ns", scan.scan_time_ns}}) {
    message[key] = ns;
  }
  message["range_min_m"] = scan.range_min_m;
  message["range_max_m"] = scan.range_max_m;
  message["ranges"] = {{"encoding", "float32"},
                       {"count", scan.ranges_m.size()},
                       {"offset", ranges_offset},
                       {"bytes", scan.ranges_m.size() * sizeof(float)}};
  return message;
}

std::string ScanBlob(const LaserScan& scan) {
  // float32 little-endian, each beam's IEEE bits as they are (+-inf, NaN included).
  static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559);
  std::string blob(scan.ranges_m.size() * 4, '\0');
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &scan.ranges_m[i], 4);
    for (int b = 0; b < 4; ++b) blob[4 * i + b] = static_cast<char>((bits >> (8 * b)) & 0xff);
  }
  return blob;
}

}  // namespace corridorsim::external
