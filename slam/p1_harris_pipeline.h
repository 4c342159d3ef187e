#pragma once
// `p1_harris`: the conventional scheme P1 compares against (P1 section 6, Figs. 15-16): Harris
// corners of the front RGB image with their registered depth as 3D point landmarks, associated
// by Mahalanobis distance, in the same EKF core as `p1_vp_doorplate`. Its corners are
// indistinguishable from each other, so association errors and a state that grows with every
// new corner are expected: the time per frame grows with the landmark count (Fig. 16), which
// this pipeline records per frame (`maps/<name>_frame_times.csv`).

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
#include "slam/features/harris_corners.h"
#include "slam/filter_support.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// Scenario key `pipelines.<name>` of type `p1_harris`.
struct P1HarrisOptions {
  double k_m = kDefaultWheelNoiseK_m;  // k of P1 eq. 17 (m^2 per m of wheel travel)
  double gate_chi2 = 11.34;     // Mahalanobis gate of an association: chi-square 99 % at 3 dof
  double pixel_sigma_px = 1.5;  // sigma of a corner's u and v
  // sigma of its depth: depth_sigma_a_m + depth_sigma_b * z^2 (a structured-light sensor)
  double depth_sigma_a_m = 0.01;
  double depth_sigma_b = 0.005;    // 1/m
  double max_depth_m = 4.0;        // corners farther than this are not used
  double search_radius_px = 30.0;  // landmarks predicted within this of a corner are candidates
  int max_corners_per_frame = 20;  // strongest first (P1 mapped 612 corners over its run)
  int max_landmarks = 1500;        // the state stops growing here (a bound, 4503 dimensions)
  HarrisCornerOptions corners;     // the detector
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<P1HarrisOptions>& P1HarrisOptionsTable();

class P1HarrisPipeline : public EkfPipeline {
 public:
  /// `calibration` must pass Check(). A calibration without a depth front camera is reported by
  /// cameras_used() and refused by the runner.
  P1HarrisPipeline(const P1HarrisOptions& options, const Calibration& calibration,
                   std::uint64_t seed);
  ~P1HarrisPipeline() override;

  void OnCamera(const CameraInput& input) override;
  std::vector<std::string> cameras_used() const override { return {"front"}; }
  std::vector<LandmarkEstimate> Landmarks() const override;
  std::vector<MapFile> TakeMaps() override;

 private:
  struct PointLandmark {
    int id = 0;
    ekf::BlockId block;
  };
  Eigen::Matrix3d MeasurementNoise(double depth_m) const;

  P1HarrisOptions options_;
  std::optional<CameraCalibration> front_;
  TimeNs last_frame_ns_ = -1;
  std::vector<PointLandmark> landmarks_;
  int next_landmark_id_ = 0;
  std::vector<FrameCost> frame_times_;  // detection, association, updates, augmentation
};

}  // namespace corridorsim::slam
