#include "harness/metrics/detection.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "harness/metrics/stats.h"

namespace corridorsim::metrics {
namespace {

using Eigen::Vector2d;
using Eigen::Vector4d;
using slam::LandmarkType;

// Detections of `type` grouped by frame, and the frames of the cameras that produced any.
struct DetectionsByFrame {
  std::map<FrameKey, std::vector<const slam::Detection*>> by_frame;
  std::vector<std::pair<FrameKey, const render::FrameTruth*>> frames;  // truth frames to score
  std::size_t without_truth = 0;  // detections whose frame has no truth
};
DetectionsByFrame GroupDetections(const PipelineRecord& pipeline, const PipelineContext& context,
                                  LandmarkType type) {
  DetectionsByFrame out;
  std::set<std::string> cameras;
  for (const slam::Detection& d : pipeline.detections) {
    if (!d.Is(type)) continue;
    cameras.insert(d.camera_id);
    if (context.frames.count({d.camera_id, d.stamp_ns}) == 0) {
      ++out.without_truth;
      continue;
    }
    out.by_frame[{d.camera_id, d.stamp_ns}].push_back(&d);
  }
  for (const auto& [key, frame] : context.frames) {
    if (cameras.count(key.first) != 0) out.frames.emplace_back(key, frame);
  }
  return out;
}

// Hits, false alarms and misses of one detector; truth that is hard to see (cut by the border,
// mostly hidden) is neither hit nor missed when matched or not.
struct DetectorCounts {
  std::size_t detections = 0;
  std::size_t true_positives = 0;
  std::size_t false_positives = 0;
  std::size_t false_negatives = 0;
  std::size_t ignored = 0;  // detections matched to truth that is not detectable
};
void AddCounts(const DetectorCounts& c, std::size_t without_truth, const MetricWriter& out) {
  out.Count("detections", c.detections);
  out.Count("true_positives", c.true_positives);
  out.Count("false_positives", c.false_positives);
  out.Count("false_negatives", c.false_negatives);
  out.Count("ignored", c.ignored);
  out.Count("without_truth", without_truth);
  out.Fraction("precision", c.true_positives, c.true_positives + c.false_positives);
  out.Fraction("recall", c.true_positives, c.true_positives + c.false_negatives);
}

// Scores the frames of one type: `cost(detection, truth index)` gives a match cost or none.
template <class Truth, class CostFn, class DetectableFn, class HitFn>
DetectorCounts ScoreFrames(const DetectionsByFrame& grouped,
                           const std::vector<Truth>& (*truth_of)(const render::FrameTruth&),
                           CostFn cost, DetectableFn detectable, HitFn on_hit) {
  DetectorCounts counts;
  static const std::vector<const slam::Detection*> kNone;
  for (const auto& [key, frame] : grouped.frames) {
    const auto it = grouped.by_frame.find(key);
    const std::vector<const slam::Detection*>& detections =
        it == grouped.by_frame.end() ? kNone : it->second;
    const std::vector<Truth>& truth = truth_of(*frame);
    std::vector<Candidate> candidates;
    for (std::size_t a = 0; a < detections.size(); ++a) {
      for (std::size_t b = 0; b < truth.size(); ++b) {
        if (const std::optional<double> c = cost(*detections[a], truth[b])) {
          candidates.push_back({*c, a, b});
        }
      }
    }
    const auto matches = GreedyMatch(std::move(candidates), detections.size(), truth.size());
    std::vector<bool> truth_matched(truth.size(), false);
    counts.detections += detections.size();
    for (const auto& [a, b] : matches) {
      truth_matched[b] = true;
      if (detectable(truth[b])) {
        ++counts.true_positives;
        on_hit(*detections[a], truth[b]);
      } else {
        ++counts.ignored;
      }
    }
    counts.false_positives += detections.size() - matches.size();
    for (std::size_t b = 0; b < truth.size(); ++b) {
      if (!truth_matched[b] && detectable(truth[b])) ++counts.false_negatives;
    }
  }
  return counts;
}

const std::vector<render::PlateTruth>& PlatesOf(const render::FrameTruth& f) { return f.plates; }
const std::vector<render::DoorTruth>& DoorsOf(const render::FrameTruth& f) { return f.doors; }

// The truth box a plate detection is matched against: the number region when the detector
// reports number regions (P1 section 3.1), else the plate's outline.
Vector4d BoxOf(const render::PlateTruth& t, slam::PlateBox kind) {
  if (kind == slam::PlateBox::kNumberRegion) {
    return Vector4d(t.number_bbox_min_px.x(), t.number_bbox_min_px.y(), t.number_bbox_max_px.x(),
                    t.number_bbox_max_px.y());
  }
  return Vector4d(t.bbox_min_px.x(), t.bbox_min_px.y(), t.bbox_max_px.x(), t.bbox_max_px.y());
}

void PlateDetectorMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                          const MetricWriter& out) {
  const DetectionsByFrame grouped = GroupDetections(pipeline, context, LandmarkType::kDoorPlate);
  const MetricsOptions& options = *context.options;
  Stats iou;
  std::size_t read = 0;
  std::size_t read_correctly = 0;
  const DetectorCounts counts = ScoreFrames<render::PlateTruth>(
      grouped, PlatesOf,
      [&](const slam::Detection& d, const render::PlateTruth& t) -> std::optional<double> {
        const double value = BoxIou(d.box_px, BoxOf(t, d.plate_box));
        if (value < options.min_box_iou) return std::nullopt;
        return -value;
      },
      [&](const render::PlateTruth& t) { return PlateLegible(t, options); },
      [&](const slam::Detection& d, const render::PlateTruth& t) {
        iou.Add(BoxIou(d.box_px, BoxOf(t, d.plate_box)));
        if (!d.label.empty()) {
          ++read;
          if (d.label == t.room_number) ++read_correctly;
        }
      });
  AddCounts(counts, grouped.without_truth, out);
  out.Set("mean_iou", iou.mean());
  out.Fraction("room_number_read_fraction", read, counts.true_positives);
  out.Fraction("room_number_accuracy", read_correctly, read);
}

// Lamps as the issue scores P3's detector: only lit circular lamps are to be detected (recall
// over those fully in the image and mostly visible); panel and switched-off lamps are what the
// detector must reject (a detection of one is a false positive, and they are counted as
// rejections); lamps cut by the border are scored apart (found, centre error); lamps mostly
// hidden are neither hit nor missed.
void LampDetectorMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                         const MetricWriter& out) {
  const DetectionsByFrame grouped = GroupDetections(pipeline, context, LandmarkType::kLamp);
  const MetricsOptions& options = *context.options;
  Stats centre_error, cut_error;
  DetectorCounts counts;
  std::size_t to_reject = 0, rejected = 0, cut = 0, cut_found = 0;
  static const std::vector<const slam::Detection*> kNone;
  for (const auto& [key, frame] : grouped.frames) {
    const auto it = grouped.by_frame.find(key);
    const std::vector<const slam::Detection*>& detections =
        it == grouped.by_frame.end() ? kNone : it->second;
    const std::vector<render::LampTruth>& truth = frame->lamps;
    std::vector<Candidate> candidates;
    for (std::size_t a = 0; a < detections.size(); ++a) {
      for (std::size_t b = 0; b < truth.size(); ++b) {
        const double distance_px = (detections[a]->pixel - truth[b].center_px).norm();
        if (distance_px <= std::max(truth[b].radius_px, options.min_gate_px)) {
          candidates.push_back({distance_px, a, b});
        }
      }
    }
    const auto matches = GreedyMatch(std::move(candidates), detections.size(), truth.size());
    std::vector<const slam::Detection*> match_of(truth.size(), nullptr);
    for (const auto& [a, b] : matches) match_of[b] = detections[a];
    counts.detections += detections.size();
    counts.false_positives += detections.size() - matches.size();
    for (std::size_t b = 0; b < truth.size(); ++b) {
      const render::LampTruth& t = truth[b];
      const slam::Detection* d = match_of[b];
      const bool visible = t.visible_fraction >= options.min_visible_fraction;
      if (t.shape != worlds::LampShape::kCircular || !t.on) {
        if (visible) {
          ++to_reject;
          rejected += d == nullptr;
        }
        counts.false_positives += d != nullptr;  // a panel or a dark lamp taken for a lamp
      } else if (t.cut_by_border) {
        if (visible) {
          ++cut;
          if (d) {
            ++cut_found;
            cut_error.Add((d->pixel - t.center_px).norm());
          }
        } else if (d) {
          ++counts.ignored;
        }
      } else if (!visible) {
        counts.ignored += d != nullptr;
      } else if (d) {
        ++counts.true_positives;
        centre_error.Add((d->pixel - t.center_px).norm());
      } else {
        ++counts.false_negatives;
      }
    }
  }
  AddCounts(counts, grouped.without_truth, out);
  out.Set("mean_center_error_px", centre_error.mean());
  out.Set("rmse_center_error_px", centre_error.rms());
  out.Set("max_center_error_px", centre_error.maximum());
  out.Count("to_reject", to_reject);
  out.Count("rejected", rejected);
  out.Fraction("rejected_fraction", rejected, to_reject);
  out.Count("border_cut", cut);
  out.Count("border_cut_found", cut_found);
  out.Set("border_cut_max_center_error_px", cut_error.maximum());
}

void DoorDetectorMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                         const MetricWriter& out) {
  const DetectionsByFrame grouped = GroupDetections(pipeline, context, LandmarkType::kDoor);
  const MetricsOptions& options = *context.options;
  std::size_t with_state = 0;
  std::size_t state_correct = 0;
  const DetectorCounts counts = ScoreFrames<render::DoorTruth>(
      grouped, DoorsOf,
      [&](const slam::Detection& d, const render::DoorTruth& t) -> std::optional<double> {
        // By the columns' bearings (P3 eq. 17) where the detector gives them.
        if (const std::optional<double> e = DoorBearingError(d, t)) {
          if (*e > options.door_bearing_gate_rad) return std::nullopt;
          return *e;
        }
        const Vector2d centre_px = 0.5 * (t.column_a_px + t.column_b_px);
        const double gate_px =
            std::max(0.5 * (t.column_a_px - t.column_b_px).norm(), options.min_gate_px);
        const double distance_px = (DetectionPixel(d) - centre_px).norm();
        if (distance_px > gate_px) return std::nullopt;
        return distance_px;
      },
      [](const render::DoorTruth& t) { return t.visible; },
      [&](const slam::Detection& d, const render::DoorTruth& t) {
        if (!d.open) return;
        ++with_state;
        // An empty doorway (no leaf) is open.
        if (*d.open == (t.state != worlds::DoorState::kClosed)) ++state_correct;
      });
  AddCounts(counts, grouped.without_truth, out);
  out.Fraction("open_state_accuracy", state_correct, with_state);
}

// Vanishing point: each detection against the nearest in-image truth VP of its frame; a hit lies
// within vp_gate_px of it. Frames whose camera is inside a corridor whose VP is in the image
// count as detectable; a detectable frame is detected when one of its detections is a hit.
void VanishingPointMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                           const MetricWriter& out) {
  const DetectionsByFrame grouped =
      GroupDetections(pipeline, context, LandmarkType::kVanishingPoint);
  const double gate_px = context.options->vp_gate_px;
  Stats error;
  Stats u_error;
  std::size_t without_vp = 0;
  std::size_t hits = 0;
  std::size_t false_positives = 0;
  std::size_t detectable_frames = 0;
  std::size_t detected_frames = 0;
  for (const auto& [key, frame] : grouped.frames) {
    const auto it = grouped.by_frame.find(key);
    const bool detectable = std::any_of(
        frame->vanishing_points.begin(), frame->vanishing_points.end(),
        [](const render::VanishingPointTruth& v) { return v.in_image && v.camera_in_segment; });
    if (detectable) ++detectable_frames;
    if (it == grouped.by_frame.end()) continue;
    bool frame_hit = false;
    for (const slam::Detection* d : it->second) {
      const render::VanishingPointTruth* nearest = nullptr;
      for (const render::VanishingPointTruth& v : frame->vanishing_points) {
        if (!v.in_image) continue;
        if (nearest == nullptr ||
            (v.pixel - d->pixel).squaredNorm() < (nearest->pixel - d->pixel).squaredNorm()) {
          nearest = &v;
        }
      }
      if (nearest == nullptr) {
        ++without_vp;
        ++false_positives;
        continue;
      }
      const double distance_px = (nearest->pixel - d->pixel).norm();
      error.Add(distance_px);
      u_error.Add(std::abs(nearest->pixel.x() - d->pixel.x()));
      if (distance_px <= gate_px) {
        ++hits;
        frame_hit = true;
      } else {
        ++false_positives;
      }
    }
    if (detectable && frame_hit) ++detected_frames;
  }
  out.Count("count", error.count);
  out.Count("without_truth", grouped.without_truth + without_vp);
  out.Count("hits", hits);
  out.Count("false_positives", false_positives);
  out.Set("mean_error_px", error.mean());
  out.Set("rmse_error_px", error.rms());
  out.Set("mean_abs_u_error_px", u_error.mean());
  out.Fraction("precision", hits, hits + false_positives);
  out.Fraction("detected_frame_fraction", detected_frames, detectable_frames);
}

}  // namespace

bool PlateLegible(const render::PlateTruth& t, const MetricsOptions& options) {
  return t.fully_in_image && t.visible_fraction >= options.min_visible_fraction &&
         t.bbox_max_px.y() - t.bbox_min_px.y() >= options.min_plate_height_px &&
         t.viewing_angle_deg <= options.max_plate_viewing_angle_deg;
}

double BoxIou(const Vector4d& a, const Vector4d& b) {
  const double w = std::min(a[2], b[2]) - std::max(a[0], b[0]);
  const double h = std::min(a[3], b[3]) - std::max(a[1], b[1]);
  if (w <= 0.0 || h <= 0.0) return 0.0;
  const double inter = w * h;
  const double area_a = (a[2] - a[0]) * (a[3] - a[1]);
  const double area_b = (b[2] - b[0]) * (b[3] - b[1]);
  return inter / (area_a + area_b - inter);
}

void AddDetectionMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                         const MetricWriter& out) {
  if (context.frames.empty()) return;
  const MetricWriter detection = out.Sub("detection");
  if (HasDetections(pipeline, LandmarkType::kVanishingPoint)) {
    VanishingPointMetrics(pipeline, context, detection.Sub("vanishing_point"));
  }
  if (HasDetections(pipeline, LandmarkType::kDoorPlate)) {
    PlateDetectorMetrics(pipeline, context, detection.Sub("door_plate"));
  }
  if (HasDetections(pipeline, LandmarkType::kLamp)) {
    LampDetectorMetrics(pipeline, context, detection.Sub("lamp"));
  }
  if (HasDetections(pipeline, LandmarkType::kDoor)) {
    DoorDetectorMetrics(pipeline, context, detection.Sub("door"));
  }
}

}  // namespace corridorsim::metrics
