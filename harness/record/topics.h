#pragma once
// The topics and frames of a recording (docs/recordings.md has the table this mirrors): ROS
// conventions (REP 105's map, odom and base_link; REP 103's axes: x forward, y left, z up, and
// cameras' `_optical_frame`s with z forward, x right, y down), standard messages where ROS has
// them, and corridorsim_msgs under /corridorsim for what replay needs exactly.

#include <string>
#include <vector>

namespace corridorsim::record {

inline constexpr char kMapFrame[] = "map";  // the world: truth, estimates, the world's markers
inline constexpr char kOdomFrame[] = "odom";
inline constexpr char kBaseFrame[] = "base_link";  // the robot frame R: floor, between the wheels

inline constexpr char kTfTopic[] = "/tf";               // map -> base_link, the ground truth
inline constexpr char kTfStaticTopic[] = "/tf_static";  // base_link -> every sensor's frame
inline constexpr char kTruthOdomTopic[] = "/ground_truth/odom";
inline constexpr char kOdomTopic[] = "/odom";            // wheel odometry, dead-reckoned
inline constexpr char kWorldTopic[] = "/world/markers";  // walls, doors, plates, lamps
inline constexpr char kTruthTopic[] = "/corridorsim/truth";
inline constexpr char kWheelTopic[] = "/corridorsim/wheel_odometry";
inline constexpr char kCameraSetTopic[] = "/corridorsim/camera_set";
inline constexpr char kEventsTopic[] = "/corridorsim/events";

/// A camera's optical frame and a body sensor's (IMU, scanner) frame.
std::string OpticalFrame(const std::string& camera_id);
std::string SensorFrame(const std::string& sensor_id);

/// "/<sensor>/<leaf>": image_raw, camera_info, depth/image_raw, imu, scan.
std::string SensorTopic(const std::string& sensor_id, const std::string& leaf);
/// "/corridorsim/<sensor>/<leaf>": frame, depth_truth, instance, semantic, truth.
std::string SensorTruthTopic(const std::string& sensor_id, const std::string& leaf);
/// "/slam/<pipeline>/<leaf>": pose, path, landmarks.
std::string PipelineTopic(const std::string& pipeline, const std::string& leaf);

/// `--record-topics`: comma-separated patterns, `*` matching any run of characters (so
/// "/front/*,/tf*" keeps the front camera's standard topics and both tf topics).
class TopicFilter {
 public:
  TopicFilter() = default;  // every topic
  /// Throws InputError (naming `flag`) for an empty pattern or one without a leading '/'.
  TopicFilter(const std::string& patterns, const std::string& flag);
  bool Keeps(const std::string& topic) const;
  bool all() const { return patterns_.empty(); }
  const std::string& text() const { return text_; }

 private:
  std::vector<std::string> patterns_;
  std::string text_;
};

}  // namespace corridorsim::record
