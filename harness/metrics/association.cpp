#include "harness/metrics/association.h"

#include <algorithm>
#include <map>
#include <optional>

namespace corridorsim::metrics {
namespace {

// Corner detections in frames with exact depth (P1 Harris, P2/P3 upward): an association is correct
// when the detection saw the same world point as the detection that created its landmark (within
// seen_point_gate_m), exact from the rendered depth.
void SeenPointAssociationMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                                 const MetricWriter& out) {
  std::map<int, const SeenPoint*> created;
  for (const auto& [index, seen] : pipeline.seen_points) {
    const slam::Detection& d = pipeline.detections[index];
    if (d.new_landmark && d.landmark_id >= 0) created.emplace(d.landmark_id, &seen);
  }
  std::size_t associations = 0;
  std::size_t correct = 0;
  std::size_t unverifiable = 0;
  for (std::size_t i = 0; i < pipeline.detections.size(); ++i) {
    const slam::Detection& d = pipeline.detections[i];
    if (!d.Is(slam::LandmarkType::kCorner) || d.landmark_id < 0 || d.new_landmark) continue;
    ++associations;
    const auto seen = pipeline.seen_points.find(i);
    const auto origin = created.find(d.landmark_id);
    if (seen == pipeline.seen_points.end() || origin == created.end()) {
      ++unverifiable;
      continue;
    }
    const double distance_m = (seen->second.p_in_world - origin->second->p_in_world).norm();
    if (distance_m <= context.options->seen_point_gate_m) ++correct;
  }
  const MetricWriter a = out.Sub("data_association").Sub("corner");
  a.Count("associations", associations);
  a.Count("correct", correct);
  a.Null("possible");  // every corner is a new point unless associated: nothing to miss
  a.Count("unverifiable", unverifiable);
  a.Fraction("precision", correct, associations - unverifiable);
  a.Null("recall");
}

}  // namespace

void AddAssociationMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                           slam::LandmarkType type, const MapMatch& map, const MetricWriter& out) {
  if (type == slam::LandmarkType::kCorner && !pipeline.seen_points.empty()) {
    SeenPointAssociationMetrics(pipeline, context, out);
    return;
  }
  std::map<int, int> estimate_of_truth;
  for (const auto& [estimate, truth] : map.truth_of_estimate) estimate_of_truth[truth] = estimate;
  std::size_t associations = 0;
  std::size_t correct = 0;
  std::size_t possible = 0;
  std::size_t unverifiable = 0;
  for (const slam::Detection& d : pipeline.detections) {
    if (!d.Is(type)) continue;
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
    if (type == slam::LandmarkType::kDoor) {
      identity = DoorIdentity(d, *frame->second, context.options->door_bearing_gate_rad, best_px);
    }
    for (const TruthPixel& t : type == slam::LandmarkType::kDoor
                                   ? std::vector<TruthPixel>{}
                                   : FrameTruthPixels(*frame->second, type)) {
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
