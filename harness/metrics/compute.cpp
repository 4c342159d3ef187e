#include "harness/metrics/compute.h"

#include <map>
#include <string>

#include "common/error.h"
#include "harness/metrics/association.h"
#include "harness/metrics/consistency.h"
#include "harness/metrics/detection.h"
#include "harness/metrics/map.h"
#include "harness/metrics/matching.h"
#include "harness/metrics/occupancy.h"
#include "harness/metrics/registry.h"
#include "harness/metrics/trajectory.h"

namespace corridorsim {
namespace {

using Json = nlohmann::ordered_json;
using metrics::MetricScope;
using metrics::MetricWriter;

void AddTimingMetrics(const PipelineRecord& pipeline, const metrics::PipelineContext& context,
                      const MetricWriter& out) {
  // Frames the pipeline processed: distinct (camera, stamp) of the cameras it used.
  const std::size_t frames = context.frames.size();
  const std::size_t steps = pipeline.estimates.size();
  double total_s = 0.0;
  for (const auto& [stage, seconds] : pipeline.stage_seconds) total_s += seconds;
  const MetricWriter t = out.Sub("timing");
  t.Count("frames", frames);
  t.Count("steps", steps);
  t.Map("stage_seconds");
  for (const auto& [stage, seconds] : pipeline.stage_seconds) {
    t.MapValue("stage_seconds", stage, seconds);
  }
  if (frames > 0) {
    t.Map("stage_ms_per_frame");
    for (const auto& [stage, seconds] : pipeline.stage_seconds) {
      t.MapValue("stage_ms_per_frame", stage, seconds * 1e3 / static_cast<double>(frames));
    }
    t.Set("total_ms_per_frame", total_s * 1e3 / static_cast<double>(frames));
  } else {
    t.Null("total_ms_per_frame");
  }
  // An external program's CPU time is not corridorsim's threads': its figures, both sides named,
  // are in timing.json's `protocol` section (PipelineRecord::protocol_timing).
  if (pipeline.protocol_timing.is_null()) {
    if (frames > 0) {
      t.Set("cpu_ms_per_frame", pipeline.cpu_seconds * 1e3 / static_cast<double>(frames));
    } else {
      t.Null("cpu_ms_per_frame");
    }
    t.Set("cpu_seconds", pipeline.cpu_seconds);
  }
  if (steps > 0) {
    t.Set("total_ms_per_step", total_s * 1e3 / static_cast<double>(steps));
  } else {
    t.Null("total_ms_per_step");
  }
}

// `truth_as_written`: input.truth as ground_truth.tum holds it (metrics::PosesAsWritten).
Json PipelineMetrics(const MetricsInput& input, const std::vector<TruthPose>& truth_as_written,
                     const PipelineRecord& pipeline) {
  Json object;
  const MetricWriter out(object, MetricScope::kPipeline);
  if (pipeline.failure) {
    // What it gave before it failed is no result: none of its metrics could be compared.
    out.Sub("health").Count("failed", 1);
    return object;
  }
  const metrics::PipelineContext context = metrics::MakeContext(input, pipeline);

  // The trajectory metrics score the poses as the run's TUM files hold them, so that they can
  // be recomputed from the files to the last digit (metrics::PoseAsWritten).
  const metrics::MatchedTrajectory matched =
      metrics::MatchToTruth(truth_as_written, metrics::PosesAsWritten(pipeline.estimates));
  metrics::AddTrajectoryMetrics(matched, out);
  metrics::AddNeesMetrics(matched, out);
  const std::size_t malformed_innovations = metrics::AddNisMetrics(pipeline.innovations, out);

  // Map and association per type; map.<type> comes first, so "map" precedes "data_association".
  std::map<slam::LandmarkType, metrics::MapMatch> matches;
  for (const slam::LandmarkType type : metrics::kMapTypes) {
    if (!metrics::HasType(pipeline, type)) continue;
    const metrics::MapMatch& map = matches[type] =
        metrics::AddMapMetrics(pipeline, context, type, out);
    if (!context.frames.empty() && metrics::HasDetections(pipeline, type)) {
      metrics::AddAssociationMetrics(pipeline, context, type, map, out);
    }
  }
  if (pipeline.occupancy_map != nullptr) {
    // The dense map against the world's exact geometry (harness/metrics/occupancy.h).
    const metrics::OccupancyQuality q = metrics::ComputeOccupancyQuality(
        *input.world, *pipeline.occupancy_map, metrics::OccupancyQualityOptions{});
    const MetricWriter occupancy = out.Sub("map").Sub("occupancy");
    occupancy.Set("resolution_m", pipeline.occupancy_map->getResolution());
    occupancy.Count("occupied_voxels", static_cast<std::size_t>(q.occupied_voxels));
    occupancy.Count("truth_observed", static_cast<std::size_t>(q.truth_observed));
    occupancy.Fraction("precision", static_cast<std::size_t>(q.occupied_near_truth),
                       static_cast<std::size_t>(q.occupied_voxels));
    occupancy.Fraction("recall", static_cast<std::size_t>(q.truth_observed_recalled),
                       static_cast<std::size_t>(q.truth_observed));
  }
  if (!pipeline.areas.empty()) metrics::AddAreaMetrics(pipeline, context, matches, out);
  metrics::AddDetectionMetrics(pipeline, context, out);
  AddTimingMetrics(pipeline, context, out);

  // The pipeline's own health, then the malformed output the metrics met (absent when none).
  const MetricWriter health = out.Sub("health");
  health.Count("non_positive_covariance",
               static_cast<std::size_t>(pipeline.health.non_positive_covariance));
  health.Count("rejected_updates", static_cast<std::size_t>(pipeline.health.rejected_updates));
  health.Count("rejected_odometry", static_cast<std::size_t>(pipeline.health.rejected_odometry));
  health.Count("rejected_frames", static_cast<std::size_t>(pipeline.health.rejected_frames));
  health.Count("malformed_innovations", malformed_innovations);
  health.Count("non_finite_covariances", matched.non_finite_covariances);
  health.Count("non_finite_estimates", matched.non_finite_estimates);
  return object;
}

void AddRunMetrics(const MetricsInput& input, const MetricWriter& out) {
  const MetricWriter run = out.Sub("run");
  double wall_total_s = 0.0;
  for (const auto& [stage, seconds] : input.timing.wall_seconds) wall_total_s += seconds;
  run.Set("sim_seconds", input.timing.sim_seconds);
  run.Map("wall_seconds");
  for (const auto& [stage, seconds] : input.timing.wall_seconds) {
    run.MapValue("wall_seconds", stage, seconds);
  }
  run.Set("wall_total_s", wall_total_s);
  if (wall_total_s > 0.0) {
    run.Set("real_time_factor", input.timing.sim_seconds / wall_total_s);
    run.Map("wall_fraction");
    for (const auto& [stage, seconds] : input.timing.wall_seconds) {
      run.MapValue("wall_fraction", stage, seconds / wall_total_s);
    }
  } else {
    run.Null("real_time_factor");
  }
}

}  // namespace

nlohmann::ordered_json ComputeMetrics(const MetricsInput& input) {
  CheckOrDie(input.world != nullptr, "ComputeMetrics", "input.world is null");
  Json out;
  out["schema_version"] = 1;
  const MetricWriter root(out, MetricScope::kRun);
  AddRunMetrics(input, root);
  std::map<std::string, std::size_t> frames_per_camera;
  for (const FrameTruthSample& f : input.frames) ++frames_per_camera[f.truth.camera_id];
  root.Count("frames.count", input.frames.size());
  root.Map("frames.per_camera");
  for (const auto& [camera, count] : frames_per_camera) {
    root.MapCount("frames.per_camera", camera, count);
  }
  Json pipelines = Json::object();
  const std::vector<TruthPose> truth_as_written = metrics::PosesAsWritten(input.truth);
  for (const PipelineRecord& pipeline : input.pipelines) {
    CheckOrDie(!pipelines.contains(pipeline.name), "ComputeMetrics", "two pipelines share a name");
    pipelines[pipeline.name] = PipelineMetrics(input, truth_as_written, pipeline);
  }
  out["pipelines"] = std::move(pipelines);
  return out;
}

}  // namespace corridorsim
