#pragma once
// The interface every SLAM pipeline implements, as a real robot would use it: it consumes
// common/ sensor messages (wheel odometry, camera images, depth) with the robot's calibration
// and produces a stamped pose estimate with covariance, its landmarks with covariances and ids,
// optional maps, and what it detected in each frame. Pipelines never see ground truth: slam/
// depends on common/ only (tests/layering_test.cmake).

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"

namespace octomap {
class OcTree;
}

namespace corridorsim::slam {

/// A depth sensor's valid range (m): it reports 0 (invalid) for depths outside [min_m, max_m].
struct DepthRange {
  double min_m;  // nearest valid depth
  double max_m;  // farthest valid depth
};

/// What a robot knows about one of its cameras: intrinsics and mount, as calibrated.
struct CameraCalibration {
  std::string id;                   // "front", "lateral", "upward"
  CameraModel model;                // intrinsics (common/camera_models.h)
  SE3 robot_from_camera;            // mount: the optical frame in the robot frame R
  std::optional<DepthRange> depth;  // depth cameras: registered depth arrives with the colour
                                    // image, valid in this range; nothing for colour-only ones
};

/// What a robot knows about one of its IMUs: its mount and the noise of its data sheet (Kalibr's
/// imu.yaml names and units; the simulator's values when noise is on, else 0).
struct ImuCalibration {
  std::string id;
  SE3 robot_from_imu;  // mount: the IMU's body axes in the robot frame R
  double rate_hz;
  double gyroscope_noise_density;      // rad/s/sqrt(Hz)
  double gyroscope_random_walk;        // rad/s^2/sqrt(Hz)
  double accelerometer_noise_density;  // m/s^2/sqrt(Hz)
  double accelerometer_random_walk;    // m/s^3/sqrt(Hz)
};

/// What a robot knows about one of its planar laser scanners: mount and geometry (the rest of a
/// sweep's geometry comes with each LaserScan).
struct LaserCalibration {
  std::string id;
  SE3 robot_from_laser;  // mount: x the 0 rad beam, z the scan plane's normal
  double rate_hz;
  int beams;             // per sweep
  double range_sigma_m;  // range noise (0 without noise)
};

/// What a robot knows about itself, as its calibration file holds it: nominal values, never the
/// simulator's real ones. The fields have no defaults: whoever builds a Calibration fills every
/// one (the harness from the scenario's options, harness/scenario/calibration.h).
struct Calibration {
  double wheelbase_m;        // nominal distance between the wheels' contact points (B, P1 eq. 13)
  double wheel_diameter_m;   // nominal wheel diameter
  int ticks_per_revolution;  // encoder counts per wheel revolution; 0 = distances unquantised
  std::vector<CameraCalibration> cameras;
  std::vector<ImuCalibration> imus;
  std::vector<LaserCalibration> lasers;

  const CameraCalibration* Find(const std::string& id) const {
    for (const CameraCalibration& c : cameras) {
      if (c.id == id) return &c;
    }
    return nullptr;
  }
  /// The first problem (key relative to the calibration, e.g. "wheelbase_m" or
  /// "cameras.front.depth.max_m"), or nothing.
  std::optional<OptionsProblem> Check() const;
};

/// A camera frame as a pipeline receives it: the colour image and, for a depth camera, the
/// registered depth (0 = invalid).
struct CameraInput {
  StampedImage image;
  std::optional<StampedDepth> depth;
};

/// The robot's pose estimate. Covariance over (x m, y m, yaw rad), yaw last.
struct PoseEstimate {
  TimeNs stamp_ns = 0;
  SE2 world_from_robot;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// Landmark types shared by pipelines and metrics (P1: door plates, vanishing points; P2/P3:
/// corners, lamps, doors).
enum class LandmarkType { kDoorPlate, kCorner, kLamp, kDoor, kVanishingPoint };
std::string LandmarkTypeName(LandmarkType type);

/// A measurement type of a pipeline's own (issue 53): wall lines, visual odometry, scan matches,
/// a gyroscope bias update. A pipeline declares its types up front (Pipeline::measurement_types)
/// and reports innovations and detections of them by name (Innovation::measurement,
/// Detection::measurement); metrics.json, studies and the viewer then give them NIS statistics as
/// they give the shipped landmark types (docs/metrics.md, `nis.<type>`). A type it did not declare,
/// or an innovation whose dof differs from the declared one, fails the pipeline at once.
struct MeasurementType {
  std::string name;  // [a-z][a-z0-9_]{0,31}, not a LandmarkType's name
  int dof = 0;       // its innovations' degrees of freedom, in [1, kMaxMeasurementDof]
};
/// Bounds of a pipeline's declaration.
inline constexpr int kMaxMeasurementTypes = 32;
inline constexpr int kMaxMeasurementDof = 64;
inline constexpr std::size_t kMaxMeasurementNameLength = 32;
/// Whether `name` may name a measurement type: [a-z][a-z0-9_]{0,31} and not a LandmarkType's name.
bool IsMeasurementTypeName(const std::string& name);
/// What is wrong with a declaration (a bad or reserved name, a repeated one, a dof out of range,
/// too many types), or nothing.
std::optional<std::string> MeasurementTypesProblem(const std::vector<MeasurementType>& types);

/// Where a landmark's estimate stands: initialising (not yet fully constrained, e.g. a door plate
/// seen from one place only: its range is not observable from one frame) or converged.
enum class LandmarkStatus { kInitializing, kConverged };
std::string LandmarkStatusName(LandmarkStatus status);

/// One named point of a landmark made of several (P3 eq. 11: a door's two columns).
struct LandmarkPoint {
  std::string role;                                             // "column_a", "column_b"
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();     // m^2
};

/// One landmark of the pipeline's map, in the world frame.
struct LandmarkEstimate {
  int id = 0;  // the pipeline's own id, stable over the run
  LandmarkType type = LandmarkType::kCorner;
  LandmarkStatus status = LandmarkStatus::kConverged;
  // The landmark's reference point: a plate's centre, a corner, a lamp's centre, a door's
  // midpoint, the vanishing point's virtual-plane point (P1 Fig. 10).
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();     // m^2
  std::vector<LandmarkPoint> points;  // the parts of a multi-point landmark (doors), else empty
  std::string label;                  // door plates: the recognised room number ("" if none)
};

/// P2 Fig. 12: the map divided at the doors into the corridor and the rooms behind them
/// (slam/mapping/door_areas.h says how).
enum class AreaKind { kCorridor, kRoom };
struct MapArea {
  int id = 0;  // 0: the corridor; rooms 1, 2, ... in the order their doors were registered
  AreaKind kind = AreaKind::kCorridor;
  int door_landmark_id = -1;  // rooms: the door landmark leading into it
  // Rooms: the outline, counter-clockwise, world x-y (m). The corridor has none: it is the rest
  // of the plane.
  std::vector<Eigen::Vector2d> polygon;
  std::vector<int> landmark_ids;  // the point landmarks in it, ascending
};

/// What a door-plate detection's box outlines: P1 detects the number region (section 3.1); other
/// detectors may report the whole plate.
enum class PlateBox { kNumberRegion, kOutline };

/// One detection in one frame, with the association the pipeline made for it. Which fields a
/// type needs is checked at the boundary (DetectionProblem below).
struct Detection {
  TimeNs stamp_ns = 0;
  std::string camera_id;
  LandmarkType type = LandmarkType::kCorner;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();   // centre (lamps, plates), point (corners),
                                                     // vanishing point
  double radius_px = 0.0;                            // lamps
  Eigen::Vector4d box_px = Eigen::Vector4d::Zero();  // plates, doors: min x, min y, max x, max y
  PlateBox plate_box = PlateBox::kNumberRegion;      // plates: what box_px outlines
  std::string label;                                 // plates: recognised room number
  std::optional<bool> open;                          // doors: open (true) or closed
  // Doors: the bearings of columns a and b from the camera centre in the robot frame (P3 eq. 17,
  // rad); NaN when the detector does not give them.
  Eigen::Vector2d column_bearings_rad =
      Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  // The detector's confidence, for precision-recall curves: plates the SVM margin s(x) (P1 eq.
  // 5), corners their Harris response, the vanishing point its line count; NaN when none.
  double score = std::numeric_limits<double>::quiet_NaN();
  // Plates: the smallest per-digit recognition score in [0, 1] (P1 Fig. 8); NaN when not read.
  double recognition_score = std::numeric_limits<double>::quiet_NaN();
  int landmark_id = -1;       // the landmark it was associated with (-1: none, e.g. rejected)
  bool new_landmark = false;  // it created landmark_id
  // A detection of a measurement type the pipeline declared (MeasurementType::name): then `type`
  // is ignored, and only camera_id, pixel, box_px (optional) and score are read. Empty: a
  // detection of `type`.
  std::string measurement;

  /// Whether it is a detection of the shipped landmark type `t` (not of a declared type).
  bool Is(LandmarkType t) const { return measurement.empty() && type == t; }
};

/// What is wrong with a detection a pipeline reported, or nothing: a non-finite pixel, a
/// plate or door without a proper box (min < max), a lamp without a positive radius, a label on
/// a type that has none, a score outside its range. The runner treats a problem as a bug of the
/// pipeline.
std::optional<std::string> DetectionProblem(const Detection& detection);

/// One update's normalised innovation squared (NIS) and its degrees of freedom.
struct Innovation {
  TimeNs stamp_ns = 0;
  LandmarkType type = LandmarkType::kCorner;
  double nis = 0.0;
  int dof = 0;
  bool accepted = true;  // false: gated out
  // An update of a measurement type the pipeline declared (MeasurementType::name; `type` is then
  // ignored and `dof` must be the declared one). Empty: a landmark update of `type`.
  std::string measurement;
};

/// The name a detection's or an innovation's statistics go under: its declared measurement type,
/// else its landmark type's name.
std::string MeasurementName(const Detection& detection);
std::string MeasurementName(const Innovation& innovation);

/// Numerical trouble and bad input a pipeline met (STYLE item 10): counted and reported, never
/// hidden.
struct PipelineHealth {
  int non_positive_covariance = 0;  // innovation covariances that were not positive definite
  int rejected_updates = 0;         // updates refused: non-finite residual, gated out, ...
  int rejected_odometry = 0;        // odometry messages refused: non-finite, out of time order
  int rejected_frames = 0;          // camera frames refused: empty, wrong size, out of order,
                                    // depth of the wrong size
};

/// One map file a pipeline produces: the runner writes `bytes` atomically to
/// `maps/<pipeline><suffix>` (slam/ does no file I/O).
struct MapFile {
  std::string suffix;  // ".bt" (OctoMap binary), "_semantic.json", ...
  std::string bytes;
};

class Pipeline {
 public:
  virtual ~Pipeline() = default;
  /// Starts the estimate at a known pose (filters share the start pose, as the papers' runs do).
  virtual void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) = 0;
  virtual void OnOdometry(const WheelOdometry& odometry) = 0;
  /// A camera frame; pipelines that use no camera ignore it.
  virtual void OnCamera(const CameraInput& input) { (void)input; }
  /// An IMU sample, in stamp order with the other messages (docs/sensors.md); pipelines that use
  /// no IMU ignore it. Every pipeline receives every IMU's samples (ImuSample::sensor_id).
  virtual void OnImu(const ImuSample& sample) { (void)sample; }
  /// A laser sweep, delivered once its last beam has fired (LaserScan::stamp_ns is its first
  /// beam's); pipelines that use no scanner ignore it.
  virtual void OnScan(const LaserScan& scan) { (void)scan; }
  /// Which cameras the pipeline reads (the runner renders only cameras somebody reads).
  virtual std::vector<std::string> cameras_used() const { return {}; }
  /// The measurement types of its own it will report innovations or detections of (asked once,
  /// right after Initialize; MeasurementType above). The shipped landmark types need no
  /// declaration.
  virtual std::vector<MeasurementType> measurement_types() const { return {}; }
  virtual PoseEstimate Estimate() const = 0;
  virtual std::vector<LandmarkEstimate> Landmarks() const { return {}; }
  /// Detections and innovations since the last call (moved out).
  virtual std::vector<Detection> TakeDetections() { return {}; }
  virtual std::vector<Innovation> TakeInnovations() { return {}; }
  /// Ends the run: the last sensor message has arrived (a pipeline may flush pending work, e.g.
  /// insert its last keyframe). Called once; Landmarks() and TakeMaps() follow.
  virtual void Finish() {}
  /// The maps built during the run, moved out (called once, after Finish()).
  virtual std::vector<MapFile> TakeMaps() { return {}; }
  /// The map divided into areas at the doors (P2 Fig. 12), or empty for pipelines without doors.
  virtual std::vector<MapArea> Areas() const { return {}; }
  /// The dense occupancy map for the map-quality metrics (valid until TakeMaps()), or nullptr.
  virtual const octomap::OcTree* occupancy_map() const { return nullptr; }
  /// Seconds spent per stage so far (e.g. "predict", "detect", "update").
  virtual std::map<std::string, double> stage_seconds() const { return {}; }
  virtual PipelineHealth health() const { return {}; }
};

}  // namespace corridorsim::slam
