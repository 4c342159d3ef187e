#pragma once
// P1 section 5's location-based map: the front RGB-D sensor's depth cloud inserted into an OctoMap
// (octomap::OcTree, probabilistic occupancy with ray casting from the sensor origin) at keyframes,
// i.e. when the camera has moved keyframe_distance_m or turned keyframe_angle_deg since the last
// one. The cloud is every pixel_stride-th pixel, optionally thinned by the voxel-grid filter
// (P1 Fig. 12b); rays are cut at max_range_m, which bounds the insertion's cost (it grows with
// ray length). The map leaves as the bytes of a .bt file (OcTree::writeBinaryConst); slam/ writes
// no files.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <octomap/OcTree.h>

#include <Eigen/Core>

#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "slam/mapping/point_cloud.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// The defaults meet P1's budget of <= 30 ms per keyframe for the 640x480 front depth frame:
/// bench_mapping on the default world gives 15.6 ms CPU per keyframe at 0.10 m, stride 4 and 4 m
/// (9.0 ms at 3 m, 31.7 ms at 5 m); 0.05 m costs 4-8 times more (56 ms at 3 m and stride 8).
struct OccupancyMapperOptions {
  double resolution_m = 0.10;        // m, edge of the octree's smallest voxel
  double max_range_m = 4.0;          // m, rays are cut here (endpoints beyond it are not occupied)
  int pixel_stride = 4;              // px, every stride-th pixel of every stride-th depth row
  double voxel_leaf_m = 0.0;         // m, voxel-grid filter before insertion; 0 = off
  double keyframe_distance_m = 0.5;  // m the camera moves between keyframes
  double keyframe_angle_deg = 15.0;  // deg the camera turns between keyframes
  std::optional<OptionsProblem> Check() const;
};
/// The keys of the mapper's options (a pipeline's `map:` section).
const OptionTable<OccupancyMapperOptions>& OccupancyMapperOptionsTable();

struct OccupancyMapperStats {
  int frames = 0;                    // depth frames offered
  int keyframes = 0;                 // of them inserted
  std::int64_t points_inserted = 0;  // cloud points after stride, range and filter
  double insert_seconds = 0.0;       // wall-clock in cloud building and insertion, all keyframes
  double max_keyframe_seconds = 0.0;
  double ms_per_keyframe() const { return keyframes > 0 ? 1e3 * insert_seconds / keyframes : 0.0; }
};

class OccupancyMapper {
 public:
  /// `options` must pass Check(); `camera` must have a depth range and a model passing Check().
  OccupancyMapper(const OccupancyMapperOptions& options, const CameraCalibration& camera);

  /// A depth frame taken at world_from_camera: inserted when it is a keyframe (the first frame
  /// always is). Returns whether it was.
  bool OnDepth(const ImageF& depth_m, const SE3& world_from_camera);
  /// Whether a frame at world_from_camera would be a keyframe.
  bool IsKeyframe(const SE3& world_from_camera) const;
  /// Inserts the frame whatever the keyframe rule says.
  void Insert(const ImageF& depth_m, const SE3& world_from_camera);

  const octomap::OcTree& octree() const { return *octree_; }
  const OccupancyMapperStats& stats() const { return stats_; }
  /// The sensor origins of the keyframes, in the world frame, in insertion order.
  const std::vector<Eigen::Vector3d>& keyframe_origins_in_world() const { return origins_; }
  /// The map as the bytes of a .bt file (octovis, octomap-tools read it).
  std::string BinaryBytes() const;

 private:
  OccupancyMapperOptions options_;
  DepthCloudProjector projector_;
  std::unique_ptr<octomap::OcTree> octree_;
  std::optional<SE3> last_keyframe_;
  std::vector<Eigen::Vector3d> origins_;
  std::vector<Eigen::Vector3d> points_;  // reused buffer
  OccupancyMapperStats stats_;
};

/// An octree read back from .bt bytes; nullptr when they are not one.
std::unique_ptr<octomap::OcTree> OcTreeFromBinaryBytes(const std::string& bytes);

}  // namespace corridorsim::slam
