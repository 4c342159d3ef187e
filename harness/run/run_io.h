#pragma once
// Files of drives and runs that more than one job writes: events, estimates with covariance.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "common/time.h"
#include "sim/simulation.h"
#include "slam/pipeline.h"

namespace corridorsim {

/// Drives and runs write the ground truth on this grid (every odometry stamp at the default
/// 50 Hz lies on it; metrics interpolate between its points).
inline constexpr double kTruthFileRateHz = 100.0;

/// A stamp as seconds with all nine decimals of the integer nanoseconds ("12.020000000"), as the
/// TUM files, the export and the sensors' CSV write it: exact, whatever the magnitude.
std::string StampSeconds(TimeNs stamp_ns);

/// A number of a sensor's CSV row: nine significant digits (`%.9g`), and REP 117's non-finite
/// laser ranges as `inf`, `-inf`, `nan` (what numpy, pandas and Python's float() read).
std::string CsvNumber(double value);

/// One event of events.json: {t, t_ns, type, ...} with the fields of its kind.
nlohmann::ordered_json EventJson(const sim::Event& event);

/// A planar estimate as a line of OpenVINS ov_eval's trajectory-with-covariance format:
/// "t tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33", the
/// orientation covariance (rad^2, only the yaw entry Pr33 is non-zero) then the position
/// covariance (m^2, x-y block; z is known). The x-y-yaw cross terms have no place in the format.
std::string OvEvalLine(TimeNs stamp_ns, const SE2& pose, const Eigen::Matrix3d& covariance_xy_yaw);

/// The header comment of an ov_eval file.
std::string OvEvalHeader();

/// `<pipeline>_landmarks.json`: the pipeline's final map, one object per landmark in id order:
/// id, type, status, label, position_in_world (m), covariance (3x3 row-major, m^2) and, for
/// multi-point landmarks, its points (role, position, covariance). Stable JSON (docs/metrics.md).
nlohmann::ordered_json LandmarksJson(const std::vector<slam::LandmarkEstimate>& landmarks);

/// `<pipeline>_detections.csv`: every detection, in the order the pipeline reported them:
/// stamp_s, camera, type, u_px, v_px, box (min x, min y, max x, max y; empty for types without
/// one), plate_box, radius_px, label, open, score, recognition_score, landmark_id, new_landmark,
/// bearing_a_rad, bearing_b_rad (doors: the columns' bearings of P3 eq. 17; empty otherwise).
std::string DetectionsCsv(const std::vector<slam::Detection>& detections);

}  // namespace corridorsim
