#include "slam/mapping/voxel_filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace corridorsim::slam {

const OptionTable<VoxelFilterOptions>& VoxelFilterOptionsTable() {
  return StaticOptionTable<VoxelFilterOptions>([](OptionTable<VoxelFilterOptions>& t) {
    t.Add("leaf_size_m", &VoxelFilterOptions::leaf_size_m, "m",
          "edge of the voxel grid's cubes: one point (the centroid) per occupied cube")
        .Range(0.001, 10);
  });
}

std::optional<OptionsProblem> VoxelFilterOptions::Check() const {
  return CheckOptionBounds(VoxelFilterOptionsTable(), *this);
}

VoxelFilterResult VoxelFilter(const std::vector<Eigen::Vector3d>& points,
                              const VoxelFilterOptions& options) {
  CheckOrDie(!options.Check(), "slam::VoxelFilter", "the options fail their Check()");
  const double inverse_leaf = 1.0 / options.leaf_size_m;
  // (voxel key, index of the point): sorted, the points of one voxel are adjacent and in input
  // order, so the centroid's sum runs in the same order every time.
  struct Keyed {
    std::array<std::int64_t, 3> key;
    std::size_t index;
    bool operator<(const Keyed& other) const {
      return key != other.key ? key < other.key : index < other.index;
    }
  };
  std::vector<Keyed> keyed;
  keyed.reserve(points.size());
  VoxelFilterResult result;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Keyed k{{0, 0, 0}, i};
    bool ok = true;
    for (int axis = 0; axis < 3; ++axis) {
      const double index = std::floor(points[i][axis] * inverse_leaf);
      // Also false for NaN and infinities.
      if (!(std::abs(index) <= kVoxelFilterMaxIndex)) {
        ok = false;
        break;
      }
      k.key[axis] = static_cast<std::int64_t>(index);
    }
    if (ok) {
      keyed.push_back(k);
    } else {
      ++result.dropped;
    }
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t begin = 0; begin < keyed.size();) {
    std::size_t end = begin;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    while (end < keyed.size() && keyed[end].key == keyed[begin].key) {
      sum += points[keyed[end].index];
      ++end;
    }
    result.points.push_back(sum / static_cast<double>(end - begin));
    begin = end;
  }
  return result;
}

}  // namespace corridorsim::slam
