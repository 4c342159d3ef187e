#include "harness/workbench/train_detectors_internal.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/io/stable_json.h"

// train-detectors' held-out evaluation (EvaluateView) and its report: training_report.json's
// `evaluation` (read within 3 m and 30 deg, false readings, by distance and viewing angle, the
// digits) and training_report.png (the bars and the digit confusion matrix).

namespace corridorsim::train_detectors_internal {
namespace {

constexpr double kTargetDistanceM = 3.0;
constexpr double kTargetAngleDeg = 30.0;
constexpr double kTargetReadFraction = 0.98;
constexpr double kTargetFalseFraction = 0.005;
constexpr double kSeenFraction = 0.95;  // a plate counts as seen: whole and unoccluded

// The part of a box inside the image, [0, width] x [0, height] (as detections' boxes lie).
slam::BoxPx InImage(const slam::BoxPx& b, const Image8& image) {
  return slam::BoxPx{std::max(b.min_x, 0.0), std::max(b.min_y, 0.0),
                     std::min(b.max_x, double(image.width)),
                     std::min(b.max_y, double(image.height))};
}
// The fraction of b's area that a covers.
double Coverage(const slam::BoxPx& a, const slam::BoxPx& b) {
  const double ix = std::min(a.max_x, b.max_x) - std::max(a.min_x, b.min_x);
  const double iy = std::min(a.max_y, b.max_y) - std::max(a.min_y, b.min_y);
  const double area = b.width() * b.height();
  return ix > 0 && iy > 0 && area > 0 ? ix * iy / area : 0.0;
}
bool Seen(const render::PlateTruth& p) {
  return p.fully_in_image && p.visible_fraction >= kSeenFraction;
}

// The Wilson score 95 % interval of a proportion k / n: what a held-out figure from a hundred
// plates can claim (one plate moves 127 plates' figure by 0.8 points). [0, 1] when n = 0.
nlohmann::ordered_json WilsonInterval(int k, int n) {
  if (n <= 0) return nlohmann::ordered_json::array({0.0, 1.0});
  constexpr double z = 1.959963984540054;
  const double p = double(k) / n, z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4 * n)) / (1 + z2n);
  return nlohmann::ordered_json::array(
      {RoundToStep(std::max(0.0, centre - half), json_steps::kRatio),
       RoundToStep(std::min(1.0, centre + half), json_steps::kRatio)});
}

int Bin(double v, const double* edges, std::size_t n) {
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (v < edges[k + 1]) return static_cast<int>(k);
  }
  return static_cast<int>(n) - 2;  // the last bin takes what lies beyond
}

// Each bin's counters with its edges, `min_<unit>` and `max_<unit>`.
template <std::size_t N>
nlohmann::ordered_json BinsJson(const std::array<Counts, N>& bins,
                                const std::array<double, N + 1>& edges, const std::string& unit) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < N; ++k) {
    nlohmann::ordered_json b = bins[k].Json();
    b["min_" + unit] = edges[k];
    b["max_" + unit] = edges[k + 1];
    out.push_back(b);
  }
  return out;
}

}  // namespace

void EvaluateView(const LabelledView& view, const PlateFonts& fonts,
                  const slam::DoorPlateModels& models, const TrainDetectorsOptions& o,
                  Evaluation* e) {
  ++e->views;
  const std::vector<slam::DoorPlateDetection> detections =
      slam::DetectDoorPlates(view.rgb, models, o.detection);
  // Detections against number regions: the best-overlapping plate of each. A region the image
  // border cuts is matched by its part inside the image, where a detection can lie (a number
  // read whole beside the border is not a false reading).
  std::vector<int> plate_of(detections.size(), -1);
  for (std::size_t i = 0; i < detections.size(); ++i) {
    double best = 0.0;
    for (std::size_t k = 0; k < view.plates.size(); ++k) {
      const double iou = slam::IntersectionOverUnion(detections[i].box_px,
                                                     InImage(NumberBox(view.plates[k]), view.rgb));
      if (iou >= kMatchIou && iou > best) {
        best = iou;
        plate_of[i] = static_cast<int>(k);
      }
    }
    ++e->detections;
    e->true_detections += plate_of[i] >= 0;
    const slam::RoomNumberReading& r = detections[i].reading;
    if (r.accepted) {
      // A false reading is a wrong number accepted: right when it is the number of a plate whose
      // number region (inside the image) the detection covers at least half of, also when the
      // box holds more than the number (a plate's frame beside the image border).
      ++e->accepted;
      bool right = false;
      for (const render::PlateTruth& p : view.plates) {
        right = right || (r.number == p.room_number &&
                          Coverage(detections[i].box_px, InImage(NumberBox(p), view.rgb)) >= 0.5);
      }
      e->false_accepted += !right;
    }
  }
  for (std::size_t k = 0; k < view.plates.size(); ++k) {
    const render::PlateTruth& p = view.plates[k];
    if (!Seen(p)) continue;
    ++e->plates_seen;
    // The plate's detection: the highest-scoring one matched to it.
    const slam::DoorPlateDetection* best = nullptr;
    for (std::size_t i = 0; i < detections.size(); ++i) {
      if (plate_of[i] == int(k) && (!best || detections[i].svm_score > best->svm_score)) {
        best = &detections[i];
      }
    }
    const bool detected = best != nullptr;
    const bool read = detected && best->reading.accepted && best->reading.number == p.room_number;
    e->plates_detected += detected;
    const auto add = [&](Counts& c) {
      ++c.plates;
      c.detected += detected;
      c.read += read;
    };
    add(e->by_distance[std::size_t(
        Bin(p.distance_m, kDistanceEdges.data(), kDistanceEdges.size()))]);
    add(e->by_angle[std::size_t(Bin(p.viewing_angle_deg, kAngleEdges.data(), kAngleEdges.size()))]);
    if (p.distance_m <= kTargetDistanceM && p.viewing_angle_deg <= kTargetAngleDeg) {
      add(e->target);
      if (HeldOut(o, FontOf(fonts, p.id))) add(e->target_held_out);
    }
    if (detected && best->reading.digits.size() == p.room_number.size()) {
      for (std::size_t i = 0; i < p.room_number.size(); ++i) {
        const slam::DigitReading& d = best->reading.digits[i];
        const int truth = p.room_number[i] - '0', got = d.digit - '0';
        if (truth < 0 || truth > 9 || got < 0 || got > 9) continue;
        ++e->confusion[std::size_t(truth)][std::size_t(got)];
        if (truth == got) {
          ++e->digits_correct;
          e->correct_score_min = std::min(e->correct_score_min, d.score);
        } else {
          ++e->digits_wrong;
          e->wrong_score_max = std::max(e->wrong_score_max, d.score);
        }
      }
    }
  }
}

nlohmann::ordered_json EvaluationJson(const Evaluation& e) {
  nlohmann::ordered_json j;
  j["views"] = e.views;
  j["plates_seen"] = e.plates_seen;
  j["detection"] = {{"detections", e.detections},
                    {"true", e.true_detections},
                    {"precision", Ratio(e.true_detections, e.detections)},
                    {"recall", Ratio(e.plates_detected, e.plates_seen)}};
  nlohmann::ordered_json target = e.target.Json();
  target["max_distance_m"] = kTargetDistanceM;
  target["max_viewing_angle_deg"] = kTargetAngleDeg;
  target["required"] = kTargetReadFraction;
  target["reading_accuracy_ci95"] = WilsonInterval(e.target.read, e.target.plates);
  target["met"] =
      e.target.plates > 0 && double(e.target.read) >= kTargetReadFraction * e.target.plates;
  j["read_within_3m_30deg"] = target;
  j["read_within_3m_30deg_held_out_fonts"] = e.target_held_out.Json();
  j["false_readings"] = {
      {"accepted", e.accepted},
      {"false", e.false_accepted},
      {"fraction", Ratio(e.false_accepted, e.accepted)},
      {"fraction_ci95", WilsonInterval(e.false_accepted, e.accepted)},
      {"required_below", kTargetFalseFraction},
      {"met", e.accepted > 0 && double(e.false_accepted) < kTargetFalseFraction * e.accepted}};
  j["by_distance"] = BinsJson(e.by_distance, kDistanceEdges, "m");
  j["by_viewing_angle"] = BinsJson(e.by_angle, kAngleEdges, "deg");
  j["digits"] = {{"correct", e.digits_correct},
                 {"wrong", e.digits_wrong},
                 {"correct_score_min", RoundToStep(e.correct_score_min, json_steps::kRatio)},
                 {"wrong_score_max", RoundToStep(e.wrong_score_max, json_steps::kRatio)}};
  j["digit_confusion_rows_true_cols_read"] = nlohmann::ordered_json::array();
  for (const auto& row : e.confusion) j["digit_confusion_rows_true_cols_read"].push_back(row);
  return j;
}

// training_report.png: reading accuracy and recall by distance and by viewing angle (bars),
// and the digit confusion matrix.
Image8 DrawReport(const Evaluation& e) {
  const int w = 1200, h = 480;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto text = [&](const std::string& s, int x, int y, double scale = 0.45) {
    cv::putText(img, s, {x, y}, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  };
  const auto bars = [&](int x0, const std::string& title, const std::vector<std::string>& labels,
                        const std::vector<const Counts*>& bins) {
    const int top = 60, bottom = 400, width = 360;
    text(title, x0, 30, 0.55);
    cv::rectangle(img, {x0, top}, {x0 + width, bottom}, cv::Scalar(0, 0, 0), 1);
    for (int f : {0, 50, 90, 100}) {
      const int y = bottom - (bottom - top) * f / 100;
      cv::line(img, {x0, y}, {x0 + width, y}, cv::Scalar(200, 200, 200), 1);
      text(std::to_string(f) + "%", x0 - 38, y + 4, 0.35);
    }
    const int n = static_cast<int>(bins.size());
    const int slot = width / n;
    for (int k = 0; k < n; ++k) {
      const Counts& c = *bins[std::size_t(k)];
      const double recall = c.plates ? double(c.detected) / c.plates : 0;
      const double read = c.plates ? double(c.read) / c.plates : 0;
      const int xa = x0 + k * slot + 6, bw = (slot - 12) / 2;
      cv::rectangle(img, {xa, bottom - int((bottom - top) * recall)}, {xa + bw, bottom},
                    cv::Scalar(60, 120, 220), cv::FILLED);
      cv::rectangle(img, {xa + bw, bottom - int((bottom - top) * read)}, {xa + 2 * bw, bottom},
                    cv::Scalar(40, 160, 60), cv::FILLED);
      text(labels[std::size_t(k)], xa, bottom + 18, 0.38);
      text("n=" + std::to_string(c.plates), xa, bottom + 34, 0.35);
    }
  };
  std::vector<std::string> dl, al;
  std::vector<const Counts*> db, ab;
  for (std::size_t k = 0; k < e.by_distance.size(); ++k) {
    char s[32];
    std::snprintf(s, sizeof s, "%.0f-%.0fm", kDistanceEdges[k], kDistanceEdges[k + 1]);
    dl.push_back(s);
    db.push_back(&e.by_distance[k]);
  }
  for (std::size_t k = 0; k < e.by_angle.size(); ++k) {
    char s[32];
    std::snprintf(s, sizeof s, "%.0f-%.0f", kAngleEdges[k], kAngleEdges[k + 1]);
    al.push_back(s);
    ab.push_back(&e.by_angle[k]);
  }
  bars(50, "by distance", dl, db);
  text("blue: detected, green: read correctly (held-out worlds, seen plates)", 50, 465, 0.45);
  bars(460, "by viewing angle (deg)", al, ab);
  // Confusion matrix: rows true digit, columns read digit; shade by row fraction.
  const int cx = 880, cy = 60, cell = 30;
  text("digit confusion (rows true, cols read)", cx - 20, 30, 0.5);
  for (int t = 0; t < 10; ++t) {
    int row = 0;
    for (int r = 0; r < 10; ++r) row += e.confusion[std::size_t(t)][std::size_t(r)];
    text(std::to_string(t), cx - 16, cy + t * cell + 20);
    text(std::to_string(t), cx + t * cell + 10, cy - 6);
    for (int r = 0; r < 10; ++r) {
      const int v = e.confusion[std::size_t(t)][std::size_t(r)];
      const double f = row ? double(v) / row : 0.0;
      const int shade = 255 - int(200 * f);
      cv::rectangle(img, {cx + r * cell, cy + t * cell}, {cx + (r + 1) * cell, cy + (t + 1) * cell},
                    t == r ? cv::Scalar(shade, 255, shade) : cv::Scalar(255, shade, shade),
                    cv::FILLED);
      cv::rectangle(img, {cx + r * cell, cy + t * cell}, {cx + (r + 1) * cell, cy + (t + 1) * cell},
                    cv::Scalar(180, 180, 180), 1);
      if (v > 0) text(std::to_string(v), cx + r * cell + 2, cy + t * cell + 19, 0.32);
    }
  }
  Image8 out(w, h, 3);
  for (int y = 0; y < h; ++y) std::memcpy(out.Pixel(0, y), img.ptr(y), std::size_t(w) * 3);
  return out;
}

}  // namespace corridorsim::train_detectors_internal
