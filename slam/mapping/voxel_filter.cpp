#include "slam/mapping/voxel_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace corridorsim::slam {

std::optional<OptionsProblem> VoxelFilterOptions::Check() const {
  return CheckOptionBounds(VoxelFilterOptionsTable(), *this);
}

VoxelFilterResult VoxelFilter(const std::vector<Eigen::Vector3d>& points,
                              const VoxelFilterOptions& options) {
  CheckOrDie(!options.Check(), "slam::VoxelFilter", "the options fail their Check()");
  const double inverse_leaf = 1.0 / options.leaf_size_m;
  // (voxel key, index of the point), the key packing the three offset indices in 21 bits each:
  // sorted, the points of one voxel are adjacent and in input order, so the centroid's sum runs
  // in the same order every time, and the voxels come out in (x, y, z) index order.
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed;
  keyed.reserve(points.size());
  VoxelFilterResult result;
  constexpr std::int64_t kOffset = std::int64_t{1} << 20;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t key = 0;
    bool ok = true;
    for (int axis = 0; axis < 3; ++axis) {
      const double index = std::floor(points[i][axis] * inverse_leaf);
      // Also false for NaN and infinities.
      if (!(std::abs(index) <= kVoxelFilterMaxIndex)) {
        ok = false;
        break;
      }
      key = (key << 21) | static_cast<std::uint64_t>(static_cast<std::int64_t>(index) + kOffset);
    }
    if (ok) {
      keyed.emplace_back(key, i);
    } else {
      ++result.dropped;
    }
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t begin = 0; begin < keyed.size();) {
    std::size_t end = begin;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    while (end < keyed.size() && keyed[end].first == keyed[begin].first) {
      sum += points[keyed[end].second];
      ++end;
    }
    result.points.push_back(sum / static_cast<double>(end - begin));
    begin = end;
  }
  return result;
}

}  // namespace corridorsim::slam
