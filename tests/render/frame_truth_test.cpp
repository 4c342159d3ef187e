// Tests render/frame_truth.cpp: landmarks seen by hand-placed cameras in a generated world (and in
// the tiny hand-made world for reflections), checked against closed-form projections computed
// here independently of the camera-model code: vanishing points, plates seen straight on, lamps
// under an upward fisheye, door bearings (P2 eq. 8, P3 eq. 17), occlusion by label images,
// corners behind the camera, the range cut-off and the JSON output.
#include "render/frame_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include <catch2/catch.hpp>

#include "common/camera_models.h"
#include "common/pose.h"
#include "tests/support/generated_worlds.h"
#include "tests/support/test_cameras.h"
#include "tests/support/tiny_world.h"
#include "tests/support/tolerances.h"
#include "worlds/world.h"

namespace corridorsim::render {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using test::kFrameTruthPx;
using test::kFrameTruthRad;

constexpr double kPi = std::numbers::pi;

const worlds::World& GeneratedWorld() { return test::GeneratedWorld(7); }

// The front camera: the Kinect's 640 x 480 pinhole, f = 525 px.
PinholeRadTan FrontPinhole() { return test::Kinect(); }

using test::UpwardFisheye;

Matrix3d Rz(double yaw) { return Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix(); }

// Camera axes given in the world: x right, y down, z forward (OpenCV optical frame).
SE3 CameraPose(const Vector3d& right, const Vector3d& down, const Vector3d& forward,
               const Vector3d& position) {
  Matrix3d world_from_camera;
  world_from_camera.col(0) = right;
  world_from_camera.col(1) = down;
  world_from_camera.col(2) = forward;
  return SE3(world_from_camera, position);
}

// A forward camera at `position` looking along world +x turned by `yaw` about +z.
SE3 FrontCamera(const Vector3d& position, double yaw) {
  const Matrix3d r = Rz(yaw);
  return CameraPose(r * -Vector3d::UnitY(), r * -Vector3d::UnitZ(), r * Vector3d::UnitX(),
                    position);
}

// A camera at `eye` looking at `target`, image down towards world -z.
SE3 LookAt(const Vector3d& eye, const Vector3d& target) {
  const Vector3d forward = (target - eye).normalized();
  const Vector3d right = forward.cross(Vector3d::UnitZ()).normalized();
  return CameraPose(right, forward.cross(right), forward, eye);
}

// Upward camera: optical axis world +z; camera x, y = robot x, y for a robot with the same yaw.
SE3 UpwardCamera(const Vector3d& position, double yaw) { return SE3(Rz(yaw), position); }

SE3 RobotAt(const Vector3d& position, double yaw) {
  return SE3::FromSE2(SE2(position.x(), position.y(), yaw));
}

FrameTruthInput Input(const worlds::World& world, const CameraModel& model,
                      const SE3& world_from_camera, const SE3& world_from_robot) {
  FrameTruthInput input;
  input.world = &world;
  input.camera_id = "test_camera";
  input.model = model;
  input.world_from_camera = world_from_camera;
  input.world_from_robot = world_from_robot;
  return input;
}

// Closed forms written out here, independent of common/camera_models.cpp.
Vector2d PinholePixel(const PinholeRadTan& c, const SE3& world_from_camera,
                      const Vector3d& p_in_world) {
  const Vector3d p =
      world_from_camera.rotation().transpose() * (p_in_world - world_from_camera.translation());
  return {c.fx * p.x() / p.z() + c.cx, c.fy * p.y() / p.z() + c.cy};
}
Vector2d EquidistantPixel(const KannalaBrandt& c, const SE3& world_from_camera,
                          const Vector3d& p_in_world) {
  const Vector3d p =
      world_from_camera.rotation().transpose() * (p_in_world - world_from_camera.translation());
  const double r = std::hypot(p.x(), p.y());
  const double theta = std::atan2(r, p.z());
  return {c.fx * theta * p.x() / r + c.cx, c.fy * theta * p.y() / r + c.cy};
}

template <class Entry>
const Entry* FindId(const std::vector<Entry>& entries, int id) {
  const auto it =
      std::find_if(entries.begin(), entries.end(), [&](const Entry& e) { return e.id == id; });
  return it == entries.end() ? nullptr : &*it;
}
// The pointer would dangle: keep the FrameTruth in a variable.
template <class Entry>
const Entry* FindId(const std::vector<Entry>&& entries, int id) = delete;

double AngleDiff(double a, double b) { return std::abs(NormalizeAngle(a - b)); }

// The truth of lamp `id` in the frame of the upward `camera` at `position` (robot yaw 0): the
// lamp must be in the frame.
LampTruth LampSeenFromBelow(const worlds::World& world, const CameraModel& camera,
                            const Vector3d& position, int id) {
  const FrameTruth truth =
      ComputeFrameTruth(Input(world, camera, UpwardCamera(position, 0.0), RobotAt(position, 0.0)));
  const LampTruth* seen = FindId(truth.lamps, id);
  REQUIRE(seen != nullptr);
  return *seen;
}

// The camera of the plate tests: facing plates[index] straight on from `distance_m`.
SE3 FacingPlate(const worlds::DoorPlate& plate, double distance_m) {
  const Vector3d right = Vector3d::UnitZ().cross(plate.normal);
  return CameraPose(right, -Vector3d::UnitZ(), -plate.normal,
                    plate.center + distance_m * plate.normal);
}

const worlds::Lamp& FirstCorridorCircularLamp(const worlds::World& world) {
  const auto it = std::find_if(world.lamps.begin(), world.lamps.end(), [](const worlds::Lamp& l) {
    return l.shape == worlds::LampShape::kCircular && l.room_door_id < 0 && l.center.x() > 6.0;
  });
  REQUIRE(it != world.lamps.end());
  return *it;
}

// ---- vanishing points ---------------------------------------------------------------------------

TEST_CASE(
    "vanishing point of an aligned front camera is the principal point and moves by fx tan(yaw)",
    "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const PinholeRadTan camera = FrontPinhole();
  const Vector3d position(5.0, 0.0, 1.2);
  for (const double yaw : {0.0, 0.2, -0.3}) {
    CAPTURE(yaw);
    const FrameTruth truth =
        ComputeFrameTruth(Input(world, camera, FrontCamera(position, yaw), RobotAt(position, yaw)));
    REQUIRE(!truth.vanishing_points.empty());
    const VanishingPointTruth& vp = truth.vanishing_points.front();
    CHECK(vp.segment_id == world.segments.front().id);
    CHECK(vp.pixel.x() == Approx(camera.cx + camera.fx * std::tan(yaw)).margin(kFrameTruthPx));
    CHECK(vp.pixel.y() == Approx(camera.cy).margin(kFrameTruthPx));
    CHECK(vp.in_image);
    CHECK(vp.camera_in_segment);
    CHECK(vp.direction_in_world.isApprox(Vector2d(1, 0)));
    CHECK(vp.u_from_principal_px == Approx(camera.fx * std::tan(yaw)).margin(kFrameTruthPx));
    // P1 eq. 19 at infinite range: f_v sin(phi_r - alpha) with alpha = 0.
    CHECK(vp.p1_eq19_px == Approx(camera.fx * std::sin(yaw)).margin(kFrameTruthPx));
    CHECK(vp.bearing_rad == Approx(-yaw).margin(kFrameTruthRad));
  }
}

TEST_CASE("vanishing point takes the axis direction in front of the camera",
          "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const Vector3d position(30.0, 0.3, 1.2);
  const FrameTruth truth = ComputeFrameTruth(
      Input(world, FrontPinhole(), FrontCamera(position, kPi), RobotAt(position, kPi)));
  REQUIRE(!truth.vanishing_points.empty());
  CHECK(truth.vanishing_points.front().direction_in_world.isApprox(Vector2d(-1, 0)));
  CHECK(truth.vanishing_points.front().pixel.x() ==
        Approx(FrontPinhole().cx).margin(kFrameTruthPx));
}

// ---- door plates --------------------------------------------------------------------------------

TEST_CASE("a plate seen straight on is centred, fx * width / distance wide, at viewing angle 0",
          "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  REQUIRE(world.plates.size() > 3);
  const worlds::DoorPlate& plate = world.plates[3];
  const PinholeRadTan camera = FrontPinhole();
  const double distance = 1.2;
  const SE3 world_from_camera = FacingPlate(plate, distance);
  const FrameTruth truth = ComputeFrameTruth(
      Input(world, camera, world_from_camera, RobotAt(world_from_camera.translation(), 0.0)));
  const PlateTruth* seen = FindId(truth.plates, plate.id);
  REQUIRE(seen != nullptr);
  const double half_w = camera.fx * plate.size_m.x() / distance / 2;
  const double half_h = camera.fy * plate.size_m.y() / distance / 2;
  CHECK(seen->room_number == plate.room_number);
  CHECK(seen->bbox_max_px.x() - seen->bbox_min_px.x() == Approx(2 * half_w).margin(kFrameTruthPx));
  CHECK(seen->bbox_max_px.y() - seen->bbox_min_px.y() == Approx(2 * half_h).margin(kFrameTruthPx));
  CHECK((seen->bbox_min_px + seen->bbox_max_px).x() / 2 == Approx(camera.cx).margin(kFrameTruthPx));
  CHECK((seen->bbox_min_px + seen->bbox_max_px).y() / 2 == Approx(camera.cy).margin(kFrameTruthPx));
  // Top-left, top-right, bottom-right, bottom-left for a viewer facing the plate.
  const Vector2d expected[4] = {{camera.cx - half_w, camera.cy - half_h},
                                {camera.cx + half_w, camera.cy - half_h},
                                {camera.cx + half_w, camera.cy + half_h},
                                {camera.cx - half_w, camera.cy + half_h}};
  for (int k = 0; k < 4; ++k) {
    CAPTURE(k);
    CHECK((seen->corners_px[std::size_t(k)] - expected[k]).norm() < kFrameTruthPx);
  }
  CHECK((seen->center_px - Vector2d(camera.cx, camera.cy)).norm() < kFrameTruthPx);
  CHECK(seen->distance_m == Approx(distance).margin(test::kGeomTolM));
  CHECK(seen->viewing_angle_deg == Approx(0.0).margin(1e-6));
  CHECK(seen->visible_fraction == 1.0);
  CHECK(seen->fully_in_image);
}

TEST_CASE("a plate seen from the side has the viewing angle of its offset",
          "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::DoorPlate& plate = world.plates[3];
  const PinholeRadTan camera = FrontPinhole();
  const Vector3d right = Vector3d::UnitZ().cross(plate.normal);
  SE3 world_from_camera = FacingPlate(plate, 1.2);
  world_from_camera =
      SE3(world_from_camera.quaternion(), world_from_camera.translation() + 0.5 * right);
  const FrameTruth truth = ComputeFrameTruth(
      Input(world, camera, world_from_camera, RobotAt(world_from_camera.translation(), 0.0)));
  const PlateTruth* seen = FindId(truth.plates, plate.id);
  REQUIRE(seen != nullptr);
  CHECK(seen->viewing_angle_deg == Approx(std::atan2(0.5, 1.2) * 180.0 / kPi).margin(1e-6));
  CHECK(seen->distance_m == Approx(std::hypot(0.5, 1.2)).margin(test::kGeomTolM));
  CHECK((seen->center_px - PinholePixel(camera, world_from_camera, plate.center)).norm() <
        kFrameTruthPx);
}

TEST_CASE("a plate seen from behind its wall is not listed", "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::DoorPlate& plate = world.plates[3];
  // Behind the wall, looking at the plate's back through the wall.
  const SE3 world_from_camera =
      CameraPose(-Vector3d::UnitZ().cross(plate.normal), -Vector3d::UnitZ(), plate.normal,
                 plate.center - 1.2 * plate.normal);
  const FrameTruth truth = ComputeFrameTruth(
      Input(world, FrontPinhole(), world_from_camera, RobotAt(world_from_camera.translation(), 0)));
  CHECK(FindId(truth.plates, plate.id) == nullptr);
}

TEST_CASE("an instance image decides how much of a plate is visible", "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::DoorPlate& plate = world.plates[3];
  const PinholeRadTan camera = FrontPinhole();
  const SE3 world_from_camera = FacingPlate(plate, 1.2);
  FrameTruthInput input =
      Input(world, camera, world_from_camera, RobotAt(world_from_camera.translation(), 0.0));
  const auto plate_id = static_cast<std::uint32_t>(plate.id);
  std::vector<std::uint32_t> instance(std::size_t(camera.width * camera.height), 0);
  input.instance = &instance;

  SECTION("no pixel carries the plate: not listed") {
    const FrameTruth truth = ComputeFrameTruth(input);
    CHECK(FindId(truth.plates, plate.id) == nullptr);
  }
  SECTION("every pixel carries the plate: fully visible") {
    std::fill(instance.begin(), instance.end(), plate_id);
    const FrameTruth truth = ComputeFrameTruth(input);
    const PlateTruth* seen = FindId(truth.plates, plate.id);
    REQUIRE(seen != nullptr);
    CHECK(seen->visible_fraction == 1.0);
  }
  SECTION("only columns left of 310 carry the plate: two of five grid columns") {
    // Grid columns at -0.4, -0.2, 0, 0.2, 0.4 of the plate width (> 80 px) around cx = 319.5.
    for (int row = 0; row < camera.height; ++row) {
      for (int col = 0; col < 310; ++col)
        instance[std::size_t(row * camera.width + col)] = plate_id;
    }
    const FrameTruth truth = ComputeFrameTruth(input);
    const PlateTruth* seen = FindId(truth.plates, plate.id);
    REQUIRE(seen != nullptr);
    CHECK(seen->visible_fraction == Approx(10.0 / 25.0));
  }
}

// ---- lamps --------------------------------------------------------------------------------------

TEST_CASE(
    "an upward fisheye under a circular lamp sees it at the principal point, fx atan(r/h) wide",
    "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::Lamp& lamp = FirstCorridorCircularLamp(world);
  const KannalaBrandt camera = UpwardFisheye();
  const Vector3d position(lamp.center.x(), lamp.center.y(), 1.0);
  const double h = lamp.center.z() - position.z();
  const LampTruth seen = LampSeenFromBelow(world, camera, position, lamp.id);
  CHECK_FALSE(seen.reflection);
  CHECK(seen.shape == worlds::LampShape::kCircular);
  CHECK((seen.center_px - Vector2d(camera.cx, camera.cy)).norm() < kFrameTruthPx);
  CHECK(seen.radius_px == Approx(camera.fx * std::atan(lamp.radius_m / h)).margin(kFrameTruthPx));
  CHECK_FALSE(seen.cut_by_border);
  CHECK(seen.visible_fraction == 1.0);
  CHECK(seen.on == lamp.on);
  REQUIRE(seen.polar.has_value());
  CHECK(seen.polar->r_px == Approx(0.0).margin(kFrameTruthPx));
}

TEST_CASE("a lamp moved towards the image border is cut by the border", "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::Lamp& lamp = FirstCorridorCircularLamp(world);
  const KannalaBrandt camera = UpwardFisheye();
  const double h = lamp.center.z() - 1.0;
  // Centre at row 475 of 480: theta = (475 - cy) / fx below the lamp, shifted along world y.
  const double target_row = 475.0;
  const double shift = h * std::tan((target_row - camera.cy) / camera.fx);
  const Vector3d position(lamp.center.x(), lamp.center.y() - shift, 1.0);
  const LampTruth seen = LampSeenFromBelow(world, camera, position, lamp.id);
  CHECK(seen.center_px.y() == Approx(target_row).margin(kFrameTruthPx));
  CHECK(seen.center_px.x() == Approx(camera.cx).margin(kFrameTruthPx));
  CHECK(seen.cut_by_border);
  CHECK(seen.visible_fraction > 0.0);
  CHECK(seen.visible_fraction < 1.0);
  // P3 eq. 16 polar coordinates of the centre: r = d f / dz, theta = bearing in the robot frame.
  REQUIRE(seen.polar.has_value());
  CHECK(seen.polar->r_px == Approx(shift * camera.fx / h).margin(kFrameTruthPx));
  CHECK(AngleDiff(seen.polar->theta_rad, kPi / 2) < kFrameTruthRad);
  CHECK(AngleDiff(seen.polar->p2_theta_rad, 0.0) < kFrameTruthRad);
}

TEST_CASE("a panel lamp's radius is half the diagonal of its image box", "[render][frame_truth]") {
  const worlds::World world = test::TinyWorld();
  const worlds::Lamp& panel = world.lamps[1];
  REQUIRE(panel.shape == worlds::LampShape::kPanel);
  const KannalaBrandt camera = UpwardFisheye();
  const Vector3d position(panel.center.x(), panel.center.y(), 1.0);
  const double h = panel.center.z() - position.z();
  const LampTruth seen = LampSeenFromBelow(world, camera, position, panel.id);
  // Equidistant: the outline's extreme columns and rows are the midpoints of its sides.
  const double half_u = camera.fx * std::atan(panel.size_m.x() / 2 / h);
  const double half_v = camera.fy * std::atan(panel.size_m.y() / 2 / h);
  CHECK(seen.shape == worlds::LampShape::kPanel);
  CHECK(seen.radius_px == Approx(std::hypot(half_u, half_v)).margin(kFrameTruthPx));
  CHECK_FALSE(seen.on);
}

TEST_CASE("a reflection is listed only when the mirrored lamp is seen through the strip",
          "[render][frame_truth]") {
  const worlds::World world = test::TinyWorld();
  const worlds::Reflector& reflector = world.reflectors.front();
  const PinholeRadTan camera = FrontPinhole();
  SECTION("line of sight through the strip") {
    const Vector3d eye(3.0, 1.0, 2.0);
    const FrameTruth truth = ComputeFrameTruth(
        Input(world, camera, LookAt(eye, reflector.apparent_lamp_center), RobotAt(eye, 0.0)));
    const LampTruth* seen = FindId(truth.lamps, reflector.id);
    REQUIRE(seen != nullptr);
    CHECK(seen->reflection);
    CHECK(seen->mirrored_lamp_id == reflector.mirrored_lamp_id);
    CHECK((seen->center_px - Vector2d(camera.cx, camera.cy)).norm() < kFrameTruthPx);
    CHECK(seen->visible_fraction == 1.0);
  }
  SECTION("line of sight through the solid wall below the strip") {
    const Vector3d eye(3.0, 0.0, 0.3);
    const FrameTruth truth = ComputeFrameTruth(
        Input(world, camera, LookAt(eye, reflector.apparent_lamp_center), RobotAt(eye, 0.0)));
    CHECK(FindId(truth.lamps, reflector.id) == nullptr);
  }
}

// ---- doors --------------------------------------------------------------------------------------

TEST_CASE("door column bearings follow P3 eq. 17 and P2 eq. 8", "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::Doorway& door = world.doors.front();
  const KannalaBrandt camera = UpwardFisheye();
  const Vector2d beside = (door.column_a + door.column_b) / 2 + 0.8 * door.inward_normal;
  const Vector3d position(beside.x(), beside.y(), 0.3);
  for (const double yaw : {0.0, 0.7, -2.5}) {
    CAPTURE(yaw);
    const SE3 world_from_camera = UpwardCamera(position, yaw);
    const FrameTruth truth =
        ComputeFrameTruth(Input(world, camera, world_from_camera, RobotAt(position, yaw)));
    const DoorTruth* seen = FindId(truth.doors, door.id);
    REQUIRE(seen != nullptr);
    CHECK(seen->state == door.state);
    CHECK(seen->visible);
    const auto check_column = [&](const Vector2d& column, const Vector2d& pixel, double bearing,
                                  double p2_theta, double image_angle) {
      const Vector3d top(column.x(), column.y(), door.top_height_m);
      const Vector3d p_in_camera =
          world_from_camera.rotation().transpose() * (top - world_from_camera.translation());
      const double expected = std::atan2(p_in_camera.y(), p_in_camera.x());
      CHECK(AngleDiff(bearing, expected) < kFrameTruthRad);
      CHECK(AngleDiff(p2_theta, kPi / 2 - expected) < kFrameTruthRad);
      CHECK(AngleDiff(image_angle, expected) < kFrameTruthRad);
      CHECK((pixel - EquidistantPixel(camera, world_from_camera, top)).norm() < kFrameTruthPx);
    };
    check_column(door.column_a, seen->column_a_px, seen->bearing_a_rad, seen->p2_theta_a_rad,
                 seen->image_angle_a_rad);
    check_column(door.column_b, seen->column_b_px, seen->bearing_b_rad, seen->p2_theta_b_rad,
                 seen->image_angle_b_rad);
  }
}

TEST_CASE("a door whose columns carry no door id in the instance image is not visible",
          "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::Doorway& door = world.doors.front();
  const KannalaBrandt camera = UpwardFisheye();
  const Vector2d beside = (door.column_a + door.column_b) / 2 + 0.8 * door.inward_normal;
  const Vector3d position(beside.x(), beside.y(), 0.3);
  FrameTruthInput input = Input(world, camera, UpwardCamera(position, 0.0), RobotAt(position, 0.0));
  std::vector<std::uint32_t> instance(std::size_t(camera.width * camera.height), 0);
  input.instance = &instance;
  const FrameTruth hidden_truth = ComputeFrameTruth(input);
  const DoorTruth* hidden = FindId(hidden_truth.doors, door.id);
  REQUIRE(hidden != nullptr);
  CHECK_FALSE(hidden->visible);
  std::fill(instance.begin(), instance.end(), static_cast<std::uint32_t>(door.id));
  const FrameTruth shown_truth = ComputeFrameTruth(input);
  const DoorTruth* shown = FindId(shown_truth.doors, door.id);
  REQUIRE(shown != nullptr);
  CHECK(shown->visible);
}

// ---- corners ------------------------------------------------------------------------------------

TEST_CASE("corners behind a front camera are not listed; the others are where a pinhole puts them",
          "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const PinholeRadTan camera = FrontPinhole();
  const Vector3d position(5.0, 0.0, 1.2);
  const SE3 world_from_camera = FrontCamera(position, 0.0);
  FrameTruthInput input = Input(world, camera, world_from_camera, RobotAt(position, 0.0));
  const FrameTruth truth = ComputeFrameTruth(input);

  // Independent count: in front, within range, inside the image.
  int expected = 0;
  int behind_in_range = 0;
  for (const worlds::CornerPoint& corner : world.corner_points) {
    const Vector3d delta = corner.position - position;
    if (delta.norm() > input.max_range_m) continue;
    if (delta.x() <= 0.0) {
      ++behind_in_range;
      continue;
    }
    const Vector2d pixel = PinholePixel(camera, world_from_camera, corner.position);
    if (pixel.x() >= -0.5 && pixel.x() < 639.5 && pixel.y() >= -0.5 && pixel.y() < 479.5) {
      ++expected;
    }
  }
  REQUIRE(behind_in_range > 0);
  REQUIRE(expected > 0);
  CHECK(truth.corners.size() == std::size_t(expected));
  for (const CornerTruth& c : truth.corners) {
    const auto corner = std::find_if(world.corner_points.begin(), world.corner_points.end(),
                                     [&](const worlds::CornerPoint& p) { return p.id == c.id; });
    REQUIRE(corner != world.corner_points.end());
    CHECK(corner->position.x() > position.x());
    CHECK((c.pixel - PinholePixel(camera, world_from_camera, corner->position)).norm() <
          kFrameTruthPx);
  }

  SECTION("a semantic image without ceiling pixels hides every corner") {
    std::vector<std::uint8_t> semantic(std::size_t(camera.width * camera.height),
                                       static_cast<std::uint8_t>(worlds::SemanticClass::kWall));
    input.semantic = &semantic;
    CHECK(ComputeFrameTruth(input).corners.empty());
    std::fill(semantic.begin(), semantic.end(),
              static_cast<std::uint8_t>(worlds::SemanticClass::kCeiling));
    CHECK(ComputeFrameTruth(input).corners.size() == truth.corners.size());
  }
}

// ---- range cut-off and JSON ---------------------------------------------------------------------

TEST_CASE("landmarks beyond max_range_m are not listed", "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const Vector3d position(5.0, 0.0, 1.2);
  FrameTruthInput input =
      Input(world, FrontPinhole(), FrontCamera(position, 0.0), RobotAt(position, 0.0));
  input.max_range_m = 100.0;
  const FrameTruth far = ComputeFrameTruth(input);
  input.max_range_m = 25.0;
  const FrameTruth near = ComputeFrameTruth(input);
  CHECK(std::any_of(far.plates.begin(), far.plates.end(),
                    [](const PlateTruth& p) { return p.distance_m > 25.0; }));
  CHECK(std::all_of(near.plates.begin(), near.plates.end(),
                    [](const PlateTruth& p) { return p.distance_m <= 25.0; }));
  CHECK(near.plates.size() < far.plates.size());
  CHECK(near.corners.size() < far.corners.size());
}

TEST_CASE("frame truth JSON names every field, rounds numbers and is stable",
          "[render][frame_truth]") {
  const worlds::World& world = GeneratedWorld();
  const worlds::DoorPlate& plate = world.plates[3];
  const SE3 world_from_camera = FacingPlate(plate, 1.2);
  const FrameTruthInput input =
      Input(world, FrontPinhole(), world_from_camera, RobotAt(world_from_camera.translation(), 0));
  const nlohmann::ordered_json json = FrameTruthJson(ComputeFrameTruth(input));
  CHECK(json.dump() == FrameTruthJson(ComputeFrameTruth(input)).dump());
  for (const char* key : {"camera_id", "world_from_camera", "world_from_robot", "plates", "lamps",
                          "doors", "vanishing_points", "corners"}) {
    CAPTURE(key);
    CHECK(json.contains(key));
  }
  CHECK(json["camera_id"] == "test_camera");
  const Vector3d& t = world_from_camera.translation();
  REQUIRE(json["world_from_camera"]["t"].size() == 3);
  REQUIRE(json["world_from_camera"]["q"].size() == 4);
  CHECK(json["world_from_camera"]["t"][0].get<double>() == Approx(t.x()).margin(1e-6));
  CHECK(json["world_from_camera"]["t"][2].get<double>() == Approx(t.z()).margin(1e-6));
  CHECK(std::abs(json["world_from_camera"]["q"][3].get<double>()) ==
        Approx(std::abs(world_from_camera.quaternion().w())).margin(1e-9));
  // The JSON pose convention (common/io/stable_json.h): qw >= 0.
  CHECK(json["world_from_camera"]["q"][3].get<double>() >= 0.0);
  CHECK(json["world_from_robot"]["q"][3].get<double>() >= 0.0);

  const auto entry = std::find_if(json["plates"].begin(), json["plates"].end(),
                                  [&](const auto& p) { return p["id"] == plate.id; });
  REQUIRE(entry != json["plates"].end());
  for (const char* key : {"id", "room_number", "corners_px", "center_px", "bbox_px", "distance_m",
                          "viewing_angle_deg", "visible_fraction", "fully_in_image"}) {
    CAPTURE(key);
    CHECK(entry->contains(key));
  }
  CHECK((*entry)["corners_px"].size() == 4);
  const double u = (*entry)["center_px"][0].get<double>();
  CHECK(std::abs(u * 1e4 - std::round(u * 1e4)) < 1e-6);
  CHECK((*entry)["room_number"] == plate.room_number);

  // A front camera sees the corridor's vanishing point, lamps and corners.
  const Vector3d position(5.0, 0.0, 1.2);
  const nlohmann::ordered_json front = FrameTruthJson(ComputeFrameTruth(
      Input(world, FrontPinhole(), FrontCamera(position, 0.0), RobotAt(position, 0.0))));
  REQUIRE(!front["vanishing_points"].empty());
  for (const char* key : {"segment_id", "direction", "pixel", "in_image", "camera_in_segment",
                          "u_from_principal_px", "bearing_rad", "p1_eq19_px"}) {
    CAPTURE(key);
    CHECK(front["vanishing_points"][0].contains(key));
  }
  REQUIRE(!front["lamps"].empty());
  for (const char* key : {"id", "shape", "reflection", "on", "center_px", "radius_px",
                          "cut_by_border", "visible_fraction"}) {
    CAPTURE(key);
    CHECK(front["lamps"][0].contains(key));
  }
  REQUIRE(!front["corners"].empty());
  for (const char* key : {"id", "kind", "pixel"}) {
    CAPTURE(key);
    CHECK(front["corners"][0].contains(key));
  }
  CHECK_FALSE(front["corners"][0].contains("polar"));  // upward cameras only
  REQUIRE(!front["doors"].empty());
  for (const char* key :
       {"id", "state", "column_a_px", "column_b_px", "bearing_a_rad", "bearing_b_rad",
        "p2_theta_a_rad", "p2_theta_b_rad", "image_angle_a_rad", "image_angle_b_rad", "visible"}) {
    CAPTURE(key);
    CHECK(front["doors"][0].contains(key));
  }
}

}  // namespace
}  // namespace corridorsim::render
