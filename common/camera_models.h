// Camera projection models in the OpenCV optical frame: x right, y down, z forward (m).
// Pixel coordinates follow OpenCV: (0, 0) is the centre of the top-left pixel, so the image covers
// [-0.5, width - 0.5) x [-0.5, height - 0.5).
#pragma once

#include <optional>
#include <string>
#include <variant>

#include <Eigen/Core>

namespace corridorsim {

// Pinhole camera with OpenCV's radial-tangential ("plumb_bob") distortion:
//   x = X/Z, y = Y/Z, r^2 = x^2 + y^2, radial = 1 + k1 r^2 + k2 r^4 + k3 r^6,
//   x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2), y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y,
//   u = fx x_d + cx, v = fy y_d + cy.
struct PinholeRadTan {
  int width = 0;    // px
  int height = 0;   // px
  double fx = 0.0;  // px
  double fy = 0.0;  // px
  double cx = 0.0;  // px, principal point column
  double cy = 0.0;  // px, principal point row
  double k1 = 0.0;  // radial distortion coefficients (unitless)
  double k2 = 0.0;
  double p1 = 0.0;  // tangential distortion coefficients (unitless)
  double p2 = 0.0;
  double k3 = 0.0;

  // No distortion, fx = fy chosen so that the image spans `horizontal_fov_rad` edge to edge
  // (from column -0.5 to width - 0.5), principal point at the image centre.
  static PinholeRadTan FromFov(int width, int height, double horizontal_fov_rad);

  // Pixel of `p_in_camera` and, if asked for, its Jacobian (px/m). nullopt when z <= 0 or when the
  // normalised radius lies beyond the first turning point of the radial distortion r * radial(r),
  // where the model folds back onto the image.
  std::optional<Eigen::Vector2d> Project(
      const Eigen::Vector3d& p_in_camera,
      Eigen::Matrix<double, 2, 3>* d_pixel_d_point = nullptr) const;
  // Unit bearing in the camera frame; Gauss-Newton undistortion converged to ~1e-15 in normalised
  // coordinates for pixels inside the model's valid range.
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel) const;

  // Angle (rad) between the bearings of the left and right image edges, on the principal row.
  double HorizontalFovRad() const;
  // Angle (rad) between the bearings of the top and bottom image edges, on the principal column.
  double VerticalFovRad() const;
  // The larger of HorizontalFovRad() and VerticalFovRad(); Check() requires it below 150 deg.
  double FieldOfViewRad() const;

  bool IsInImage(const Eigen::Vector2d& pixel) const;
  // What is wrong with the parameters, or nullopt when they are valid.
  std::optional<std::string> Check() const;
};

// Kannala-Brandt equidistant fisheye as in OpenCV cv::fisheye and Kalibr "pinhole-equidistant":
//   theta = atan2(sqrt(X^2 + Y^2), Z), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6
//   + k4 theta^8), u = fx theta_d X / sqrt(X^2 + Y^2) + cx, v = fy theta_d Y / sqrt(X^2 + Y^2) +
//   cy.
// theta is taken from atan2, so points behind the image plane (z <= 0) project as long as theta is
// inside the valid range: below pi and below the first turning point of theta_d(theta).
struct KannalaBrandt {
  int width = 0;    // px
  int height = 0;   // px
  double fx = 0.0;  // px per rad of theta_d
  double fy = 0.0;  // px per rad of theta_d
  double cx = 0.0;  // px, principal point column
  double cy = 0.0;  // px, principal point row
  double k1 = 0.0;  // coefficients of theta^3 .. theta^9 (unitless)
  double k2 = 0.0;
  double k3 = 0.0;
  double k4 = 0.0;

  // Equidistant (k = 0), fx = fy = min(width, height) / fov_rad: the image circle of full angle
  // `fov_rad` has diameter min(width, height) px, i.e. the image spans `fov_rad` edge to edge along
  // its smaller dimension. Principal point at the image centre.
  static KannalaBrandt FromFov(int width, int height, double fov_rad);

  // Pixel of `p_in_camera` and, if asked for, its Jacobian (px/m). nullopt when theta is outside
  // the valid range (see above) or the point is at the origin.
  std::optional<Eigen::Vector2d> Project(
      const Eigen::Vector3d& p_in_camera,
      Eigen::Matrix<double, 2, 3>* d_pixel_d_point = nullptr) const;
  // Unit bearing in the camera frame; Newton solve of theta_d(theta), theta clamped to [0, pi].
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel) const;

  // Angle (rad) swept from the left to the right image edge, on the principal row (may exceed pi).
  double HorizontalFovRad() const;
  // Angle (rad) swept from the top to the bottom image edge, on the principal column.
  double VerticalFovRad() const;
  // Angle swept across the smaller image dimension (as FromFov); Check() requires it below 180 deg.
  double FieldOfViewRad() const;

  bool IsInImage(const Eigen::Vector2d& pixel) const;
  // What is wrong with the parameters, or nullopt when they are valid.
  std::optional<std::string> Check() const;
};

using CameraModel = std::variant<PinholeRadTan, KannalaBrandt>;

std::optional<Eigen::Vector2d> Project(const CameraModel& camera,
                                       const Eigen::Vector3d& p_in_camera,
                                       Eigen::Matrix<double, 2, 3>* d_pixel_d_point = nullptr);
Eigen::Vector3d Unproject(const CameraModel& camera, const Eigen::Vector2d& pixel);
bool IsInImage(const CameraModel& camera, const Eigen::Vector2d& pixel);
std::optional<std::string> Check(const CameraModel& camera);

}  // namespace corridorsim
