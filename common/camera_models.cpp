#include "common/camera_models.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <type_traits>

#include <Eigen/LU>

namespace corridorsim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kPinholeMaxFovRad = 150.0 / kDegPerRad;
constexpr double kFisheyeMaxFovRad = 180.0 / kDegPerRad;
constexpr int kMaxSolverIterations = 50;
// The fisheye's safeguarded Newton: room for bisection steps over [0, pi] down to adjacent
// doubles (about 55) where Newton steps leave the bracket.
constexpr int kMaxFisheyeSolverIterations = 100;
// A model whose corner pixel does not survive Unproject -> Project within this (px) is rejected.
constexpr double kCornerRoundTripPx = 1e-6;
// Search bound for a turning point of the pinhole's distortion (squared normalised radius): far
// beyond any incidence angle a double can tell from 90 deg.
constexpr double kMaxSquaredRadius = 1e300;

// ---- the valid range: first root of a distortion slope polynomial ------------------------------

// c[0] + c[1] s + c[2] s^2 + ... (Horner).
double Evaluate(const std::vector<double>& c, double s) {
  double value = 0.0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) value = value * s + *it;
  return value;
}

std::vector<double> Derivative(const std::vector<double>& c) {
  std::vector<double> d;
  for (std::size_t i = 1; i < c.size(); ++i) d.push_back(static_cast<double>(i) * c[i]);
  return d;
}

// The polynomial without its zero leading coefficients.
std::vector<double> Trimmed(std::vector<double> c) {
  while (!c.empty() && c.back() == 0.0) c.pop_back();
  return c;
}

// Bisection on [lo, hi] where c changes sign (c(lo) and c(hi) of opposite signs or c(hi) == 0,
// c monotone): the end of the last interval of adjacent doubles, on the side of hi's sign.
double Bisect(const std::vector<double>& c, double lo, double hi) {
  const bool hi_positive = Evaluate(c, hi) > 0.0;
  for (;;) {
    const double mid = lo + 0.5 * (hi - lo);
    if (!(mid > lo && mid < hi)) return hi;
    ((Evaluate(c, mid) > 0.0) == hi_positive ? hi : lo) = mid;
  }
}

// The points in (lo, hi) where the polynomial c changes sign, ascending (roots of even
// multiplicity, where it only touches zero, may be missing). Between consecutive roots of c' the
// polynomial is monotone, so each such piece holds at most one sign change.
std::vector<double> SignChanges(const std::vector<double>& c, double lo, double hi) {
  const std::vector<double> p = Trimmed(c);
  if (p.size() <= 1) return {};
  std::vector<double> ends = {lo};
  if (p.size() == 2) {
    ends.push_back(hi);
  } else {
    for (const double s : SignChanges(Derivative(p), lo, hi)) ends.push_back(s);
    ends.push_back(hi);
  }
  std::vector<double> roots;
  for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
    const double a = Evaluate(p, ends[i]), b = Evaluate(p, ends[i + 1]);
    if ((a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0)) {
      roots.push_back(Bisect(p, ends[i], ends[i + 1]));
    }
  }
  return roots;
}

// The first s in [0, hi] where the slope polynomial c (c[0] = 1) is not positive, or +inf when it
// stays positive there (and for non-finite coefficients, which Check() rejects).
double FirstNonPositive(const std::vector<double>& c, double hi) {
  for (const double coefficient : c) {
    if (!std::isfinite(coefficient)) return kInfinity;
  }
  const std::vector<double> p = Trimmed(c);
  std::vector<double> ends = {0.0};
  for (const double s : SignChanges(Derivative(p), 0.0, hi)) ends.push_back(s);
  ends.push_back(hi);
  // Monotone pieces in order: the first whose end is not positive holds the root.
  for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
    if (Evaluate(p, ends[i + 1]) <= 0.0) {
      const double lo = ends[i], end = ends[i + 1];
      // p(lo) > 0 >= p(end): the smallest double of the piece with p <= 0, by bisection.
      double a = lo, b = end;
      for (;;) {
        const double mid = a + 0.5 * (b - a);
        if (!(mid > a && mid < b)) return b;
        (Evaluate(p, mid) <= 0.0 ? b : a) = mid;
      }
    }
  }
  return kInfinity;
}

// The pinhole's valid range as a squared normalised radius: the first turning point of
// r * radial(r), where d(r radial(r)) / dr = 1 + 3 k1 r^2 + 5 k2 r^4 + 7 k3 r^6 reaches zero.
double PinholeMaxSquaredRadius(const PinholeRadTan& c) {
  const std::vector<double> slope = {1.0, 3.0 * c.k1, 5.0 * c.k2, 7.0 * c.k3};
  // Beyond the Cauchy bound 1 + max |c_i / c_n| the slope has no root.
  const std::vector<double> p = Trimmed(slope);
  double bound = 0.0;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    bound = std::max(bound, std::abs(p[i] / p.back()));
  }
  return FirstNonPositive(slope, std::min(1.0 + bound, kMaxSquaredRadius));
}

// The fisheye's valid range: theta below pi and below the first turning point of theta_d, where
// d theta_d / d theta = 1 + 3 k1 theta^2 + 5 k2 theta^4 + 7 k3 theta^6 + 9 k4 theta^8 reaches 0.
double FisheyeMaxTheta(const KannalaBrandt& c) {
  const double max_theta2 =
      FirstNonPositive({1.0, 3.0 * c.k1, 5.0 * c.k2, 7.0 * c.k3, 9.0 * c.k4}, kPi * kPi);
  return std::min(kPi, std::sqrt(max_theta2));
}

// ---- checks ---------------------------------------------------------------------------------

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
std::optional<std::string> CheckCorners(const CameraModel& camera) {
  const double right = camera.width() - 0.5;
  const double bottom = camera.height() - 0.5;
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
double AngleBetweenEdges(const CameraModel& camera, const Eigen::Vector2d& first,
                         const Eigen::Vector2d& second, int axis) {
  const Eigen::Vector3d a = camera.Unproject(first);
  const Eigen::Vector3d b = camera.Unproject(second);
  return std::atan2(b[axis], b.z()) - std::atan2(a[axis], a.z());
}

// ---- PinholeRadTan ----------------------------------------------------------------------------

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

std::optional<Eigen::Vector2d> ProjectPinhole(const PinholeRadTan& c, double max_squared_radius,
                                              const Eigen::Vector3d& p_in_camera,
                                              Eigen::Matrix<double, 2, 3>* d_pixel_d_point) {
  const double z = p_in_camera.z();
  if (!(z > 0.0)) return std::nullopt;
  const Eigen::Vector2d xy = p_in_camera.head<2>() / z;
  if (!(xy.squaredNorm() < max_squared_radius)) return std::nullopt;

  Eigen::Matrix2d d_distorted_d_xy;
  const Eigen::Vector2d distorted =
      Distort(c, xy, d_pixel_d_point != nullptr ? &d_distorted_d_xy : nullptr);
  if (d_pixel_d_point != nullptr) {
    Eigen::Matrix<double, 2, 3> d_xy_d_point;
    d_xy_d_point << 1.0 / z, 0.0, -xy.x() / z, 0.0, 1.0 / z, -xy.y() / z;
    *d_pixel_d_point = Eigen::Vector2d(c.fx, c.fy).asDiagonal() * d_distorted_d_xy * d_xy_d_point;
  }
  return Eigen::Vector2d(c.fx * distorted.x() + c.cx, c.fy * distorted.y() + c.cy);
}

Eigen::Vector3d UnprojectPinhole(const PinholeRadTan& c, const Eigen::Vector2d& pixel,
                                 Eigen::Matrix<double, 3, 2>* d_bearing_d_pixel) {
  const Eigen::Vector2d target((pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy);
  // Newton (square Gauss-Newton) on Distort(xy) = target, started at the distorted point.
  Eigen::Vector2d xy = target;
  for (int i = 0; i < kMaxSolverIterations; ++i) {
    Eigen::Matrix2d d_distorted_d_xy;
    const Eigen::Vector2d residual = Distort(c, xy, &d_distorted_d_xy) - target;
    const Eigen::Vector2d step = d_distorted_d_xy.partialPivLu().solve(residual);
    if (!step.allFinite()) break;
    xy -= step;
    if (step.norm() <= 1e-15 * std::max(1.0, xy.norm())) break;
  }
  const Eigen::Vector3d ray(xy.x(), xy.y(), 1.0);
  const Eigen::Vector3d bearing = ray.normalized();
  if (d_bearing_d_pixel != nullptr) {
    // bearing = ray / |ray|: d bearing / d ray = (I - b b^T) / |ray|; d xy / d target is the
    // inverse of the distortion's Jacobian at the solution; d target / d pixel = diag(1/fx, 1/fy).
    Eigen::Matrix2d d_distorted_d_xy;
    Distort(c, xy, &d_distorted_d_xy);
    const Eigen::Matrix<double, 3, 2> d_bearing_d_xy =
        ((Eigen::Matrix3d::Identity() - bearing * bearing.transpose()) / ray.norm()).leftCols<2>();
    *d_bearing_d_pixel = d_bearing_d_xy * d_distorted_d_xy.inverse() *
                         Eigen::Vector2d(1.0 / c.fx, 1.0 / c.fy).asDiagonal();
  }
  return bearing;
}

// ---- KannalaBrandt ----------------------------------------------------------------------------

// 1 + 3 k1 t + 5 k2 t^2 + 7 k3 t^3 + 9 k4 t^4 at t = theta^2: d theta_d / d theta.
double FisheyeSlope(const KannalaBrandt& c, double theta2) {
  const double c1 = 3.0 * c.k1, c2 = 5.0 * c.k2, c3 = 7.0 * c.k3, c4 = 9.0 * c.k4;
  return 1.0 + theta2 * (c1 + theta2 * (c2 + theta2 * (c3 + theta2 * c4)));
}

std::optional<Eigen::Vector2d> ProjectFisheye(const KannalaBrandt& c, double max_theta,
                                              const Eigen::Vector3d& p_in_camera,
                                              Eigen::Matrix<double, 2, 3>* d_pixel_d_point) {
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
      *d_pixel_d_point << c.fx / z, 0.0, -c.fx * x / (z * z), 0.0, c.fy / z, -c.fy * y / (z * z);
    }
    return Eigen::Vector2d(c.fx * x / z + c.cx, c.fy * y / z + c.cy);
  }

  const double theta = std::atan2(r_xy, z);
  if (!(theta < max_theta)) return std::nullopt;
  const double theta2 = theta * theta;
  const double theta_d =
      theta * (1.0 + theta2 * (c.k1 + theta2 * (c.k2 + theta2 * (c.k3 + theta2 * c.k4))));
  const double scale = theta_d / r_xy;  // px per m before fx, fy

  if (d_pixel_d_point != nullptr) {
    const double d_theta_d_d_theta = FisheyeSlope(c, theta2);
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
    *d_pixel_d_point = Eigen::Vector2d(c.fx, c.fy).asDiagonal() * d_normalised_d_point;
  }
  return Eigen::Vector2d(c.fx * scale * x + c.cx, c.fy * scale * y + c.cy);
}

Eigen::Vector3d UnprojectFisheye(const KannalaBrandt& c, double max_theta,
                                 const Eigen::Vector2d& pixel,
                                 Eigen::Matrix<double, 3, 2>* d_bearing_d_pixel) {
  const Eigen::Vector2d normalised((pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy);
  const Eigen::Matrix2d d_normalised_d_pixel = Eigen::Vector2d(1.0 / c.fx, 1.0 / c.fy).asDiagonal();
  const double theta_d = normalised.norm();
  if (!(theta_d > 0.0)) {
    // At the principal point theta = theta_d to first order: d bearing / d normalised = [I; 0].
    if (d_bearing_d_pixel != nullptr) {
      d_bearing_d_pixel->setZero();
      d_bearing_d_pixel->topRows<2>() = d_normalised_d_pixel;
    }
    return Eigen::Vector3d::UnitZ();
  }

  // Newton on theta (1 + k1 theta^2 + ...) = theta_d, started at the equidistant solution and
  // kept inside the valid range [0, max_theta], where theta_d(theta) increases: the bracket
  // [lo, hi] holds the root, and a step that leaves it (or a slope that is not positive) bisects
  // instead. Beyond the valid range theta tends to max_theta.
  double lo = 0.0, hi = max_theta;
  double theta = std::min(theta_d, max_theta);
  for (int i = 0; i < kMaxFisheyeSolverIterations; ++i) {
    const double theta2 = theta * theta;
    const double residual =
        theta * (1.0 + theta2 * (c.k1 + theta2 * (c.k2 + theta2 * (c.k3 + theta2 * c.k4)))) -
        theta_d;
    if (residual == 0.0) break;
    (residual > 0.0 ? hi : lo) = theta;
    const double slope = FisheyeSlope(c, theta2);
    double next = theta - residual / slope;
    if (!(slope > 0.0) || !(next >= lo && next <= hi)) next = lo + 0.5 * (hi - lo);
    const double step = theta - next;
    theta = next;
    if (std::abs(step) <= 1e-15 * std::max(1.0, theta)) break;
  }
  const Eigen::Vector2d direction = normalised / theta_d;
  const double sin_theta = std::sin(theta);
  const double cos_theta = std::cos(theta);
  if (d_bearing_d_pixel != nullptr) {
    // bearing = (g(theta_d) n, cos theta) with g = sin theta / theta_d and d theta / d theta_d =
    // 1 / slope; d theta_d / d n = direction^T.
    const double d_theta_d_theta_d = 1.0 / FisheyeSlope(c, theta * theta);
    const double g = sin_theta / theta_d;
    const double d_g_d_theta_d = (cos_theta * d_theta_d_theta_d - g) / theta_d;
    Eigen::Matrix<double, 3, 2> d_bearing_d_normalised;
    d_bearing_d_normalised.topRows<2>() =
        g * Eigen::Matrix2d::Identity() + d_g_d_theta_d * normalised * direction.transpose();
    d_bearing_d_normalised.row(2) = -sin_theta * d_theta_d_theta_d * direction.transpose();
    *d_bearing_d_pixel = d_bearing_d_normalised * d_normalised_d_pixel;
  }
  return Eigen::Vector3d(sin_theta * direction.x(), sin_theta * direction.y(), cos_theta);
}

std::optional<std::string> CheckPinhole(const CameraModel& camera) {
  const PinholeRadTan& c = *camera.pinhole();
  if (auto problem = CheckCommon(c)) return problem;
  if (!std::isfinite(c.k1) || !std::isfinite(c.k2) || !std::isfinite(c.k3) ||
      !std::isfinite(c.p1) || !std::isfinite(c.p2)) {
    return "distortion coefficients must be finite";
  }
  if (auto problem = CheckCorners(camera)) return problem;
  const double fov = camera.FieldOfViewRad();
  if (!(fov < kPinholeMaxFovRad)) {
    return "pinhole field of view " + FormatDeg(fov) + " must be below " +
           FormatDeg(kPinholeMaxFovRad) + "; use a fisheye model";
  }
  return std::nullopt;
}

std::optional<std::string> CheckFisheye(const CameraModel& camera) {
  const KannalaBrandt& c = *camera.kannala_brandt();
  if (auto problem = CheckCommon(c)) return problem;
  if (!std::isfinite(c.k1) || !std::isfinite(c.k2) || !std::isfinite(c.k3) ||
      !std::isfinite(c.k4)) {
    return "distortion coefficients must be finite";
  }
  const double fov = camera.FieldOfViewRad();
  if (!(fov < kFisheyeMaxFovRad)) {
    return "fisheye field of view " + FormatDeg(fov) + " must be below " +
           FormatDeg(kFisheyeMaxFovRad);
  }
  if (auto problem = CheckCorners(camera)) return problem;
  return std::nullopt;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Parameter structs

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

std::string_view CameraModelKindName(CameraModelKind kind) {
  return kind == CameraModelKind::kPinholeRadTan ? "pinhole_radtan" : "kannala_brandt";
}

// ---------------------------------------------------------------------------------------------
// CameraModel

CameraModel::CameraModel() : CameraModel(PinholeRadTan{}) {}

CameraModel::CameraModel(const PinholeRadTan& pinhole)
    : params_(pinhole),
      max_squared_radius_(PinholeMaxSquaredRadius(pinhole)),
      max_incidence_rad_(std::atan(std::sqrt(max_squared_radius_))) {}

CameraModel::CameraModel(const KannalaBrandt& kannala_brandt)
    : params_(kannala_brandt),
      max_squared_radius_(kInfinity),
      max_incidence_rad_(FisheyeMaxTheta(kannala_brandt)) {}

CameraModelKind CameraModel::kind() const {
  return pinhole() != nullptr ? CameraModelKind::kPinholeRadTan : CameraModelKind::kKannalaBrandt;
}

int CameraModel::width() const {
  return std::visit([](const auto& m) { return m.width; }, params_);
}

int CameraModel::height() const {
  return std::visit([](const auto& m) { return m.height; }, params_);
}

Eigen::Vector2d CameraModel::principal_point() const {
  return std::visit([](const auto& m) { return Eigen::Vector2d(m.cx, m.cy); }, params_);
}

CameraIntrinsics CameraModel::intrinsics() const {
  return std::visit(
      [&](const auto& m) {
        CameraIntrinsics in{std::string(name()), m.width, m.height, m.fx, m.fy, m.cx, m.cy, {}};
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, PinholeRadTan>) {
          in.distortion = {m.k1, m.k2, m.p1, m.p2, m.k3};
        } else {
          in.distortion = {m.k1, m.k2, m.k3, m.k4};
        }
        return in;
      },
      params_);
}

std::optional<Eigen::Vector2d> CameraModel::Project(
    const Eigen::Vector3d& p_in_camera, Eigen::Matrix<double, 2, 3>* d_pixel_d_point) const {
  if (const PinholeRadTan* p = pinhole()) {
    return ProjectPinhole(*p, max_squared_radius_, p_in_camera, d_pixel_d_point);
  }
  return ProjectFisheye(*kannala_brandt(), max_incidence_rad_, p_in_camera, d_pixel_d_point);
}

Eigen::Vector3d CameraModel::Unproject(const Eigen::Vector2d& pixel,
                                       Eigen::Matrix<double, 3, 2>* d_bearing_d_pixel) const {
  if (const PinholeRadTan* p = pinhole()) return UnprojectPinhole(*p, pixel, d_bearing_d_pixel);
  return UnprojectFisheye(*kannala_brandt(), max_incidence_rad_, pixel, d_bearing_d_pixel);
}

bool CameraModel::IsInImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() < width() - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() < height() - 0.5;
}

double CameraModel::HorizontalFovRad() const {
  const double cy = std::visit([](const auto& m) { return m.cy; }, params_);
  return AngleBetweenEdges(*this, {-0.5, cy}, {width() - 0.5, cy}, 0);
}

double CameraModel::VerticalFovRad() const {
  const double cx = std::visit([](const auto& m) { return m.cx; }, params_);
  return AngleBetweenEdges(*this, {cx, -0.5}, {cx, height() - 0.5}, 1);
}

double CameraModel::FieldOfViewRad() const {
  if (pinhole() != nullptr) return std::max(HorizontalFovRad(), VerticalFovRad());
  return width() <= height() ? HorizontalFovRad() : VerticalFovRad();
}

std::optional<std::string> CameraModel::Check() const {
  return pinhole() != nullptr ? CheckPinhole(*this) : CheckFisheye(*this);
}

}  // namespace corridorsim
