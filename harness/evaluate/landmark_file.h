#pragma once
// A landmark map `corridorsim evaluate --landmarks NAME=FILE` scores: the format of a run's
// `<pipeline>_landmarks.json` (harness/run/run_io.h LandmarksJson), documented in
// docs/evaluation.md. A JSON array, one object per landmark:
//   {"id": 3, "type": "lamp", "status": "converged", "label": "",
//    "position_in_world": [x, y, z], "covariance": [[..], [..], [..]],
//    "points": [{"role": "column_a", "position_in_world": [..], "covariance": [[..]..]}, ...]}
// id, type and position_in_world are required; status (default converged), label, covariance
// and points (doors: column_a and column_b) optional. Unknown keys are refused. Coordinates lie
// within +-kMaxCoordinateMetres, covariance entries within +-kMaxCovarianceEntry
// (trajectory_file.h), as a trajectory's.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "slam/pipeline.h"

namespace corridorsim::evaluate {

inline constexpr std::uint64_t kMaxLandmarkFileBytes = 256ull << 20;  // 256 MiB
inline constexpr std::size_t kMaxLandmarks = 1'000'000;
inline constexpr std::size_t kMaxLandmarkPoints = 64;

/// Parses `text` (the contents of `file`). Throws InputError naming the file and the field
/// (`[12].position_in_world`); two landmarks with one id are refused.
std::vector<slam::LandmarkEstimate> ParseLandmarkMap(std::string_view text,
                                                     const std::string& file);

/// ReadRegularFile (at most kMaxLandmarkFileBytes) then ParseLandmarkMap.
std::vector<slam::LandmarkEstimate> ReadLandmarkMap(const std::string& file);

}  // namespace corridorsim::evaluate
