#pragma once
// Metrics of a closed-loop run (issue 5): trajectory errors (ATE unaligned and SE2-aligned, RPE
// over travelled distance, final error), consistency (NEES of the pose, NIS per landmark type),
// map errors after matching to ground truth, data association, detector quality against the
// per-frame truth, timing; and the scenario `expectations` that assert on them. The runner
// collects the inputs and calls ComputeMetrics once; the JSON schema is docs/metrics.md.
//
// Errors are estimate minus truth in the world frame W (metres, rad, yaw wrapped to (-pi, pi]).
// Metrics that do not apply (no landmarks, no frames, a zero denominator) are absent or null,
// never invented. Every number is rounded to a fixed step per unit so the JSON is byte-stable.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "common/time.h"
#include "render/frame_truth.h"
#include "slam/pipeline.h"
#include "worlds/world.h"

namespace corridorsim {

struct TruthPose {
  TimeNs stamp_ns = 0;
  SE2 world_from_robot;
};

struct EstimateSample {
  TimeNs stamp_ns = 0;
  SE2 world_from_robot;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // over (x m, y m, yaw rad)
};

/// The truth of one rendered camera frame (render::FrameTruth carries the camera id).
struct FrameTruthSample {
  TimeNs stamp_ns = 0;
  render::FrameTruth truth;
};

struct PipelineRecord {
  std::string name;  // unique in the run; the key of its object in metrics.json
  std::vector<std::string> cameras_used;          // Pipeline::cameras_used(): frames it processed
  std::vector<EstimateSample> estimates;          // at every odometry message, stamp order
  std::vector<slam::LandmarkEstimate> landmarks;  // the final map
  std::vector<slam::Detection> detections;        // all frames
  std::vector<slam::Innovation> innovations;
  std::map<std::string, double> stage_seconds;  // the pipeline's own stages (s)
  slam::PipelineHealth health;
};

struct RunTiming {
  double sim_seconds = 0.0;                    // simulated time of the run
  std::map<std::string, double> wall_seconds;  // physics, rendering, pipelines, metrics, writing
};

/// Gates and thresholds of the matching steps (defaults in code; docs/metrics.md explains them).
struct MetricsOptions {
  double landmark_gate_m = 1.0;    // map matching: horizontal distance estimate-to-truth
  double identity_gate_px = 25.0;  // a detection's true identity: nearest truth within this
  double min_box_iou = 0.5;        // plates: a detection matches a truth box at this IoU or more
  double min_gate_px = 5.0;  // lamps, doors: the smallest centre gate (truth radius, half width)
  double min_visible_fraction = 0.5;  // truth less visible than this is neither hit nor missed
};

struct MetricsInput {
  const worlds::World* world = nullptr;  // must be set
  std::vector<TruthPose> truth;          // 100 Hz grid, stamp order; interpolated where needed
  std::vector<FrameTruthSample> frames;  // every camera frame rendered
  std::vector<PipelineRecord> pipelines;
  RunTiming timing;
  MetricsOptions options;
};

/// metrics.json (docs/metrics.md). Aborts (a bug) when input.world is null, truth is not in
/// stamp order or two pipelines share a name.
nlohmann::ordered_json ComputeMetrics(const MetricsInput& input);

/// Per-time errors for plots: CSV "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees",
/// one row per estimate with truth at its stamp; t in s; errors estimate minus truth (world frame,
/// yaw wrapped); sigmas from the covariance diagonal; NEES over 3 dof, empty where the covariance
/// is not positive definite.
std::string ErrorSeriesCsv(const std::vector<TruthPose>& truth, const PipelineRecord& pipeline);

// ---- Expectations: `expectations` of a scenario, e.g. "p1_vp_doorplate.ate_rmse_m < 0.15" ----

struct Expectation {
  enum class Op { kLess, kLessEqual, kGreater, kGreaterEqual };
  std::string pipeline;  // the pipeline's name
  std::string metric;    // dotted path under the pipeline's object, one of MetricNames()
  Op op = Op::kLess;
  double value = 0.0;
  std::string text;  // as written
};

/// Parses "<pipeline>.<metric> <op> <number>", op one of < <= > >=. Returns the error message,
/// or nothing on success (then *out is set).
std::optional<std::string> ParseExpectation(const std::string& text, Expectation* out);

/// Every scalar metric name a pipeline can have, in schema order.
std::vector<std::string> MetricNames();

struct ExpectationResult {
  Expectation expectation;
  std::optional<double> measured;  // empty: the metric is missing or null (the check fails)
  bool passed = false;
};

std::vector<ExpectationResult> CheckExpectations(const nlohmann::ordered_json& metrics,
                                                 const std::vector<Expectation>& expectations);

}  // namespace corridorsim
