#include "common/camera_models.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/jacobian_check.h"
#include "tests/support/test_cameras.h"
#include "tests/support/tolerances.h"

namespace corridorsim {
namespace {

using test::CheckJacobian;
using test::kFovRad;
using test::kJacobianRelTol;
using test::kRoundTripBearing;
using test::kRoundTripPx;
using test::NumericalJacobian;

constexpr double kPi = std::numbers::pi;
constexpr double kRadPerDeg = kPi / 180.0;
constexpr int kRandomPoints = 2000;

// Uniform in [lo, hi) from the top 53 bits of the engine output, identical on every platform.
double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Point at incidence angle in [0, max_theta_rad] from +z, any azimuth, 0.2 to 20 m away.
Eigen::Vector3d RandomPoint(std::mt19937_64& rng, double max_theta_rad) {
  const double theta = Uniform(rng, 0.0, max_theta_rad);
  const double phi = Uniform(rng, -kPi, kPi);
  const double range = Uniform(rng, 0.2, 20.0);
  return range * Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                 std::cos(theta));
}

// lo, lo + step, ... and hi itself.
std::vector<double> GridWithEnds(double lo, double hi, double step) {
  std::vector<double> values;
  for (double value = lo; value < hi; value += step) values.push_back(value);
  values.push_back(hi);
  return values;
}

double AngleFromAxis(const Eigen::Vector3d& bearing) {
  return std::atan2(bearing.head<2>().norm(), bearing.z());
}

// Largest incidence angle seen by the image: the corners.
double CornerThetaRad(const CameraModel& camera) {
  double max_theta = 0.0;
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(camera.width() - 0.5, -0.5),
        Eigen::Vector2d(-0.5, camera.height() - 0.5),
        Eigen::Vector2d(camera.width() - 0.5, camera.height() - 0.5)}) {
    max_theta = std::max(max_theta, AngleFromAxis(camera.Unproject(corner)));
  }
  return max_theta;
}

// 640x480 camera with distortion typical of a calibrated wide webcam / RGB-D colour camera.
PinholeRadTan DistortedPinhole() {
  return test::WithWebcamDistortion(
      {.width = 640, .height = 480, .fx = 525.0, .fy = 523.0, .cx = 319.2, .cy = 240.7});
}

// 640x480 fisheyes spanning 110 and 130 deg across the image height, with small k1..k4.
KannalaBrandt Fisheye110() {
  KannalaBrandt camera = KannalaBrandt::FromFov(640, 480, 110.0 * kRadPerDeg);
  camera.fy *= 1.002;
  camera.cx += 1.3;
  camera.cy -= 0.8;
  return test::WithSmallFisheyeDistortion(camera);
}

KannalaBrandt Fisheye130() {
  KannalaBrandt camera = KannalaBrandt::FromFov(640, 480, 130.0 * kRadPerDeg);
  camera.k1 = -0.01;
  camera.k2 = 0.004;
  camera.k3 = -0.0005;
  camera.k4 = 0.0001;
  return camera;
}

std::vector<std::pair<std::string, CameraModel>> TestCameras() {
  return {{"pinhole radtan", DistortedPinhole()},
          {"fisheye 110 deg", Fisheye110()},
          {"fisheye 130 deg", Fisheye130()}};
}

TEST_CASE("test cameras are valid", "[camera]") {
  for (const auto& [name, camera] : TestCameras()) {
    INFO(name << ": " << camera.Check().value_or("ok"));
    CHECK_FALSE(camera.Check().has_value());
  }
}

TEST_CASE("Project(Unproject(pixel)) returns the pixel over the whole image", "[camera]") {
  for (const auto& [name, camera] : TestCameras()) {
    const double right = camera.width() - 0.5;
    const double bottom = camera.height() - 0.5;
    for (const double v : GridWithEnds(-0.5, bottom, 8.0)) {
      for (const double u : GridWithEnds(-0.5, right, 8.0)) {
        const Eigen::Vector2d pixel(u, v);
        INFO(name << ", pixel " << pixel.transpose());
        const Eigen::Vector3d bearing = camera.Unproject(pixel);
        REQUIRE(std::abs(bearing.norm() - 1.0) <= kRoundTripBearing);
        const std::optional<Eigen::Vector2d> reprojected = camera.Project(bearing);
        REQUIRE(reprojected.has_value());
        REQUIRE((*reprojected - pixel).norm() <= kRoundTripPx);
      }
    }
  }
}

TEST_CASE("Unproject(Project(p)) returns the bearing of random points seen by the image",
          "[camera]") {
  std::mt19937_64 rng(20240611);
  for (const auto& [name, camera] : TestCameras()) {
    const double max_theta = CornerThetaRad(camera);
    for (int i = 0; i < kRandomPoints; ++i) {
      const Eigen::Vector3d p_in_camera = RandomPoint(rng, max_theta);
      INFO(name << ", point " << p_in_camera.transpose());
      const std::optional<Eigen::Vector2d> pixel = camera.Project(p_in_camera);
      REQUIRE(pixel.has_value());
      const Eigen::Vector3d bearing = camera.Unproject(*pixel);
      REQUIRE((bearing - p_in_camera.normalized()).norm() <= kRoundTripBearing);
    }
  }
}

TEST_CASE("fisheye 130 deg sees points at and beyond its edge, behind the image plane",
          "[camera]") {
  const CameraModel camera = Fisheye130();
  const KannalaBrandt& k = *camera.kannala_brandt();
  // The corners of a 130 deg (across the height) 4:3 fisheye look behind the image plane.
  REQUIRE(CornerThetaRad(camera) > 100.0 * kRadPerDeg);
  for (const double theta_deg : {64.0, 65.0, 66.0, 80.0, 89.9, 90.0, 90.1, 95.0, 105.0}) {
    for (const double phi : {-2.5, -kPi / 2, 0.0, 0.4, kPi / 2, kPi}) {
      const double theta = theta_deg * kRadPerDeg;
      const Eigen::Vector3d p_in_camera =
          3.0 * Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                std::cos(theta));
      INFO("theta " << theta_deg << " deg, phi " << phi);
      const std::optional<Eigen::Vector2d> pixel = camera.Project(p_in_camera);
      REQUIRE(pixel.has_value());
      // The pixel lies in the azimuth direction of the point.
      const Eigen::Vector2d offset(pixel->x() - k.cx, pixel->y() - k.cy);
      CHECK(std::atan2(offset.y(), offset.x()) ==
            Approx(std::atan2(std::sin(phi), std::cos(phi))).margin(1e-9));
      CHECK((camera.Unproject(*pixel) - p_in_camera.normalized()).norm() <= kRoundTripBearing);
    }
  }
}

TEST_CASE("analytic projection Jacobians match central differences at random points",
          "[camera][jacobian]") {
  std::mt19937_64 rng(7);
  for (const auto& [name, camera] : TestCameras()) {
    const double max_theta = CornerThetaRad(camera);
    std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(1e-12, 0, 2),
                                           Eigen::Vector3d(0, -3e-7, 0.5),
                                           Eigen::Vector3d(1e-4, 2e-4, 1)};
    for (int i = 0; i < kRandomPoints; ++i) points.push_back(RandomPoint(rng, max_theta));
    for (const Eigen::Vector3d& p_in_camera : points) {
      INFO(name << ", point " << p_in_camera.transpose());
      Eigen::Matrix<double, 2, 3> d_pixel_d_point;
      const std::optional<Eigen::Vector2d> pixel = camera.Project(p_in_camera, &d_pixel_d_point);
      REQUIRE(pixel.has_value());
      // The Jacobian output must not change the pixel.
      REQUIRE((*pixel - camera.Project(p_in_camera).value()).norm() == 0.0);
      const Eigen::Matrix<double, 2, 3> numerical = NumericalJacobian<2, 3>(
          [&c = camera](const Eigen::Vector3d& p) { return c.Project(p).value(); }, p_in_camera);
      CheckJacobian(d_pixel_d_point, numerical);
    }
  }
}

TEST_CASE("pinhole does not project points at or behind the image plane", "[camera]") {
  const CameraModel camera = DistortedPinhole();
  CHECK_FALSE(camera.Project(Eigen::Vector3d(0.1, 0.2, 0.0)).has_value());
  CHECK_FALSE(camera.Project(Eigen::Vector3d(0.1, 0.2, -1.0)).has_value());
  CHECK_FALSE(camera.Project(Eigen::Vector3d(0.0, 0.0, -1.0)).has_value());
  CHECK(camera.Project(Eigen::Vector3d(1e-4, 2e-4, 1e-3)).has_value());
}

TEST_CASE("pinhole does not project points beyond the turning point of its distortion",
          "[camera]") {
  // r (1 - 0.5 r^2) turns at r = sqrt(2/3); beyond, points would fold back into the image.
  PinholeRadTan params = PinholeRadTan::FromFov(640, 480, 60.0 * kRadPerDeg);
  params.k1 = -0.5;
  const CameraModel camera = params;
  const double turning_r = std::sqrt(2.0 / 3.0);
  CHECK(camera.max_incidence_rad() == Approx(std::atan(turning_r)).epsilon(1e-14));
  CHECK(camera.Project(Eigen::Vector3d(0.98 * turning_r, 0.0, 1.0)).has_value());
  CHECK_FALSE(camera.Project(Eigen::Vector3d(1.02 * turning_r, 0.0, 1.0)).has_value());
  CHECK_FALSE(camera.Project(Eigen::Vector3d(0.0, 3.0, 1.0)).has_value());
}

TEST_CASE("fisheye does not project points beyond the turning point of theta_d or at theta = pi",
          "[camera]") {
  // theta (1 - 0.3 theta^2) turns at theta = sqrt(1/0.9) = 1.054 rad.
  KannalaBrandt params = KannalaBrandt::FromFov(640, 480, 90.0 * kRadPerDeg);
  params.k1 = -0.3;
  const CameraModel camera = params;
  CHECK(camera.max_incidence_rad() == Approx(std::sqrt(1.0 / 0.9)).epsilon(1e-14));
  const auto point_at = [](double theta) {
    return Eigen::Vector3d(std::sin(theta), 0.0, std::cos(theta));
  };
  CHECK(camera.Project(point_at(1.0)).has_value());
  CHECK_FALSE(camera.Project(point_at(1.1)).has_value());
  const CameraModel equidistant = KannalaBrandt::FromFov(640, 480, 130.0 * kRadPerDeg);
  CHECK(equidistant.max_incidence_rad() == kPi);
  CHECK(equidistant.Project(point_at(3.0)).has_value());
  CHECK_FALSE(equidistant.Project(Eigen::Vector3d(0.0, 0.0, -1.0)).has_value());
  CHECK_FALSE(equidistant.Project(Eigen::Vector3d::Zero()).has_value());
}

TEST_CASE("fisheye Unproject inverts Project up to the edge of the valid range", "[camera]") {
  // theta_d = theta + 0.3 theta^3 - 0.1 theta^5 turns at theta = 1.605 rad, where theta_d = 1.78:
  // pixels near the edge have theta_d beyond theta_max, so Newton started at the equidistant
  // solution theta = theta_d starts outside the valid range (and on the falling side of theta_d).
  KannalaBrandt params = KannalaBrandt::FromFov(640, 480, 90.0 * kRadPerDeg);
  params.k1 = 0.3;
  params.k2 = -0.1;
  const CameraModel camera = params;
  const double max_theta = camera.max_incidence_rad();
  REQUIRE(max_theta == Approx(std::sqrt(0.9 + std::sqrt(0.81 + 2.0))).epsilon(1e-12));
  for (const double fraction : {0.5, 0.9, 0.99, 0.999, 0.9999}) {
    for (const double azimuth : {0.0, 0.7, 2.0, 3.5, 5.1}) {
      const double theta = fraction * max_theta;
      const Eigen::Vector3d ray(std::sin(theta) * std::cos(azimuth),
                                std::sin(theta) * std::sin(azimuth), std::cos(theta));
      INFO("theta " << theta << " rad, azimuth " << azimuth);
      const std::optional<Eigen::Vector2d> pixel = camera.Project(ray);
      REQUIRE(pixel.has_value());
      const Eigen::Vector3d bearing = camera.Unproject(*pixel);
      CHECK(AngleFromAxis(bearing) < max_theta);
      const std::optional<Eigen::Vector2d> again = camera.Project(bearing);
      REQUIRE(again.has_value());
      CHECK((*again - *pixel).norm() < kRoundTripPx);
      // Near the turning point theta_d is flat: the angle is only as good as the pixel allows.
      CHECK(std::acos(std::clamp(bearing.dot(ray), -1.0, 1.0)) < 1e-5);
    }
  }
  // Beyond the valid range the bearing stays at its edge, never beyond (the caller's Project
  // then says the pixel shows nothing).
  const Eigen::Vector3d beyond = camera.Unproject(params.fx * 1.9 * Eigen::Vector2d(1.0, 0.0) +
                                                  Eigen::Vector2d(params.cx, params.cy));
  CHECK(AngleFromAxis(beyond) <= max_theta);
  CHECK(AngleFromAxis(beyond) == Approx(max_theta).epsilon(1e-6));
}

TEST_CASE("pinhole FromFov spans the horizontal field of view edge to edge", "[camera]") {
  for (const double fov_deg : {40.0, 90.0, 120.0, 149.0}) {
    for (const auto& [width, height] : {std::pair{640, 480}, std::pair{480, 640}}) {
      INFO(width << "x" << height << " at " << fov_deg << " deg");
      const CameraModel camera = PinholeRadTan::FromFov(width, height, fov_deg * kRadPerDeg);
      CHECK(camera.HorizontalFovRad() == Approx(fov_deg * kRadPerDeg).margin(kFovRad));
      // The left edge of column 0 is at -fov/2.
      const Eigen::Vector3d left_edge =
          camera.Unproject(Eigen::Vector2d(-0.5, camera.pinhole()->cy));
      CHECK(std::atan2(left_edge.x(), left_edge.z()) ==
            Approx(-0.5 * fov_deg * kRadPerDeg).margin(kFovRad));
      CHECK(camera.FieldOfViewRad() ==
            Approx(std::max(camera.HorizontalFovRad(), camera.VerticalFovRad())).margin(kFovRad));
    }
  }
}

TEST_CASE("fisheye FromFov spans the field of view across the smaller image dimension",
          "[camera]") {
  for (const double fov_deg : {110.0, 130.0, 179.0}) {
    for (const auto& [width, height] : {std::pair{640, 480}, std::pair{480, 640}}) {
      INFO(width << "x" << height << " at " << fov_deg << " deg");
      const double fov = fov_deg * kRadPerDeg;
      const CameraModel camera = KannalaBrandt::FromFov(width, height, fov);
      CHECK(camera.FieldOfViewRad() == Approx(fov).margin(kFovRad));
      const double smaller_fov =
          width < height ? camera.HorizontalFovRad() : camera.VerticalFovRad();
      CHECK(smaller_fov == Approx(fov).margin(kFovRad));
      // A point at fov/2 from the axis lands on the edge of the smaller dimension.
      const double half = 0.5 * fov;
      const Eigen::Vector3d p_in_camera = width < height
                                              ? Eigen::Vector3d(std::sin(half), 0, std::cos(half))
                                              : Eigen::Vector3d(0, std::sin(half), std::cos(half));
      const KannalaBrandt& k = *camera.kannala_brandt();
      const Eigen::Vector2d edge =
          width < height ? Eigen::Vector2d(width - 0.5, k.cy) : Eigen::Vector2d(k.cx, height - 0.5);
      CHECK((camera.Project(p_in_camera).value() - edge).norm() <= kRoundTripPx);
    }
  }
}

TEST_CASE("Check rejects a zero or negative image size", "[camera]") {
  PinholeRadTan pinhole = PinholeRadTan::FromFov(640, 480, 90.0 * kRadPerDeg);
  REQUIRE_FALSE(CameraModel(pinhole).Check().has_value());
  pinhole.width = 0;
  CHECK(CameraModel(pinhole).Check().has_value());
  KannalaBrandt fisheye = KannalaBrandt::FromFov(640, 480, 120.0 * kRadPerDeg);
  REQUIRE_FALSE(CameraModel(fisheye).Check().has_value());
  fisheye.height = -480;
  CHECK(CameraModel(fisheye).Check().has_value());
  CHECK(CameraModel().Check().has_value());
}

TEST_CASE("Check rejects non-positive or non-finite focal lengths", "[camera]") {
  PinholeRadTan pinhole = DistortedPinhole();
  pinhole.fy = 0.0;
  CHECK(CameraModel(pinhole).Check().has_value());
  KannalaBrandt fisheye = Fisheye130();
  fisheye.fx = std::nan("");
  CHECK(CameraModel(fisheye).Check().has_value());
}

// `just_below` passes Check; `at_limit` fails it with a problem about the field of view.
void CheckFovLimit(const CameraModel& just_below, const CameraModel& at_limit) {
  CHECK_FALSE(just_below.Check().has_value());
  const std::optional<std::string> problem = at_limit.Check();
  REQUIRE(problem.has_value());
  CHECK_THAT(*problem, Catch::Contains("field of view"));
}

TEST_CASE("Check rejects a pinhole field of view of 150 deg or more", "[camera]") {
  CheckFovLimit(PinholeRadTan::FromFov(640, 480, 149.0 * kRadPerDeg),
                PinholeRadTan::FromFov(640, 480, 150.0 * kRadPerDeg));
  // Portrait: the vertical field of view is the wider one.
  CHECK(CameraModel(PinholeRadTan::FromFov(300, 640, 130.0 * kRadPerDeg)).Check().has_value());
}

TEST_CASE("Check rejects a fisheye field of view of 180 deg or more", "[camera]") {
  CheckFovLimit(KannalaBrandt::FromFov(640, 480, 179.0 * kRadPerDeg),
                KannalaBrandt::FromFov(640, 480, 180.0 * kRadPerDeg));
}

TEST_CASE("Check rejects distortion that turns over inside the image", "[camera]") {
  PinholeRadTan camera = PinholeRadTan::FromFov(640, 480, 100.0 * kRadPerDeg);
  camera.k1 = -0.5;
  const std::optional<std::string> problem = CameraModel(camera).Check();
  REQUIRE(problem.has_value());
  CHECK_THAT(*problem, Catch::Contains("corner"));
}

TEST_CASE("IsInImage covers pixel centres from 0 to size - 1 plus half a pixel", "[camera]") {
  const CameraModel camera = PinholeRadTan::FromFov(640, 480, 90.0 * kRadPerDeg);
  CHECK(camera.IsInImage(Eigen::Vector2d(-0.5, -0.5)));
  CHECK(camera.IsInImage(Eigen::Vector2d(639.49, 479.49)));
  CHECK_FALSE(camera.IsInImage(Eigen::Vector2d(639.5, 10.0)));
  CHECK_FALSE(camera.IsInImage(Eigen::Vector2d(10.0, -0.51)));
}

TEST_CASE("CameraModel holds one kind and gives its parameters back", "[camera]") {
  const KannalaBrandt fisheye = Fisheye110();
  const CameraModel camera = fisheye;
  CHECK(camera.kind() == CameraModelKind::kKannalaBrandt);
  CHECK(camera.name() == "kannala_brandt");
  REQUIRE(camera.kannala_brandt() != nullptr);
  CHECK(*camera.kannala_brandt() == fisheye);
  CHECK(camera.pinhole() == nullptr);
  CHECK(camera.width() == 640);
  CHECK(camera.height() == 480);
  // A pinhole with the same intrinsics projects the same point elsewhere.
  PinholeRadTan pinhole;
  pinhole.width = fisheye.width;
  pinhole.height = fisheye.height;
  pinhole.fx = fisheye.fx;
  pinhole.fy = fisheye.fy;
  pinhole.cx = fisheye.cx;
  pinhole.cy = fisheye.cy;
  const CameraModel other = pinhole;
  CHECK(other.kind() == CameraModelKind::kPinholeRadTan);
  CHECK(other.name() == "pinhole_radtan");
  CHECK(other.kannala_brandt() == nullptr);
  const Eigen::Vector3d p_in_camera(0.4, -0.3, 1.2);
  CHECK((other.Project(p_in_camera).value() - camera.Project(p_in_camera).value()).norm() > 1.0);
  CHECK_FALSE(other == camera);
  // A default model is an empty pinhole.
  CHECK(CameraModel().kind() == CameraModelKind::kPinholeRadTan);
  CHECK(CameraModel().width() == 0);
}

TEST_CASE("intrinsics() lists the distortion in OpenCV's order; principal_point() its (cx, cy)",
          "[camera]") {
  test::CheckIntrinsics(CameraModel(DistortedPinhole()).intrinsics(),
                        {.model = "pinhole_radtan",
                         .width = 640,
                         .height = 480,
                         .fx = 525.0,
                         .fy = 523.0,
                         .cx = 319.2,
                         .cy = 240.7,
                         .distortion = {-0.28, 0.07, 1e-4, -2e-4, -0.005}});
  const KannalaBrandt k = Fisheye110();
  test::CheckIntrinsics(CameraModel(k).intrinsics(), {.model = "kannala_brandt",
                                                      .width = k.width,
                                                      .height = k.height,
                                                      .fx = k.fx,
                                                      .fy = k.fy,
                                                      .cx = k.cx,
                                                      .cy = k.cy,
                                                      .distortion = {k.k1, k.k2, k.k3, k.k4}});
  // principal_point() is intrinsics()' (cx, cy).
  CHECK(CameraModel(DistortedPinhole()).principal_point() == Eigen::Vector2d(319.2, 240.7));
  CHECK(CameraModel(k).principal_point() == Eigen::Vector2d(k.cx, k.cy));
}

TEST_CASE("analytic unprojection Jacobians match central differences at random pixels",
          "[camera][jacobian]") {
  std::mt19937_64 rng(11);
  for (const auto& [name, camera] : TestCameras()) {
    const KannalaBrandt* k = camera.kannala_brandt();
    const PinholeRadTan* p = camera.pinhole();
    const Eigen::Vector2d principal =
        k != nullptr ? Eigen::Vector2d(k->cx, k->cy) : Eigen::Vector2d(p->cx, p->cy);
    const double focal = k != nullptr ? k->fx : p->fx;
    std::vector<Eigen::Vector2d> pixels = {
        principal, principal + Eigen::Vector2d(1e-7, 0), principal + Eigen::Vector2d(0.3, -0.2),
        Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(camera.width() - 0.5, camera.height() - 0.5)};
    for (int i = 0; i < kRandomPoints; ++i) {
      pixels.emplace_back(Uniform(rng, -0.5, camera.width() - 0.5),
                          Uniform(rng, -0.5, camera.height() - 0.5));
    }
    for (const Eigen::Vector2d& pixel : pixels) {
      INFO(name << ", pixel " << pixel.transpose());
      Eigen::Matrix<double, 3, 2> d_bearing_d_pixel;
      const Eigen::Vector3d bearing = camera.Unproject(pixel, &d_bearing_d_pixel);
      // The Jacobian output must not change the bearing.
      REQUIRE((bearing - camera.Unproject(pixel)).norm() == 0.0);
      const Eigen::Matrix<double, 3, 2> numerical = NumericalJacobian<3, 2>(
          [&c = camera](const Eigen::Vector2d& q) { return c.Unproject(q); }, pixel);
      // Compared per focal length (d bearing / d (pixel / fx), entries of order 1): per pixel the
      // entries are ~1/fx, below the helper's absolute floor.
      CheckJacobian(focal * d_bearing_d_pixel, focal * numerical);
      // A unit bearing moves perpendicular to itself.
      CHECK((bearing.transpose() * focal * d_bearing_d_pixel).norm() <= kJacobianRelTol);
    }
  }
}

TEST_CASE("the valid range is the first turning point of the distortion", "[camera]") {
  // d(r radial(r)) / dr = 1 + 3 k1 r^2 + 5 k2 r^4 = 1 - 1.5 r^2 + 0.5 r^4 for k1 = -0.5,
  // k2 = 0.1: zero at r^2 = 1 and r^2 = 2. The first one counts, although the slope is positive
  // again beyond r^2 = 2.
  PinholeRadTan pinhole = PinholeRadTan::FromFov(640, 480, 60.0 * kRadPerDeg);
  pinhole.k1 = -0.5;
  pinhole.k2 = 0.1;
  const CameraModel camera = pinhole;
  CHECK(camera.max_incidence_rad() == Approx(kPi / 4).epsilon(1e-14));
  CHECK(camera.Project(Eigen::Vector3d(0.999, 0.0, 1.0)).has_value());
  CHECK_FALSE(camera.Project(Eigen::Vector3d(1.001, 0.0, 1.0)).has_value());
  CHECK_FALSE(camera.Project(Eigen::Vector3d(0.0, 3.0, 1.0)).has_value());
  // A negative leading coefficient turns over somewhere; without distortion every point in front
  // projects.
  CHECK(CameraModel(DistortedPinhole()).max_incidence_rad() < kPi / 2);
  const CameraModel undistorted = PinholeRadTan::FromFov(640, 480, 60.0 * kRadPerDeg);
  CHECK(undistorted.max_incidence_rad() == kPi / 2);
  CHECK(undistorted.Project(Eigen::Vector3d(1e6, 0.0, 1.0)).has_value());
  // The fisheye's slope d theta_d / d theta with the same k1, k2 is zero at theta^2 = 1 and 2.
  KannalaBrandt fisheye = KannalaBrandt::FromFov(640, 480, 90.0 * kRadPerDeg);
  fisheye.k1 = -0.5;
  fisheye.k2 = 0.1;
  CHECK(CameraModel(fisheye).max_incidence_rad() == Approx(1.0).epsilon(1e-14));
}

}  // namespace
}  // namespace corridorsim
