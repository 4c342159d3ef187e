#pragma once
// The ROS messages a recording holds (docs/recordings.md), as plain structs. Each one lists its
// fields once, in the order of its .msg definition, in a static `Fields(visitor, message)`; the
// visitors write ROS 2's CDR (CdrOut), read it back (CdrIn, for replay) and write ROS 1's
// serialization (harness/record/bag_writer.cpp). The definitions (ROS 2 Humble's, the text a
// recording embeds as its schemas) are in ros_schemas.cpp.
//
// corridorsim_msgs are corridorsim's own: what a run needs to be replayed byte for byte (the
// truth, exact wheel ticks, the grouping of camera frames) beside the standard messages that
// robotics tools read.

#include <array>
#include <concepts>
#include <cstdint>
#include <span>
#include <string>
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.stamp);
    v(m.frame_id);
  }
};

struct Vector3 {
  static constexpr const char* kType = "geometry_msgs/msg/Vector3";
  double x = 0, y = 0, z = 0;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.x);
    v(m.y);
    v(m.z);
  }
};
struct Point {
  static constexpr const char* kType = "geometry_msgs/msg/Point";
  double x = 0, y = 0, z = 0;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.x);
    v(m.y);
    v(m.z);
  }
};
struct Quaternion {
  static constexpr const char* kType = "geometry_msgs/msg/Quaternion";
  double x = 0, y = 0, z = 0, w = 1;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.x);
    v(m.y);
    v(m.z);
    v(m.w);
  }
};
struct Pose {
  static constexpr const char* kType = "geometry_msgs/msg/Pose";
  Point position;
  Quaternion orientation;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.position);
    v(m.orientation);
  }
};
struct PoseWithCovariance {
  static constexpr const char* kType = "geometry_msgs/msg/PoseWithCovariance";
  Pose pose;
  std::array<double, 36> covariance{};  // x, y, z, rotation about x, y, z; row-major
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.pose);
    v(m.covariance);
  }
};
struct Twist {
  static constexpr const char* kType = "geometry_msgs/msg/Twist";
  Vector3 linear, angular;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.linear);
    v(m.angular);
  }
};
struct TwistWithCovariance {
  static constexpr const char* kType = "geometry_msgs/msg/TwistWithCovariance";
  Twist twist;
  std::array<double, 36> covariance{};
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.twist);
    v(m.covariance);
  }
};
struct Transform {
  static constexpr const char* kType = "geometry_msgs/msg/Transform";
  Vector3 translation;
  Quaternion rotation;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.translation);
    v(m.rotation);
  }
};
struct TransformStamped {
  static constexpr const char* kType = "geometry_msgs/msg/TransformStamped";
  Header header;
  std::string child_frame_id;
  Transform transform;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.child_frame_id);
    v(m.transform);
  }
};
struct TFMessage {
  static constexpr const char* kType = "tf2_msgs/msg/TFMessage";
  std::vector<TransformStamped> transforms;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.transforms);
  }
};
struct PoseStamped {
  static constexpr const char* kType = "geometry_msgs/msg/PoseStamped";
  Header header;
  Pose pose;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.pose);
  }
};
struct PoseWithCovarianceStamped {
  static constexpr const char* kType = "geometry_msgs/msg/PoseWithCovarianceStamped";
  Header header;
  PoseWithCovariance pose;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.pose);
  }
};
struct Path {
  static constexpr const char* kType = "nav_msgs/msg/Path";
  Header header;
  std::vector<PoseStamped> poses;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.poses);
  }
};
struct Odometry {
  static constexpr const char* kType = "nav_msgs/msg/Odometry";
  Header header;
  std::string child_frame_id;
  PoseWithCovariance pose;    // in header.frame_id
  TwistWithCovariance twist;  // in child_frame_id
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.child_frame_id);
    v(m.pose);
    v(m.twist);
  }
};

struct Image {
  static constexpr const char* kType = "sensor_msgs/msg/Image";
  Header header;
  std::uint32_t height = 0, width = 0;
  std::string encoding;  // "rgb8", "32FC1" (metres), "mono8", "32SC1"
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;  // bytes per row
  std::vector<std::uint8_t> data;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.height);
    v(m.width);
    v(m.encoding);
    v(m.is_bigendian);
    v(m.step);
    v(m.data);
  }
};
struct RegionOfInterest {
  static constexpr const char* kType = "sensor_msgs/msg/RegionOfInterest";
  std::uint32_t x_offset = 0, y_offset = 0, height = 0, width = 0;
  bool do_rectify = false;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.x_offset);
    v(m.y_offset);
    v(m.height);
    v(m.width);
    v(m.do_rectify);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.height);
    v(m.width);
    v(m.distortion_model);
    v(m.d);
    v(m.k);
    v(m.r);
    v(m.p);
    v(m.binning_x);
    v(m.binning_y);
    v(m.roi);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.orientation);
    v(m.orientation_covariance);
    v(m.angular_velocity);
    v(m.angular_velocity_covariance);
    v(m.linear_acceleration);
    v(m.linear_acceleration_covariance);
  }
};
struct LaserScan {
  static constexpr const char* kType = "sensor_msgs/msg/LaserScan";
  Header header;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.angle_min);
    v(m.angle_max);
    v(m.angle_increment);
    v(m.time_increment);
    v(m.scan_time);
    v(m.range_min);
    v(m.range_max);
    v(m.ranges);
    v(m.intensities);
  }
};

struct ColorRGBA {
  static constexpr const char* kType = "std_msgs/msg/ColorRGBA";
  float r = 0, g = 0, b = 0, a = 1;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.r);
    v(m.g);
    v(m.b);
    v(m.a);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.ns);
    v(m.id);
    v(m.type);
    v(m.action);
    v(m.pose);
    v(m.scale);
    v(m.color);
    v(m.lifetime);
    v(m.frame_locked);
    v(m.points);
    v(m.colors);
    v(m.text);
    v(m.mesh_resource);
    v(m.mesh_use_embedded_materials);
  }
};
struct MarkerArray {
  static constexpr const char* kType = "visualization_msgs/msg/MarkerArray";
  std::vector<Marker> markers;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.markers);
  }
};

// --- corridorsim_msgs: exact values for replay (docs/recordings.md) ---

/// The ground truth at one stamp (sim::TruthSample): the planar pose, the 3D state and the
/// cameras' poses, every number as the simulation holds it.
struct Truth {
  static constexpr const char* kType = "corridorsim_msgs/msg/Truth";
  Header header;     // frame_id: map
  std::uint8_t kind = 0;  // 0 the start, 1 a truth-grid or odometry stamp, 2 the run's end
  double x = 0, y = 0, yaw = 0;  // world_from_robot_2d
  Pose pose;                     // world_from_robot (3D)
  Vector3 linear_velocity, angular_velocity;  // in the world frame
  double left_wheel_angle = 0, right_wheel_angle = 0;
  std::vector<Pose> camera_poses;  // world_from_camera of the rig's rendered cameras
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.kind);
    v(m.x);
    v(m.y);
    v(m.yaw);
    v(m.pose);
    v(m.linear_velocity);
    v(m.angular_velocity);
    v(m.left_wheel_angle);
    v(m.right_wheel_angle);
    v(m.camera_poses);
  }
};
/// Wheel odometry as the encoders report it (WheelOdometry): P1 eq. 13's input, exactly.
struct WheelOdometry {
  static constexpr const char* kType = "corridorsim_msgs/msg/WheelOdometry";
  Header header;
  std::int64_t interval_ns = 0;
  double left_distance = 0, right_distance = 0;
  std::int64_t left_ticks = 0, right_ticks = 0;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.interval_ns);
    v(m.left_distance);
    v(m.right_distance);
    v(m.left_ticks);
    v(m.right_ticks);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.frame_index);
    v(m.world_from_camera);
    v(m.world_from_robot);
  }
};
/// The cameras of one set (sensor_bus.h's CameraSet), after their frames: dropped[i] says that
/// cameras[i]'s frame was due and lost.
struct CameraSet {
  static constexpr const char* kType = "corridorsim_msgs/msg/CameraSet";
  Header header;
  std::vector<std::string> cameras;
  std::vector<bool> dropped;
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.cameras);
    v(m.dropped);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.exact_angular_velocity);
    v(m.exact_linear_acceleration);
    v(m.gyroscope_bias);
    v(m.accelerometer_bias);
    v(m.world_from_imu);
    v(m.velocity_in_world);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.angle_min);
    v(m.angle_increment);
    v(m.time_increment_ns);
    v(m.scan_time_ns);
    v(m.complete_ns);
    v(m.range_min);
    v(m.range_max);
    v(m.true_ranges);
    v(m.instance_ids);
    v(m.semantic_classes);
    v(m.incidences);
    v(m.world_from_laser);
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
  template <class V, class M>
  static void Fields(V& v, M& m) {
    v(m.header);
    v(m.kind);
    v(m.instance_id);
    v(m.semantic_class);
    v(m.position);
    v(m.depth);
    v(m.left_wheel);
    v(m.distance);
    v(m.camera_id);
  }
};

template <class T>
concept Message = requires { T::kType; };

/// ROS 2's schema text of `type` ("sensor_msgs/msg/Image"): its definition, then each message it
/// uses, after a line of 80 '=' and "MSG: pkg/Name" (the `ros2msg` schema encoding of MCAP).
/// Aborts for a type that is not above (a bug).
std::string Ros2Schema(const std::string& type);
/// The definition of one type alone (ros_schemas.cpp); every type above has one.
const std::string& Ros2Definition(const std::string& type);

// --- ROS 2 CDR ---

class CdrOut {
 public:
  template <class T>
    requires std::is_arithmetic_v<T>
  void operator()(const T& value) {
    writer_.Primitive(value);
  }
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
  template <Message T>
  void operator()(const T& message) {
    T::Fields(*this, message);
  }
  void operator()(const Header& header) { Header::Fields(*this, header); }
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
  void operator()(T& value) {
    value = reader_.Primitive<T>();
  }
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
  template <Message T>
  void operator()(T& message) {
    T::Fields(*this, message);
  }
  void operator()(Header& header) { Header::Fields(*this, header); }
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

/// A message from CDR bytes; throws CdrError (naming `what`) when they are not one.
template <Message T>
T FromCdr(std::span<const std::uint8_t> data, const std::string& what) {
  CdrIn in(data, what);
  T message;
  in(message);
  return message;
}

}  // namespace corridorsim::ros
