#pragma once
// Frame truth: the landmarks one camera sees in one frame, in that camera's image, computed from
// the World's exact geometry (STYLE item 9: truth, before any noise or detector). Optional label
// images from the renderer add occlusion; without them only the image border and the camera
// model's valid range decide what is seen.
//
// Pixels: (0, 0) is the centre of the top-left pixel (common/camera_models.h). Angles in rad
// unless the name says deg. Bearings follow the papers' upward-camera models: x_R, y_R is the
// camera's optical centre projected on the floor plane (the papers mount the camera on the robot's
// axis; the image shows the camera's own viewpoint) and theta_R the robot's yaw.
//
// Cost: every landmark list of the world is scanned once with a squared-distance test against
// max_range_m (a few ns each, so thousands of far corner points stay cheap); only landmarks within
// range are projected.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/camera_models.h"
#include "common/pose.h"
#include "worlds/world.h"

namespace corridorsim::render {

struct FrameTruthInput {
  const worlds::World* world = nullptr;  // must be set
  std::string camera_id;
  CameraModel model;      // the camera's projection (pinhole with distortion, or KB fisheye)
  SE3 world_from_camera;  // OpenCV optical frame: x right, y down, z forward
  SE3 world_from_robot;   // robot frame (x forward, z up): gives theta_R of the papers' bearings
  // Optional label images, width * height row-major (row 0 on top), or nullptr: instance ids
  // (worlds ids, 0 = nothing) for occlusion, and worlds::SemanticClass values for corners.
  const std::vector<std::uint32_t>* instance = nullptr;
  const std::vector<std::uint8_t>* semantic = nullptr;
  double max_range_m = 25.0;  // landmarks farther than this from the optical centre are skipped
};

/// Polar image coordinates of a point above an upward camera, P2 eq. 7 / P3 eq. 16 (corners;
/// P3: lamps share the corner model). Present only for an upward camera (optical axis within
/// 45 deg of world +z) and a point above its optical centre. dx, dy, dz: point minus optical
/// centre in the world. With a fisheye the image radius is fx * atan(d / dz), not this pinhole r.
struct UpwardPolar {
  double r_px = 0.0;          // sqrt(dx^2 + dy^2) * f / dz, f = the model's fx (P2 eq. 7 z_r)
  double theta_rad = 0.0;     // atan2(dy, dx) - theta_R in (-pi, pi] (P3 eq. 16 theta_C)
  double p2_theta_rad = 0.0;  // pi/2 - atan2(dy, dx) + theta_R in (-pi, pi] (P2 eq. 7 z_theta)
};

struct PlateTruth {
  int id = 0;
  std::string room_number;  // P1 eq. 20 signature s_d
  // Front-face corners for a viewer facing the plate: top-left, top-right, bottom-right,
  // bottom-left. "Right" = z x normal (world), "top" = +z.
  std::array<Eigen::Vector2d, 4> corners_px;
  Eigen::Vector2d center_px;    // projection of the face centre (P1 eq. 20: u_d = center_px.x - cx)
  Eigen::Vector2d bbox_min_px;  // of the projected outline (32 points, follows distortion)
  Eigen::Vector2d bbox_max_px;
  // The number region (worlds::DoorPlate::number_*_in_face: the drawn digits, what P1's
  // detector finds): the bbox of its projected outline (32 points, follows distortion).
  Eigen::Vector2d number_bbox_min_px{0, 0};
  Eigen::Vector2d number_bbox_max_px{0, 0};
  double distance_m = 0.0;         // optical centre to plate centre
  double viewing_angle_deg = 0.0;  // between the plate normal and the plate-to-camera direction
  double visible_fraction = 0.0;   // of a 5x5 grid of cell centres on the face (see .cpp)
  bool fully_in_image = false;     // the whole outline projects inside the image
};

struct LampTruth {
  int id = 0;  // lamp id, or the reflector id for a reflection
  worlds::LampShape shape = worlds::LampShape::kCircular;
  bool reflection = false;    // a lamp seen mirrored through a reflector strip (P3 Fig. 3c)
  int mirrored_lamp_id = -1;  // reflections: the lamp the reflector mirrors
  bool on = true;
  Eigen::Vector2d center_px;  // projection of the 3D centre (may lie outside the image)
  double radius_px = 0.0;  // circular: mean rim distance from center_px; panel: half bbox diagonal
  bool cut_by_border = false;        // some rim point projects outside the image
  double visible_fraction = 0.0;     // of the rim and centre sample points (see .cpp)
  std::optional<UpwardPolar> polar;  // of the centre, P3 eq. 16
};

struct DoorTruth {
  int id = 0;
  worlds::DoorState state = worlds::DoorState::kClosed;
  // Column centre lines at top_height (where an upward camera sees a column meet the bar).
  Eigen::Vector2d column_a_px;
  Eigen::Vector2d column_b_px;
  double bearing_a_rad = 0.0;  // P3 eq. 17: atan2(y_D - y_R, x_D - x_R) - theta_R, (-pi, pi]
  double bearing_b_rad = 0.0;
  double p2_theta_a_rad = 0.0;  // P2 eq. 8: pi/2 - atan2(y_D - y_R, x_D - x_R) + theta_R
  double p2_theta_b_rad = 0.0;
  // Angle of the column's image line about the principal point, atan2(v - cy, u - cx): what a
  // detector reads off an upward image (equals bearing_*_rad when camera x, y = robot x, y).
  double image_angle_a_rad = 0.0;
  double image_angle_b_rad = 0.0;
  bool visible = false;  // both column tops in the image and, with labels, both columns seen
};

struct VanishingPointTruth {
  int segment_id = 0;
  Eigen::Vector2d direction_in_world;  // unit axis direction with the sign in front of the camera
  Eigen::Vector2d pixel;               // projection of the point at infinity along it
  bool in_image = false;
  bool camera_in_segment = false;    // the optical centre lies over this segment's floor rectangle
  double u_from_principal_px = 0.0;  // pixel.x - cx: the u coordinate P1 eq. 19 measures
  double bearing_rad = 0.0;          // direction in the robot frame, atan2(dy, dx) - theta_R
  double p1_eq19_px = 0.0;           // P1 eq. 19 model at infinite range: f_v sin(theta_R - alpha)
};

struct CornerTruth {
  int id = 0;
  worlds::CornerKind kind = worlds::CornerKind::kTileSeam;
  Eigen::Vector2d pixel;
  std::optional<UpwardPolar> polar;  // P2 eq. 7 / P3 eq. 16
};

struct FrameTruth {
  std::string camera_id;
  SE3 world_from_camera;
  SE3 world_from_robot;
  std::vector<PlateTruth> plates;  // world order
  std::vector<LampTruth> lamps;    // lamps in world order, then reflections in world order
  std::vector<DoorTruth> doors;
  std::vector<VanishingPointTruth> vanishing_points;  // one per segment whose direction projects
  std::vector<CornerTruth> corners;
};

/// The landmarks `input`'s camera sees. Aborts (a bug) when input.world is null or a label image
/// has the wrong size.
FrameTruth ComputeFrameTruth(const FrameTruthInput& input);

/// Stable JSON: pixels rounded to 1e-4 px, metres to 1e-6 m, angles to 1e-8 rad (1e-6 deg),
/// fractions to 1e-6, quaternions to 1e-9.
nlohmann::ordered_json FrameTruthJson(const FrameTruth& truth);

}  // namespace corridorsim::render
