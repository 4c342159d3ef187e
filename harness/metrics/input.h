#pragma once
// What the runner collects during a closed-loop run for the metrics (docs/metrics.md): the truth,
// every rendered frame's truth, and each pipeline's estimates, map, detections and innovations.

#include <cstdint>
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

/// What a rendered frame shows at a detection's pixel, read off its exact depth and instance
/// buffers: the truth a point landmark made from that detection is scored against.
struct SeenPoint {
  Eigen::Vector3d p_in_world = Eigen::Vector3d::Zero();  // m
  std::uint32_t instance_id = 0;                         // worlds id of the surface, 0 = none
};

/// A pipeline that failed: a call into it threw. It is called no more; what it gave before stays
/// in its record (estimates, detections), and its metrics are `health.failed` only.
struct PipelineFailure {
  TimeNs stamp_ns = 0;  // the stamp of the message it failed on (the last one seen for Finish)
  std::string call;     // "OnOdometry", "OnCamera", "Finish", ...
  std::string what;     // the exception's text, made printable and bounded
};

struct PipelineRecord {
  std::string name;  // unique in the run; the key of its object in metrics.json
  std::optional<PipelineFailure> failure;         // set when a call into the pipeline threw
  std::vector<std::string> cameras_used;          // Pipeline::cameras_used(): frames it processed
  std::vector<EstimateSample> estimates;          // at every odometry message, stamp order
  std::vector<slam::LandmarkEstimate> landmarks;  // the final map
  std::vector<slam::Detection> detections;        // all frames
  // Corner detections in frames with exact depth (CameraOptions::ReadsDepth): the point seen at
  // the detection's pixel, by index into `detections` (absent where the depth there is invalid).
  std::map<std::size_t, SeenPoint> seen_points;
  std::vector<slam::Innovation> innovations;
  std::vector<slam::MapArea> areas;             // Pipeline::Areas(): the map divided at the doors
  std::map<std::string, double> stage_seconds;  // the pipeline's own stages (s)
  // CPU seconds of the threads that ran the calls into the pipeline, during them (the runner's
  // measure: its cost whatever shared the cores, as stage_seconds is wall time).
  double cpu_seconds = 0.0;
  slam::PipelineHealth health;
  // The pipeline's dense map (Pipeline::occupancy_map) for the map-quality metrics, or nullptr;
  // owned by the pipeline, valid until its maps are written.
  const octomap::OcTree* occupancy_map = nullptr;
  // An external pipeline's program's output (stdout and stderr, its last MiB): the run folder's
  // <name>.log; empty for the others.
  std::string log;
  // An external pipeline's cost on both sides of the connection (timing.json's
  // `pipelines.<name>.protocol`, harness/external/exchange_timing.h); null for the others, whose
  // `cpu_seconds` is their own cost (an external one's would be corridorsim's side only, so its
  // timing names it `protocol.corridorsim_cpu_seconds` instead).
  nlohmann::ordered_json protocol_timing;
  // What was wrong with an external program's replies but cost no result (printed as warnings).
  std::vector<std::string> warnings;
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
  // A plate is legible, so detectable and observed, only where a camera the pipeline uses saw it
  // large enough and not too obliquely: the outline at least this many pixels high ...
  double min_plate_height_px = 16.0;
  double max_plate_viewing_angle_deg = 60.0;  // ... and its normal within this of the view ray
  double vp_gate_px = 20.0;  // a vanishing-point detection hits a truth VP within this distance
  // A corner detection associated with a landmark is correct when it saw the point the
  // landmark's creating detection saw, within this distance (m).
  double seen_point_gate_m = 0.10;
  // Doors (P3 eq. 11, 17): a detection is a door when both its column bearings lie within this
  // of the door's (either order) ...
  double door_bearing_gate_rad = 0.10;
  // ... and a door landmark is a doorway when both its columns lie within this of the doorway's.
  double door_column_gate_m = 0.40;
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
