#pragma once
// Trajectory files `corridorsim evaluate` reads: TUM (`t tx ty tz qx qy qz qw`, the format of a
// run's `<pipeline>.tum` and of the TUM RGB-D benchmark) and OpenVINS ov_eval's trajectory with
// covariance (the same 8 columns, then the orientation and position covariances' upper triangles:
// `Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33`, a run's `<pipeline>_cov.txt`).
// docs/evaluation.md is the format's reference. The file is user input: every malformed line is
// an InputError naming the file, the line and the column.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/time.h"

namespace corridorsim::evaluate {

/// Bounds of one trajectory file, checked while it is read (docs/evaluation.md, "Memory"): the
/// file is read line by line, never held whole, and a pose is 64 bytes (208 with ov_eval's
/// covariances).
inline constexpr std::uint64_t kMaxTrajectoryFileBytes = 1ull << 30;  // 1 GiB
inline constexpr std::size_t kMaxTrajectoryPoses = 10'000'000;
inline constexpr std::size_t kMaxTrajectoryLineBytes = 4096;  // 20 numbers of 200 characters
/// |t| of a stamp (s): within TimeNs's safe range (common/time.h), past Unix time of 2096.
inline constexpr double kMaxStampSeconds = 4.0e9;
/// |coordinate| of a position (m) and |entry| of a covariance (m^2, rad^2): far past any map
/// (UTM's 1e7 m), near enough that sums of squares over kMaxTrajectoryPoses stay finite.
inline constexpr double kMaxCoordinateMetres = 1e9;
inline constexpr double kMaxCovarianceEntry = 1e12;

struct TrajectoryPose {
  TimeNs stamp_ns = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // world_from_robot t (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // unit, qw >= 0
};

/// ov_eval's covariance blocks of one pose, both in the world frame.
struct PoseCovariance {
  Eigen::Matrix3d orientation = Eigen::Matrix3d::Zero();  // rad^2
  Eigen::Matrix3d position = Eigen::Matrix3d::Zero();     // m^2
};

struct Trajectory {
  enum class Format { kTum, kOvEval };
  Format format = Format::kTum;
  std::vector<TrajectoryPose> poses;        // stamps strictly increasing
  std::vector<PoseCovariance> covariances;  // ov_eval: one per pose; TUM: empty
};

std::string FormatName(Trajectory::Format format);  // "tum", "ov_eval"

/// Parses `text` (the contents of `file`): lines of 8 (TUM) or 20 (ov_eval) numbers separated by
/// spaces or tabs, every data line the same count; `#` comment lines and blank lines skipped; a
/// line ends at LF (a CR before it is dropped) and holds at most kMaxTrajectoryLineBytes (CR
/// included). A stamp is decimal seconds (exact to the nanosecond for up to 9 decimals; an exponent
/// is read as a double and rounded to the nanosecond), within +-kMaxStampSeconds, each after the
/// one before. The quaternion is Hamilton (x, y, z, w) of norm 1 within 1e-2 (normalised). Every
/// number finite, positions within +-kMaxCoordinateMetres and covariance entries within
/// +-kMaxCovarianceEntry; at most kMaxTrajectoryPoses poses. Throws InputError at file:line:column.
Trajectory ParseTrajectory(std::string_view text, const std::string& file);

/// ParseTrajectory of the regular file `file` (at most kMaxTrajectoryFileBytes), read line by
/// line (ReadRegularFileLines) twice: its data lines counted, then parsed into vectors of that
/// size. The text is never held whole.
Trajectory ReadTrajectory(const std::string& file);

}  // namespace corridorsim::evaluate
