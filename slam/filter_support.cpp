#include "slam/filter_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/wheel_odometry_model.h"

namespace corridorsim::slam {

std::optional<std::string> OdometryProblem(const WheelOdometry& odometry, TimeNs last_ns) {
  if (!std::isfinite(odometry.left_distance_m) || !std::isfinite(odometry.right_distance_m)) {
    return "a wheel distance is not finite";
  }
  if (std::abs(odometry.left_distance_m) > kMaxWheelDistancePerMessage_m ||
      std::abs(odometry.right_distance_m) > kMaxWheelDistancePerMessage_m) {
    return "a wheel distance exceeds the bound of one message";
  }
  if (odometry.stamp_ns < last_ns) return "older than the previous message";
  return std::nullopt;
}

void PredictWithWheelOdometry(const WheelOdometry& odometry, double wheelbase_m, double k_m,
                              ekf::EkfState* state) {
  const Eigen::Vector3d x = state->RobotPose();
  Eigen::Matrix3d F;
  Eigen::Matrix<double, 3, 2> G;
  // P1 eq. 13: the motion model, with F = d f / d x_r and G = d f / d u.
  const SE2 predicted = ApplyWheelOdometry(SE2(x.x(), x.y(), x.z()), odometry.left_distance_m,
                                           odometry.right_distance_m, wheelbase_m, &F, &G);
  // P1 eq. 17: Q = diag(k |s_l|, k |s_r|); eq. 14: P^- = F P F^T + G Q G^T.
  const Eigen::Matrix2d Q =
      WheelOdometryNoise(odometry.left_distance_m, odometry.right_distance_m, k_m);
  state->PredictRobot(Eigen::Vector3d(predicted.x(), predicted.y(), predicted.yaw()), F,
                      G * Q * G.transpose());
}

std::optional<std::string> FrameProblem(const CameraInput& input,
                                        const CameraCalibration& calibration, TimeNs last_ns) {
  const Image8& image = input.image.image;
  if (image.empty()) return "an empty image";
  if (image.width != calibration.model.width() || image.height != calibration.model.height()) {
    return "an image of another size than the calibration's";
  }
  if (image.channels != 1 && image.channels != 3 && image.channels != 4) {
    return "an image with an unsupported channel count";
  }
  if (image.data.size() != static_cast<std::size_t>(image.width) * image.height * image.channels) {
    return "an image whose buffer does not match its size";
  }
  if (last_ns >= 0 && input.image.stamp_ns <= last_ns) return "a frame out of time order";
  if (input.depth) {
    const ImageF& depth = input.depth->depth_m;
    if (depth.width != image.width || depth.height != image.height ||
        depth.data.size() != static_cast<std::size_t>(depth.width) * depth.height) {
      return "a depth image of another size than the colour image";
    }
  }
  return std::nullopt;
}

bool IsBlackImage(const Image8& image, int max_level) {
  return std::none_of(image.data.begin(), image.data.end(),
                      [max_level](std::uint8_t v) { return v > max_level; });
}

bool HasNoValidDepth(const ImageF& depth_m) {
  return std::none_of(depth_m.data.begin(), depth_m.data.end(),
                      [](float z) { return std::isfinite(z) && z > 0.0f; });
}

std::unique_ptr<ekf::EkfState> StateAtKnownPose(const SE2& world_from_robot) {
  return std::make_unique<ekf::EkfState>(
      Eigen::Vector3d(world_from_robot.x(), world_from_robot.y(), world_from_robot.yaw()),
      Eigen::Matrix3d::Zero());
}

void PredictOrRefuse(const WheelOdometry& odometry, double wheelbase_m, double k_m,
                     ekf::EkfState* state, TimeNs* stamp_ns, PipelineHealth* health,
                     StageClock* clock) {
  if (state == nullptr || OdometryProblem(odometry, *stamp_ns)) {
    ++health->rejected_odometry;
    return;
  }
  const StageClock::Clock::time_point t0 = StageClock::Clock::now();
  PredictWithWheelOdometry(odometry, wheelbase_m, k_m, state);
  *stamp_ns = odometry.stamp_ns;
  clock->Add("predict", StageClock::SecondsSince(t0));
}

PoseEstimate EstimateOf(const ekf::EkfState& state, TimeNs stamp_ns) {
  PoseEstimate e;
  e.stamp_ns = stamp_ns;
  const Eigen::Vector3d x = state.RobotPose();
  e.world_from_robot = SE2(x.x(), x.y(), x.z());
  e.covariance = state.Covariance(ekf::EkfState::robot(), ekf::EkfState::robot());
  return e;
}

std::vector<std::size_t> AssignClosestFirst(const std::vector<GatedPair>& pairs) {
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return pairs[a].cost < pairs[b].cost; });
  std::vector<std::size_t> taken;
  std::vector<std::size_t> observations_used, landmarks_used;
  for (const std::size_t i : order) {
    const GatedPair& p = pairs[i];
    const auto used = [](const std::vector<std::size_t>& v, std::size_t x) {
      return std::find(v.begin(), v.end(), x) != v.end();
    };
    if (used(observations_used, p.observation) || used(landmarks_used, p.landmark)) continue;
    observations_used.push_back(p.observation);
    landmarks_used.push_back(p.landmark);
    taken.push_back(i);
  }
  return taken;
}

MapFile FrameCostsCsv(const std::vector<FrameCost>& costs) {
  std::string csv = "stamp_s,landmarks,frame_ms\n";
  char line[96];
  for (const FrameCost& f : costs) {
    std::snprintf(line, sizeof line, "%.9f,%d,%.3f\n", ToSeconds(f.stamp_ns), f.landmarks,
                  1e3 * f.seconds);
    csv += line;
  }
  return {"_frame_times.csv", std::move(csv)};
}

}  // namespace corridorsim::slam
