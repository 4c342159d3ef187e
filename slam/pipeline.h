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

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"

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

/// What a robot knows about itself, as its calibration file holds it: nominal values, never the
/// simulator's real ones. The fields have no defaults: whoever builds a Calibration fills every
/// one (the harness from the scenario's options, harness/calibration.h).
struct Calibration {
  double wheelbase_m;        // nominal distance between the wheels' contact points (B, P1 eq. 13)
  double wheel_diameter_m;   // nominal wheel diameter
  int ticks_per_revolution;  // encoder counts per wheel revolution; 0 = distances unquantised
  std::vector<CameraCalibration> cameras;

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

/// One landmark of the pipeline's map, in the world frame.
struct LandmarkEstimate {
  int id = 0;  // the pipeline's own id, stable over the run
  LandmarkType type = LandmarkType::kCorner;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();     // m^2
  std::string label;  // door plates: the recognised room number ("" if none)
};

/// One detection in one frame, with the association the pipeline made for it.
struct Detection {
  TimeNs stamp_ns = 0;
  std::string camera_id;
  LandmarkType type = LandmarkType::kCorner;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();   // centre (lamps, plates), point (corners),
                                                     // vanishing point
  double radius_px = 0.0;                            // lamps
  Eigen::Vector4d box_px = Eigen::Vector4d::Zero();  // plates, doors: min x, min y, max x, max y
  std::string label;                                 // plates: recognised room number
  std::optional<bool> open;                          // doors: open (true) or closed
  int landmark_id = -1;       // the landmark it was associated with (-1: none, e.g. rejected)
  bool new_landmark = false;  // it created landmark_id
};

/// One landmark update's normalised innovation squared (NIS) and its degrees of freedom.
struct Innovation {
  TimeNs stamp_ns = 0;
  LandmarkType type = LandmarkType::kCorner;
  double nis = 0.0;
  int dof = 0;
  bool accepted = true;  // false: gated out
};

/// Numerical trouble a pipeline met (STYLE item 10): counted and reported, never hidden.
struct PipelineHealth {
  int non_positive_covariance = 0;
  int rejected_updates = 0;
};

class Pipeline {
 public:
  virtual ~Pipeline() = default;
  virtual std::string name() const = 0;
  /// Starts the estimate at a known pose (filters share the start pose, as the papers' runs do).
  virtual void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) = 0;
  virtual void OnOdometry(const WheelOdometry& odometry) = 0;
  /// A camera frame; pipelines that use no camera ignore it.
  virtual void OnCamera(const CameraInput& input) { (void)input; }
  /// Which cameras the pipeline reads (the runner renders only cameras somebody reads).
  virtual std::vector<std::string> cameras_used() const { return {}; }
  virtual PoseEstimate Estimate() const = 0;
  virtual std::vector<LandmarkEstimate> Landmarks() const { return {}; }
  /// Detections and innovations since the last call (moved out).
  virtual std::vector<Detection> TakeDetections() { return {}; }
  virtual std::vector<Innovation> TakeInnovations() { return {}; }
  /// Writes maps (OctoMap .bt, semantic maps) into `dir`; returns the files written.
  virtual std::vector<std::filesystem::path> WriteMaps(const std::filesystem::path& dir) const {
    (void)dir;
    return {};
  }
  /// Seconds spent per stage so far (e.g. "predict", "detect", "update").
  virtual std::map<std::string, double> stage_seconds() const { return {}; }
  virtual PipelineHealth health() const { return {}; }
};

}  // namespace corridorsim::slam
