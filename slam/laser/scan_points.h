#pragma once
// A laser sweep as the points laser_slam matches and inserts (docs/laser_slam.md): the beams'
// endpoints in the robot frame at one reference instant, each beam undistorted with the wheel
// odometry's motion over the sweep (docs/sensors.md, "Undistorting": beam i fired at
// stamp + i * time_increment, from where the scanner was then; ROS's laser_geometry does the
// same with /tf). Ranges that REP 117 marks as no measurement (NaN, +inf, -inf) and ranges
// outside [range_min, range_max] are dropped and counted.

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"

namespace corridorsim::slam::laser {

/// The recent odometry-integrated poses (odom_from_robot, in the frame dead reckoning starts in),
/// the last `capacity` of them, for the pose at any instant of a sweep.
class OdometryTrack {
 public:
  explicit OdometryTrack(std::size_t capacity) : capacity_(capacity) {}
  /// Appends a pose; stamps must not decrease (an equal stamp replaces the last pose).
  void Add(TimeNs stamp_ns, const SE2& odom_from_robot);
  /// The pose at `stamp_ns`: interpolated between the poses around it, extrapolated at the
  /// last two poses' velocity up to `max_extrapolation_ns` past the last one (held there beyond),
  /// held at the first pose before it. Nothing while the track is empty.
  std::optional<SE2> At(TimeNs stamp_ns, TimeNs max_extrapolation_ns) const;
  bool empty() const { return poses_.empty(); }
  TimeNs last_stamp_ns() const { return poses_.back().first; }
  const SE2& last_pose() const { return poses_.back().second; }

 private:
  std::size_t capacity_;
  std::deque<std::pair<TimeNs, SE2>> poses_;
};

struct ScanPoints {
  std::vector<Eigen::Vector2d> points;  // robot frame at the reference instant, beam order (m)
  int non_finite = 0;                   // NaN, +inf, -inf (REP 117)
  int out_of_range = 0;                 // finite but outside [range_min, min(range_max, max)]
};

/// The sweep's beam endpoints in the robot frame at `reference_ns`, undistorted with `track`
/// (beam i at scan.stamp_ns + i * time_increment_ns; each beam's point taken through
/// `robot_from_laser` into the robot at its instant, then through the odometry's motion to the
/// reference). Beams beyond `max_range_m` (or the scan's range_max) are dropped. The scan plane
/// is taken as the robot's x-y plane (a level scanner: the 3D point's z is dropped).
ScanPoints ScanToPoints(const LaserScan& scan, const SE3& robot_from_laser,
                        const OdometryTrack& track, TimeNs reference_ns, double max_range_m);

}  // namespace corridorsim::slam::laser
