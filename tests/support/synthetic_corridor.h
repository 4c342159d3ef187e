#pragma once
// A synthetic corridor image for detector and pipeline tests: a box corridor drawn with OpenCV's
// anti-aliased polygons as a pinhole camera sees it, with its exact vanishing point.

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "common/image.h"
#include "slam/features/image_conversion.h"

namespace corridorsim::test {

inline constexpr int kCorridorImageWidth = 640;
inline constexpr int kCorridorImageHeight = 480;
inline constexpr double kCorridorDeg = std::numbers::pi / 180.0;

// A pinhole camera looking down a box corridor (world: x along the corridor, y left, z up).
struct CorridorView {
  double fx = 320.0 / std::tan(29.0 * kCorridorDeg);  // the front camera's 58 deg
  double cx = (kCorridorImageWidth - 1) / 2.0, cy = (kCorridorImageHeight - 1) / 2.0;
  Eigen::Vector3d camera_in_world{0.0, 0.3, 1.0};
  double yaw_rad = 4.0 * kCorridorDeg;
  double pitch_rad = -2.0 * kCorridorDeg;  // looking slightly down

  // camera (x right, y down, z forward) from world.
  Eigen::Matrix3d CameraFromWorld() const {
    const Eigen::Matrix3d world_from_body =
        (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(-pitch_rad, Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    Eigen::Matrix3d body_from_camera;  // body x forward, y left, z up
    body_from_camera << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    return (world_from_body * body_from_camera).transpose();
  }
  Eigen::Vector2d Project(const Eigen::Vector3d& p_in_world) const {
    const Eigen::Vector3d p = CameraFromWorld() * (p_in_world - camera_in_world);
    return {cx + fx * p.x() / p.z(), cy + fx * p.y() / p.z()};
  }
  // The corridor axis' vanishing point: the projection of the direction +x.
  Eigen::Vector2d VanishingPoint() const {
    const Eigen::Vector3d d = CameraFromWorld() * Eigen::Vector3d::UnitX();
    return {cx + fx * d.x() / d.z(), cy + fx * d.y() / d.z()};
  }
};

// Fills the world quad (corners in order) with grey `shade`, anti-aliased at 1/16 px.
inline void FillQuad(cv::Mat* image, const CorridorView& view,
                     const std::vector<Eigen::Vector3d>& quad, int shade) {
  std::vector<cv::Point> points;
  for (const Eigen::Vector3d& corner : quad) {
    const Eigen::Vector2d px = view.Project(corner);
    points.emplace_back(static_cast<int>(std::lround(px.x() * 16)),
                        static_cast<int>(std::lround(px.y() * 16)));
  }
  cv::fillConvexPoly(*image, points, cv::Scalar(shade, shade, shade), cv::LINE_AA, 4);
}

// A 2.4 m wide, 2.7 m high corridor from x = 0.5 m to an end wall at 30 m: floor in four strips
// of alternating shade, doors on both walls, lamp panels on the ceiling.
inline Image8 DrawCorridor(const CorridorView& view) {
  using V = Eigen::Vector3d;
  cv::Mat image(kCorridorImageHeight, kCorridorImageWidth, CV_8UC3, cv::Scalar(0, 0, 0));
  const double x0 = 0.5, x1 = 30.0, w = 1.2, h = 2.7;
  FillQuad(&image, view, {V(x1, w, 0), V(x1, -w, 0), V(x1, -w, h), V(x1, w, h)}, 120);    // end
  FillQuad(&image, view, {V(x0, w, h), V(x1, w, h), V(x1, -w, h), V(x0, -w, h)}, 215);    // ceiling
  FillQuad(&image, view, {V(x0, w, 0), V(x1, w, 0), V(x1, w, h), V(x0, w, h)}, 165);      // left
  FillQuad(&image, view, {V(x0, -w, 0), V(x0, -w, h), V(x1, -w, h), V(x1, -w, 0)}, 150);  // right
  for (int k = 0; k < 4; ++k) {
    const double ya = -w + 0.6 * k, yb = ya + 0.6;
    FillQuad(&image, view, {V(x0, ya, 0), V(x1, ya, 0), V(x1, yb, 0), V(x0, yb, 0)},
             k % 2 ? 55 : 85);
  }
  for (double x = 3.0; x + 1.0 < x1; x += 5.0) {
    const double side = std::fmod(x, 10.0) < 5.0 ? w - 0.001 : -w + 0.001;
    FillQuad(&image, view, {V(x, side, 0), V(x + 1, side, 0), V(x + 1, side, 2.1), V(x, side, 2.1)},
             95);
    FillQuad(&image, view,
             {V(x + 1.5, -0.3, h), V(x + 2.7, -0.3, h), V(x + 2.7, 0.3, h), V(x + 1.5, 0.3, h)},
             250);
  }
  return slam::ImageFromMat(image);
}

}  // namespace corridorsim::test
