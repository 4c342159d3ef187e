#include "harness/workbench/score.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "common/io/stable_json.h"
#include "harness/workbench/dataset.h"
#include "harness/workbench/score_internal.h"

// `score`'s evaluation (score.h: EvaluateDetections), pycocotools' COCOeval for each class:
// detections matched to labels image by image at every threshold (IoU, or pixel distance for
// corners), the 101-point interpolated AP, the best-F1 operating point, the localisation error,
// the plates' reading accuracy and the recall binned by distance, viewing angle and appearance.

namespace corridorsim {
namespace {

using Json = nlohmann::ordered_json;
using score_internal::CircleBox;
using score_internal::FormatNumber;

double BoxIou(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double w = std::min(a[0] + a[2], b[0] + b[2]) - std::max(a[0], b[0]);
  const double h = std::min(a[1] + a[3], b[1] + b[3]) - std::max(a[1], b[1]);
  if (w <= 0.0 || h <= 0.0) return 0.0;
  const double inter = w * h;
  const double uni = a[2] * a[3] + b[2] * b[3] - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

// How close a detection is to a label: IoU for boxes and circles (higher is better), pixel
// distance for corners (lower is better). Lamps with a circle on both sides use the circles.
struct Geometry {
  bool distance = false;  // corners

  double Similarity(const ScoreDetection& d, const ScoreLabel& g) const {
    if (distance) return PointDistance(d, g);
    if (d.circle && g.circle) return CircleIou(*d.circle, *g.circle);
    return BoxIou(DetectionBox(d), g.bbox);
  }
  static std::array<double, 4> DetectionBox(const ScoreDetection& d) {
    if (d.bbox) return *d.bbox;
    if (d.circle) return CircleBox(*d.circle);
    return {(*d.point)[0], (*d.point)[1], 0.0, 0.0};
  }
  static std::array<double, 2> DetectionPoint(const ScoreDetection& d) {
    if (d.point) return *d.point;
    if (d.circle) return {(*d.circle)[0], (*d.circle)[1]};
    return {(*d.bbox)[0] + 0.5 * (*d.bbox)[2], (*d.bbox)[1] + 0.5 * (*d.bbox)[3]};
  }
  static std::array<double, 2> LabelPoint(const ScoreLabel& g) {
    if (g.point) return *g.point;
    if (g.circle) return {(*g.circle)[0], (*g.circle)[1]};
    return {g.bbox[0] + 0.5 * g.bbox[2], g.bbox[1] + 0.5 * g.bbox[3]};
  }
  static double PointDistance(const ScoreDetection& d, const ScoreLabel& g) {
    const auto a = DetectionPoint(d);
    const auto b = LabelPoint(g);
    return std::hypot(a[0] - b[0], a[1] - b[1]);
  }
};

// One image's detections and labels of one class, matched at every threshold.
struct ImageMatch {
  std::vector<const ScoreDetection*> detections;  // by descending score, at most maxDets
  std::vector<const ScoreLabel*> labels;
  // [threshold][detection]: the matched label's index, or -1; [threshold][label] likewise.
  std::array<std::vector<int>, kThresholdCount> detection_match;
  std::array<std::vector<int>, kThresholdCount> label_match;
};

// pycocotools COCOeval.evaluateImg (areaRng all, no crowd, maxDets 100): detections in
// descending score (stable: equal scores keep the file's order, as np.argsort(kind='mergesort')),
// each takes the unmatched label with the best IoU that reaches the threshold (a later label of
// equal IoU wins, as there).
void MatchImage(const Geometry& geometry, ImageMatch* m) {
  std::stable_sort(
      m->detections.begin(), m->detections.end(),
      [](const ScoreDetection* a, const ScoreDetection* b) { return a->score > b->score; });
  if (m->detections.size() > kMaxDetectionsPerImage) m->detections.resize(kMaxDetectionsPerImage);
  const std::size_t nd = m->detections.size(), ng = m->labels.size();
  std::vector<double> similarity(nd * ng);
  for (std::size_t d = 0; d < nd; ++d) {
    for (std::size_t g = 0; g < ng; ++g) {
      similarity[d * ng + g] = geometry.Similarity(*m->detections[d], *m->labels[g]);
    }
  }
  for (int t = 0; t < kThresholdCount; ++t) {
    m->detection_match[t].assign(nd, -1);
    m->label_match[t].assign(ng, -1);
    for (std::size_t d = 0; d < nd; ++d) {
      int best = -1;
      if (geometry.distance) {
        double limit = CornerThresholdPx(t);
        for (std::size_t g = 0; g < ng; ++g) {
          if (m->label_match[t][g] >= 0 || similarity[d * ng + g] > limit) continue;
          limit = similarity[d * ng + g];
          best = static_cast<int>(g);
        }
      } else {
        double limit = std::min(IouThreshold(t), 1.0 - 1e-10);
        for (std::size_t g = 0; g < ng; ++g) {
          if (m->label_match[t][g] >= 0 || similarity[d * ng + g] < limit) continue;
          limit = similarity[d * ng + g];
          best = static_cast<int>(g);
        }
      }
      if (best < 0) continue;
      m->detection_match[t][d] = best;
      m->label_match[t][best] = static_cast<int>(d);
    }
  }
}

struct Ranked {
  double score;
  bool true_positive;
};

// pycocotools COCOeval.accumulate for one class and threshold: all images' detections by
// descending score (stable, in image order), cumulative TP / FP, precision made monotone from the
// end, then sampled at the 101 recall points np.linspace(0, 1, 101) with searchsorted(side
// 'left'); recall points beyond the last reached recall get precision 0. Returns the 101 values.
std::array<double, 101> InterpolatedPrecision(std::vector<Ranked> ranked, std::size_t labels) {
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const Ranked& a, const Ranked& b) { return a.score > b.score; });
  const std::size_t nd = ranked.size();
  std::vector<double> recall(nd), precision(nd);
  double tp = 0.0, fp = 0.0;
  for (std::size_t i = 0; i < nd; ++i) {
    (ranked[i].true_positive ? tp : fp) += 1.0;
    recall[i] = tp / static_cast<double>(labels);
    precision[i] = tp / (fp + tp + std::numeric_limits<double>::epsilon());  // np.spacing(1)
  }
  for (std::size_t i = nd; i-- > 1;) precision[i - 1] = std::max(precision[i - 1], precision[i]);
  std::array<double, 101> q{};
  for (int r = 0; r <= 100; ++r) {
    const double at = static_cast<double>(r) * (1.0 / 100.0);  // np.linspace's values
    const std::size_t i = static_cast<std::size_t>(
        std::lower_bound(recall.begin(), recall.end(), at) - recall.begin());
    q[r] = i < nd ? precision[i] : 0.0;
  }
  return q;
}

Json OrNull(std::optional<double> v, double steps = json_steps::kRatio) {
  return v ? Json(RoundToStep(*v, steps)) : Json(nullptr);
}

// Recall of labels grouped by a value: `edges` are the bins' lower bounds (the last bin is open).
Json BinnedRecall(const std::vector<std::pair<double, bool>>& values,
                  const std::vector<double>& edges, const std::vector<std::string>& names) {
  Json bins = Json::array();
  for (std::size_t b = 0; b < edges.size(); ++b) {
    const double lo = edges[b];
    const double hi = b + 1 < edges.size() ? edges[b + 1] : std::numeric_limits<double>::infinity();
    int labels = 0, matched = 0;
    for (const auto& [value, found] : values) {
      const bool last = b + 1 == edges.size();
      if (value >= lo && (value < hi || (last && value <= hi))) {
        ++labels;
        matched += found;
      }
    }
    bins.push_back(
        {{"bin", names[b]},
         {"labels", labels},
         {"matched", matched},
         {"recall", labels ? Json(RoundToStep(double(matched) / labels, json_steps::kRatio))
                           : Json(nullptr)}});
  }
  return bins;
}

// numpy.percentile's default (linear interpolation between closest ranks).
double Percentile(const std::vector<double>& sorted, double p) {
  const double rank = p * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (rank - double(lo)) * (sorted[hi] - sorted[lo]);
}

Json EvaluateClass(const ScoreDataset& dataset, const std::vector<ScoreDetection>& detections,
                   int category) {
  const Geometry geometry{category == kCategoryCeilingCorner};
  std::map<std::int64_t, ImageMatch> images;  // image order, as pycocotools' sorted imgIds
  std::size_t label_count = 0, detection_count = 0;
  for (const ScoreLabel& g : dataset.labels) {
    if (g.category_id != category) continue;
    images[g.image_id].labels.push_back(&g);
    ++label_count;
  }
  for (const ScoreDetection& d : detections) {
    if (d.category_id != category) continue;
    images[d.image_id].detections.push_back(&d);
    ++detection_count;
  }
  for (auto& [id, m] : images) MatchImage(geometry, &m);

  Json j;
  j["labels"] = label_count;
  j["detections"] = detection_count;
  j["matching"] = geometry.distance ? "keypoint distance (px), 10 ... 1" : "IoU, 0.50 ... 0.95";

  // AP per threshold (undefined without labels, as pycocotools' -1).
  std::array<std::array<double, 101>, kThresholdCount> curves{};
  std::optional<double> ap50, ap;
  if (label_count > 0) {
    double sum = 0.0;
    for (int t = 0; t < kThresholdCount; ++t) {
      std::vector<Ranked> ranked;
      for (const auto& [id, m] : images) {
        for (std::size_t d = 0; d < m.detections.size(); ++d) {
          ranked.push_back(Ranked{m.detections[d]->score, m.detection_match[t][d] >= 0});
        }
      }
      curves[t] = InterpolatedPrecision(std::move(ranked), label_count);
      const double a = std::accumulate(curves[t].begin(), curves[t].end(), 0.0) / 101.0;
      if (t == 0) ap50 = a;
      sum += a;
    }
    ap = sum / kThresholdCount;
  }

  // The operating point: the score threshold with the best F1 at the loosest threshold (a cut
  // keeps every detection at or above it, so only the last of equal scores is a candidate).
  std::vector<Ranked> ranked;
  for (const auto& [id, m] : images) {
    for (std::size_t d = 0; d < m.detections.size(); ++d) {
      ranked.push_back(Ranked{m.detections[d]->score, m.detection_match[0][d] >= 0});
    }
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const Ranked& a, const Ranked& b) { return a.score > b.score; });
  std::optional<double> precision, recall, f1, threshold;
  if (label_count > 0) {
    recall = 0.0;
    f1 = 0.0;
  }
  int tp = 0;
  for (std::size_t i = 0; i < ranked.size(); ++i) {
    tp += ranked[i].true_positive;
    if (i + 1 < ranked.size() && ranked[i + 1].score == ranked[i].score) continue;
    const double p = double(tp) / double(i + 1);
    const double r = label_count ? double(tp) / double(label_count) : 0.0;
    const double f = p + r > 0.0 ? 2.0 * p * r / (p + r) : 0.0;
    if (!threshold || (label_count > 0 && f > *f1)) {
      precision = p;
      recall = label_count ? std::optional<double>(r) : std::nullopt;
      f1 = label_count ? std::optional<double>(f) : std::nullopt;
      threshold = ranked[i].score;
    }
  }
  j["precision"] = OrNull(precision);
  j["recall"] = OrNull(recall);
  j["f1"] = OrNull(f1);
  j["score_threshold"] = threshold ? Json(*threshold) : Json(nullptr);
  j["ap50"] = OrNull(ap50);
  j["ap"] = OrNull(ap);

  // Localisation error and reading accuracy of the matches at the loosest threshold.
  double error_sum = 0.0;
  int matched = 0, read = 0, read_right = 0;
  for (const auto& [id, m] : images) {
    for (std::size_t d = 0; d < m.detections.size(); ++d) {
      const int g = m.detection_match[0][d];
      if (g < 0) continue;
      const ScoreDetection& det = *m.detections[d];
      const ScoreLabel& label = *m.labels[g];
      error_sum += Geometry::PointDistance(det, label);
      ++matched;
      if (det.room_number) {
        ++read;
        read_right += *det.room_number == label.room_number;
      }
    }
  }
  j["loc_error_px"] =
      matched ? Json(RoundToStep(error_sum / matched, json_steps::kPx)) : Json(nullptr);
  if (category == kCategoryDoorPlate) {
    j["reading_accuracy"] =
        read ? Json(RoundToStep(double(read_right) / read, json_steps::kRatio)) : Json(nullptr);
    j["readings"] = read;
  }

  // The 101-point interpolated PR curve at the loosest threshold (score.png draws it).
  Json curve = Json::array();
  if (label_count > 0) {
    for (int r = 0; r <= 100; ++r) curve.push_back(RoundToStep(curves[0][r], json_steps::kRatio));
  }
  j["pr_curve_precision_at_recall_0_to_1"] = std::move(curve);

  // Recall at the loosest threshold by the labels' distance, viewing angle and image appearance.
  std::vector<std::pair<double, bool>> by_distance, by_angle;
  std::map<std::string, std::vector<std::pair<double, bool>>> by_appearance;
  for (const auto& [id, m] : images) {
    const ScoreImage* image = dataset.images.count(id) ? &dataset.images.at(id) : nullptr;
    for (std::size_t g = 0; g < m.labels.size(); ++g) {
      const bool found = m.label_match[0][g] >= 0;
      if (m.labels[g]->distance_m) by_distance.emplace_back(*m.labels[g]->distance_m, found);
      if (m.labels[g]->viewing_angle_deg) {
        by_angle.emplace_back(*m.labels[g]->viewing_angle_deg, found);
      }
      if (image) {
        for (const auto& [key, value] : image->appearance)
          by_appearance[key].emplace_back(value, found);
      }
    }
  }
  j["recall_by_distance_m"] = BinnedRecall(by_distance, {0, 2, 4, 8}, {"0-2", "2-4", "4-8", "8+"});
  j["recall_by_viewing_angle_deg"] =
      BinnedRecall(by_angle, {0, 15, 30, 45, 60}, {"0-15", "15-30", "30-45", "45-60", "60+"});
  Json appearance = Json::object();
  for (const auto& [key, values] : by_appearance) {
    // Quartiles of the key over the dataset's images that carry it.
    std::vector<double> sorted;
    for (const auto& [id, image] : dataset.images) {
      if (image.appearance.count(key)) sorted.push_back(image.appearance.at(key));
    }
    std::sort(sorted.begin(), sorted.end());
    std::vector<double> edges = {sorted.front(), Percentile(sorted, 0.25), Percentile(sorted, 0.5),
                                 Percentile(sorted, 0.75)};
    std::vector<std::string> names;
    for (std::size_t b = 0; b < edges.size(); ++b) {
      names.push_back(FormatNumber(edges[b]) + "-" +
                      FormatNumber(b + 1 < edges.size() ? edges[b + 1] : sorted.back()));
    }
    appearance[key] = BinnedRecall(values, edges, names);
  }
  j["recall_by_appearance"] = std::move(appearance);
  return j;
}

}  // namespace

double IouThreshold(int k) { return 0.5 + static_cast<double>(k) * ((0.95 - 0.5) / 9.0); }
double CornerThresholdPx(int k) { return static_cast<double>(kThresholdCount - k); }

double CircleIou(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const double r1 = a[2], r2 = b[2];
  const double d = std::hypot(a[0] - b[0], a[1] - b[1]);
  const double area1 = std::numbers::pi * r1 * r1, area2 = std::numbers::pi * r2 * r2;
  double inter = 0.0;
  if (d >= r1 + r2) {
    inter = 0.0;
  } else if (d <= std::abs(r1 - r2)) {
    inter = std::min(area1, area2);
  } else {
    // The lens: two circular segments (the standard circle-circle intersection area).
    const double c1 = std::clamp((d * d + r1 * r1 - r2 * r2) / (2 * d * r1), -1.0, 1.0);
    const double c2 = std::clamp((d * d + r2 * r2 - r1 * r1) / (2 * d * r2), -1.0, 1.0);
    const double k = (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2);
    inter = r1 * r1 * std::acos(c1) + r2 * r2 * std::acos(c2) - 0.5 * std::sqrt(std::max(k, 0.0));
  }
  const double uni = area1 + area2 - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

nlohmann::ordered_json EvaluateDetections(const ScoreDataset& dataset,
                                          const std::vector<ScoreDetection>& detections) {
  Json classes;
  for (int c = 1; c <= kDatasetCategoryCount; ++c) {
    classes[DatasetCategoryName(c)] = EvaluateClass(dataset, detections, c);
  }
  return classes;
}

}  // namespace corridorsim
