#pragma once
// Voxel-grid filter (P1 Fig. 12b: a ~300k-point depth cloud thinned to ~20k before the OctoMap
// insertion): one point per occupied voxel of a grid of cubes of leaf_size_m aligned with the
// frame's origin, the centroid of the points that fell into it. The output is ordered by voxel
// key (x, then y, then z), never by a hash, so the same cloud gives the same bytes.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/error.h"
#include "common/options_table.h"

namespace corridorsim::slam {

struct VoxelFilterOptions {
  double leaf_size_m = 0.05;  // m, edge of the grid's cubes
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<VoxelFilterOptions>& VoxelFilterOptionsTable();

/// Points whose voxel index along an axis exceeds this in magnitude are dropped: the index would
/// not fit its 21 bits of the 64-bit key (52 km from the origin at a 0.05 m leaf).
inline constexpr double kVoxelFilterMaxIndex = (1 << 20) - 1;

struct VoxelFilterResult {
  std::vector<Eigen::Vector3d> points;  // centroids, in the input's frame, by voxel key
  std::size_t dropped = 0;              // non-finite points and points beyond the key's range
};

/// The voxel-grid filter of `points` with `options` (Check() must pass).
VoxelFilterResult VoxelFilter(const std::vector<Eigen::Vector3d>& points,
                              const VoxelFilterOptions& options);

}  // namespace corridorsim::slam
