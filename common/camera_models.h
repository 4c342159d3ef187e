// Camera projection models in the OpenCV optical frame: x right, y down, z forward (m).
// Pixel coordinates follow OpenCV: (0, 0) is the centre of the top-left pixel, so the image covers
// [-0.5, width - 0.5) x [-0.5, height - 0.5).
//
// The parameter structs (PinholeRadTan, KannalaBrandt) are plain data; CameraModel wraps one of
// them behind one interface (as COLMAP's camera models and OpenVINS' CamBase): Project and
// Unproject with their Jacobians, the field of view, Check(), and the intrinsics as calibration
// files write them. A CameraModel is immutable: build the parameters, then assign them.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/Core>

namespace corridorsim {

// Pinhole camera with OpenCV's radial-tangential ("plumb_bob") distortion:
//   x = X/Z, y = Y/Z, r^2 = x^2 + y^2, radial = 1 + k1 r^2 + k2 r^4 + k3 r^6,
//   x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2), y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y,
//   u = fx x_d + cx, v = fy y_d + cy.
// Points project when z > 0 and the normalised radius lies before the first turning point of the
// radial distortion r * radial(r), where the model folds back onto the image.
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

  bool operator==(const PinholeRadTan&) const = default;
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

  bool operator==(const KannalaBrandt&) const = default;
};

enum class CameraModelKind { kPinholeRadTan, kKannalaBrandt };

/// "pinhole_radtan" or "kannala_brandt": the `model` of intrinsics.json.
std::string_view CameraModelKindName(CameraModelKind kind);

/// A model's intrinsics as calibration files hold them.
struct CameraIntrinsics {
  std::string model;  // CameraModelKindName: "pinhole_radtan" or "kannala_brandt"
  int width = 0;      // px
  int height = 0;     // px
  double fx = 0.0;    // px (fisheye: px per rad of theta_d)
  double fy = 0.0;    // px
  double cx = 0.0;    // px, principal point column
  double cy = 0.0;    // px, principal point row
  // pinhole_radtan: k1, k2, p1, p2, k3 (OpenCV's order; Kalibr's radial-tangential takes the
  // first four); kannala_brandt: k1, k2, k3, k4 (cv::fisheye, Kalibr's equidistant).
  std::vector<double> distortion;
};

/// One camera's projection model: a PinholeRadTan or a KannalaBrandt and what follows from its
/// parameters (the valid range, computed once). Copyable and immutable.
class CameraModel {
 public:
  /// An empty pinhole (0 x 0 px); Check() reports it.
  CameraModel();
  CameraModel(const PinholeRadTan& pinhole);         // NOLINT(google-explicit-constructor)
  CameraModel(const KannalaBrandt& kannala_brandt);  // NOLINT(google-explicit-constructor)

  CameraModelKind kind() const;
  /// CameraModelKindName(kind()).
  std::string_view name() const { return CameraModelKindName(kind()); }
  /// The parameters, or nullptr when the model is of the other kind.
  const PinholeRadTan* pinhole() const { return std::get_if<PinholeRadTan>(&params_); }
  const KannalaBrandt* kannala_brandt() const { return std::get_if<KannalaBrandt>(&params_); }

  int width() const;   // px
  int height() const;  // px
  CameraIntrinsics intrinsics() const;
  /// (cx, cy), px: without building intrinsics() (no allocation; for per-pixel use).
  Eigen::Vector2d principal_point() const;
  /// The largest incidence angle (rad from the optical axis) the model projects: the first
  /// turning point of the radial distortion for the pinhole (at most pi/2), of theta_d(theta) for
  /// the fisheye (at most pi). Points at or beyond it do not project.
  double max_incidence_rad() const { return max_incidence_rad_; }

  /// Pixel of `p_in_camera` and, if asked for, its Jacobian (px/m). nullopt outside the valid
  /// range (pinhole: also at or behind the image plane) or at the origin.
  std::optional<Eigen::Vector2d> Project(
      const Eigen::Vector3d& p_in_camera,
      Eigen::Matrix<double, 2, 3>* d_pixel_d_point = nullptr) const;
  /// Unit bearing in the camera frame of `pixel` and, if asked for, its Jacobian (1/px), for
  /// pixels inside the valid range. Pinhole: Newton on the distortion, converged to ~1e-15 in
  /// normalised coordinates; fisheye: Newton on theta_d(theta) kept inside the valid range
  /// [0, max_incidence_rad()] (bisecting where a step leaves it), so a pixel just inside the
  /// range's edge maps back to it; beyond the edge the bearing is the edge's.
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel,
                            Eigen::Matrix<double, 3, 2>* d_bearing_d_pixel = nullptr) const;
  bool IsInImage(const Eigen::Vector2d& pixel) const;

  /// Angle (rad) between the bearings of the left and right image edges, on the principal row
  /// (a fisheye's may exceed pi).
  double HorizontalFovRad() const;
  /// Angle (rad) between the bearings of the top and bottom image edges, on the principal column.
  double VerticalFovRad() const;
  /// Pinhole: the larger of the two, below 150 deg for Check(); fisheye: the angle across the
  /// smaller image dimension (as FromFov), below 180 deg for Check().
  double FieldOfViewRad() const;

  /// What is wrong with the parameters, or nullopt when they are valid.
  std::optional<std::string> Check() const;

  bool operator==(const CameraModel& other) const { return params_ == other.params_; }

 private:
  std::variant<PinholeRadTan, KannalaBrandt> params_;
  // Pinhole: squared normalised radius of the distortion's first turning point (+inf if none).
  double max_squared_radius_;
  double max_incidence_rad_;
};

}  // namespace corridorsim
