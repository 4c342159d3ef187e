#include "harness/metrics/association.h"

#include <algorithm>
#include <map>
#include <optional>

namespace corridorsim::metrics {

void AddAssociationMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                           slam::LandmarkType type, const MapMatch& map, const MetricWriter& out) {
  std::map<int, int> estimate_of_truth;
  for (const auto& [estimate, truth] : map.truth_of_estimate) estimate_of_truth[truth] = estimate;
  std::size_t associations = 0;
  std::size_t correct = 0;
  std::size_t possible = 0;
  std::size_t unverifiable = 0;
  for (const slam::Detection& d : pipeline.detections) {
    if (d.type != type) continue;
    const auto frame = context.frames.find({d.camera_id, d.stamp_ns});
    const bool to_unknown_landmark =
        d.landmark_id >= 0 && map.truth_of_estimate.count(d.landmark_id) == 0 &&
        std::none_of(pipeline.landmarks.begin(), pipeline.landmarks.end(),
                     [&d](const slam::LandmarkEstimate& l) { return l.id == d.landmark_id; });
    if (frame == context.frames.end() || to_unknown_landmark) {
      // No truth for its frame, or its landmark is not in the final map (deleted).
      ++unverifiable;
      continue;
    }
    std::optional<int> identity;
    double best_px = context.options->identity_gate_px;
    for (const TruthPixel& t : FrameTruthPixels(*frame->second, type)) {
      const double distance_px = (t.pixel - DetectionPixel(d)).norm();
      if (distance_px <= best_px) {
        best_px = distance_px;
        identity = t.id;
      }
    }
    const auto mapped = map.truth_of_estimate.find(d.landmark_id);
    const bool maps_to_identity =
        identity && mapped != map.truth_of_estimate.end() && mapped->second == *identity;
    if (d.new_landmark && maps_to_identity) continue;  // the initialisation
    const bool associated = d.landmark_id >= 0 && !d.new_landmark;
    if (associated) ++associations;
    if (associated && maps_to_identity) ++correct;
    if (identity && estimate_of_truth.count(*identity) != 0) ++possible;
  }
  const MetricWriter a = out.Sub("data_association").Sub(slam::LandmarkTypeName(type));
  a.Count("associations", associations);
  a.Count("correct", correct);
  a.Count("possible", possible);
  a.Count("unverifiable", unverifiable);
  a.Fraction("precision", correct, associations);
  a.Fraction("recall", correct, possible);
}

}  // namespace corridorsim::metrics
