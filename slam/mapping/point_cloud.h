#pragma once
// Depth image to 3D points (P1 section 5: the front RGB-D sensor's dense cloud that feeds the
// OctoMap): every pixel_stride-th pixel of a registered depth image (metres along the optical axis,
// 0 = invalid) is lifted through the camera model's Unproject (pinhole with distortion or
// Kannala-Brandt fisheye) and, with world_from_camera, into the world frame.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// The point at `depth_m` along the optical axis (z in the camera frame) through `pixel`, in the
/// camera frame: p = depth * b / b_z with b = model.Unproject(pixel). nullopt when the pixel's ray
/// does not point forward (b_z <= kMinForwardBearing: a fisheye's rays at or beyond 90 deg, whose
/// depth along the axis names no point). `d_point_d_pixel_depth` is d p / d (u, v, depth).
std::optional<Eigen::Vector3d> UnprojectDepth(const CameraModel& model,
                                              const Eigen::Vector2d& pixel, double depth_m,
                                              Eigen::Matrix3d* d_point_d_pixel_depth = nullptr);

/// Rays with a smaller z component of their unit bearing are not unprojected (about 89.9 deg).
inline constexpr double kMinForwardBearing = 1e-3;

/// Which pixels of a depth image become points.
struct DepthCloudOptions {
  int pixel_stride = 1;  // px: every stride-th pixel of every stride-th row (1 = all)
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<DepthCloudOptions>& DepthCloudOptionsTable();

/// Lifts depth images of one camera to points. The per-pixel rays b / b_z are computed once (the
/// pinhole's distortion is inverted by Newton per pixel, too slow to repeat every frame).
class DepthCloudProjector {
 public:
  /// `options` must pass Check(), `model` its Check() and `range` 0 < min_m <= max_m.
  DepthCloudProjector(const DepthCloudOptions& options, const CameraModel& model,
                      const DepthRange& range);

  /// The points of `depth_m` (the model's size) in the camera frame, row by row: pixels with a
  /// depth inside the sensor's range [min_m, max_m] (0, non-finite and out-of-range depths are
  /// skipped). `points_in_camera` is cleared first.
  void PointsInCamera(const ImageF& depth_m, std::vector<Eigen::Vector3d>* points_in_camera) const;
  /// The same points in the world frame: world_from_camera * p_in_camera.
  void PointsInWorld(const ImageF& depth_m, const SE3& world_from_camera,
                     std::vector<Eigen::Vector3d>* points_in_world) const;

  /// How many pixels are sampled per image (the bound on a cloud's size).
  std::size_t sampled_pixel_count() const { return pixel_index_.size(); }

 private:
  int width_, height_;
  DepthRange range_;
  std::vector<std::size_t> pixel_index_;             // y * width + x of each sampled pixel
  std::vector<Eigen::Vector3d> ray_per_unit_depth_;  // b / b_z of each sampled pixel
};

}  // namespace corridorsim::slam
