#pragma once
// The upward-camera EKF-SLAM of P3 (and P2): wheel odometry predicts (P3 eqs. 12-13), corners
// and circular lamps seen by the upward camera update (P3 eqs. 14-20) through their polar image
// coordinates (P3 eq. 16, P2 eq. 7; slam/ekf/upward_models.h). Registered as
//   p3_upward   corners (FAST) + lamps,
//   p3_corners  corners only (P3's "conventional method", Fig. 18a),
//   p2_upward   corners (Harris, as P2),
// all one class with different defaults (docs/p3.md).
//
// Landmarks are bearing-only: each is initialised at its first sighting as an inverse-depth point
// (anchor, ray, inverse height) whose inverse height carries P3's prior of heights 0-5 m as a
// Gaussian (P3 section V; docs/p3.md derives it), so that it enters the filter at once and its
// height is learnt from the parallax of later sightings. Association: lamps by Mahalanobis
// distance (NIS gate) alone, corners by their patch's normalised cross-correlation within the
// gate (P3; patches sampled turned by the heading estimate, so that they match after a turn).
// Landmarks predicted in the image but rarely matched are deleted (P3 Fig. 16c).

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
#include "slam/features/ceiling_lamps.h"
#include "slam/features/corner_patches.h"
#include "slam/features/upward_doors.h"
#include "slam/filter_support.h"
#include "slam/mapping/door_areas.h"
#include "slam/pipeline.h"
#include "slam/upward_door_verifier.h"

namespace corridorsim::slam {

/// Scenario key `pipelines.<name>` of type `p3_upward`, `p3_corners` or `p2_upward`.
struct P3UpwardOptions {
  double k_m = kDefaultWheelNoiseK_m;  // k of the wheel noise (P3 eq. 13's Q, as P1 eq. 17)
  bool use_corners = true;
  bool use_lamps = true;
  bool use_doors = true;         // open doors as two-column landmarks (P3 section III, eq. 17)
  double door_sigma_rad = 0.02;  // sigma of a column's bearing (P3 eq. 17's measurement)
  // P3 section V: landmark heights above the floor from min_height_m to max_height_m; the
  // inverse height above the camera is Gaussian with +-2 sigma spanning that range (heights
  // closer than min_above_camera_m to the camera's are not seen by an upward camera).
  double min_height_m = 0.0;
  double max_height_m = 5.0;
  double min_above_camera_m = 0.5;
  double corner_sigma_px = 1.0;    // sigma of a corner's image position (each axis)
  double lamp_sigma_px = 0.35;     // sigma of a lamp centre's image position (docs/p3.md)
  double gate_chi2 = 9.21;         // NIS gate of an association (chi-square 99 % at 2 dof)
  double search_radius_px = 40.0;  // landmarks predicted within this of a detection are candidates
  double min_correlation = 0.9;    // corners: patch NCC needed to match
  double min_polar_radius_px = 12.0;  // closer to the principal point theta is ill-defined: unused
  double min_ray_z = 0.25;  // rays further than acos(this) from the vertical start no landmark
  double new_landmark_clearance_px = 15.0;  // a new landmark this far from every predicted one
  int max_new_corners_per_frame = 6;
  // New corners start only while fewer corners than this were matched in the frame (the view
  // keeps this many tracked; more add little and fill the state): without it the 400 landmarks
  // were spent two thirds down a 40 m corridor, and the rest of it ran on dead reckoning.
  int max_tracked_corners = 20;
  // A frame that finds the map empty (the first) starts at least this many corners (0: as many
  // as any frame). The first frame is the only one whose heading the filter knows exactly, so its
  // landmarks fix the heading of all the map chained to them (docs/p3.md).
  int first_frame_corners = 0;
  int max_landmarks = 400;  // the state holds at most this many point landmarks
  // With the state full, a new landmark takes the place of the corner landmark matched longest
  // ago, if that one is out of view and unmatched for at least retire_after_s (it is marginalised
  // out: removed with its rows of the covariance). Without it a full state stops mapping, and
  // the rest of a long run goes on dead reckoning; with it the map keeps the most recent corners
  // (and every lamp), and only a return after that long finds its old corners gone.
  double retire_after_s = 20.0;
  // P3 Fig. 16c: a landmark predicted in the image at least delete_after times and matched in
  // fewer than min_match_fraction of them is deleted.
  int delete_after = 8;
  double min_match_fraction = 0.3;
  CornerPatchOptions corners;
  CeilingLampOptions lamps;
  UpwardDoorOptions doors;            // the door candidates (slam/features/upward_doors.h)
  DoorVerifierOptions door_verifier;  // their particle filter and test (upward_door_verifier.h)
  DoorAreaOptions areas;              // the map divided at the doors (slam/mapping/door_areas.h)
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<P3UpwardOptions>& P3UpwardOptionsTable();
/// The defaults of each registered type: p3_upward (FAST + lamps), p3_corners (FAST only),
/// p2_upward (Harris, no lamps).
P3UpwardOptions P3UpwardDefaults();
P3UpwardOptions P3CornersDefaults();
P3UpwardOptions P2UpwardDefaults();

class P3UpwardPipeline : public EkfPipeline {
 public:
  /// `calibration` must pass Check(). Without an upward camera the pipeline reports it in
  /// cameras_used() and the runner refuses the scenario.
  P3UpwardPipeline(const P3UpwardOptions& options, const Calibration& calibration,
                   std::uint64_t seed);
  ~P3UpwardPipeline() override;

  void OnCamera(const CameraInput& input) override;
  std::vector<std::string> cameras_used() const override { return {"upward"}; }
  std::vector<LandmarkEstimate> Landmarks() const override;
  /// `_doors.json` (pipelines with doors): each registered door's registration, with the
  /// particle filter's samples at that moment (P3 Fig. 9), its H(A, B) and its final columns.
  /// `_areas.json` too: Areas() (P2 Fig. 12).
  std::vector<MapFile> TakeMaps() override;
  std::vector<MapArea> Areas() const override;

 private:
  struct PointLandmark {
    int id = 0;
    LandmarkType type = LandmarkType::kCorner;
    ekf::BlockId block;
    std::vector<float> patch;    // corners: the patch at the first sighting
    int predicted = 0;           // frames it was predicted in the image
    int matched = 0;             // frames it was matched
    TimeNs last_matched_ns = 0;  // started or last matched
    int updates = 0;
  };
  struct DoorLandmark {
    int id = 0;
    ekf::BlockId block;
    double top_height_m = 0.0;  // the particle filter's height of the column tops
    int updates = 0;
    TimeNs registered_ns = 0;
    double hausdorff_px = 0.0;  // H(A, B) of the open-door test (P3 eq. 9)
    Eigen::Vector2d camera_xy = Eigen::Vector2d::Zero();  // where it was registered from
    std::vector<DoorParticle> particles;  // the samples at registration (x1, y1, x2, y2, h)
  };
  struct Observation;  // one detection of a frame (the .cpp)

  void ProcessFrame(const CameraInput& input);

  P3UpwardOptions options_;
  std::optional<CameraCalibration> upward_;
  double rho_prior_ = 1.0;        // mean of the inverse height prior (1/m)
  double rho_prior_sigma_ = 1.0;  // its sigma
  TimeNs last_frame_ns_ = -1;
  std::vector<PointLandmark> landmarks_;
  std::vector<DoorLandmark> doors_;
  std::optional<UpwardDoorVerifier> verifier_;
  int next_landmark_id_ = 0;
};

}  // namespace corridorsim::slam
