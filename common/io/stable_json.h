#pragma once
// The project's one stable JSON writer: every file it writes (ground_truth.json, frame truth,
// metrics.json, events, the dataset export's JSON) rounds its numbers to fixed decimal steps
// through here and writes poses in one convention, so that equal inputs print equal bytes.

#include <string>

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include "common/pose.h"

namespace corridorsim {

/// Decimal steps per unit: a value is written as a multiple of 1 / steps (docs/metrics.md,
/// docs/frames.md).
namespace json_steps {
inline constexpr double kMetres = 1e6;      // 1 um; also seconds
inline constexpr double kSeconds = 1e6;     // 1 us
inline constexpr double kRad = 1e8;         // 10 nrad
inline constexpr double kDeg = 1e6;         // 1 udeg
inline constexpr double kPx = 1e4;          // 1e-4 px
inline constexpr double kMs = 1e4;          // 0.1 us
inline constexpr double kRatio = 1e6;       // fractions, NEES, NIS, real-time factor
inline constexpr double kUnitVector = 1e9;  // quaternion components, unit directions
}  // namespace json_steps

/// `value` rounded to the nearest multiple of 1 / steps_per_unit (a power of ten, at least 1).
/// Dividing the integer count of steps by steps_per_unit (not multiplying by the step) gives the
/// double nearest to the decimal, which JSON prints in its shortest form (2.3, not
/// 2.3000000000000003); -0 becomes 0 so that equal values print equal text. NaN and infinities
/// pass through (nlohmann::json writes them as null).
double RoundToStep(double value, double steps_per_unit);

/// [x, y] and [x, y, z], each component rounded with RoundToStep.
nlohmann::ordered_json RoundedJson(const Eigen::Vector2d& v, double steps_per_unit);
nlohmann::ordered_json RoundedJson(const Eigen::Vector3d& v, double steps_per_unit);

/// The pose convention of every JSON file: {"t": [x, y, z], "q": [qx, qy, qz, qw]}; t in metres
/// rounded to json_steps::kMetres, q (Eigen's coeffs() order, Hamilton, unit norm) rounded to
/// json_steps::kUnitVector, with the sign chosen so that qw >= 0 (q and -q are one rotation).
nlohmann::ordered_json PoseJson(const SE3& pose);

/// Every floating-point number in `json` (at any depth) rounded with RoundToStep, for documents
/// whose numbers share one step (timing.json: seconds and ratios).
void RoundNumbers(nlohmann::ordered_json& json, double steps_per_unit);

/// `json` as text (`indent` < 0: one line). Every JSON text the project writes or sends goes
/// through here: a string holding bytes that are not UTF-8 (text from outside: an exception
/// message, a program's output, a file or folder name) is written with each such byte as U+FFFD
/// instead of throwing after the work (docs/frames.md, "Text from outside").
template <class Json>
std::string JsonText(const Json& json, int indent = -1) {
  return json.dump(indent, ' ', false, Json::error_handler_t::replace);
}

/// The text of a JSON file: JsonText with `indent` (2 by default), then a newline.
template <class Json>
std::string JsonFileText(const Json& json, int indent = 2) {
  return JsonText(json, indent) + "\n";
}

}  // namespace corridorsim
