// Tests slam/mapping/point_cloud.cpp: depth images of known planes lifted to points on them.
#include "slam/mapping/point_cloud.h"

#include <cmath>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/jacobian_check.h"
#include "tests/support/test_cameras.h"
#include "tests/support/tolerances.h"

namespace corridorsim::slam {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The depth image of the plane {p : normal . p = offset} (camera frame) seen by `model`: each
// pixel's z where its ray meets the plane (0 where it does not, in front of the camera).
ImageF PlaneDepth(const CameraModel& model, const Eigen::Vector3d& normal, double offset) {
  ImageF depth(model.width(), model.height());
  for (int y = 0; y < model.height(); ++y) {
    for (int x = 0; x < model.width(); ++x) {
      const Eigen::Vector3d b = model.Unproject(Eigen::Vector2d(x, y));
      if (b.z() <= kMinForwardBearing) continue;
      const Eigen::Vector3d ray = b / b.z();
      const double t = offset / normal.dot(ray);
      if (t > 0) depth.at(x, y) = static_cast<float>(t);
    }
  }
  return depth;
}

TEST_CASE("a depth image of a tilted plane unprojects to points on that plane", "[slam][mapping]") {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const double offset = 2.5;
  const std::vector<CameraModel> models = {
      PinholeRadTan::FromFov(64, 48, 58 * kDeg),
      test::WithWebcamDistortion(PinholeRadTan::FromFov(64, 48, 70 * kDeg)),
      test::WithSmallFisheyeDistortion(KannalaBrandt::FromFov(64, 48, 110 * kDeg)),
  };
  for (const CameraModel& model : models) {
    INFO("model " << model.name());
    const ImageF depth = PlaneDepth(model, normal, offset);
    const DepthCloudProjector projector(DepthCloudOptions{}, model, DepthRange{0.1, 100.0});
    std::vector<Eigen::Vector3d> points;
    projector.PointsInCamera(depth, &points);
    REQUIRE(points.size() > 1000);
    for (const Eigen::Vector3d& p : points) {
      // float depth: relative rounding 6e-8 of a few metres.
      CHECK(std::abs(normal.dot(p) - offset) < test::kFloatTol);
      // Each point projects back onto a pixel centre of the image.
      const std::optional<Eigen::Vector2d> pixel = model.Project(p);
      REQUIRE(pixel);
      CHECK(std::abs(pixel->x() - std::round(pixel->x())) < 1e-3);
      CHECK(std::abs(pixel->y() - std::round(pixel->y())) < 1e-3);
    }
  }
}

TEST_CASE("a fisheye's rays at or beyond 90 degrees give no point", "[slam][mapping]") {
  // 170 deg across the image's side: the corners look 120 deg off the axis, backwards.
  const CameraModel model = KannalaBrandt::FromFov(40, 40, 170 * kDeg);
  REQUIRE_FALSE(model.Check());
  const DepthCloudProjector projector(DepthCloudOptions{}, model, DepthRange{0.1, 10.0});
  int forward = 0;
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 40; ++x) forward += model.Unproject(Eigen::Vector2d(x, y)).z() > 1e-3;
  }
  CHECK(forward < 40 * 40);
  CHECK(projector.sampled_pixel_count() == static_cast<std::size_t>(forward));
  CHECK_FALSE(UnprojectDepth(model, Eigen::Vector2d(0, 0), 1.0));
}

TEST_CASE("the stride samples every stride-th pixel and the range drops depths outside it",
          "[slam][mapping]") {
  const CameraModel model = PinholeRadTan::FromFov(640, 480, 58 * kDeg);
  ImageF depth(640, 480, 3.0f);
  DepthCloudOptions options;
  options.pixel_stride = 4;
  const DepthCloudProjector projector(options, model, DepthRange{0.5, 4.0});
  CHECK(projector.sampled_pixel_count() == 160u * 120u);
  std::vector<Eigen::Vector3d> points;
  projector.PointsInCamera(depth, &points);
  CHECK(points.size() == 160u * 120u);

  // Pixels on the stride's grid with depths outside [0.5, 4], invalid (0) or NaN are dropped;
  // a pixel off the grid is never read.
  depth.at(0, 0) = 0.0f;
  depth.at(4, 0) = 0.49f;
  depth.at(8, 0) = 4.01f;
  depth.at(12, 0) = std::numeric_limits<float>::quiet_NaN();
  depth.at(16, 0) = std::numeric_limits<float>::infinity();
  depth.at(20, 0) = 0.5f;  // the range is closed
  depth.at(24, 0) = 4.0f;
  depth.at(1, 0) = 0.0f;  // off the grid
  projector.PointsInCamera(depth, &points);
  CHECK(points.size() == 160u * 120u - 5u);
  CHECK(DepthCloudOptions{.pixel_stride = 0}.Check()->key == "pixel_stride");
  CHECK_FALSE(options.Check());
}

TEST_CASE("points go into the world frame through world_from_camera", "[slam][mapping]") {
  const CameraModel model = PinholeRadTan::FromFov(32, 24, 60 * kDeg);
  // Camera on a robot at (3, 1) facing +x (optical z along world +x, x along world -y, y down).
  Eigen::Matrix3d world_from_optical;
  world_from_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const SE3 world_from_camera(world_from_optical, Eigen::Vector3d(3.0, 1.0, 0.5));
  // A wall at world x = 5: depth 2 m everywhere.
  const ImageF depth(32, 24, 2.0f);
  const DepthCloudProjector projector(DepthCloudOptions{}, model, DepthRange{0.1, 10.0});
  std::vector<Eigen::Vector3d> points;
  projector.PointsInWorld(depth, world_from_camera, &points);
  REQUIRE(points.size() == 32u * 24u);
  for (const Eigen::Vector3d& p : points) CHECK(std::abs(p.x() - 5.0) < test::kGeomTolM);
  // The top-left pixel looks left (+y) and up (+z).
  CHECK(points.front().y() > 1.0);
  CHECK(points.front().z() > 0.5);
}

TEST_CASE("UnprojectDepth's Jacobian over pixel and depth matches central differences",
          "[slam][mapping]") {
  const std::vector<CameraModel> models = {
      test::WithWebcamDistortion(PinholeRadTan::FromFov(640, 480, 70 * kDeg)),
      test::WithSmallFisheyeDistortion(KannalaBrandt::FromFov(640, 480, 110 * kDeg)),
  };
  for (const CameraModel& model : models) {
    for (const Eigen::Vector3d& x :
         {Eigen::Vector3d(100.5, 50.25, 1.5), Eigen::Vector3d(320, 240, 3),
          Eigen::Vector3d(600, 400, 0.7)}) {
      INFO("model " << model.name() << " at " << x.transpose());
      Eigen::Matrix3d analytic;
      const std::optional<Eigen::Vector3d> p = UnprojectDepth(model, x.head<2>(), x.z(), &analytic);
      REQUIRE(p);
      CHECK(std::abs(p->z() - x.z()) < test::kGeomTolM);
      const Eigen::Matrix3d numerical = test::NumericalJacobian<3, 3>(
          [&](const Eigen::Vector3d& v) { return *UnprojectDepth(model, v.head<2>(), v.z()); }, x);
      test::CheckJacobian(analytic, numerical);
    }
  }
}

}  // namespace
}  // namespace corridorsim::slam
