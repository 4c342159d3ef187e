#include "harness/metrics/occupancy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/options_checker.h"

namespace corridorsim::metrics {
namespace {

using octomap::OcTreeKey;

// The keys within `tolerance` (Chebyshev) of `key`, for `visit` until it returns true.
template <class Visit>
bool AnyNear(const OcTreeKey& key, int tolerance, Visit visit) {
  for (int dx = -tolerance; dx <= tolerance; ++dx) {
    for (int dy = -tolerance; dy <= tolerance; ++dy) {
      for (int dz = -tolerance; dz <= tolerance; ++dz) {
        const int x = key[0] + dx, y = key[1] + dy, z = key[2] + dz;
        if (x < 0 || y < 0 || z < 0 || x > 0xffff || y > 0xffff || z > 0xffff) continue;
        if (visit(OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                            static_cast<octomap::key_type>(z)))) {
          return true;
        }
      }
    }
  }
  return false;
}

}  // namespace

std::optional<OptionsProblem> OccupancyQualityOptions::Check() const {
  OptionsChecker check;
  check.InRange(tolerance_voxels, 0, 3, "tolerance_voxels");
  check.Positive(static_cast<double>(max_triangle_box_tests), "max_triangle_box_tests");
  check.Positive(static_cast<double>(max_octree_voxels), "max_octree_voxels");
  return check.problem();
}

bool TriangleTouchesBox(const Eigen::Vector3d& box_center, const Eigen::Vector3d& box_half_size,
                        const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c) {
  const Eigen::Vector3d v[3] = {a - box_center, b - box_center, c - box_center};
  const Eigen::Vector3d& h = box_half_size;
  // The box's axes: the triangle's bounding box against the box.
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = std::min({v[0][axis], v[1][axis], v[2][axis]});
    const double hi = std::max({v[0][axis], v[1][axis], v[2][axis]});
    if (lo > h[axis] || hi < -h[axis]) return false;
  }
  const Eigen::Vector3d edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  // The triangle's plane against the box.
  const Eigen::Vector3d normal = edges[0].cross(edges[1]);
  if (std::abs(normal.dot(v[0])) > h.dot(normal.cwiseAbs())) return false;
  // The 9 cross products of the box's axes with the triangle's edges.
  for (int axis = 0; axis < 3; ++axis) {
    for (const Eigen::Vector3d& edge : edges) {
      const Eigen::Vector3d direction = Eigen::Vector3d::Unit(axis).cross(edge);
      if (direction.squaredNorm() == 0.0) continue;  // edge along the axis: covered above
      const double p0 = direction.dot(v[0]), p1 = direction.dot(v[1]), p2 = direction.dot(v[2]);
      const double radius = h.dot(direction.cwiseAbs());
      if (std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius) return false;
    }
  }
  return true;
}

OccupancyQuality ComputeOccupancyQuality(const worlds::World& world, const octomap::OcTree& octree,
                                         const OccupancyQualityOptions& options) {
  CheckOrDie(!options.Check(), "metrics::ComputeOccupancyQuality", "the options fail Check()");
  OccupancyQuality quality;
  const double resolution = octree.getResolution();
  const int tolerance = options.tolerance_voxels;
  const unsigned max_depth = octree.getTreeDepth();

  // The octree's occupied voxels at its finest resolution (pruned leaves expanded).
  octomap::KeySet occupied;
  bool any_known = false;
  OcTreeKey known_min(0xffff, 0xffff, 0xffff), known_max(0, 0, 0);
  for (auto it = octree.begin_leafs(), end = octree.end_leafs(); it != end; ++it) {
    any_known = true;
    const int cells = 1 << (max_depth - it.getDepth());  // voxels along an edge of the leaf
    // The leaf's first voxel: its key with the bits below its depth cleared.
    const OcTreeKey key = it.getIndexKey();
    for (int axis = 0; axis < 3; ++axis) {
      known_min[axis] = std::min<octomap::key_type>(known_min[axis], key[axis]);
      known_max[axis] = std::max<octomap::key_type>(
          known_max[axis], static_cast<octomap::key_type>(key[axis] + cells - 1));
    }
    if (!octree.isNodeOccupied(*it)) continue;
    if (static_cast<std::int64_t>(occupied.size()) + std::int64_t{cells} * cells * cells >
        options.max_octree_voxels) {
      throw std::runtime_error("occupancy metric: the octree has more than " +
                               std::to_string(options.max_octree_voxels) + " occupied voxels");
    }
    for (int i = 0; i < cells; ++i) {
      for (int j = 0; j < cells; ++j) {
        for (int k = 0; k < cells; ++k) {
          occupied.insert(OcTreeKey(static_cast<octomap::key_type>(key[0] + i),
                                    static_cast<octomap::key_type>(key[1] + j),
                                    static_cast<octomap::key_type>(key[2] + k)));
        }
      }
    }
  }
  if (!any_known) return quality;

  // The truth voxels within the known keys' box grown by the tolerance: nothing farther can be
  // observed or near an occupied voxel.
  int lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = std::max(0, known_min[axis] - tolerance);
    hi[axis] = std::min(0xffff, known_max[axis] + tolerance);
  }
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * resolution);
  const auto key_of = [&](double coordinate) {
    return static_cast<int>(std::floor(coordinate / resolution)) + 32768;  // OctoMap's tree_max_val
  };
  octomap::KeySet truth;
  std::int64_t tests = 0;
  for (const worlds::Mesh& mesh : world.meshes) {
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const Eigen::Vector3d a = mesh.positions[mesh.indices[t]].cast<double>();
      const Eigen::Vector3d b = mesh.positions[mesh.indices[t + 1]].cast<double>();
      const Eigen::Vector3d c = mesh.positions[mesh.indices[t + 2]].cast<double>();
      int first[3], last[3];
      bool inside = true;
      for (int axis = 0; axis < 3; ++axis) {
        // One voxel of margin: a triangle on a voxel face touches the voxels on both sides.
        first[axis] = std::max(lo[axis], key_of(std::min({a[axis], b[axis], c[axis]})) - 1);
        last[axis] = std::min(hi[axis], key_of(std::max({a[axis], b[axis], c[axis]})) + 1);
        inside = inside && first[axis] <= last[axis];
      }
      if (!inside) continue;
      tests += std::int64_t{last[0] - first[0] + 1} * (last[1] - first[1] + 1) *
               (last[2] - first[2] + 1);
      if (tests > options.max_triangle_box_tests) {
        throw std::runtime_error("occupancy metric: more than " +
                                 std::to_string(options.max_triangle_box_tests) +
                                 " triangle-voxel tests (world too large for the resolution)");
      }
      for (int x = first[0]; x <= last[0]; ++x) {
        for (int y = first[1]; y <= last[1]; ++y) {
          for (int z = first[2]; z <= last[2]; ++z) {
            const OcTreeKey key(static_cast<octomap::key_type>(x),
                                static_cast<octomap::key_type>(y),
                                static_cast<octomap::key_type>(z));
            if (truth.count(key) > 0) continue;
            const Eigen::Vector3d center((x - 32768 + 0.5) * resolution,
                                         (y - 32768 + 0.5) * resolution,
                                         (z - 32768 + 0.5) * resolution);
            if (TriangleTouchesBox(center, half, a, b, c)) truth.insert(key);
          }
        }
      }
    }
  }

  // Counts only: the sets' (hash) order reaches no output.
  quality.occupied_voxels = static_cast<std::int64_t>(occupied.size());
  for (const OcTreeKey& key : occupied) {
    quality.occupied_near_truth +=
        AnyNear(key, tolerance, [&](const OcTreeKey& k) { return truth.count(k) > 0; });
  }
  quality.truth_voxels = static_cast<std::int64_t>(truth.size());
  for (const OcTreeKey& key : truth) {
    if (octree.search(key) == nullptr) continue;
    ++quality.truth_observed;
    quality.truth_observed_recalled +=
        AnyNear(key, tolerance, [&](const OcTreeKey& k) { return occupied.count(k) > 0; });
  }
  if (quality.occupied_voxels > 0) {
    quality.precision = static_cast<double>(quality.occupied_near_truth) /
                        static_cast<double>(quality.occupied_voxels);
  }
  if (quality.truth_observed > 0) {
    quality.recall = static_cast<double>(quality.truth_observed_recalled) /
                     static_cast<double>(quality.truth_observed);
  }
  return quality;
}

}  // namespace corridorsim::metrics
