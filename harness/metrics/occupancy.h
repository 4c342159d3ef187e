#pragma once
// Map quality of an OctoMap against the world (P1 section 5's location-based map): the ground-truth
// occupancy is every voxel of the octree's grid whose cube meets a triangle of the world's meshes
// (walls, floor, ceiling, doors and their leaves, plates, lamps, furniture: exact triangle-box
// tests), and the octree is scored where the sensor saw:
//   precision = occupied octree voxels with a truth voxel within tolerance_voxels / occupied ones
//   recall    = observed truth voxels (the octree knows them, free or occupied) with an occupied
//               octree voxel within tolerance_voxels / observed truth voxels
// "Within" is the Chebyshev distance in voxels (1: the 3x3x3 block around a voxel). Pruned octree
// leaves count as the voxels they cover.

#include <cstdint>
#include <optional>

#include <octomap/OcTree.h>

#include <Eigen/Core>

#include "common/error.h"
#include "worlds/world.h"

namespace corridorsim::metrics {

struct OccupancyQualityOptions {
  int tolerance_voxels = 1;  // voxels, Chebyshev distance that still counts as a hit
  // Bounds on the work (voxel-triangle tests, octree voxels expanded from pruned leaves); beyond
  // them ComputeOccupancyQuality throws std::runtime_error rather than run for hours.
  std::int64_t max_triangle_box_tests = 400'000'000;
  std::int64_t max_octree_voxels = 50'000'000;
  std::optional<OptionsProblem> Check() const;
};

struct OccupancyQuality {
  double precision = 0.0;                    // 0 when the octree has no occupied voxel
  double recall = 0.0;                       // 0 when no truth voxel was observed
  std::int64_t occupied_voxels = 0;          // octree, at its finest resolution
  std::int64_t occupied_near_truth = 0;      // of them, within tolerance of a truth voxel
  std::int64_t truth_voxels = 0;             // in the octree's known bounding box (+ tolerance)
  std::int64_t truth_observed = 0;           // of them, known to the octree
  std::int64_t truth_observed_recalled = 0;  // of those, within tolerance of an occupied voxel
};

/// Whether the triangle (a, b, c) meets the closed axis-aligned box (Akenine-Moller's separating
/// axis test: the box's 3 axes, the triangle's normal and the 9 edge cross products).
bool TriangleTouchesBox(const Eigen::Vector3d& box_center, const Eigen::Vector3d& box_half_size,
                        const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c);

/// The map quality of `octree` against `world`'s meshes (`options` must pass Check()).
OccupancyQuality ComputeOccupancyQuality(const worlds::World& world, const octomap::OcTree& octree,
                                         const OccupancyQualityOptions& options);

}  // namespace corridorsim::metrics
