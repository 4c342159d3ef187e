#include "slam/ekf_pipeline.h"

namespace corridorsim::slam {

EkfPipeline::EkfPipeline(double wheelbase_m, double k_m) : wheelbase_m_(wheelbase_m), k_m_(k_m) {}

EkfPipeline::~EkfPipeline() = default;

void EkfPipeline::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  state_ = StateAtKnownPose(world_from_robot);
  stamp_ns_ = stamp_ns;
}

void EkfPipeline::OnOdometry(const WheelOdometry& odometry) {
  PredictOrRefuse(odometry, wheelbase_m_, k_m_, state_.get(), &stamp_ns_, &health_, &clock_);
}

PoseEstimate EkfPipeline::Estimate() const {
  if (!state_) return {};
  return EstimateOf(*state_, stamp_ns_);
}

}  // namespace corridorsim::slam
