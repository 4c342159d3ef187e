#pragma once
// The ROS messages a recording holds (docs/recordings.md), as plain structs. Each one lists its
// fields once, in the order of its .msg definition, in a static `Fields()` (pointers to its
// members, which VisitFields walks); the visitors write ROS 2's CDR (CdrOut), read it back (CdrIn,
// for replay) and write ROS 1's serialization (harness/record/bag_writer.cpp). The definitions (ROS
// 2 Humble's, the text a recording embeds as its schemas) are in ros_schemas.cpp.
//
// corridorsim_msgs are corridorsim's own: what a run needs to be replayed byte for byte (the
// truth, exact wheel ticks, the grouping of camera frames) beside the standard messages that
// robotics tools read.

#include <array>
#include <concepts>
#include <cstdint>
#include <span>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "common/io/cdr.h"
#include "common/time.h"

namespace corridorsim::ros {

// builtin_interfaces/msg/Time and Duration: seconds and nanoseconds of a TimeNs.
struct Time {
  TimeNs ns = 0;
};
struct Duration {
  TimeNs ns = 0;
};

struct Header {
  static constexpr const char* kType = "std_msgs/msg/Header";
  Time stamp;
  std::string frame_id;
  static constexpr auto Fields() { return std::tuple{&Header::stamp, &Header::frame_id}; }
};

struct Vector3 {
  static constexpr const char* kType = "geometry_msgs/msg/Vector3";
  double x = 0, y = 0, z = 0;
  static constexpr auto Fields() { return std::tuple{&Vector3::x, &Vector3::y, &Vector3::z}; }
};
struct Point {
  static constexpr const char* kType = "geometry_msgs/msg/Point";
  double x = 0, y = 0, z = 0;
  static constexpr auto Fields() { return std::tuple{&Point::x, &Point::y, &Point::z}; }
};
struct Quaternion {
  static constexpr const char* kType = "geometry_msgs/msg/Quaternion";
  double x = 0, y = 0, z = 0, w = 1;
  static constexpr auto Fields() {
    return std::tuple{&Quaternion::x, &Quaternion::y, &Quaternion::z, &Quaternion::w};
  }
};
struct Pose {
  static constexpr const char* kType = "geometry_msgs/msg/Pose";
  Point position;
  Quaternion orientation;
  static constexpr auto Fields() { return std::tuple{&Pose::position, &Pose::orientation}; }
};
struct PoseWithCovariance {
  static constexpr const char* kType = "geometry_msgs/msg/PoseWithCovariance";
  Pose pose;
  std::array<double, 36> covariance{};  // x, y, z, rotation about x, y, z; row-major
  static constexpr auto Fields() {
    return std::tuple{&PoseWithCovariance::pose, &PoseWithCovariance::covariance};
  }
};
struct Twist {
  static constexpr const char* kType = "geometry_msgs/msg/Twist";
  Vector3 linear, angular;
  static constexpr auto Fields() { return std::tuple{&Twist::linear, &Twist::angular}; }
};
struct TwistWithCovariance {
  static constexpr const char* kType = "geometry_msgs/msg/TwistWithCovariance";
  Twist twist;
  std::array<double, 36> covariance{};
  static constexpr auto Fields() {
    return std::tuple{&TwistWithCovariance::twist, &TwistWithCovariance::covariance};
  }
};
struct Transform {
  static constexpr const char* kType = "geometry_msgs/msg/Transform";
  Vector3 translation;
  Quaternion rotation;
  static constexpr auto Fields() {
    return std::tuple{&Transform::translation, &Transform::rotation};
  }
};
struct TransformStamped {
  static constexpr const char* kType = "geometry_msgs/msg/TransformStamped";
  Header header;
  std::string child_frame_id;
  Transform transform;
  static constexpr auto Fields() {
    return std::tuple{&TransformStamped::header, &TransformStamped::child_frame_id,
                      &TransformStamped::transform};
  }
};
struct TFMessage {
  static constexpr const char* kType = "tf2_msgs/msg/TFMessage";
  std::vector<TransformStamped> transforms;
  static constexpr auto Fields() { return std::tuple{&TFMessage::transforms}; }
};
struct PoseStamped {
  static constexpr const char* kType = "geometry_msgs/msg/PoseStamped";
  Header header;
  Pose pose;
  static constexpr auto Fields() { return std::tuple{&PoseStamped::header, &PoseStamped::pose}; }
};
struct PoseWithCovarianceStamped {
  static constexpr const char* kType = "geometry_msgs/msg/PoseWithCovarianceStamped";
  Header header;
  PoseWithCovariance pose;
  static constexpr auto Fields() {
    return std::tuple{&PoseWithCovarianceStamped::header, &PoseWithCovarianceStamped::pose};
  }
};
struct Path {
  static constexpr const char* kType = "nav_msgs/msg/Path";
  Header header;
  std::vector<PoseStamped> poses;
  static constexpr auto Fields() { return std::tuple{&Path::header, &Path::poses}; }
};
struct Odometry {
  static constexpr const char* kType = "nav_msgs/msg/Odometry";
  Header header;
  std::string child_frame_id;
  PoseWithCovariance pose;    // in header.frame_id
  TwistWithCovariance twist;  // in child_frame_id
  static constexpr auto Fields() {
    return std::tuple{&Odometry::header, &Odometry::child_frame_id, &Odometry::pose,
                      &Odometry::twist};
  }
};

/// sensor_msgs/Image with its pixels owned (`Image`, what readers make) or another's
/// (`ImageView`: a frame's buffer as the recorder writes it, or a chunk's bytes as replay reads
/// them, without a copy). Same type, same bytes.
template <class Data>
struct BasicImage {
  static constexpr const char* kType = "sensor_msgs/msg/Image";
  Header header;
  std::uint32_t height = 0, width = 0;
  std::string encoding;  // "rgb8", "32FC1" (metres), "mono8", "16UC1" or "32SC1" (labels)
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;  // bytes per row
  Data data;
  static constexpr auto Fields() {
    return std::tuple{&BasicImage::header,   &BasicImage::height,       &BasicImage::width,
                      &BasicImage::encoding, &BasicImage::is_bigendian, &BasicImage::step,
                      &BasicImage::data};
  }
  /// The same image over other storage (a copy of the pixels when To owns them).
  template <class To>
  To As() const {
    return To{header,
              height,
              width,
              encoding,
              is_bigendian,
              step,
              decltype(To::data)(data.begin(), data.end())};
  }
};
using Image = BasicImage<std::vector<std::uint8_t>>;
using ImageView = BasicImage<std::span<const std::uint8_t>>;
struct RegionOfInterest {
  static constexpr const char* kType = "sensor_msgs/msg/RegionOfInterest";
  std::uint32_t x_offset = 0, y_offset = 0, height = 0, width = 0;
  bool do_rectify = false;
  static constexpr auto Fields() {
    return std::tuple{&RegionOfInterest::x_offset, &RegionOfInterest::y_offset,
                      &RegionOfInterest::height, &RegionOfInterest::width,
                      &RegionOfInterest::do_rectify};
  }
};
struct CameraInfo {
  static constexpr const char* kType = "sensor_msgs/msg/CameraInfo";
  Header header;
  std::uint32_t height = 0, width = 0;
  std::string distortion_model;  // "plumb_bob", "equidistant"
  std::vector<double> d;
  std::array<double, 9> k{};
  std::array<double, 9> r{};
  std::array<double, 12> p{};
  std::uint32_t binning_x = 0, binning_y = 0;
  RegionOfInterest roi;
  static constexpr auto Fields() {
    return std::tuple{&CameraInfo::header,    &CameraInfo::height,
                      &CameraInfo::width,     &CameraInfo::distortion_model,
                      &CameraInfo::d,         &CameraInfo::k,
                      &CameraInfo::r,         &CameraInfo::p,
                      &CameraInfo::binning_x, &CameraInfo::binning_y,
                      &CameraInfo::roi};
  }
};
struct Imu {
  static constexpr const char* kType = "sensor_msgs/msg/Imu";
  Header header;
  Quaternion orientation;
  std::array<double, 9> orientation_covariance{};  // [0] = -1: no orientation (REP 145)
  Vector3 angular_velocity;
  std::array<double, 9> angular_velocity_covariance{};
  Vector3 linear_acceleration;
  std::array<double, 9> linear_acceleration_covariance{};
  static constexpr auto Fields() {
    return std::tuple{&Imu::header,
                      &Imu::orientation,
                      &Imu::orientation_covariance,
                      &Imu::angular_velocity,
                      &Imu::angular_velocity_covariance,
                      &Imu::linear_acceleration,
                      &Imu::linear_acceleration_covariance};
  }
};
struct LaserScan {
  static constexpr const char* kType = "sensor_msgs/msg/LaserScan";
  Header header;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
  static constexpr auto Fields() {
    return std::tuple{&LaserScan::header,         &LaserScan::angle_min,
                      &LaserScan::angle_max,      &LaserScan::angle_increment,
                      &LaserScan::time_increment, &LaserScan::scan_time,
                      &LaserScan::range_min,      &LaserScan::range_max,
                      &LaserScan::ranges,         &LaserScan::intensities};
  }
};

struct ColorRGBA {
  static constexpr const char* kType = "std_msgs/msg/ColorRGBA";
  float r = 0, g = 0, b = 0, a = 1;
  static constexpr auto Fields() {
    return std::tuple{&ColorRGBA::r, &ColorRGBA::g, &ColorRGBA::b, &ColorRGBA::a};
  }
};
struct Marker {
  static constexpr const char* kType = "visualization_msgs/msg/Marker";
  enum : std::int32_t { kArrow = 0, kCube = 1, kSphere = 2, kCylinder = 3, kLineStrip = 4 };
  enum : std::int32_t { kLineList = 5, kCubeList = 6, kSphereList = 7, kText = 9 };
  Header header;
  std::string ns;
  std::int32_t id = 0, type = 0, action = 0;  // action 0: add
  Pose pose;
  Vector3 scale;
  ColorRGBA color;
  Duration lifetime;  // 0: forever
  bool frame_locked = false;
  std::vector<Point> points;
  std::vector<ColorRGBA> colors;
  std::string text, mesh_resource;
  bool mesh_use_embedded_materials = false;
  static constexpr auto Fields() {
    return std::tuple{&Marker::header,
                      &Marker::ns,
                      &Marker::id,
                      &Marker::type,
                      &Marker::action,
                      &Marker::pose,
                      &Marker::scale,
                      &Marker::color,
                      &Marker::lifetime,
                      &Marker::frame_locked,
                      &Marker::points,
                      &Marker::colors,
                      &Marker::text,
                      &Marker::mesh_resource,
                      &Marker::mesh_use_embedded_materials};
  }
};
struct MarkerArray {
  static constexpr const char* kType = "visualization_msgs/msg/MarkerArray";
  std::vector<Marker> markers;
  static constexpr auto Fields() { return std::tuple{&MarkerArray::markers}; }
};

// --- corridorsim_msgs: exact values for replay (docs/recordings.md) ---

/// The ground truth at one stamp (sim::TruthSample): the planar pose, the 3D state and the
/// cameras' poses, every number as the simulation holds it.
struct Truth {
  static constexpr const char* kType = "corridorsim_msgs/msg/Truth";
  Header header;                 // frame_id: map
  std::uint8_t kind = 0;         // 0 the start, 1 a truth-grid or odometry stamp, 2 the run's end
  double x = 0, y = 0, yaw = 0;  // world_from_robot_2d
  Pose pose;                     // world_from_robot (3D)
  Vector3 linear_velocity, angular_velocity;  // in the world frame
  double left_wheel_angle = 0, right_wheel_angle = 0;
  std::vector<Pose> camera_poses;  // world_from_camera of the rig's rendered cameras
  static constexpr auto Fields() {
    return std::tuple{&Truth::header,
                      &Truth::kind,
                      &Truth::x,
                      &Truth::y,
                      &Truth::yaw,
                      &Truth::pose,
                      &Truth::linear_velocity,
                      &Truth::angular_velocity,
                      &Truth::left_wheel_angle,
                      &Truth::right_wheel_angle,
                      &Truth::camera_poses};
  }
};
/// Wheel odometry as the encoders report it (WheelOdometry): P1 eq. 13's input, exactly.
struct WheelOdometry {
  static constexpr const char* kType = "corridorsim_msgs/msg/WheelOdometry";
  Header header;
  std::int64_t interval_ns = 0;
  double left_distance = 0, right_distance = 0;
  std::int64_t left_ticks = 0, right_ticks = 0;
  static constexpr auto Fields() {
    return std::tuple{&WheelOdometry::header,        &WheelOdometry::interval_ns,
                      &WheelOdometry::left_distance, &WheelOdometry::right_distance,
                      &WheelOdometry::left_ticks,    &WheelOdometry::right_ticks};
  }
};
/// One rendered frame's truth: its clock index and poses (the images are on the camera's
/// standard topics and corridorsim's label topics at the same stamp).
struct CameraFrame {
  static constexpr const char* kType = "corridorsim_msgs/msg/CameraFrame";
  Header header;  // frame_id: the camera's optical frame
  std::uint64_t frame_index = 0;
  Pose world_from_camera;
  Pose world_from_robot;
  static constexpr auto Fields() {
    return std::tuple{&CameraFrame::header, &CameraFrame::frame_index,
                      &CameraFrame::world_from_camera, &CameraFrame::world_from_robot};
  }
};
/// The cameras of one set (sensor_bus.h's CameraSet), after their frames: dropped[i] says that
/// cameras[i]'s frame was due and lost.
struct CameraSet {
  static constexpr const char* kType = "corridorsim_msgs/msg/CameraSet";
  Header header;
  std::vector<std::string> cameras;
  std::vector<bool> dropped;
  static constexpr auto Fields() {
    return std::tuple{&CameraSet::header, &CameraSet::cameras, &CameraSet::dropped};
  }
};
/// An IMU sample's truth (sim::ImuMessage): the noise-free sample, the biases, the pose.
struct ImuTruth {
  static constexpr const char* kType = "corridorsim_msgs/msg/ImuTruth";
  Header header;
  Vector3 exact_angular_velocity, exact_linear_acceleration;
  Vector3 gyroscope_bias, accelerometer_bias;
  Pose world_from_imu;
  Vector3 velocity_in_world;
  static constexpr auto Fields() {
    return std::tuple{&ImuTruth::header,
                      &ImuTruth::exact_angular_velocity,
                      &ImuTruth::exact_linear_acceleration,
                      &ImuTruth::gyroscope_bias,
                      &ImuTruth::accelerometer_bias,
                      &ImuTruth::world_from_imu,
                      &ImuTruth::velocity_in_world};
  }
};
/// A sweep's exact parameters (LaserScan carries them as float32) and its truth per beam.
struct ScanTruth {
  static constexpr const char* kType = "corridorsim_msgs/msg/ScanTruth";
  Header header;  // the first beam's stamp
  double angle_min = 0, angle_increment = 0;
  std::int64_t time_increment_ns = 0, scan_time_ns = 0, complete_ns = 0;
  double range_min = 0, range_max = 0;
  std::vector<double> true_ranges;
  std::vector<std::int32_t> instance_ids;
  std::vector<std::uint8_t> semantic_classes;
  std::vector<double> incidences;
  std::vector<Pose> world_from_laser;  // per beam
  static constexpr auto Fields() {
    return std::tuple{&ScanTruth::header,           &ScanTruth::angle_min,
                      &ScanTruth::angle_increment,  &ScanTruth::time_increment_ns,
                      &ScanTruth::scan_time_ns,     &ScanTruth::complete_ns,
                      &ScanTruth::range_min,        &ScanTruth::range_max,
                      &ScanTruth::true_ranges,      &ScanTruth::instance_ids,
                      &ScanTruth::semantic_classes, &ScanTruth::incidences,
                      &ScanTruth::world_from_laser};
  }
};
/// A simulation event (events.json's, docs/metrics.md).
struct Event {
  static constexpr const char* kType = "corridorsim_msgs/msg/Event";
  Header header;
  std::string kind;  // collision_begin, collision_end, slip, path_done, timeout, frame_dropped
  std::int32_t instance_id = 0;
  std::uint8_t semantic_class = 0;
  Point position;
  double depth = 0;
  bool left_wheel = false;
  double distance = 0;
  std::string camera_id;
  static constexpr auto Fields() {
    return std::tuple{&Event::header,         &Event::kind,     &Event::instance_id,
                      &Event::semantic_class, &Event::position, &Event::depth,
                      &Event::left_wheel,     &Event::distance, &Event::camera_id};
  }
};

template <class T>
concept Message = requires {
  T::kType;
};

/// Calls `visitor(message.field)` for each field of `message` in its definition's order (the
/// message's `Fields()`: pointers to its members). `message` may be const (writing) or not.
template <class V, class M>
void VisitFields(V& visitor, M& message) {
  std::apply([&](auto... field) { (visitor(message.*field), ...); },
             std::remove_const_t<M>::Fields());
}

/// ROS 2's schema text of `type` ("sensor_msgs/msg/Image"): its definition, then each message it
/// uses, after a line of 80 '=' and "MSG: pkg/Name" (the `ros2msg` schema encoding of MCAP).
/// Aborts for a type that is not above (a bug).
std::string Ros2Schema(const std::string& type);
/// The definition of one type alone (ros_schemas.cpp); every type above has one.
const std::string& Ros2Definition(const std::string& type);

// --- ROS 2 CDR ---

class CdrOut {
 public:
  CdrOut() = default;
  explicit CdrOut(std::vector<std::uint8_t>&& buffer) : writer_(std::move(buffer)) {}
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const T& value) { writer_.Primitive(value); }
  void operator()(const bool& value) { writer_.Bool(value); }
  void operator()(const std::string& value) { writer_.String(value); }
  void operator()(const Time& t) { Stamp(t.ns); }
  void operator()(const Duration& d) { Stamp(d.ns); }
  template <class T, std::size_t N>
  void operator()(const std::array<T, N>& values) {
    if constexpr (std::is_arithmetic_v<T>) {
      writer_.Elements(std::span<const T>(values));
    } else {
      for (const T& value : values) (*this)(value);
    }
  }
  template <class T>
  void operator()(const std::vector<T>& values) {
    writer_.SequenceLength(values.size());
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      writer_.Elements(std::span<const T>(values));
    } else {
      for (const auto& value : values) (*this)(static_cast<const T&>(value));
    }
  }
  void operator()(const std::span<const std::uint8_t>& bytes) {  // uint8[] of an ImageView
    writer_.SequenceLength(bytes.size());
    writer_.Elements(bytes);
  }
  template <Message T>
  void operator()(const T& message) {
    VisitFields(*this, message);
  }
  void operator()(const Header& header) { VisitFields(*this, header); }
  CdrWriter& writer() { return writer_; }

 private:
  void Stamp(TimeNs ns);
  CdrWriter writer_;
};

class CdrIn {
 public:
  CdrIn(std::span<const std::uint8_t> data, std::string what) : reader_(data, std::move(what)) {}
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(T& value) { value = reader_.Primitive<T>(); }
  void operator()(bool& value) { value = reader_.Bool(); }
  void operator()(std::string& value) { value = reader_.String(); }
  void operator()(Time& t) { t.ns = Stamp(); }
  void operator()(Duration& d) { d.ns = Stamp(); }
  template <class T, std::size_t N>
  void operator()(std::array<T, N>& values) {
    if constexpr (std::is_arithmetic_v<T>) {
      reader_.Elements(std::span<T>(values));
    } else {
      for (T& value : values) (*this)(value);
    }
  }
  void operator()(std::vector<bool>& values) {
    values.resize(reader_.SequenceLength(1));
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = reader_.Bool();
  }
  template <class T>
  void operator()(std::vector<T>& values) {
    if constexpr (std::is_arithmetic_v<T>) {
      values.resize(reader_.SequenceLength(sizeof(T)));
      reader_.Elements(std::span<T>(values));
    } else {
      values.resize(reader_.SequenceLength(1));
      for (T& value : values) (*this)(value);
    }
  }
  void operator()(std::span<const std::uint8_t>& bytes) {  // an ImageView's pixels, in place
    bytes = reader_.Bytes(reader_.SequenceLength(1));
  }
  template <Message T>
  void operator()(T& message) {
    VisitFields(*this, message);
  }
  void operator()(Header& header) { VisitFields(*this, header); }
  std::size_t remaining() const { return reader_.remaining(); }

 private:
  TimeNs Stamp();
  CdrReader reader_;
};

/// A message as CDR bytes (with the encapsulation header).
template <Message T>
std::vector<std::uint8_t> ToCdr(const T& message) {
  CdrOut out;
  out(message);
  return out.writer().Take();
}

/// The same into `buffer`, whose memory is reused.
template <Message T>
void ToCdr(const T& message, std::vector<std::uint8_t>* buffer) {
  CdrOut out(std::move(*buffer));
  out(message);
  *buffer = out.writer().Take();
}

/// A message from CDR bytes; throws CdrError (naming `what`) when they are not one.
template <Message T>
T FromCdr(std::span<const std::uint8_t> data, const std::string& what) {
  CdrIn in(data, what);
  T message;
  in(message);
  return message;
}

}  // namespace corridorsim::ros
