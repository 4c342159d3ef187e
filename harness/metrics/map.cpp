#include "harness/metrics/map.h"

#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "harness/metrics/detection.h"
#include "harness/metrics/stats.h"

namespace corridorsim::metrics {

using slam::LandmarkType;

namespace {

// The seen point of each corner landmark: the point its creating detection's pixel showed.
std::map<int, const SeenPoint*> SeenPointsOfLandmarks(const PipelineRecord& pipeline) {
  std::map<int, const SeenPoint*> out;
  for (const auto& [index, seen] : pipeline.seen_points) {
    const slam::Detection& d = pipeline.detections[index];
    if (d.new_landmark && d.landmark_id >= 0) out.emplace(d.landmark_id, &seen);
  }
  return out;
}

// Corner landmarks made from detections in depth frames (P1's Harris baseline): each is scored
// against the world point seen at its creating detection's pixel, exact from the rendered depth,
// not against the nearest tile crossing (every estimate in a tiled ceiling has one within 1 m).
void SeenPointMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                         const std::map<int, const SeenPoint*>& seen, const MetricWriter& m) {
  Stats error;
  Stats z_error;
  std::size_t estimated = 0;
  std::size_t matched = 0;
  for (const slam::LandmarkEstimate& l : pipeline.landmarks) {
    if (l.type != LandmarkType::kCorner) continue;
    ++estimated;
    const auto it = seen.find(l.id);
    if (it == seen.end()) continue;
    const Eigen::Vector3d& truth = it->second->p_in_world;
    const double d = (l.position_in_world.head<2>() - truth.head<2>()).norm();
    if (d > context.options->landmark_gate_m) continue;
    ++matched;
    error.Add(d);
    z_error.Add(std::abs(l.position_in_world.z() - truth.z()));
  }
  m.Count("estimated", estimated);
  m.Count("matched", matched);
  m.Count("spurious", estimated - matched);
  m.Null("observed");  // the seen points are what was observed; nothing else can be missed
  m.Null("missed");
  m.Set("mean_error_m", error.mean());
  m.Set("rmse_m", error.rms());
  m.Set("max_error_m", error.maximum());
  m.Set("z_rmse_m", z_error.rms());
}

}  // namespace

MapMatch AddMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                       LandmarkType type, const MetricWriter& out) {
  if (type == LandmarkType::kCorner) {
    const std::map<int, const SeenPoint*> seen = SeenPointsOfLandmarks(pipeline);
    if (!seen.empty()) {
      SeenPointMapMetrics(pipeline, context, seen, out.Sub("map").Sub("corner"));
      return {};
    }
  }
  const std::vector<TruthLandmark> truth = TruthLandmarks(*context.world, type);
  std::vector<const slam::LandmarkEstimate*> estimates;
  for (const slam::LandmarkEstimate& l : pipeline.landmarks) {
    if (l.type == type) estimates.push_back(&l);
  }
  // Horizontal distance: P1's plates and P2/P3's doors are planar states.
  std::vector<Candidate> candidates;
  for (std::size_t a = 0; a < estimates.size(); ++a) {
    for (std::size_t b = 0; b < truth.size(); ++b) {
      const double d =
          (estimates[a]->position_in_world.head<2>() - truth[b].position_in_world.head<2>()).norm();
      if (d <= context.options->landmark_gate_m) candidates.push_back({d, a, b});
    }
  }
  const auto matches = GreedyMatch(std::move(candidates), estimates.size(), truth.size());

  MapMatch result;
  Stats error;
  Stats z_error;
  std::size_t labels_agree = 0;
  std::set<int> matched_truth;
  for (const auto& [a, b] : matches) {
    result.truth_of_estimate[estimates[a]->id] = truth[b].id;
    matched_truth.insert(truth[b].id);
    error.Add(
        (estimates[a]->position_in_world.head<2>() - truth[b].position_in_world.head<2>()).norm());
    z_error.Add(std::abs(estimates[a]->position_in_world.z() - truth[b].position_in_world.z()));
    if (estimates[a]->label == truth[b].label) ++labels_agree;
  }

  const MetricWriter m = out.Sub("map").Sub(slam::LandmarkTypeName(type));
  m.Count("estimated", estimates.size());
  m.Count("matched", matches.size());
  m.Count("spurious", estimates.size() - matches.size());
  // Observed: ground truth that appears in a frame the pipeline processed; only these can be
  // missed (the rest of the world was never in view).
  if (context.frames.empty()) {
    m.Null("observed");
    m.Null("missed");
  } else {
    std::set<int> observed;
    for (const auto& [key, frame] : context.frames) {
      if (type == LandmarkType::kDoorPlate) {
        // A plate is observed where it was legible (a dot 20 m ahead is not).
        for (const render::PlateTruth& t : frame->plates) {
          if (PlateLegible(t, *context.options)) observed.insert(t.id);
        }
        continue;
      }
      for (const TruthPixel& t : FrameTruthPixels(*frame, type)) observed.insert(t.id);
    }
    std::size_t missed = 0;
    for (const int id : observed) missed += matched_truth.count(id) == 0 ? 1 : 0;
    m.Count("observed", observed.size());
    m.Count("missed", missed);
  }
  m.Set("mean_error_m", error.mean());
  m.Set("rmse_m", error.rms());
  m.Set("max_error_m", error.maximum());
  if (type == LandmarkType::kCorner || type == LandmarkType::kLamp) {
    m.Set("z_rmse_m", z_error.rms());
  }
  if (type == LandmarkType::kDoorPlate) {
    m.Fraction("room_number_accuracy", labels_agree, matches.size());
  }
  return result;
}

}  // namespace corridorsim::metrics
