// bench_ekf: the EKF core's cost on the standard workload. N point landmarks uniform in a
// 40 x 40 m square, all in the state from the start; the robot on a 12 m radius circle at 0.5 m
// per step with odometry noise (0.03 m, 0.015 m, 1 deg per step); a range-bearing sensor (0.1 m,
// 0.5 deg) observing the 10 nearest landmarks each step, associated by id. Reports the median
// wall time of one step (predict + the 10 observations' models and updates) for N = 100, 300,
// 1000, with the 10 updates stacked into one (the default: the faster, see below) or applied one
// by one (--mode sequential), or both side by side (--mode both).
//
//   bench_ekf [--steps S] [--mode stacked|sequential|both] [--json FILE]
//
// Measured on the shared 2-core build machine (AMD EPYC, SSE2 build, thread CPU time; the wall
// clock there is 2-3x longer under load): stacked 0.18 / 1.27 / 9.4 ms, sequential 0.31 / 2.3 /
// 31 ms for N = 100 / 300 / 1000. Stacked wins everywhere: one symmetric rank-20 update streams P
// once, where ten rank-2 updates stream it ten times (memory-bound from N = 300 on). At N = 1000
// the rank-20 update alone costs 9.1-9.4 ms (Eigen's SYRK at about 8.7 GFlop/s, near SSE2 peak):
// the step is at the floor of P -= K (H P).
//
// Seeded (common/random.h): the same numbers every run; only the timings vary.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <time.h>

#include <Eigen/Core>

#include "common/pose.h"
#include "common/random.h"
#include "slam/ekf/ekf_state.h"
#include "slam/ekf/measurement_models.h"
#include "tests/support/planar_motion.h"

namespace {

using corridorsim::NormalizeAngle;
using corridorsim::RandomStream;
using corridorsim::SE2;
namespace ekf = corridorsim::slam::ekf;

constexpr double kPi = std::numbers::pi;
constexpr double kRadiusM = 12.0;
constexpr double kStepM = 0.5;
constexpr double kOdometrySigma[3] = {0.03, 0.015, 1.0 * kPi / 180.0};
constexpr double kRangeSigmaM = 0.1;
constexpr double kBearingSigmaRad = 0.5 * kPi / 180.0;
constexpr double kLandmarkPriorSigmaM = 0.2;  // as the EKF consistency test
constexpr int kObserved = 10;
constexpr int kWarmupSteps = 5;

enum class Mode { kSequential, kStacked };

// This thread's CPU time (ms): unlike the wall clock, it does not count the time the machine's
// other processes took the core (the shared build machine is often oversubscribed).
double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

struct Figures {
  double median_ms = 0.0;      // wall clock
  double median_cpu_ms = 0.0;  // thread CPU time
  double mean_nees = 0.0;      // of the robot pose over the run (a sanity check: about 3)
  int rejected = 0;            // updates refused (gate, non-finite, not positive definite)
};

using corridorsim::test::Compose;

Figures Run(int landmark_count, int steps, Mode mode) {
  RandomStream world_rng(1, static_cast<std::uint64_t>(landmark_count), "bench.ekf.world");
  RandomStream odometry_rng(1, static_cast<std::uint64_t>(landmark_count), "bench.ekf.odometry");
  RandomStream sensor_rng(1, static_cast<std::uint64_t>(landmark_count), "bench.ekf.sensor");
  std::vector<Eigen::Vector2d> landmarks;
  for (int i = 0; i < landmark_count; ++i) {
    landmarks.emplace_back(world_rng.Uniform(-20, 20), world_rng.Uniform(-20, 20));
  }
  SE2 truth(kRadiusM, 0.0, kPi / 2);
  ekf::EkfState state(Eigen::Vector3d(truth.x(), truth.y(), truth.yaw()),
                      Eigen::Matrix3d::Identity() * 1e-8);
  std::vector<ekf::BlockId> ids;
  for (const Eigen::Vector2d& l : landmarks) {
    ekf::Augmentation a;
    const double s = kLandmarkPriorSigmaM;
    a.value = l + Eigen::Vector2d(world_rng.Normal(0, s), world_rng.Normal(0, s));
    a.d_value_d_measurement = Eigen::MatrixXd::Identity(2, 2);
    a.measurement_noise = Eigen::MatrixXd::Identity(2, 2) * s * s;
    ids.push_back(state.Augment(a));
  }
  Eigen::Matrix3d odometry_cov = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) odometry_cov(k, k) = kOdometrySigma[k] * kOdometrySigma[k];
  Eigen::Matrix2d sensor_cov = Eigen::Matrix2d::Zero();
  sensor_cov(0, 0) = kRangeSigmaM * kRangeSigmaM;
  sensor_cov(1, 1) = kBearingSigmaRad * kBearingSigmaRad;
  const double gate_2dof = 13.8155;  // chi-square(2) 99.9 %
  const double turn = kStepM / kRadiusM;
  const Eigen::Vector3d delta(kRadiusM * std::sin(turn), kRadiusM * (1.0 - std::cos(turn)), turn);

  Figures figures;
  std::vector<double> step_ms, step_cpu_ms;
  double nees_sum = 0.0;
  std::vector<int> order(landmarks.size());
  std::vector<ekf::Measurement> measurements(kObserved);
  for (int step = 0; step < kWarmupSteps + steps; ++step) {
    // Truth and sensing (not timed).
    truth = Compose(truth, delta);
    Eigen::Vector3d odometry = delta;
    for (int k = 0; k < 3; ++k) odometry[k] += odometry_rng.Normal(0, kOdometrySigma[k]);
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::partial_sort(order.begin(), order.begin() + kObserved, order.end(), [&](int a, int b) {
      const double da = (landmarks[a] - truth.translation()).squaredNorm();
      const double db = (landmarks[b] - truth.translation()).squaredNorm();
      return da < db || (da == db && a < b);
    });
    Eigen::Vector2d z[kObserved];
    for (int o = 0; o < kObserved; ++o) {
      z[o] = ekf::RangeBearing(truth, landmarks[order[o]]);
      z[o][0] += sensor_rng.Normal(0, kRangeSigmaM);
      z[o][1] += sensor_rng.Normal(0, kBearingSigmaRad);
    }

    const auto start = std::chrono::steady_clock::now();
    const double start_cpu_ms = ThreadCpuMs();
    const Eigen::Vector3d x = state.RobotPose();
    Eigen::Matrix3d f, g;
    const SE2 predicted = Compose(SE2(x[0], x[1], x[2]), odometry, &f, &g);
    state.PredictRobot(Eigen::Vector3d(predicted.x(), predicted.y(), predicted.yaw()), f,
                       g * odometry_cov * g.transpose());
    for (int o = 0; o < kObserved; ++o) {
      const Eigen::Vector3d r = state.RobotPose();
      Eigen::Matrix<double, 2, 3> d_z_d_pose;
      Eigen::Matrix2d d_z_d_landmark;
      const ekf::BlockId id = ids[order[o]];
      const Eigen::Vector2d h =
          ekf::RangeBearing(SE2(r[0], r[1], r[2]), state.Value(id), &d_z_d_pose, &d_z_d_landmark);
      ekf::Measurement& m = measurements[o];
      m.blocks = {ekf::EkfState::robot(), id};
      m.jacobian.resize(2, 5);
      m.jacobian << d_z_d_pose, d_z_d_landmark;
      m.residual = Eigen::Vector2d(z[o][0] - h[0], NormalizeAngle(z[o][1] - h[1]));
      m.noise = sensor_cov;
      if (mode == Mode::kSequential && !state.Update(m, gate_2dof).accepted) ++figures.rejected;
    }
    if (mode == Mode::kStacked) {
      // Per-measurement gates first (Mahalanobis), then one stacked update of the accepted.
      std::vector<ekf::Measurement> accepted;
      accepted.reserve(kObserved);
      for (const ekf::Measurement& m : measurements) {
        const std::optional<double> nis = state.Nis(m);
        if (nis && *nis <= gate_2dof) {
          accepted.push_back(m);
        } else {
          ++figures.rejected;
        }
      }
      if (!accepted.empty() &&
          !state.UpdateStacked(accepted, std::numeric_limits<double>::infinity()).accepted) {
        figures.rejected += static_cast<int>(accepted.size());
      }
    }
    const double stop_cpu_ms = ThreadCpuMs();
    const auto stop = std::chrono::steady_clock::now();
    if (step >= kWarmupSteps) {
      step_ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
      step_cpu_ms.push_back(stop_cpu_ms - start_cpu_ms);
    }
    Eigen::Vector3d error = state.RobotPose() - Eigen::Vector3d(truth.x(), truth.y(), truth.yaw());
    error[2] = NormalizeAngle(error[2]);
    const Eigen::Matrix3d cov = state.Covariance(ekf::EkfState::robot(), ekf::EkfState::robot());
    nees_sum += error.dot(cov.ldlt().solve(error));
  }
  figures.median_ms = Median(step_ms);
  figures.median_cpu_ms = Median(step_cpu_ms);
  figures.mean_nees = nees_sum / (kWarmupSteps + steps);
  return figures;
}

int Usage(const char* message) {
  std::fprintf(stderr,
               "bench_ekf: %s\nusage: bench_ekf [--steps S (1-100000)] [--mode "
               "stacked|sequential|both] [--json FILE]\n",
               message);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int steps = 200;
  bool run_sequential = false;
  bool run_stacked = true;
  std::string json_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--steps" && i + 1 < argc) {
      char* end = nullptr;
      const long value = std::strtol(argv[++i], &end, 10);
      if (end == argv[i] || *end != '\0' || value < 1 || value > 100000) {
        return Usage("--steps must be an integer in [1, 100000]");
      }
      steps = static_cast<int>(value);
    } else if (arg == "--mode" && i + 1 < argc) {
      const std::string mode = argv[++i];
      if (mode != "stacked" && mode != "sequential" && mode != "both") {
        return Usage("--mode must be stacked, sequential or both");
      }
      run_sequential = mode != "stacked";
      run_stacked = mode != "sequential";
    } else if (arg == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else {
      return Usage(("unknown argument '" + arg + "'").c_str());
    }
  }
  const int sizes[] = {100, 300, 1000};
  const double targets_ms[] = {0.25, 2.0, 18.0};
  std::printf("bench_ekf: median ms per step (predict + %d range-bearing updates), %d steps\n",
              kObserved, steps);
  std::printf("wall clock (cpu: this thread's CPU time); a mode not run shows 0\n");
  std::printf("%6s %6s %22s %22s %10s %10s\n", "N", "dim", "sequential_ms (cpu)",
              "stacked_ms (cpu)", "target_ms", "mean_nees");
  std::string json =
      "{\n  \"steps\": " + std::to_string(steps) + ",\n  \"results\": [\n";  // a mode not run: 0
  for (int k = 0; k < 3; ++k) {
    // A mode not run reports zeros.
    const Figures sequential = run_sequential ? Run(sizes[k], steps, Mode::kSequential) : Figures{};
    const Figures stacked = run_stacked ? Run(sizes[k], steps, Mode::kStacked) : Figures{};
    std::printf("%6d %6d %12.4f (%7.4f) %12.4f (%7.4f) %10.2f %10.3f\n", sizes[k], 3 + 2 * sizes[k],
                sequential.median_ms, sequential.median_cpu_ms, stacked.median_ms,
                stacked.median_cpu_ms, targets_ms[k],
                run_stacked ? stacked.mean_nees : sequential.mean_nees);
    char line[640];
    std::snprintf(line, sizeof(line),
                  "    {\"landmarks\": %d, \"sequential_ms\": %.4f, \"sequential_cpu_ms\": %.4f, "
                  "\"stacked_ms\": %.4f, \"stacked_cpu_ms\": %.4f, "
                  "\"target_ms\": %.2f, \"mean_nees_sequential\": %.4f, "
                  "\"mean_nees_stacked\": %.4f, \"rejected_sequential\": %d, "
                  "\"rejected_stacked\": %d}%s\n",
                  sizes[k], sequential.median_ms, sequential.median_cpu_ms, stacked.median_ms,
                  stacked.median_cpu_ms, targets_ms[k], sequential.mean_nees, stacked.mean_nees,
                  sequential.rejected, stacked.rejected, k < 2 ? "," : "");
    json += line;
  }
  json += "  ]\n}\n";
  if (!json_path.empty()) {
    std::ofstream out(json_path, std::ios::binary);
    out << json;
    if (!out) {
      std::fprintf(stderr, "bench_ekf: cannot write %s\n", json_path.c_str());
      return 1;
    }
  }
  return 0;
}
