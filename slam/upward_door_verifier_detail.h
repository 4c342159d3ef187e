#pragma once
// What slam/upward_door_verifier.cpp (the options' checks, the particle filter) and
// slam/upward_door_hausdorff.cpp (the open-or-closed test) share; not part of the SDK.

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "slam/upward_door_verifier.h"

namespace corridorsim::slam::door_detail {

// Leaf depths tried at most (DoorVerifierOptions::Check).
inline constexpr int kMaxLeafDepths = 100;
// A verifying track's columns may move this many converged_sigma_m off the plane's.
inline constexpr double kMaxColumnShift = 4.0;

// The leaf depths tried: min_leaf_depth_m, then every leaf_depth_step_m up to max_leaf_depth_m.
inline std::size_t LeafDepths(const DoorVerifierOptions& o) {
  const double steps = (o.max_leaf_depth_m - o.min_leaf_depth_m) / o.leaf_depth_step_m;
  return std::size_t(std::clamp(int(std::floor(steps + 1e-9)) + 1, 1, kMaxLeafDepths));
}

// Whether a leaf depth lies in front of the columns' plane (min + k step: rounding aside).
inline bool InFront(double depth) { return depth < -1e-9; }

}  // namespace corridorsim::slam::door_detail
