#pragma once
// `p1_vp_doorplate`: P1's corridor RGB-D EKF-SLAM (../shared/papers P1, docs/p1.md). The state
// is the robot pose, the vanishing points and the door plates with their room-number signature
// (P1 eqs. 7-12); odometry predicts (eqs. 13-17); the front RGB-D sensor's vanishing point
// corrects the heading (eq. 19, section 2) and the lateral camera's door plates, recognised by
// number (section 3), correct the position along the corridor (eq. 20, Table 1, eqs. 21-27).
// The front depth builds an OctoMap at keyframes and the plates a semantic map (section 5).
//
// Where P1 is silent or wrong, and what this pipeline does (docs/p1.md explains each):
// - Eq. 20's sine term has the wrong sign (slam/ekf/measurement_models.h derives it); the
//   models are the exact pinhole projections through the calibrated mounts.
// - A plate's range is not observable from one frame: delayed initialisation. The first
//   accepted reading of a number clones the robot pose into the state; when a later reading of
//   the same number sees the plate with enough parallax, the plate is triangulated from the
//   clone and the current pose (Jacobians over both, P1 eq. 27 generalised) and the clone goes.
//   A number must be read `min_readings` times before it may become a landmark, so that a single
//   false reading never does.
// - A VP landmark stands for a corridor's direction, seen from either end: on a round trip's way
//   back the front camera sees the corridor's other end, the same direction turned by pi (P1
//   runs one way). A VP detection is associated with the VP landmark whose point (or the point
//   opposite it) projects into the image, by NIS; a direction not yet in the map (after a turn
//   into another corridor) becomes a new VP landmark.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/options_table.h"
#include "common/wheel_odometry_model.h"
#include "slam/ekf/ekf_state.h"
#include "slam/ekf_pipeline.h"
#include "slam/features/door_plates.h"
#include "slam/features/vanishing_point.h"
#include "slam/filter_support.h"
#include "slam/mapping/occupancy_mapper.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// Scenario key `pipelines.<name>` of type `p1_vp_doorplate`.
struct P1VpDoorplateOptions {
  double k_m = kDefaultWheelNoiseK_m;  // k of P1 eq. 17 (m^2 per m of wheel travel)
  double gate_chi2 = 10.83;            // NIS gate of every update: chi-square 99.9 % at 1 dof

  bool use_vanishing_point = true;
  // sigma of the VP's u (P1 eq. 19's R): the weighted detector's RMS u error over round trips of
  // held-out seeds 11-14 of default.yaml, 0.54 px (0.48-0.62 per seed; docs/p1.md)
  double vp_sigma_px = 0.6;
  double vp_virtual_distance_m = 1000.0;  // the virtual plane (P1 Fig. 10), from the camera
  VanishingPointOptions vanishing_point;  // the detector (P1 section 2)

  bool use_door_plates = true;
  double plate_sigma_px = 1.5;  // sigma_u of P1 eq. 25 (the signature's entry is 0)
  double plate_height_m = 1.6;  // nominal height of a plate's number (the state is planar)
  // A plate is initialised only when the height it was seen at (its row v and triangulated depth)
  // lies within this of plate_height_m: numbers on posters and notice boards hang elsewhere.
  double plate_height_tolerance_m = 0.15;
  int min_readings = 2;             // readings of a number before it may become a landmark
  double min_parallax_deg = 8.0;    // triangulation parallax needed to initialise a plate
  double max_plate_range_m = 6.0;   // a triangulated plate farther than this is refused
  double pending_timeout_s = 30.0;  // a number not initialised within this is forgotten
  std::string models_dir;        // the detectors' trained models; "" = models/ of the source tree
  DoorPlateOptions door_plates;  // detector and reader (P1 section 3)

  bool octomap = true;                 // build the dense map from the front depth (P1 section 5)
  OccupancyMapperOptions octomap_map;  // resolution, range, keyframes

  std::optional<OptionsProblem> Check() const;
};
const OptionTable<P1VpDoorplateOptions>& P1VpDoorplateOptionsTable();

class P1VpDoorplatePipeline : public EkfPipeline {
 public:
  /// `calibration` must pass Check(). Loads the door-plate models (throws ModelFileError).
  /// Cameras the calibration lacks are reported by cameras_used() and refused by the runner.
  P1VpDoorplatePipeline(const P1VpDoorplateOptions& options, const Calibration& calibration,
                        std::uint64_t seed);
  ~P1VpDoorplatePipeline() override;

  void OnCamera(const CameraInput& input) override;
  std::vector<std::string> cameras_used() const override;
  std::vector<LandmarkEstimate> Landmarks() const override;
  std::vector<MapFile> TakeMaps() override;
  const octomap::OcTree* occupancy_map() const override;

 private:
  struct VpLandmark {
    int id = 0;
    ekf::BlockId block;
  };
  struct PlateLandmark {
    int id = 0;
    ekf::BlockId block;
    int updates = 0;
  };
  // A number read but not yet a landmark: the pose clone of its first sighting and its u there.
  struct PendingPlate {
    ekf::BlockId clone;
    double u_first = 0.0;
    TimeNs first_ns = 0;
    int readings = 0;
  };

  void OnFront(const CameraInput& input);
  void OnLateral(const CameraInput& input);
  void ObserveVanishingPoint(TimeNs stamp_ns, double u, Detection* detection);
  void ObservePlate(TimeNs stamp_ns, const std::string& number, const Eigen::Vector2d& pixel,
                    Detection* detection);
  void ForgetStalePending(TimeNs stamp_ns);
  void Record(TimeNs stamp_ns, LandmarkType type, const ekf::UpdateResult& result);

  P1VpDoorplateOptions options_;
  std::optional<CameraCalibration> front_;
  std::optional<CameraCalibration> lateral_;
  std::optional<DoorPlateModels> models_;
  std::unique_ptr<OccupancyMapper> mapper_;
  std::map<std::string, TimeNs> last_frame_ns_;
  std::vector<VpLandmark> vps_;
  std::map<std::string, PlateLandmark> plates_;  // by room number (P1 Table 1's signature)
  std::vector<FrameCost> frame_times_;           // P1 Fig. 16
  double octomap_seconds_in_frame_ = 0.0;
  std::map<std::string, PendingPlate> pending_;
  int next_landmark_id_ = 0;
};

}  // namespace corridorsim::slam
