#include "harness/workbench/score.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/image.h"
#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "harness/run/run_folder.h"
#include "worlds/image_io.h"

// `score`'s job (score.h: RunScore): the input read (score_input.cpp), the evaluation
// (score_evaluation.cpp), the table on stdout, the --expect checks (exit 3 when one fails) and the
// report folder: score.json and score.png (a row per class: the PR curve and the recall bars).

namespace corridorsim {
namespace {

using Json = nlohmann::ordered_json;

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
