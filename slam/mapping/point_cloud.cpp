#include "slam/mapping/point_cloud.h"

#include <cmath>

namespace corridorsim::slam {

std::optional<Eigen::Vector3d> UnprojectDepth(const CameraModel& model,
                                              const Eigen::Vector2d& pixel, double depth_m,
                                              Eigen::Matrix3d* d_point_d_pixel_depth) {
  Eigen::Matrix<double, 3, 2> d_bearing_d_pixel;
  const Eigen::Vector3d bearing =
      model.Unproject(pixel, d_point_d_pixel_depth != nullptr ? &d_bearing_d_pixel : nullptr);
  if (!(bearing.z() > kMinForwardBearing)) return std::nullopt;
  const Eigen::Vector3d ray = bearing / bearing.z();  // z = 1: the point at unit depth
  if (d_point_d_pixel_depth != nullptr) {
    // d (b / b_z) = (db - ray db_z) / b_z, times the depth; d p / d depth = ray.
    const Eigen::Matrix<double, 3, 2> d_ray_d_pixel =
        (d_bearing_d_pixel - ray * d_bearing_d_pixel.row(2)) / bearing.z();
    d_point_d_pixel_depth->leftCols<2>() = depth_m * d_ray_d_pixel;
    d_point_d_pixel_depth->col(2) = ray;
  }
  return depth_m * ray;
}

std::optional<OptionsProblem> DepthCloudOptions::Check() const {
  return CheckOptionBounds(DepthCloudOptionsTable(), *this);
}

DepthCloudProjector::DepthCloudProjector(const DepthCloudOptions& options, const CameraModel& model,
                                         const DepthRange& range)
    : width_(model.width()), height_(model.height()), range_(range) {
  CheckOrDie(!options.Check(), "slam::DepthCloudProjector", "the options fail their Check()");
  CheckOrDie(!model.Check(), "slam::DepthCloudProjector", "the camera model fails its Check()");
  CheckOrDie(range.min_m > 0 && range.min_m <= range.max_m && std::isfinite(range.max_m),
             "slam::DepthCloudProjector", "the depth range is not 0 < min_m <= max_m");
  const int stride = options.pixel_stride;
  for (int y = 0; y < height_; y += stride) {
    for (int x = 0; x < width_; x += stride) {
      const std::optional<Eigen::Vector3d> ray = UnprojectDepth(model, Eigen::Vector2d(x, y), 1.0);
      if (!ray) continue;
      pixel_index_.push_back(static_cast<std::size_t>(y) * width_ + x);
      ray_per_unit_depth_.push_back(*ray);
    }
  }
}

void DepthCloudProjector::PointsInCamera(const ImageF& depth_m,
                                         std::vector<Eigen::Vector3d>* points_in_camera) const {
  CheckOrDie(depth_m.width == width_ && depth_m.height == height_ &&
                 depth_m.data.size() == static_cast<std::size_t>(width_) * height_,
             "slam::DepthCloudProjector", "the depth image does not have the camera's size");
  points_in_camera->clear();
  points_in_camera->reserve(pixel_index_.size());
  for (std::size_t i = 0; i < pixel_index_.size(); ++i) {
    const double depth = depth_m.data[pixel_index_[i]];
    // Also skips 0 (invalid) and NaN (every comparison with NaN is false).
    if (!(depth >= range_.min_m && depth <= range_.max_m)) continue;
    points_in_camera->push_back(depth * ray_per_unit_depth_[i]);
  }
}

void DepthCloudProjector::PointsInWorld(const ImageF& depth_m, const SE3& world_from_camera,
                                        std::vector<Eigen::Vector3d>* points_in_world) const {
  PointsInCamera(depth_m, points_in_world);
  const Eigen::Matrix3d rotation = world_from_camera.rotation();
  const Eigen::Vector3d& translation = world_from_camera.translation();
  for (Eigen::Vector3d& p : *points_in_world) p = rotation * p + translation;
}

}  // namespace corridorsim::slam
