#pragma once
// The `odometry` pipeline: dead reckoning from wheel odometry with the covariance propagated by
// P1 eqs. 13-17 (the baseline every SLAM pipeline is compared against, P1 Figs. 15-16). It reads
// no camera and keeps no landmarks.

#include <chrono>
#include <cstdint>
#include <optional>

#include "common/error.h"
#include "common/options_table.h"
#include "common/wheel_odometry_model.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// Scenario key `pipelines.odometry`.
struct OdometryPipelineOptions {
  // k of P1 eq. 17: each wheel's distance has variance k |s| (m^2 per m). Matching the
  // simulated robot's `robot.odometry.random_k_m` makes the filter consistent (NEES in band);
  // both default to kDefaultWheelNoiseK_m.
  double k_m = kDefaultWheelNoiseK_m;
  std::optional<OptionsProblem> Check() const;
};
/// The keys of `pipelines.odometry` (the harness parses and echoes them, the docs list them).
const OptionTable<OdometryPipelineOptions>& OdometryPipelineOptionsTable();

class OdometryPipeline : public Pipeline {
 public:
  /// `calibration` must pass Check(); the pipeline uses its nominal wheelbase. It draws no random
  /// numbers (`seed` is unused).
  OdometryPipeline(const OdometryPipelineOptions& options, const Calibration& calibration,
                   std::uint64_t seed = 0);
  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  PoseEstimate Estimate() const override { return estimate_; }
  std::map<std::string, double> stage_seconds() const override;
  PipelineHealth health() const override { return health_; }

 private:
  OdometryPipelineOptions options_;
  double wheelbase_m_;
  PoseEstimate estimate_;
  PipelineHealth health_;
  std::chrono::steady_clock::duration predict_time_{};
};

}  // namespace corridorsim::slam
