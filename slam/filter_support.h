#pragma once
// What the EKF pipelines (P1's vanishing point + door plates, the Harris baseline; later P2/P3)
// share around the EKF core: the wheel-odometry prediction (P1 eqs. 13-17) and the checks that
// keep bad sensor data out of a filter (a NaN distance, a message out of time order, a black or
// empty frame, a depth image of the wrong size). Bad data is refused and counted in the
// pipeline's health, never applied.

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/sensor_messages.h"
#include "common/time.h"
#include "slam/ekf/ekf_state.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// The largest wheel distance one odometry message may carry (m): a robot at 2 m/s covers 0.04 m
/// per 50 Hz message; a message claiming more than this is corrupt.
inline constexpr double kMaxWheelDistancePerMessage_m = 10.0;

/// Why an odometry message cannot be used (not finite, beyond the bound, older than `last_ns`),
/// or nothing.
std::optional<std::string> OdometryProblem(const WheelOdometry& odometry, TimeNs last_ns);

/// P1 eqs. 13-17 on the robot block of `state`: the differential-drive motion model with
/// Q = diag(k |s_l|, k |s_r|) (m^2), propagated as P = F P F^T + G Q G^T (eq. 14, the landmark
/// blocks untouched: eqs. 15-16).
void PredictWithWheelOdometry(const WheelOdometry& odometry, double wheelbase_m, double k_m,
                              ekf::EkfState* state);

/// Why a camera frame cannot be used, or nothing: an empty image or one whose size is not the
/// calibration's, a stamp older than the camera's last frame (`last_ns`, -1 = none yet), a depth
/// image of another size than the colour image.
std::optional<std::string> FrameProblem(const CameraInput& input,
                                        const CameraCalibration& calibration, TimeNs last_ns);

/// Whether `image` is black: no pixel above `max_level` (a dead sensor or a lens cap).
bool IsBlackImage(const Image8& image, int max_level = 8);

/// Whether a depth image has no valid pixel (all zero or not finite).
bool HasNoValidDepth(const ImageF& depth_m);

/// The filter at a known start pose (the pipelines share it, as P1's runs do): the robot block at
/// `world_from_robot` with zero covariance.
std::unique_ptr<ekf::EkfState> StateAtKnownPose(const SE2& world_from_robot);

class StageClock;

/// One odometry message into a filter: predicted (PredictWithWheelOdometry, timed as "predict",
/// `*stamp_ns` advanced) or, when there is no state yet or OdometryProblem refuses it, counted in
/// `health->rejected_odometry` and dropped.
void PredictOrRefuse(const WheelOdometry& odometry, double wheelbase_m, double k_m,
                     ekf::EkfState* state, TimeNs* stamp_ns, PipelineHealth* health,
                     StageClock* clock);

/// One gated pairing of an observation with a landmark and its cost (the NIS, or any score where
/// smaller is better).
struct GatedPair {
  std::size_t observation = 0;
  std::size_t landmark = 0;
  double cost = 0.0;
};

/// Global nearest neighbour by greedy assignment: the pairs in order of increasing cost (ties:
/// the order given), each observation and each landmark taken at most once. Returns the indices
/// into `pairs` of the pairs taken, cheapest first. Unlike going through the observations in
/// turn, an observation that gates onto a landmark cannot take it from a closer one.
std::vector<std::size_t> AssignClosestFirst(const std::vector<GatedPair>& pairs);

/// The robot pose of the filter as a PoseEstimate at `stamp_ns`.
PoseEstimate EstimateOf(const ekf::EkfState& state, TimeNs stamp_ns);

/// P1 Fig. 16: what one camera frame cost the filter against the landmarks in its state.
struct FrameCost {
  TimeNs stamp_ns = 0;
  int landmarks = 0;     // in the state after the frame
  double seconds = 0.0;  // the filter's work on the frame (detection, association, updates)
};
/// `maps/<pipeline>_frame_times.csv`: "stamp_s,landmarks,frame_ms" (wall clock: not
/// byte-reproducible, like timing.json).
MapFile FrameCostsCsv(const std::vector<FrameCost>& costs);

/// Wall seconds per stage ("predict", "detect", ...), accumulated.
class StageClock {
 public:
  using Clock = std::chrono::steady_clock;
  static double SecondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  }
  void Add(const std::string& stage, double seconds) { seconds_[stage] += seconds; }
  const std::map<std::string, double>& seconds() const { return seconds_; }

 private:
  std::map<std::string, double> seconds_;
};

}  // namespace corridorsim::slam
