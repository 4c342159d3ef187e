#pragma once
// What the runner collects during a closed-loop run for the metrics (docs/metrics.md): the truth,
// every rendered frame's truth, and each pipeline's estimates, map, detections and innovations.

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

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

}  // namespace corridorsim
