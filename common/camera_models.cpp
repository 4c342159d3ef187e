#include "common/camera_models.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

#include <Eigen/LU>

namespace corridorsim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kPinholeMaxFovRad = 150.0 / kDegPerRad;
constexpr double kFisheyeMaxFovRad = 180.0 / kDegPerRad;
constexpr int kMaxSolverIterations = 50;
// Incidence-angle step (rad) of the scan for a turning point of the distortion.
constexpr double kMonotoneScanStepRad = 0.005;
// A model whose corner pixel does not survive Unproject -> Project within this (px) is rejected.
constexpr double kCornerRoundTripPx = 1e-6;

// 1 + c[0] s + c[1] s^2 + c[2] s^3 + c[3] s^4.
double SlopePolynomial(const std::array<double, 4>& c, double s) {
  return 1.0 + s * (c[0] + s * (c[1] + s * (c[2] + s * c[3])));
}

// True when the distortion slope SlopePolynomial(c, s(angle)) stays positive for incidence angles
// in [0, max_angle], where s(angle) = squared_radius(angle). A lower bound (negative terms only)
// and the end point settle most calls; otherwise the angle is scanned in kMonotoneScanStepRad
// steps.
template <class SquaredRadius>
bool SlopePositiveUpTo(const std::array<double, 4>& c, double max_angle,
                       SquaredRadius squared_radius) {
  const std::array<double, 4> negative_part = {std::min(c[0], 0.0), std::min(c[1], 0.0),
                                               std::min(c[2], 0.0), std::min(c[3], 0.0)};
  const double max_squared_radius = squared_radius(max_angle);
  if (SlopePolynomial(negative_part, max_squared_radius) > 0.0) return true;
  if (SlopePolynomial(c, max_squared_radius) <= 0.0) return false;
  for (double angle = 0.0;; angle += kMonotoneScanStepRad) {
    angle = std::min(angle, max_angle);
    if (SlopePolynomial(c, squared_radius(angle)) <= 0.0) return false;
    if (angle == max_angle) return true;
  }
}

std::string FormatDeg(double rad) {
  std::ostringstream out;
  out << rad * kDegPerRad << " deg";
  return out.str();
}

// Problems shared by both models: image size, focal lengths, finiteness.
template <class Camera>
std::optional<std::string> CheckCommon(const Camera& camera) {
  std::ostringstream out;
  if (camera.width <= 0 || camera.height <= 0) {
    out << "image size must be positive, got " << camera.width << "x" << camera.height;
    return out.str();
  }
  if (!(camera.fx > 0.0) || !(camera.fy > 0.0) || !std::isfinite(camera.fx) ||
      !std::isfinite(camera.fy)) {
    out << "focal lengths must be positive and finite, got fx=" << camera.fx << " fy=" << camera.fy;
    return out.str();
  }
  if (!std::isfinite(camera.cx) || !std::isfinite(camera.cy)) {
    out << "principal point must be finite, got cx=" << camera.cx << " cy=" << camera.cy;
    return out.str();
  }
  return std::nullopt;
}

// The model must map every image corner to a bearing and back; otherwise the distortion has
// turned over (or run out of angle) inside the image.
template <class Camera>
std::optional<std::string> CheckCorners(const Camera& camera) {
  const double right = camera.width - 0.5;
  const double bottom = camera.height - 0.5;
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(right, -0.5), Eigen::Vector2d(-0.5, bottom),
        Eigen::Vector2d(right, bottom)}) {
    const std::optional<Eigen::Vector2d> reprojected = camera.Project(camera.Unproject(corner));
    if (!reprojected || (*reprojected - corner).norm() > kCornerRoundTripPx) {
      std::ostringstream out;
      out << "distortion is not invertible at image corner (" << corner.x() << ", " << corner.y()
          << ")";
      return out.str();
    }
  }
  return std::nullopt;
}

// Signed angle (rad) between the bearings of two pixels, measured in the plane of `axis` and z.
template <class Camera>
double AngleBetweenEdges(const Camera& camera, const Eigen::Vector2d& first,
                         const Eigen::Vector2d& second, int axis) {
  const Eigen::Vector3d a = camera.Unproject(first);
  const Eigen::Vector3d b = camera.Unproject(second);
  return std::atan2(b[axis], b.z()) - std::atan2(a[axis], a.z());
}

// Radial-tangential distortion of normalised coordinates, with its 2x2 Jacobian if asked for.
Eigen::Vector2d Distort(const PinholeRadTan& c, const Eigen::Vector2d& xy,
                        Eigen::Matrix2d* d_distorted_d_xy) {
  const double x = xy.x();
  const double y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  const Eigen::Vector2d distorted(x * radial + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x),
                                  y * radial + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y);
  if (d_distorted_d_xy != nullptr) {
    const double d_radial_d_r2 = c.k1 + r2 * (2.0 * c.k2 + r2 * 3.0 * c.k3);
    *d_distorted_d_xy << radial + 2.0 * x * x * d_radial_d_r2 + 2.0 * c.p1 * y + 6.0 * c.p2 * x,
        2.0 * x * y * d_radial_d_r2 + 2.0 * c.p1 * x + 2.0 * c.p2 * y,
        2.0 * x * y * d_radial_d_r2 + 2.0 * c.p1 * x + 2.0 * c.p2 * y,
        radial + 2.0 * y * y * d_radial_d_r2 + 6.0 * c.p1 * y + 2.0 * c.p2 * x;
  }
  return distorted;
}

// d(r radial(r)) / dr as a polynomial in r^2.
std::array<double, 4> PinholeRadialSlope(const PinholeRadTan& c) {
  return {3.0 * c.k1, 5.0 * c.k2, 7.0 * c.k3, 0.0};
}

// d theta_d / d theta as a polynomial in theta^2.
std::array<double, 4> FisheyeThetaSlope(const KannalaBrandt& c) {
  return {3.0 * c.k1, 5.0 * c.k2, 7.0 * c.k3, 9.0 * c.k4};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// PinholeRadTan

PinholeRadTan PinholeRadTan::FromFov(int width, int height, double horizontal_fov_rad) {
  PinholeRadTan camera;
  camera.width = width;
  camera.height = height;
  camera.fx = 0.5 * width / std::tan(0.5 * horizontal_fov_rad);
  camera.fy = camera.fx;
  camera.cx = 0.5 * (width - 1);
  camera.cy = 0.5 * (height - 1);
  return camera;
}

std::optional<Eigen::Vector2d> PinholeRadTan::Project(
    const Eigen::Vector3d& p_in_camera, Eigen::Matrix<double, 2, 3>* d_pixel_d_point) const {
  const double z = p_in_camera.z();
  if (!(z > 0.0)) return std::nullopt;
  const Eigen::Vector2d xy = p_in_camera.head<2>() / z;
  const double r2 = xy.squaredNorm();
  if (!SlopePositiveUpTo(PinholeRadialSlope(*this), std::atan(std::sqrt(r2)), [](double angle) {
        const double r = std::tan(angle);
        return r * r;
      })) {
    return std::nullopt;
  }

  Eigen::Matrix2d d_distorted_d_xy;
  const Eigen::Vector2d distorted =
      Distort(*this, xy, d_pixel_d_point != nullptr ? &d_distorted_d_xy : nullptr);
  if (d_pixel_d_point != nullptr) {
    Eigen::Matrix<double, 2, 3> d_xy_d_point;
    d_xy_d_point << 1.0 / z, 0.0, -xy.x() / z, 0.0, 1.0 / z, -xy.y() / z;
    *d_pixel_d_point = Eigen::Vector2d(fx, fy).asDiagonal() * d_distorted_d_xy * d_xy_d_point;
  }
  return Eigen::Vector2d(fx * distorted.x() + cx, fy * distorted.y() + cy);
}

Eigen::Vector3d PinholeRadTan::Unproject(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d target((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  // Newton (square Gauss-Newton) on Distort(xy) = target, started at the distorted point.
  Eigen::Vector2d xy = target;
  for (int i = 0; i < kMaxSolverIterations; ++i) {
    Eigen::Matrix2d d_distorted_d_xy;
    const Eigen::Vector2d residual = Distort(*this, xy, &d_distorted_d_xy) - target;
    const Eigen::Vector2d step = d_distorted_d_xy.partialPivLu().solve(residual);
    if (!step.allFinite()) break;
    xy -= step;
    if (step.norm() <= 1e-15 * std::max(1.0, xy.norm())) break;
  }
  return Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
}

double PinholeRadTan::HorizontalFovRad() const {
  return AngleBetweenEdges(*this, {-0.5, cy}, {width - 0.5, cy}, 0);
}

double PinholeRadTan::VerticalFovRad() const {
  return AngleBetweenEdges(*this, {cx, -0.5}, {cx, height - 0.5}, 1);
}

double PinholeRadTan::FieldOfViewRad() const {
  return std::max(HorizontalFovRad(), VerticalFovRad());
}

bool PinholeRadTan::IsInImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() < width - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() < height - 0.5;
}

std::optional<std::string> PinholeRadTan::Check() const {
  if (auto problem = CheckCommon(*this)) return problem;
  if (!std::isfinite(k1) || !std::isfinite(k2) || !std::isfinite(k3) || !std::isfinite(p1) ||
      !std::isfinite(p2)) {
    return "distortion coefficients must be finite";
  }
  if (auto problem = CheckCorners(*this)) return problem;
  const double fov = FieldOfViewRad();
  if (!(fov < kPinholeMaxFovRad)) {
    return "pinhole field of view " + FormatDeg(fov) + " must be below " +
           FormatDeg(kPinholeMaxFovRad) + "; use a fisheye model";
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// KannalaBrandt

KannalaBrandt KannalaBrandt::FromFov(int width, int height, double fov_rad) {
  KannalaBrandt camera;
  camera.width = width;
  camera.height = height;
  camera.fx = std::min(width, height) / fov_rad;
  camera.fy = camera.fx;
  camera.cx = 0.5 * (width - 1);
  camera.cy = 0.5 * (height - 1);
  return camera;
}

std::optional<Eigen::Vector2d> KannalaBrandt::Project(
    const Eigen::Vector3d& p_in_camera, Eigen::Matrix<double, 2, 3>* d_pixel_d_point) const {
  const double x = p_in_camera.x();
  const double y = p_in_camera.y();
  const double z = p_in_camera.z();
  const double r_xy = std::hypot(x, y);
  const double norm = p_in_camera.norm();
  if (!(norm > 0.0)) return std::nullopt;

  // On (or within rounding of) the optical axis in front of the camera: theta_d / r_xy -> 1 / z.
  if (r_xy <= 1e-9 * norm) {
    if (!(z > 0.0)) return std::nullopt;
    if (d_pixel_d_point != nullptr) {
      *d_pixel_d_point << fx / z, 0.0, -fx * x / (z * z), 0.0, fy / z, -fy * y / (z * z);
    }
    return Eigen::Vector2d(fx * x / z + cx, fy * y / z + cy);
  }

  const double theta = std::atan2(r_xy, z);
  const std::array<double, 4> slope_coefficients = FisheyeThetaSlope(*this);
  if (!(theta < kPi) ||
      !SlopePositiveUpTo(slope_coefficients, theta, [](double angle) { return angle * angle; })) {
    return std::nullopt;
  }
  const double theta2 = theta * theta;
  const double theta_d =
      theta * (1.0 + theta2 * (k1 + theta2 * (k2 + theta2 * (k3 + theta2 * k4))));
  const double scale = theta_d / r_xy;  // px per m before fx, fy

  if (d_pixel_d_point != nullptr) {
    const double d_theta_d_d_theta = SlopePolynomial(slope_coefficients, theta2);
    // d theta / d(x, y) = z (x, y) / (r_xy norm^2), d theta / dz = -r_xy / norm^2;
    // d r_xy / d(x, y) = (x, y) / r_xy.
    const double norm2 = norm * norm;
    const double d_scale_d_r_common =
        (d_theta_d_d_theta * z / norm2 - theta_d / r_xy) / (r_xy * r_xy);
    const Eigen::RowVector3d d_scale_d_point(d_scale_d_r_common * x, d_scale_d_r_common * y,
                                             -d_theta_d_d_theta / norm2);
    Eigen::Matrix<double, 2, 3> d_normalised_d_point;
    d_normalised_d_point.row(0) = x * d_scale_d_point;
    d_normalised_d_point.row(1) = y * d_scale_d_point;
    d_normalised_d_point(0, 0) += scale;
    d_normalised_d_point(1, 1) += scale;
    *d_pixel_d_point = Eigen::Vector2d(fx, fy).asDiagonal() * d_normalised_d_point;
  }
  return Eigen::Vector2d(fx * scale * x + cx, fy * scale * y + cy);
}

Eigen::Vector3d KannalaBrandt::Unproject(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d normalised((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  const double theta_d = normalised.norm();
  if (!(theta_d > 0.0)) return Eigen::Vector3d::UnitZ();

  // Newton on theta (1 + k1 theta^2 + ...) = theta_d, started at the equidistant solution.
  const std::array<double, 4> slope_coefficients = FisheyeThetaSlope(*this);
  double theta = std::min(theta_d, kPi);
  for (int i = 0; i < kMaxSolverIterations; ++i) {
    const double theta2 = theta * theta;
    const double residual =
        theta * (1.0 + theta2 * (k1 + theta2 * (k2 + theta2 * (k3 + theta2 * k4)))) - theta_d;
    const double slope = SlopePolynomial(slope_coefficients, theta2);
    if (!(slope > 0.0)) break;
    const double step = residual / slope;
    theta = std::clamp(theta - step, 0.0, kPi);
    if (std::abs(step) <= 1e-15 * std::max(1.0, theta)) break;
  }
  const Eigen::Vector2d direction = normalised / theta_d;
  return Eigen::Vector3d(std::sin(theta) * direction.x(), std::sin(theta) * direction.y(),
                         std::cos(theta));
}

double KannalaBrandt::HorizontalFovRad() const {
  return AngleBetweenEdges(*this, {-0.5, cy}, {width - 0.5, cy}, 0);
}

double KannalaBrandt::VerticalFovRad() const {
  return AngleBetweenEdges(*this, {cx, -0.5}, {cx, height - 0.5}, 1);
}

double KannalaBrandt::FieldOfViewRad() const {
  return width <= height ? HorizontalFovRad() : VerticalFovRad();
}

bool KannalaBrandt::IsInImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() < width - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() < height - 0.5;
}

std::optional<std::string> KannalaBrandt::Check() const {
  if (auto problem = CheckCommon(*this)) return problem;
  if (!std::isfinite(k1) || !std::isfinite(k2) || !std::isfinite(k3) || !std::isfinite(k4)) {
    return "distortion coefficients must be finite";
  }
  const double fov = FieldOfViewRad();
  if (!(fov < kFisheyeMaxFovRad)) {
    return "fisheye field of view " + FormatDeg(fov) + " must be below " +
           FormatDeg(kFisheyeMaxFovRad);
  }
  if (auto problem = CheckCorners(*this)) return problem;
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// CameraModel visitors

std::optional<Eigen::Vector2d> Project(const CameraModel& camera,
                                       const Eigen::Vector3d& p_in_camera,
                                       Eigen::Matrix<double, 2, 3>* d_pixel_d_point) {
  return std::visit([&](const auto& model) { return model.Project(p_in_camera, d_pixel_d_point); },
                    camera);
}

Eigen::Vector3d Unproject(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  return std::visit([&](const auto& model) { return model.Unproject(pixel); }, camera);
}

bool IsInImage(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  return std::visit([&](const auto& model) { return model.IsInImage(pixel); }, camera);
}

std::optional<std::string> Check(const CameraModel& camera) {
  return std::visit([](const auto& model) { return model.Check(); }, camera);
}

}  // namespace corridorsim
