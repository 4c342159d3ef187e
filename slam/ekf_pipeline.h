#pragma once
// What the EKF pipelines (P1's Harris baseline and vanishing point + door plates, P2/P3's upward
// camera) share as a Pipeline: the filter started at the known pose, the wheel-odometry
// prediction with its checks (P1 eqs. 13-17, slam/filter_support.h), the estimate, the
// detections and innovations handed out, the health and the stage clock. A pipeline derives from
// it and adds its cameras, landmarks and maps.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "slam/ekf/ekf_state.h"
#include "slam/filter_support.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

class EkfPipeline : public Pipeline {
 public:
  ~EkfPipeline() override;

  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) override;
  /// PredictOrRefuse: predicted, or counted in health().rejected_odometry and dropped.
  void OnOdometry(const WheelOdometry& odometry) override;
  PoseEstimate Estimate() const override;
  std::vector<Detection> TakeDetections() override { return std::move(detections_); }
  std::vector<Innovation> TakeInnovations() override { return std::move(innovations_); }
  std::map<std::string, double> stage_seconds() const override { return clock_.seconds(); }
  PipelineHealth health() const override { return health_; }

 protected:
  /// `wheelbase_m`: the calibration's B; `k_m`: the odometry noise k of P1 eq. 17 (m).
  EkfPipeline(double wheelbase_m, double k_m);

  // The stages' clock (stage_seconds(), frame costs): Clock::now() and the seconds since.
  using Clock = StageClock::Clock;
  static double SecondsSince(Clock::time_point t0) { return StageClock::SecondsSince(t0); }

  double wheelbase_m_;
  double k_m_;
  std::unique_ptr<ekf::EkfState> state_;  // null until Initialize
  TimeNs stamp_ns_ = 0;                   // of the last odometry message applied
  std::vector<Detection> detections_;
  std::vector<Innovation> innovations_;
  PipelineHealth health_;
  StageClock clock_;
};

}  // namespace corridorsim::slam
