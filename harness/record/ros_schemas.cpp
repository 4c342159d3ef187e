// ROS 2 (Humble) message definitions, as a recording embeds them (MCAP's `ros2msg` schema
// encoding): fields only, in the order ros_messages.h serializes them, and corridorsim_msgs
// (docs/recordings.md says what each field means).

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "harness/record/ros_messages.h"

namespace corridorsim::ros {
namespace {

const std::map<std::string, std::string>& Definitions() {
  static const std::map<std::string, std::string> definitions = {
      {"builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n"},
      {"builtin_interfaces/msg/Duration", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/msg/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"std_msgs/msg/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"},
      {"geometry_msgs/msg/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/msg/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/msg/Quaternion",
       "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/msg/Pose", "Point position\nQuaternion orientation\n"},
      {"geometry_msgs/msg/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/msg/Twist", "Vector3 linear\nVector3 angular\n"},
      {"geometry_msgs/msg/TwistWithCovariance", "Twist twist\nfloat64[36] covariance\n"},
      {"geometry_msgs/msg/Transform", "Vector3 translation\nQuaternion rotation\n"},
      {"geometry_msgs/msg/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
      {"geometry_msgs/msg/PoseStamped", "std_msgs/Header header\nPose pose\n"},
      {"geometry_msgs/msg/PoseWithCovarianceStamped",
       "std_msgs/Header header\nPoseWithCovariance pose\n"},
      {"tf2_msgs/msg/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"nav_msgs/msg/Path", "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n"},
      {"nav_msgs/msg/Odometry",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
       "geometry_msgs/TwistWithCovariance twist\n"},
      {"sensor_msgs/msg/Image",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 "
       "is_bigendian\nuint32 step\nuint8[] data\n"},
      {"sensor_msgs/msg/RegionOfInterest",
       "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n"},
      {"sensor_msgs/msg/CameraInfo",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
       "float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\n"
       "uint32 binning_y\nRegionOfInterest roi\n"},
      {"sensor_msgs/msg/Imu",
       "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
       "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
       "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n"
       "float64[9] linear_acceleration_covariance\n"},
      {"sensor_msgs/msg/LaserScan",
       "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
       "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
       "float32[] ranges\nfloat32[] intensities\n"},
      {"visualization_msgs/msg/Marker",
       "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\n"
       "int32 LINE_LIST=5\nint32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\n"
       "int32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\nint32 TRIANGLE_LIST=11\n"
       "int32 ADD=0\nint32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
       "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\n"
       "geometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\n"
       "builtin_interfaces/Duration lifetime\nbool frame_locked\ngeometry_msgs/Point[] points\n"
       "std_msgs/ColorRGBA[] colors\nstring text\nstring mesh_resource\n"
       "bool mesh_use_embedded_materials\n"},
      {"visualization_msgs/msg/MarkerArray", "Marker[] markers\n"},
      {"corridorsim_msgs/msg/Truth",
       "uint8 START=0\nuint8 SAMPLE=1\nuint8 END=2\n"
       "std_msgs/Header header\nuint8 kind\nfloat64 x\nfloat64 y\nfloat64 yaw\n"
       "geometry_msgs/Pose pose\ngeometry_msgs/Vector3 linear_velocity\n"
       "geometry_msgs/Vector3 angular_velocity\nfloat64 left_wheel_angle\n"
       "float64 right_wheel_angle\ngeometry_msgs/Pose[] camera_poses\n"},
      {"corridorsim_msgs/msg/WheelOdometry",
       "std_msgs/Header header\nint64 interval_ns\nfloat64 left_distance\n"
       "float64 right_distance\nint64 left_ticks\nint64 right_ticks\n"},
      {"corridorsim_msgs/msg/CameraFrame",
       "std_msgs/Header header\nuint64 frame_index\ngeometry_msgs/Pose world_from_camera\n"
       "geometry_msgs/Pose world_from_robot\n"},
      {"corridorsim_msgs/msg/CameraSet",
       "std_msgs/Header header\nstring[] cameras\nbool[] dropped\n"},
      {"corridorsim_msgs/msg/ImuTruth",
       "std_msgs/Header header\ngeometry_msgs/Vector3 exact_angular_velocity\n"
       "geometry_msgs/Vector3 exact_linear_acceleration\ngeometry_msgs/Vector3 gyroscope_bias\n"
       "geometry_msgs/Vector3 accelerometer_bias\ngeometry_msgs/Pose world_from_imu\n"
       "geometry_msgs/Vector3 velocity_in_world\n"},
      {"corridorsim_msgs/msg/ScanTruth",
       "std_msgs/Header header\nfloat64 angle_min\nfloat64 angle_increment\n"
       "int64 time_increment_ns\nint64 scan_time_ns\nint64 complete_ns\nfloat64 range_min\n"
       "float64 range_max\nfloat64[] true_ranges\nint32[] instance_ids\n"
       "uint8[] semantic_classes\nfloat64[] incidences\ngeometry_msgs/Pose[] world_from_laser\n"},
      {"corridorsim_msgs/msg/Event",
       "std_msgs/Header header\nstring kind\nint32 instance_id\nuint8 semantic_class\n"
       "geometry_msgs/Point position\nfloat64 depth\nbool left_wheel\nfloat64 distance\n"
       "string camera_id\n"},
  };
  return definitions;
}

bool IsPrimitive(const std::string& type) {
  static const std::set<std::string> primitives = {
      "bool",   "byte",   "char",   "int8",   "uint8",   "int16",   "uint16", "int32",
      "uint32", "int64",  "uint64", "float32", "float64", "string", "wstring"};
  return primitives.count(type) > 0;
}

// "Point" in geometry_msgs/msg/Pose -> geometry_msgs/msg/Point; "std_msgs/Header" ->
// std_msgs/msg/Header.
std::string Resolve(const std::string& field_type, const std::string& package) {
  const std::size_t slash = field_type.find('/');
  if (slash == std::string::npos) return package + "/msg/" + field_type;
  return field_type.substr(0, slash) + "/msg/" + field_type.substr(slash + 1);
}

// The message types a definition's fields use, in order.
std::vector<std::string> Uses(const std::string& type) {
  const std::string package = type.substr(0, type.find('/'));
  std::vector<std::string> uses;
  std::istringstream lines(Ros2Definition(type));
  std::string line;
  while (std::getline(lines, line)) {
    std::string field_type = line.substr(0, line.find(' '));
    field_type = field_type.substr(0, field_type.find('['));
    if (field_type.empty() || IsPrimitive(field_type) || line.find('=') != std::string::npos) {
      continue;
    }
    uses.push_back(Resolve(field_type, package));
  }
  return uses;
}

}  // namespace

const std::string& Ros2Definition(const std::string& type) {
  const auto it = Definitions().find(type);
  CheckOrDie(it != Definitions().end(), "Ros2Definition", ("no definition of " + type).c_str());
  return it->second;
}

std::string Ros2Schema(const std::string& type) {
  std::string schema = Ros2Definition(type);
  // Depth first, each dependency once, as rosbag2 writes them.
  std::vector<std::string> order;
  std::set<std::string> seen = {type};
  std::vector<std::string> stack = Uses(type);
  std::reverse(stack.begin(), stack.end());
  while (!stack.empty()) {
    const std::string next = stack.back();
    stack.pop_back();
    if (!seen.insert(next).second) continue;
    order.push_back(next);
    std::vector<std::string> more = Uses(next);
    for (auto it = more.rbegin(); it != more.rend(); ++it) stack.push_back(*it);
  }
  for (const std::string& dependency : order) {
    const std::string name =
        dependency.substr(0, dependency.find('/')) + "/" + dependency.substr(dependency.rfind('/') + 1);
    schema += std::string(80, '=') + "\nMSG: " + name + "\n" + Ros2Definition(dependency);
  }
  return schema;
}

void CdrOut::Stamp(TimeNs ns) {
  // builtin_interfaces: sec may be negative, nanosec in [0, 1e9).
  TimeNs sec = ns / 1'000'000'000;
  TimeNs nanosec = ns % 1'000'000'000;
  if (nanosec < 0) {
    nanosec += 1'000'000'000;
    --sec;
  }
  writer_.Primitive(static_cast<std::int32_t>(sec));
  writer_.Primitive(static_cast<std::uint32_t>(nanosec));
}

TimeNs CdrIn::Stamp() {
  const auto sec = reader_.Primitive<std::int32_t>();
  const auto nanosec = reader_.Primitive<std::uint32_t>();
  return static_cast<TimeNs>(sec) * 1'000'000'000 + static_cast<TimeNs>(nanosec);
}

}  // namespace corridorsim::ros
