#include "slam/laser/scan_points.h"

#include <algorithm>
#include <cmath>

namespace corridorsim::slam::laser {

void OdometryTrack::Add(TimeNs stamp_ns, const SE2& odom_from_robot) {
  if (!poses_.empty() && poses_.back().first == stamp_ns) {
    poses_.back().second = odom_from_robot;
    return;
  }
  poses_.emplace_back(stamp_ns, odom_from_robot);
  while (poses_.size() > capacity_) poses_.pop_front();
}

std::optional<SE2> OdometryTrack::At(TimeNs stamp_ns, TimeNs max_extrapolation_ns) const {
  if (poses_.empty()) return std::nullopt;
  if (stamp_ns <= poses_.front().first) return poses_.front().second;
  if (stamp_ns >= poses_.back().first) {
    if (poses_.size() < 2) return poses_.back().second;
    const auto& [t1, p1] = poses_.back();
    const auto& [t0, p0] = poses_[poses_.size() - 2];
    const TimeNs ahead = std::min(stamp_ns - t1, max_extrapolation_ns);
    // The last step's motion in the robot frame, scaled to `ahead` (a constant twist).
    const Eigen::Vector3d step = (p0.Inverse() * p1).Log();
    const double s = static_cast<double>(ahead) / static_cast<double>(t1 - t0);
    return p1 * SE2(s * step.x(), s * step.y(), s * step.z());
  }
  // The first pose stamped after stamp_ns, and the one before it.
  const auto after = std::upper_bound(
      poses_.begin(), poses_.end(), stamp_ns,
      [](TimeNs t, const std::pair<TimeNs, SE2>& entry) { return t < entry.first; });
  const auto before = after - 1;
  const double t = static_cast<double>(stamp_ns - before->first) /
                   static_cast<double>(after->first - before->first);
  return SE2::Interpolate(before->second, after->second, t);
}

ScanPoints ScanToPoints(const LaserScan& scan, const SE3& robot_from_laser,
                        const OdometryTrack& track, TimeNs reference_ns, double max_range_m) {
  ScanPoints out;
  const std::optional<SE2> odom_from_reference = track.At(reference_ns, scan.scan_time_ns);
  if (!odom_from_reference) return out;
  const SE2 reference_from_odom = odom_from_reference->Inverse();
  const double range_max = std::min(static_cast<double>(scan.range_max_m), max_range_m);
  out.points.reserve(scan.ranges_m.size());
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double r = scan.ranges_m[i];
    if (!std::isfinite(r)) {
      ++out.non_finite;  // REP 117: NaN lost, +inf nothing in range, -inf too near
      continue;
    }
    if (r < scan.range_min_m || r > range_max) {
      ++out.out_of_range;
      continue;
    }
    const double angle = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    const Eigen::Vector3d in_robot =
        robot_from_laser * Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), 0.0);
    const TimeNs fired_ns = scan.stamp_ns + static_cast<TimeNs>(i) * scan.time_increment_ns;
    const SE2 reference_from_robot_then =
        reference_from_odom * *track.At(fired_ns, scan.scan_time_ns);
    out.points.push_back(reference_from_robot_then * in_robot.head<2>());
  }
  return out;
}

}  // namespace corridorsim::slam::laser
