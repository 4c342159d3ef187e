#include "harness/workbench/score.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <numeric>
#include <set>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/image.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "common/io/stable_json.h"
#include "harness/run/run_folder.h"
#include "harness/workbench/dataset.h"
#include "worlds/image_io.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

using Field = JsonField;

// A COCO box [x, y, w, h] intersects the image [0, width] x [0, height] (edges included).
bool Intersects(const std::array<double, 4>& b, const ScoreImage& image) {
  return b[0] <= image.width && b[0] + b[2] >= 0.0 && b[1] <= image.height && b[1] + b[3] >= 0.0;
}

std::array<double, 4> CircleBox(const std::array<double, 3>& c) {
  return {c[0] - c[2], c[1] - c[2], 2 * c[2], 2 * c[2]};
}

double BoxIou(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double w = std::min(a[0] + a[2], b[0] + b[2]) - std::max(a[0], b[0]);
  const double h = std::min(a[1] + a[3], b[1] + b[3]) - std::max(a[1], b[1]);
  if (w <= 0.0 || h <= 0.0) return 0.0;
  const double inter = w * h;
  const double uni = a[2] * a[3] + b[2] * b[3] - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

// ---- evaluation -------------------------------------------------------------------------------

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

std::string FormatNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", v);
  return buffer;
}

// N numbers of pixel geometry, each within +-kMaxScoreCoordinatePx.
template <std::size_t N>
std::array<double, N> Pixels(const Field& f) {
  const std::array<double, N> v = f.Numbers<N>();
  for (const double x : v) {
    if (std::abs(x) > kMaxScoreCoordinatePx) {
      f.Fail("a coordinate beyond +-" + FormatNumber(kMaxScoreCoordinatePx) + " px");
    }
  }
  return v;
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

// ---- score.png --------------------------------------------------------------------------------

void DrawBars(cv::Mat& img, const cv::Rect& area, const Json& bins, const std::string& title) {
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200), bar(180, 120, 40);
  cv::rectangle(img, area, grey, 1);
  cv::putText(img, title, {area.x + 4, area.y + 14}, cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1,
              cv::LINE_AA);
  const int n = static_cast<int>(bins.size());
  if (n == 0) return;
  const int plot_top = area.y + 22, plot_bottom = area.y + area.height - 18;
  const int slot = (area.width - 8) / n;
  for (int b = 0; b < n; ++b) {
    const Json& bin = bins[b];
    const int x = area.x + 4 + b * slot;
    if (!bin["recall"].is_null()) {
      const double r = bin["recall"].get<double>();
      const int top = plot_bottom - static_cast<int>(std::lround(r * (plot_bottom - plot_top)));
      cv::rectangle(img, cv::Rect(x + 2, top, std::max(slot - 4, 1), plot_bottom - top), bar,
                    cv::FILLED);
      char text[32];
      std::snprintf(text, sizeof(text), "%.2f", r);
      cv::putText(img, text, {x + 2, std::max(top - 2, plot_top + 8)}, cv::FONT_HERSHEY_SIMPLEX,
                  0.3, black, 1, cv::LINE_AA);
    }
    cv::putText(
        img, bin["bin"].get<std::string>() + " n" + std::to_string(bin["labels"].get<int>()),
        {x + 1, area.y + area.height - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.28, black, 1, cv::LINE_AA);
  }
}

std::string ScorePng(const Json& classes) {
  constexpr int kRow = 200, kPanel = 260;
  int panels = 3;
  for (const auto& [name, c] : classes.items()) {
    panels = std::max<int>(panels, 3 + static_cast<int>(c["recall_by_appearance"].size()));
  }
  const int rows = static_cast<int>(classes.size());
  cv::Mat img(std::max(rows, 1) * kRow, panels * kPanel, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200), line(40, 40, 200);
  int row = 0;
  for (const auto& [name, c] : classes.items()) {
    const int y0 = row * kRow;
    // Precision-recall at the loosest threshold.
    const cv::Rect pr(10, y0 + 24, kPanel - 40, kRow - 50);
    cv::rectangle(img, pr, grey, 1);
    char title[160];
    const auto text_of = [](const Json& v) {
      char buffer[16];
      if (v.is_null()) return std::string("-");
      std::snprintf(buffer, sizeof(buffer), "%.3f", v.get<double>());
      return std::string(buffer);
    };
    std::snprintf(title, sizeof(title), "%s  AP50 %s  AP %s", name.c_str(),
                  text_of(c["ap50"]).c_str(), text_of(c["ap"]).c_str());
    cv::putText(img, title, {10, y0 + 16}, cv::FONT_HERSHEY_SIMPLEX, 0.42, black, 1, cv::LINE_AA);
    const Json& curve = c["pr_curve_precision_at_recall_0_to_1"];
    std::vector<cv::Point> points;
    for (std::size_t r = 0; r < curve.size(); ++r) {
      points.emplace_back(
          pr.x + static_cast<int>(std::lround(static_cast<double>(r) / 100.0 * pr.width)),
          pr.y + pr.height - static_cast<int>(std::lround(curve[r].get<double>() * pr.height)));
    }
    if (points.size() > 1) cv::polylines(img, points, false, line, 2, cv::LINE_AA);
    cv::putText(img, "recall", {pr.x + pr.width - 40, pr.y + pr.height + 14},
                cv::FONT_HERSHEY_SIMPLEX, 0.35, black, 1, cv::LINE_AA);
    cv::putText(img, "precision", {pr.x + 2, pr.y + 10}, cv::FONT_HERSHEY_SIMPLEX, 0.35, black, 1,
                cv::LINE_AA);
    DrawBars(img, cv::Rect(kPanel + 5, y0 + 5, kPanel - 10, kRow - 10), c["recall_by_distance_m"],
             "recall by distance (m)");
    DrawBars(img, cv::Rect(2 * kPanel + 5, y0 + 5, kPanel - 10, kRow - 10),
             c["recall_by_viewing_angle_deg"], "recall by viewing angle (deg)");
    int panel = 3;
    for (const auto& [key, bins] : c["recall_by_appearance"].items()) {
      DrawBars(img, cv::Rect(panel * kPanel + 5, y0 + 5, kPanel - 10, kRow - 10), bins,
               "recall by " + key);
      ++panel;
    }
    ++row;
  }
  cv::cvtColor(img, img, cv::COLOR_BGR2RGB);
  Image8 out(img.cols, img.rows, 3);
  std::memcpy(out.data.data(), img.data, out.data.size());
  return EncodePng(out, "score.png");
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

ScoreDataset ParseScoreDataset(std::string_view text, const std::string& file) {
  const Json root = ParseJsonInput(text, file);
  if (!root.is_object()) FailInFile(file, "", "expected a COCO object");
  const Field top{file, "", root};
  ScoreDataset dataset;
  std::set<std::string> appearance_keys;
  const Field images = top.At("images");
  if (!images.value.is_array()) images.Fail("expected an array");
  for (std::size_t i = 0; i < images.value.size(); ++i) {
    const Field f{file, "images[" + std::to_string(i) + "]", images.value[i]};
    if (!f.value.is_object()) f.Fail("expected an object");
    ScoreImage image;
    image.id = f.At("id").Integer();
    for (const char* key : {"width", "height"}) {
      const std::int64_t side = f.At(key).Integer();
      if (side < 1 || side > kMaxScoreImageSide) {
        f.At(key).Fail("outside [1, " + std::to_string(kMaxScoreImageSide) + "] px");
      }
      (std::string(key) == "width" ? image.width : image.height) = static_cast<int>(side);
    }
    if (f.Has("appearance")) {
      const Field a = f.At("appearance");
      if (!a.value.is_object()) a.Fail("expected an object");
      for (const auto& [key, value] : a.value.items()) {
        if (value.is_number() && std::isfinite(value.get<double>())) {
          image.appearance[key] = value.get<double>();
          appearance_keys.insert(key);
          if (appearance_keys.size() > kMaxAppearanceKeys) {
            a.Fail("more than " + std::to_string(kMaxAppearanceKeys) +
                   " distinct appearance keys in the file");
          }
        }
      }
    }
    if (!dataset.images.emplace(image.id, image).second) f.At("id").Fail("a repeated image id");
  }
  const Field annotations = top.At("annotations");
  if (!annotations.value.is_array()) annotations.Fail("expected an array");
  for (std::size_t i = 0; i < annotations.value.size(); ++i) {
    const Field f{file, "annotations[" + std::to_string(i) + "]", annotations.value[i]};
    if (!f.value.is_object()) f.Fail("expected an object");
    ScoreLabel label;
    label.image_id = f.At("image_id").Integer();
    if (!dataset.images.count(label.image_id)) f.At("image_id").Fail("no image has this id");
    const std::int64_t category = f.At("category_id").Integer();
    if (category < 1 || category > kDatasetCategoryCount) {
      f.At("category_id").Fail("unknown category");
    }
    label.category_id = static_cast<int>(category);
    label.bbox = Pixels<4>(f.At("bbox"));
    if (label.bbox[2] < 0.0 || label.bbox[3] < 0.0) {
      f.At("bbox").Fail("a box with negative width or height");
    }
    if (f.Has("circle")) {
      label.circle = Pixels<3>(f.At("circle"));
      if ((*label.circle)[2] < 0.0) f.At("circle").Fail("a negative radius");
    }
    if (f.Has("keypoints")) {
      const auto k = Pixels<3>(f.At("keypoints"));
      label.point = std::array<double, 2>{k[0], k[1]};
    }
    if (label.category_id == kCategoryCeilingCorner && !label.point) {
      f.At("keypoints").Fail("missing");
    }
    if (f.Has("room_number")) label.room_number = f.At("room_number").String();
    if (f.Has("distance_m")) label.distance_m = f.At("distance_m").Number();
    if (f.Has("viewing_angle_deg")) label.viewing_angle_deg = f.At("viewing_angle_deg").Number();
    dataset.labels.push_back(std::move(label));
  }
  return dataset;
}

ScoreDataset ReadScoreDataset(const fs::path& dir, const std::optional<std::string>& camera) {
  const std::vector<std::string> ids = ReadDatasetManifest(dir).cameras;
  std::string list;
  for (const std::string& id : ids) list += (list.empty() ? "" : ", ") + id;
  std::string chosen;
  if (camera) {
    if (std::find(ids.begin(), ids.end(), *camera) == ids.end()) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--camera",
                       "'" + *camera + "' is not a camera of the dataset (" + list + ")");
    }
    chosen = *camera;
  } else if (ids.size() == 1) {
    chosen = ids[0];
  } else {
    throw InputError(SourceLocation{"command line", 0, 0}, "--camera",
                     "the dataset has cameras " + list + ": name the one the detections are for");
  }
  const fs::path annotations = dir / chosen / "annotations.json";
  ScoreDataset dataset = ParseScoreDataset(ReadRegularFile(annotations, kMaxAnnotationsFileBytes),
                                           annotations.string());
  dataset.camera = chosen;
  return dataset;
}

std::vector<ScoreDetection> ParseDetections(std::string_view text, const std::string& file,
                                            const ScoreDataset& dataset) {
  std::vector<ScoreDetection> detections;
  // Entry by entry: memory holds the detections, not the whole document.
  const auto each = [&](std::size_t i, const Json& entry) {
    if (i >= kMaxDetections) {
      FailInFile(file, "", "more than " + std::to_string(kMaxDetections) + " detections");
    }
    const Field f{file, "[" + std::to_string(i) + "]", entry};
    if (!f.value.is_object()) f.Fail("expected an object");
    ScoreDetection d;
    d.image_id = f.At("image_id").Integer();
    const auto image = dataset.images.find(d.image_id);
    if (image == dataset.images.end()) {
      f.At("image_id")
          .Fail("no image of the dataset's " + dataset.camera + " camera has id " +
                std::to_string(d.image_id));
    }
    const std::int64_t category = f.At("category_id").Integer();
    if (category < 1 || category > kDatasetCategoryCount) {
      f.At("category_id")
          .Fail("unknown category " + std::to_string(category) +
                " (1 door_plate, 2 door, 3 lamp, 4 ceiling_corner)");
    }
    d.category_id = static_cast<int>(category);
    d.score = f.At("score").Number();
    if (f.Has("bbox")) {
      const Field b = f.At("bbox");
      d.bbox = Pixels<4>(b);
      if ((*d.bbox)[2] < 0.0 || (*d.bbox)[3] < 0.0) b.Fail("a box with negative width or height");
      if (!Intersects(*d.bbox, image->second)) b.Fail("the box lies outside the image");
    }
    if (f.Has("circle")) {
      const Field c = f.At("circle");
      if (d.category_id != kCategoryLamp) c.Fail("only lamps (category 3) may give a circle");
      d.circle = Pixels<3>(c);
      if ((*d.circle)[2] < 0.0) c.Fail("a negative radius");
      if (!Intersects(CircleBox(*d.circle), image->second)) {
        c.Fail("the circle lies outside the image");
      }
    }
    for (const char* key : {"point", "keypoints"}) {
      if (!f.Has(key)) continue;
      const Field p = f.At(key);
      if (d.category_id != kCategoryCeilingCorner) {
        p.Fail("only ceiling corners (category 4) may give a point");
      }
      if (d.point) p.Fail("a second point (give `point` or `keypoints`, not both)");
      if (std::string(key) == "point") {
        d.point = Pixels<2>(p);
      } else {
        const auto k = Pixels<3>(p);
        d.point = std::array<double, 2>{k[0], k[1]};
      }
      if (!Intersects({(*d.point)[0], (*d.point)[1], 0.0, 0.0}, image->second)) {
        p.Fail("the point lies outside the image");
      }
    }
    if (!d.bbox && !d.circle && !d.point) {
      FailInFile(file, f.path + ".bbox",
                 d.category_id == kCategoryLamp ? "missing (a lamp gives `bbox` or `circle`)"
                 : d.category_id == kCategoryCeilingCorner
                     ? "missing (a corner gives `bbox`, `point` or `keypoints`)"
                     : "missing");
    }
    if (f.Has("room_number")) d.room_number = f.At("room_number").String();
    detections.push_back(std::move(d));
  };
  ParseJsonArrayInput(text, file, "expected a JSON array of detections (COCO results format)",
                      each);
  return detections;
}

nlohmann::ordered_json EvaluateDetections(const ScoreDataset& dataset,
                                          const std::vector<ScoreDetection>& detections) {
  Json classes;
  for (int c = 1; c <= kDatasetCategoryCount; ++c) {
    classes[DatasetCategoryName(c)] = EvaluateClass(dataset, detections, c);
  }
  return classes;
}

ScoreExpectationResult CheckScoreExpectation(const nlohmann::ordered_json& evaluation,
                                             const ScoreExpectation& e) {
  ScoreExpectationResult result;
  const Json& c = evaluation.at(e.class_name);
  if (!c.contains(e.metric) || c[e.metric].is_null()) return result;
  const double v = c[e.metric].get<double>();
  result.value = v;
  switch (e.op) {
    case ScoreExpectation::Op::kGreaterEqual:
      result.passed = v >= e.value;
      break;
    case ScoreExpectation::Op::kGreater:
      result.passed = v > e.value;
      break;
    case ScoreExpectation::Op::kLessEqual:
      result.passed = v <= e.value;
      break;
    case ScoreExpectation::Op::kLess:
      result.passed = v < e.value;
      break;
  }
  return result;
}

int RunScore(const ScoreRequest& request) {
  const ScoreDataset dataset = ReadScoreDataset(request.dataset_dir, request.camera);
  const std::string file = request.detections_file.string();
  const std::vector<ScoreDetection> detections = ParseDetections(
      ReadRegularFile(request.detections_file, kMaxDetectionsFileBytes), file, dataset);
  // Checked before anything is computed or written: a refused folder is bad input.
  std::unique_ptr<StagedDirectory> folder;
  if (request.report_dir) {
    folder = StageOutputFolder(*request.report_dir, "--out", request.force,
                               {{request.detections_file, "the detections file"},
                                {request.dataset_dir, "the --dataset folder"}});
  }

  const Json classes = EvaluateDetections(dataset, detections);
  Json report;
  report["detections_file"] = request.detections_file.filename().string();
  report["camera"] = dataset.camera;
  report["images"] = dataset.images.size();
  report["labels"] = dataset.labels.size();
  report["detections"] = detections.size();
  Json thresholds = Json::array(), corner_thresholds = Json::array();
  for (int t = 0; t < kThresholdCount; ++t) {
    thresholds.push_back(RoundToStep(IouThreshold(t), json_steps::kRatio));
    corner_thresholds.push_back(CornerThresholdPx(t));
  }
  report["evaluation"] = {{"method",
                           "pycocotools COCOeval (areaRng all, maxDets 100, 101 recall "
                           "points); lamps with circles: exact circle IoU"},
                          {"iou_thresholds", thresholds},
                          {"corner_thresholds_px", corner_thresholds},
                          {"max_detections_per_image", kMaxDetectionsPerImage}};
  report["classes"] = classes;

  // The table.
  const auto cell = [](const Json& v) {
    char buffer[32];
    if (v.is_null()) return std::string("     -");
    std::snprintf(buffer, sizeof(buffer), "%6.3f", v.get<double>());
    return std::string(buffer);
  };
  std::printf("score: %zu detections on %zu images of camera %s\n", detections.size(),
              dataset.images.size(), dataset.camera.c_str());
  std::printf("%-15s %7s %7s %6s %6s %6s %6s %6s %7s\n", "class", "labels", "dets", "prec",
              "recall", "AP50", "AP", "loc_px", "reading");
  for (const auto& [name, c] : classes.items()) {
    std::printf("%-15s %7lld %7lld %s %s %s %s %s %s\n", name.c_str(),
                static_cast<long long>(c["labels"].get<std::int64_t>()),
                static_cast<long long>(c["detections"].get<std::int64_t>()),
                cell(c["precision"]).c_str(), cell(c["recall"]).c_str(), cell(c["ap50"]).c_str(),
                cell(c["ap"]).c_str(), cell(c["loc_error_px"]).c_str(),
                c.contains("reading_accuracy") ? cell(c["reading_accuracy"]).c_str() : "     -");
  }

  bool all_passed = true;
  Json checks = Json::array();
  for (const ScoreExpectation& e : request.expectations) {
    const ScoreExpectationResult r = CheckScoreExpectation(classes, e);
    all_passed = all_passed && r.passed;
    checks.push_back({{"expect", e.text},
                      {"value", r.value ? Json(*r.value) : Json(nullptr)},
                      {"passed", r.passed}});
    std::printf("expect %-30s %s  %s\n", e.text.c_str(),
                r.value ? cell(Json(*r.value)).c_str() : "undefined", r.passed ? "ok" : "FAILED");
  }
  report["expectations"] = std::move(checks);

  if (folder) {
    WriteFileAtomic(folder->path() / "score.json", JsonFileText(report));
    WriteFileAtomic(folder->path() / "score.png", ScorePng(classes));
    folder->Commit();
    std::printf("wrote %s/{score.json, score.png}\n", folder->path().string().c_str());
  }
  if (!all_passed) {
    for (const ScoreExpectation& e : request.expectations) {
      if (!CheckScoreExpectation(classes, e).passed) {
        std::fprintf(stderr, "corridorsim: score: expectation failed: %s\n", e.text.c_str());
      }
    }
    return 3;
  }
  return 0;
}

}  // namespace corridorsim
