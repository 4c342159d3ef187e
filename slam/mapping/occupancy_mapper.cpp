#include "slam/mapping/occupancy_mapper.h"

#include <cmath>
#include <sstream>

#include "slam/mapping/voxel_filter.h"

namespace corridorsim::slam {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

DepthCloudOptions CloudOptions(const OccupancyMapperOptions& options) {
  DepthCloudOptions cloud;
  cloud.pixel_stride = options.pixel_stride;
  return cloud;
}

const OccupancyMapperOptions& Checked(const OccupancyMapperOptions& options) {
  CheckOrDie(!options.Check(), "slam::OccupancyMapper", "the options fail their Check()");
  return options;
}

const DepthRange& DepthRangeOf(const CameraCalibration& camera) {
  CheckOrDie(camera.depth.has_value(), "slam::OccupancyMapper", "the camera has no depth range");
  return *camera.depth;
}

}  // namespace

std::optional<OptionsProblem> OccupancyMapperOptions::Check() const {
  return CheckOptionBounds(OccupancyMapperOptionsTable(), *this);
}

OccupancyMapper::OccupancyMapper(const OccupancyMapperOptions& options,
                                 const CameraCalibration& camera)
    : options_(Checked(options)),
      projector_(CloudOptions(options), camera.model, DepthRangeOf(camera)),
      octree_(std::make_unique<octomap::OcTree>(options_.resolution_m)) {}

bool OccupancyMapper::IsKeyframe(const SE3& world_from_camera) const {
  if (!last_keyframe_) return true;
  const double moved_m = (world_from_camera.translation() - last_keyframe_->translation()).norm();
  const double turned_rad =
      last_keyframe_->quaternion().angularDistance(world_from_camera.quaternion());
  return moved_m >= options_.keyframe_distance_m ||
         turned_rad >= options_.keyframe_angle_deg * kDegToRad;
}

bool OccupancyMapper::OnDepth(const ImageF& depth_m, const SE3& world_from_camera) {
  ++stats_.frames;
  if (!IsKeyframe(world_from_camera)) return false;
  Insert(depth_m, world_from_camera);
  return true;
}

void OccupancyMapper::Insert(const ImageF& depth_m, const SE3& world_from_camera) {
  const auto t0 = std::chrono::steady_clock::now();
  projector_.PointsInWorld(depth_m, world_from_camera, &points_);
  if (options_.voxel_leaf_m > 0) {
    VoxelFilterOptions filter;
    filter.leaf_size_m = options_.voxel_leaf_m;
    points_ = VoxelFilter(points_, filter).points;
  }
  octomap::Pointcloud cloud;
  cloud.reserve(points_.size());
  for (const Eigen::Vector3d& p : points_) {
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                    static_cast<float>(p.z()));
  }
  const Eigen::Vector3d& origin = world_from_camera.translation();
  // Rays from the sensor origin: free cells along each, the endpoint occupied; rays longer than
  // max_range_m are cut and leave no endpoint. discretize: one ray per endpoint voxel.
  octree_->insertPointCloud(
      cloud,
      octomap::point3d(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                       static_cast<float>(origin.z())),
      options_.max_range_m, /*lazy_eval=*/false, /*discretize=*/true);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ++stats_.keyframes;
  stats_.points_inserted += static_cast<std::int64_t>(points_.size());
  stats_.insert_seconds += seconds;
  stats_.max_keyframe_seconds = std::max(stats_.max_keyframe_seconds, seconds);
  last_keyframe_ = world_from_camera;
  origins_.push_back(origin);
}

std::string OccupancyMapper::BinaryBytes() const {
  std::ostringstream out(std::ios::out | std::ios::binary);
  const bool ok = octree_->writeBinaryConst(out);
  CheckOrDie(ok && out.good(), "slam::OccupancyMapper", "writing the octree to memory failed");
  return std::move(out).str();
}

std::unique_ptr<octomap::OcTree> OcTreeFromBinaryBytes(const std::string& bytes) {
  std::istringstream in(bytes, std::ios::in | std::ios::binary);
  auto tree = std::make_unique<octomap::OcTree>(0.1);
  if (!tree->readBinary(in)) return nullptr;
  return tree;
}

}  // namespace corridorsim::slam
