#pragma once
// Files of drives and runs that more than one job writes: events, estimates with covariance.

#include <string>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "common/time.h"
#include "sim/simulation.h"

namespace corridorsim {

/// Drives and runs write the ground truth on this grid (every odometry stamp at the default
/// 50 Hz lies on it; metrics interpolate between its points).
inline constexpr double kTruthFileRateHz = 100.0;

/// One event of events.json: {t, t_ns, type, ...} with the fields of its kind.
nlohmann::ordered_json EventJson(const sim::Event& event);

/// A planar estimate as a line of OpenVINS ov_eval's trajectory-with-covariance format:
/// "t tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33", the
/// orientation covariance (rad^2, only the yaw entry Pr33 is non-zero) then the position
/// covariance (m^2, x-y block; z is known). The x-y-yaw cross terms have no place in the format.
std::string OvEvalLine(TimeNs stamp_ns, const SE2& pose, const Eigen::Matrix3d& covariance_xy_yaw);

/// The header comment of an ov_eval file.
std::string OvEvalHeader();

}  // namespace corridorsim
