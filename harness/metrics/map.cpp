#include "harness/metrics/map.h"

#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "harness/metrics/stats.h"

namespace corridorsim::metrics {

using slam::LandmarkType;

MapMatch AddMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                       LandmarkType type, const MetricWriter& out) {
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
