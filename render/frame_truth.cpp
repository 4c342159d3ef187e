#include "render/frame_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "common/io/stable_json.h"

namespace corridorsim::render {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr int kPlateGrid = 5;             // plate visibility samples per side (5x5 cell centres)
constexpr int kOutlinePointsPerSide = 8;  // plate and panel outlines: 4 sides x 8 = 32 points
constexpr int kRimPoints = 32;            // circular lamp rim
constexpr double kLabelInset = 0.9;       // lamp samples pulled in from the rim (see below)
constexpr int kColumnSamples = 16;        // door column: label samples from floor to top
constexpr int kColumnSearchPx = 2;        // door column: label search half-width (px)
// Polar coordinates (P2 eq. 7, P3 eq. 16) only for cameras whose optical axis is within 45 deg of
// world +z: the axis' world z component exceeds cos(45 deg).
constexpr double kUpwardMinAxisZ = std::numbers::sqrt2 / 2;

// Yaw of a frame whose z is (nearly) up: angle of its x axis in the world x-y plane.
double YawOf(const SE3& world_from_frame) {
  const Eigen::Matrix3d r = world_from_frame.rotation();
  return std::atan2(r(1, 0), r(0, 0));
}

// Everything about the camera that every landmark needs.
class Frame {
 public:
  explicit Frame(const FrameTruthInput& input)
      : input_(input),
        camera_from_world_(input.world_from_camera.Inverse()),
        camera_in_world_(input.world_from_camera.translation()),
        intrinsics_(input.model.intrinsics()),
        robot_yaw_(YawOf(input.world_from_robot)),
        max_range_squared_(input.max_range_m * input.max_range_m),
        upward_(input.world_from_camera.rotation()(2, 2) > kUpwardMinAxisZ) {
    const std::size_t pixels = std::size_t(intrinsics_.width) * std::size_t(intrinsics_.height);
    CheckOrDie(input.instance == nullptr || input.instance->size() == pixels,
               "render::ComputeFrameTruth",
               "instance image size differs from the camera's width * height");
    CheckOrDie(input.semantic == nullptr || input.semantic->size() == pixels,
               "render::ComputeFrameTruth",
               "semantic image size differs from the camera's width * height");
  }

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const Vector3d& camera_in_world() const { return camera_in_world_; }
  double robot_yaw() const { return robot_yaw_; }
  const SE3& camera_from_world() const { return camera_from_world_; }
  bool has_instance() const { return input_.instance != nullptr; }
  bool has_semantic() const { return input_.semantic != nullptr; }

  // The cheap rejection every landmark goes through first.
  bool InRange(const Vector3d& p_in_world) const {
    return (p_in_world - camera_in_world_).squaredNorm() <= max_range_squared_;
  }

  // nullopt behind the camera or outside the model's valid angle.
  std::optional<Vector2d> Project(const Vector3d& p_in_world) const {
    return input_.model.Project(camera_from_world_ * p_in_world);
  }
  std::optional<Vector2d> ProjectDirection(const Vector3d& direction_in_camera) const {
    return input_.model.Project(direction_in_camera);
  }
  bool InImage(const Vector2d& pixel) const { return input_.model.IsInImage(pixel); }

  // Label-image index of an in-image pixel (nearest pixel centre).
  std::size_t Index(const Vector2d& pixel) const {
    const int col =
        std::clamp(static_cast<int>(std::floor(pixel.x() + 0.5)), 0, intrinsics_.width - 1);
    const int row =
        std::clamp(static_cast<int>(std::floor(pixel.y() + 0.5)), 0, intrinsics_.height - 1);
    return std::size_t(row) * std::size_t(intrinsics_.width) + std::size_t(col);
  }
  // True without an instance image; otherwise whether the pixel shows object `id`.
  bool ShowsId(const Vector2d& pixel, int id) const {
    return input_.instance == nullptr ||
           (*input_.instance)[Index(pixel)] == static_cast<std::uint32_t>(id);
  }
  // Whether object `id` appears within `radius_px` pixels of `pixel` (true without labels).
  bool ShowsIdNear(const Vector2d& pixel, int id, int radius_px) const {
    if (input_.instance == nullptr) return true;
    for (int dv = -radius_px; dv <= radius_px; ++dv) {
      for (int du = -radius_px; du <= radius_px; ++du) {
        const Vector2d probe = pixel + Vector2d(du, dv);
        if (InImage(probe) && ShowsId(probe, id)) return true;
      }
    }
    return false;
  }
  std::uint8_t SemanticAt(const Vector2d& pixel) const { return (*input_.semantic)[Index(pixel)]; }

  // P2 eq. 7 / P3 eq. 16 polar coordinates of a point above the camera.
  std::optional<UpwardPolar> Polar(const Vector3d& p_in_world) const {
    const Vector3d delta = p_in_world - camera_in_world_;
    if (!upward_ || !(delta.z() > 0.0)) return std::nullopt;
    const double alpha = std::atan2(delta.y(), delta.x());
    UpwardPolar polar;
    polar.r_px = delta.head<2>().norm() * intrinsics_.fx / delta.z();
    polar.theta_rad = NormalizeAngle(alpha - robot_yaw_);
    polar.p2_theta_rad = NormalizeAngle(kPi / 2 - alpha + robot_yaw_);
    return polar;
  }

 private:
  const FrameTruthInput& input_;
  SE3 camera_from_world_;
  Vector3d camera_in_world_;
  CameraIntrinsics intrinsics_;
  double robot_yaw_;
  double max_range_squared_;
  bool upward_;  // the optical axis points up: the papers' polar image coordinates apply
};

// Points on a rectangle's outline, `per_side` per side, starting at corners[0]; corners in order.
std::vector<Vector3d> Outline(const std::array<Vector3d, 4>& corners, int per_side) {
  std::vector<Vector3d> points;
  points.reserve(std::size_t(4 * per_side));
  for (std::size_t side = 0; side < 4; ++side) {
    const Vector3d& from = corners[side];
    const Vector3d& to = corners[(side + 1) % 4];
    for (int k = 0; k < per_side; ++k) points.push_back(from + (to - from) * k / per_side);
  }
  return points;
}

// All points projected, or nullopt if any of them does not project.
std::optional<std::vector<Vector2d>> ProjectAll(const Frame& frame,
                                                const std::vector<Vector3d>& points) {
  std::vector<Vector2d> pixels;
  pixels.reserve(points.size());
  for (const Vector3d& p : points) {
    const std::optional<Vector2d> pixel = frame.Project(p);
    if (!pixel) return std::nullopt;
    pixels.push_back(*pixel);
  }
  return pixels;
}

// ---- door plates ------------------------------------------------------------------------------

std::optional<PlateTruth> PlateInFrame(const Frame& frame, const worlds::DoorPlate& plate) {
  if (!frame.InRange(plate.center)) return std::nullopt;
  const Vector3d to_camera = frame.camera_in_world() - plate.center;
  if (!(to_camera.dot(plate.normal) > 0.0)) return std::nullopt;  // seen from behind the wall
  const Vector3d right = Vector3d::UnitZ().cross(plate.normal).normalized();
  const Vector3d half_width = right * (plate.size_m.x() / 2);
  const Vector3d half_height = Vector3d::UnitZ() * (plate.size_m.y() / 2);
  const std::array<Vector3d, 4> corners = {
      plate.center - half_width + half_height, plate.center + half_width + half_height,
      plate.center + half_width - half_height, plate.center - half_width - half_height};
  // A plate that straddles the model's valid range is not listed.
  const std::optional<std::vector<Vector2d>> outline =
      ProjectAll(frame, Outline(corners, kOutlinePointsPerSide));
  const std::optional<Vector2d> center_px = frame.Project(plate.center);
  if (!outline || !center_px) return std::nullopt;

  PlateTruth truth;
  truth.id = plate.id;
  truth.room_number = plate.room_number;
  for (std::size_t k = 0; k < 4; ++k) {
    truth.corners_px[k] = (*outline)[k * kOutlinePointsPerSide];
  }
  truth.center_px = *center_px;
  truth.bbox_min_px = truth.bbox_max_px = outline->front();
  truth.fully_in_image = true;
  for (const Vector2d& pixel : *outline) {
    truth.bbox_min_px = truth.bbox_min_px.cwiseMin(pixel);
    truth.bbox_max_px = truth.bbox_max_px.cwiseMax(pixel);
    truth.fully_in_image = truth.fully_in_image && frame.InImage(pixel);
  }
  // The number region's outline, in the face's own coordinates (x right, y up).
  const auto on_face = [&](double x_m, double y_m) {
    return Vector3d(plate.center + right * x_m + Vector3d::UnitZ() * y_m);
  };
  const Vector2d& n0 = plate.number_min_in_face;
  const Vector2d& n1 = plate.number_max_in_face;
  const std::array<Vector3d, 4> number_corners = {on_face(n0.x(), n1.y()), on_face(n1.x(), n1.y()),
                                                  on_face(n1.x(), n0.y()), on_face(n0.x(), n0.y())};
  const std::optional<std::vector<Vector2d>> number_outline =
      ProjectAll(frame, Outline(number_corners, kOutlinePointsPerSide));
  if (!number_outline) return std::nullopt;  // inside the plate's outline: projects if it does
  truth.number_bbox_min_px = truth.number_bbox_max_px = number_outline->front();
  for (const Vector2d& pixel : *number_outline) {
    truth.number_bbox_min_px = truth.number_bbox_min_px.cwiseMin(pixel);
    truth.number_bbox_max_px = truth.number_bbox_max_px.cwiseMax(pixel);
  }
  truth.distance_m = to_camera.norm();
  truth.viewing_angle_deg =
      std::acos(std::clamp(to_camera.dot(plate.normal) / truth.distance_m, -1.0, 1.0)) * kDegPerRad;

  // Visibility: centres of a 5x5 grid of cells on the face (cell centres, so no sample sits on
  // the plate's edge where the nearest label pixel may belong to the wall).
  int seen = 0;
  for (int i = 0; i < kPlateGrid; ++i) {
    for (int j = 0; j < kPlateGrid; ++j) {
      const double s = (i + 0.5) / kPlateGrid * 2.0 - 1.0;  // -0.8 .. 0.8 of the half size
      const double t = (j + 0.5) / kPlateGrid * 2.0 - 1.0;
      const std::optional<Vector2d> pixel =
          frame.Project(plate.center + s * half_width + t * half_height);
      if (pixel && frame.InImage(*pixel) && frame.ShowsId(*pixel, plate.id)) ++seen;
    }
  }
  truth.visible_fraction = double(seen) / (kPlateGrid * kPlateGrid);
  if (seen == 0) return std::nullopt;
  return truth;
}

// ---- lamps and reflections --------------------------------------------------------------------

// Rim of a lamp's emitting face (horizontal): 32 points on the circle, or on the panel outline.
std::vector<Vector3d> LampRim(const Vector3d& center, worlds::LampShape shape, double radius_m,
                              const Vector2d& size_m) {
  if (shape == worlds::LampShape::kPanel) {
    const Vector3d hx(size_m.x() / 2, 0, 0), hy(0, size_m.y() / 2, 0);
    return Outline({center - hx - hy, center + hx - hy, center + hx + hy, center - hx + hy},
                   kRimPoints / 4);
  }
  std::vector<Vector3d> rim;
  rim.reserve(kRimPoints);
  for (int k = 0; k < kRimPoints; ++k) {
    const double angle = 2.0 * kPi * k / kRimPoints;
    rim.push_back(center + radius_m * Vector3d(std::cos(angle), std::sin(angle), 0.0));
  }
  return rim;
}

// The geometric part of a lamp entry: centre, radius, border cut. nullopt when the centre or a
// rim point does not project (the lamp straddles the model's valid range).
std::optional<LampTruth> LampGeometry(const Frame& frame, const Vector3d& center,
                                      const std::vector<Vector3d>& rim, worlds::LampShape shape) {
  const std::optional<Vector2d> center_px = frame.Project(center);
  const std::optional<std::vector<Vector2d>> rim_px = ProjectAll(frame, rim);
  if (!center_px || !rim_px) return std::nullopt;
  LampTruth truth;
  truth.shape = shape;
  truth.center_px = *center_px;
  Vector2d lo = rim_px->front(), hi = rim_px->front();
  double sum_px = 0.0;
  for (const Vector2d& pixel : *rim_px) {
    lo = lo.cwiseMin(pixel);
    hi = hi.cwiseMax(pixel);
    sum_px += (pixel - *center_px).norm();
    truth.cut_by_border = truth.cut_by_border || !frame.InImage(pixel);
  }
  truth.radius_px =
      shape == worlds::LampShape::kPanel ? (hi - lo).norm() / 2 : sum_px / double(rim_px->size());
  truth.polar = frame.Polar(center);
  return truth;
}

// Visibility samples of a lamp: the centre and the rim pulled in to 90 % (a point exactly on the
// rim may round to a ceiling pixel next to the lamp in the label image).
std::vector<Vector3d> LampSamples(const Vector3d& center, const std::vector<Vector3d>& rim) {
  std::vector<Vector3d> samples = {center};
  for (const Vector3d& p : rim) samples.push_back(center + kLabelInset * (p - center));
  return samples;
}

std::optional<LampTruth> LampInFrame(const Frame& frame, const worlds::Lamp& lamp) {
  if (!frame.InRange(lamp.center)) return std::nullopt;
  const std::vector<Vector3d> rim = LampRim(lamp.center, lamp.shape, lamp.radius_m, lamp.size_m);
  std::optional<LampTruth> truth = LampGeometry(frame, lamp.center, rim, lamp.shape);
  if (!truth) return std::nullopt;
  truth->id = lamp.id;
  truth->on = lamp.on;
  const std::vector<Vector3d> samples = LampSamples(lamp.center, rim);
  int seen = 0;
  for (const Vector3d& p : samples) {
    const std::optional<Vector2d> pixel = frame.Project(p);
    if (pixel && frame.InImage(*pixel) && frame.ShowsId(*pixel, lamp.id)) ++seen;
  }
  truth->visible_fraction = double(seen) / double(samples.size());
  if (seen == 0) return std::nullopt;
  return truth;
}

// A reflector shows its mirrored lamp at apparent_lamp_center, seen through the strip (an opening
// of the wall face onto the mirror image). A sample counts when its line of sight crosses the wall
// plane inside the strip, it projects into the image and, with labels, its pixel carries the
// reflector id (the strip's meshes, mirrored lamp included, carry it).
std::optional<LampTruth> ReflectionInFrame(const Frame& frame, const worlds::World& world,
                                           const worlds::Reflector& reflector) {
  if (!frame.InRange(reflector.apparent_lamp_center)) return std::nullopt;
  const auto lamp = std::find_if(world.lamps.begin(), world.lamps.end(),
                                 [&](const auto& l) { return l.id == reflector.mirrored_lamp_id; });
  const auto wall = std::find_if(world.walls.begin(), world.walls.end(),
                                 [&](const auto& w) { return w.id == reflector.wall_id; });
  if (lamp == world.lamps.end() || wall == world.walls.end()) return std::nullopt;
  const Vector3d normal(wall->inward_normal.x(), wall->inward_normal.y(), 0.0);
  const Vector3d tangent(wall->tangent().x(), wall->tangent().y(), 0.0);
  const Vector3d& eye = frame.camera_in_world();
  const double eye_height = (eye - reflector.center).dot(normal);  // in front of the wall face
  if (!(eye_height > 0.0)) return std::nullopt;

  const Vector3d& center = reflector.apparent_lamp_center;
  const std::vector<Vector3d> rim = LampRim(center, lamp->shape, lamp->radius_m, lamp->size_m);
  std::optional<LampTruth> truth = LampGeometry(frame, center, rim, lamp->shape);
  if (!truth) return std::nullopt;
  truth->id = reflector.id;
  truth->reflection = true;
  truth->mirrored_lamp_id = lamp->id;
  truth->on = lamp->on;
  const auto through_strip = [&](const Vector3d& p) {
    const double depth = (eye - p).dot(normal);  // p behind the face: depth > eye_height
    if (!(depth > eye_height)) return false;
    const Vector3d crossing = eye + (p - eye) * (eye_height / depth);
    const Vector3d offset = crossing - reflector.center;
    return std::abs(offset.dot(tangent)) <= reflector.size_m.x() / 2 &&
           std::abs(offset.z()) <= reflector.size_m.y() / 2;
  };
  const std::vector<Vector3d> samples = LampSamples(center, rim);
  int seen = 0;
  for (const Vector3d& p : samples) {
    if (!through_strip(p)) continue;
    const std::optional<Vector2d> pixel = frame.Project(p);
    if (pixel && frame.InImage(*pixel) && frame.ShowsId(*pixel, reflector.id)) ++seen;
  }
  truth->visible_fraction = double(seen) / double(samples.size());
  if (seen == 0) return std::nullopt;
  return truth;
}

// ---- doors ------------------------------------------------------------------------------------

// Whether a door column shows in the label image somewhere between the floor and the top of the
// opening, sampled on the column's front face (protruding frame_protrusion_m into the corridor).
bool ColumnSeen(const Frame& frame, const worlds::World& world, const worlds::Doorway& door,
                const Vector2d& column) {
  if (!frame.has_instance()) return true;
  const Vector2d front = column + door.inward_normal * world.options.doors.frame_protrusion_m;
  for (int k = 0; k <= kColumnSamples; ++k) {
    const double z = door.top_height_m * k / kColumnSamples;
    const std::optional<Vector2d> pixel = frame.Project(Vector3d(front.x(), front.y(), z));
    if (pixel && frame.InImage(*pixel) && frame.ShowsIdNear(*pixel, door.id, kColumnSearchPx)) {
      return true;
    }
  }
  return false;
}

std::optional<DoorTruth> DoorInFrame(const Frame& frame, const worlds::World& world,
                                     const worlds::Doorway& door) {
  const Vector3d top_a(door.column_a.x(), door.column_a.y(), door.top_height_m);
  const Vector3d top_b(door.column_b.x(), door.column_b.y(), door.top_height_m);
  if (!frame.InRange(top_a) && !frame.InRange(top_b)) return std::nullopt;
  const std::optional<Vector2d> pixel_a = frame.Project(top_a);
  const std::optional<Vector2d> pixel_b = frame.Project(top_b);
  if (!pixel_a || !pixel_b) return std::nullopt;
  const bool a_in = frame.InImage(*pixel_a), b_in = frame.InImage(*pixel_b);
  if (!a_in && !b_in) return std::nullopt;

  DoorTruth truth;
  truth.id = door.id;
  truth.state = door.state;
  truth.column_a_px = *pixel_a;
  truth.column_b_px = *pixel_b;
  const Vector2d camera_xy = frame.camera_in_world().head<2>();
  const auto bearing = [&](const Vector2d& column) {
    const Vector2d delta = column - camera_xy;
    return std::atan2(delta.y(), delta.x());
  };
  // P3 eq. 17: theta_D = atan2(y_D - y_R, x_D - x_R) - theta_R.
  truth.bearing_a_rad = NormalizeAngle(bearing(door.column_a) - frame.robot_yaw());
  truth.bearing_b_rad = NormalizeAngle(bearing(door.column_b) - frame.robot_yaw());
  // P2 eq. 8: z_theta = pi/2 - atan2(c_y - r_y, c_x - r_x) + r_theta.
  truth.p2_theta_a_rad = NormalizeAngle(kPi / 2 - truth.bearing_a_rad);
  truth.p2_theta_b_rad = NormalizeAngle(kPi / 2 - truth.bearing_b_rad);
  const CameraIntrinsics& k = frame.intrinsics();
  truth.image_angle_a_rad = std::atan2(pixel_a->y() - k.cy, pixel_a->x() - k.cx);
  truth.image_angle_b_rad = std::atan2(pixel_b->y() - k.cy, pixel_b->x() - k.cx);
  truth.visible = a_in && b_in && ColumnSeen(frame, world, door, door.column_a) &&
                  ColumnSeen(frame, world, door, door.column_b);
  return truth;
}

// ---- vanishing points -------------------------------------------------------------------------

bool OverSegment(const worlds::CorridorSegment& segment, const Vector2d& p) {
  const Vector2d axis = segment.end - segment.start;
  const double along = (p - segment.start).dot(axis.normalized());
  const double across =
      std::abs((p - segment.start).dot(Vector2d(-axis.y(), axis.x()).normalized()));
  return along >= 0.0 && along <= axis.norm() && across <= segment.width_m / 2;
}

std::optional<VanishingPointTruth> VanishingPointInFrame(const Frame& frame,
                                                         const worlds::CorridorSegment& segment) {
  Vector2d direction = segment.direction();
  Vector3d direction_in_camera =
      frame.camera_from_world().rotation() * Vector3d(direction.x(), direction.y(), 0.0);
  if (direction_in_camera.z() < 0.0) {  // the end of the corridor in front of the camera
    direction = -direction;
    direction_in_camera = -direction_in_camera;
  }
  const std::optional<Vector2d> pixel = frame.ProjectDirection(direction_in_camera);
  if (!pixel) return std::nullopt;
  VanishingPointTruth truth;
  truth.segment_id = segment.id;
  truth.direction_in_world = direction;
  truth.pixel = *pixel;
  truth.in_image = frame.InImage(*pixel);
  truth.camera_in_segment = OverSegment(segment, frame.camera_in_world().head<2>());
  truth.u_from_principal_px = pixel->x() - frame.intrinsics().cx;
  const double alpha = std::atan2(direction.y(), direction.x());
  truth.bearing_rad = NormalizeAngle(alpha - frame.robot_yaw());
  // P1 eq. 19 with the virtual landmark at infinity along the axis: the unit vector from the
  // robot to it is (cos alpha, sin alpha), so z_v = f_v (cos a sin phi - sin a cos phi).
  truth.p1_eq19_px = frame.intrinsics().fx * std::sin(frame.robot_yaw() - alpha);
  return truth;
}

// ---- ceiling corners --------------------------------------------------------------------------

bool CeilingLike(std::uint8_t value) {
  using worlds::SemanticClass;
  const auto c = static_cast<SemanticClass>(value);
  return c == SemanticClass::kCeiling || c == SemanticClass::kVent ||
         c == SemanticClass::kSprinkler || c == SemanticClass::kSmokeDetector;
}

std::optional<CornerTruth> CornerInFrame(const Frame& frame, const worlds::CornerPoint& corner) {
  if (!frame.InRange(corner.position)) return std::nullopt;
  const std::optional<Vector2d> pixel = frame.Project(corner.position);
  if (!pixel || !frame.InImage(*pixel)) return std::nullopt;
  if (frame.has_semantic() && !CeilingLike(frame.SemanticAt(*pixel))) return std::nullopt;
  CornerTruth truth;
  truth.id = corner.id;
  truth.kind = corner.kind;
  truth.pixel = *pixel;
  truth.polar = frame.Polar(corner.position);
  return truth;
}

// ---- JSON -------------------------------------------------------------------------------------

// Fixed rounding steps (common/io/stable_json.h) so that equal truth prints equal bytes.
double Px(double v) { return RoundToStep(v, json_steps::kPx); }
double Metres(double v) { return RoundToStep(v, json_steps::kMetres); }
double Rad(double v) { return RoundToStep(v, json_steps::kRad); }
double Deg(double v) { return RoundToStep(v, json_steps::kDeg); }
double Fraction(double v) { return RoundToStep(v, json_steps::kRatio); }

nlohmann::ordered_json PixelJson(const Vector2d& p) { return RoundedJson(p, json_steps::kPx); }

void AddPolar(nlohmann::ordered_json& json, const std::optional<UpwardPolar>& polar) {
  if (!polar) return;
  json["polar"] = {{"r_px", Px(polar->r_px)},
                   {"theta_rad", Rad(polar->theta_rad)},
                   {"p2_theta_rad", Rad(polar->p2_theta_rad)}};
}

}  // namespace

FrameTruth ComputeFrameTruth(const FrameTruthInput& input) {
  CheckOrDie(input.world != nullptr, "render::ComputeFrameTruth", "FrameTruthInput::world is null");
  const worlds::World& world = *input.world;
  const Frame frame(input);
  FrameTruth truth;
  truth.camera_id = input.camera_id;
  truth.world_from_camera = input.world_from_camera;
  truth.world_from_robot = input.world_from_robot;
  for (const worlds::DoorPlate& plate : world.plates) {
    if (auto t = PlateInFrame(frame, plate)) truth.plates.push_back(std::move(*t));
  }
  for (const worlds::Lamp& lamp : world.lamps) {
    if (auto t = LampInFrame(frame, lamp)) truth.lamps.push_back(*t);
  }
  for (const worlds::Reflector& reflector : world.reflectors) {
    if (auto t = ReflectionInFrame(frame, world, reflector)) truth.lamps.push_back(*t);
  }
  for (const worlds::Doorway& door : world.doors) {
    if (auto t = DoorInFrame(frame, world, door)) truth.doors.push_back(*t);
  }
  for (const worlds::CorridorSegment& segment : world.segments) {
    if (auto t = VanishingPointInFrame(frame, segment)) truth.vanishing_points.push_back(*t);
  }
  for (const worlds::CornerPoint& corner : world.corner_points) {
    if (auto t = CornerInFrame(frame, corner)) truth.corners.push_back(*t);
  }
  return truth;
}

nlohmann::ordered_json FrameTruthJson(const FrameTruth& truth) {
  nlohmann::ordered_json json;
  json["camera_id"] = truth.camera_id;
  json["world_from_camera"] = PoseJson(truth.world_from_camera);
  json["world_from_robot"] = PoseJson(truth.world_from_robot);

  json["plates"] = nlohmann::ordered_json::array();
  for (const PlateTruth& p : truth.plates) {
    nlohmann::ordered_json e;
    e["id"] = p.id;
    e["room_number"] = p.room_number;
    e["corners_px"] = nlohmann::ordered_json::array();
    for (const Vector2d& c : p.corners_px) e["corners_px"].push_back(PixelJson(c));
    e["center_px"] = PixelJson(p.center_px);
    e["bbox_px"] = {{"min", PixelJson(p.bbox_min_px)}, {"max", PixelJson(p.bbox_max_px)}};
    e["number_bbox_px"] = {{"min", PixelJson(p.number_bbox_min_px)},
                           {"max", PixelJson(p.number_bbox_max_px)}};
    e["distance_m"] = Metres(p.distance_m);
    e["viewing_angle_deg"] = Deg(p.viewing_angle_deg);
    e["visible_fraction"] = Fraction(p.visible_fraction);
    e["fully_in_image"] = p.fully_in_image;
    json["plates"].push_back(std::move(e));
  }

  json["lamps"] = nlohmann::ordered_json::array();
  for (const LampTruth& l : truth.lamps) {
    nlohmann::ordered_json e;
    e["id"] = l.id;
    e["shape"] = worlds::LampShapeName(l.shape);
    e["reflection"] = l.reflection;
    if (l.reflection) e["mirrored_lamp_id"] = l.mirrored_lamp_id;
    e["on"] = l.on;
    e["center_px"] = PixelJson(l.center_px);
    e["radius_px"] = Px(l.radius_px);
    e["cut_by_border"] = l.cut_by_border;
    e["visible_fraction"] = Fraction(l.visible_fraction);
    AddPolar(e, l.polar);
    json["lamps"].push_back(std::move(e));
  }

  json["doors"] = nlohmann::ordered_json::array();
  for (const DoorTruth& d : truth.doors) {
    nlohmann::ordered_json e;
    e["id"] = d.id;
    e["state"] = worlds::DoorStateName(d.state);
    e["column_a_px"] = PixelJson(d.column_a_px);
    e["column_b_px"] = PixelJson(d.column_b_px);
    e["bearing_a_rad"] = Rad(d.bearing_a_rad);
    e["bearing_b_rad"] = Rad(d.bearing_b_rad);
    e["p2_theta_a_rad"] = Rad(d.p2_theta_a_rad);
    e["p2_theta_b_rad"] = Rad(d.p2_theta_b_rad);
    e["image_angle_a_rad"] = Rad(d.image_angle_a_rad);
    e["image_angle_b_rad"] = Rad(d.image_angle_b_rad);
    e["visible"] = d.visible;
    json["doors"].push_back(std::move(e));
  }

  json["vanishing_points"] = nlohmann::ordered_json::array();
  for (const VanishingPointTruth& v : truth.vanishing_points) {
    nlohmann::ordered_json e;
    e["segment_id"] = v.segment_id;
    e["direction"] = RoundedJson(v.direction_in_world, json_steps::kUnitVector);
    e["pixel"] = PixelJson(v.pixel);
    e["in_image"] = v.in_image;
    e["camera_in_segment"] = v.camera_in_segment;
    e["u_from_principal_px"] = Px(v.u_from_principal_px);
    e["bearing_rad"] = Rad(v.bearing_rad);
    e["p1_eq19_px"] = Px(v.p1_eq19_px);
    json["vanishing_points"].push_back(std::move(e));
  }

  json["corners"] = nlohmann::ordered_json::array();
  for (const CornerTruth& c : truth.corners) {
    nlohmann::ordered_json e;
    e["id"] = c.id;
    e["kind"] = worlds::CornerKindName(c.kind);
    e["pixel"] = PixelJson(c.pixel);
    AddPolar(e, c.polar);
    json["corners"].push_back(std::move(e));
  }
  return json;
}

}  // namespace corridorsim::render
