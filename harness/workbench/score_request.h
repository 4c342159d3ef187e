#pragma once
// What `corridorsim score` is asked for (harness/workbench/score.h runs it): plain data, so that
// the command-line parser (harness/cli/cli.h) needs nothing else of the job.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace corridorsim {

/// The classes and per-class metrics `--expect` may name (docs/datasets.md): class names are
/// the dataset's category names, in the order of their ids (harness/workbench/dataset.h;
/// DatasetCategoryName reads them from here).
inline constexpr const char* kScoreClassNames[] = {"door_plate", "door", "lamp", "ceiling_corner"};
inline constexpr const char* kScoreMetricNames[] = {
    "labels",          "detections", "precision", "recall",       "f1",
    "score_threshold", "ap50",       "ap",        "loc_error_px", "reading_accuracy"};

/// `--expect door_plate.recall>=0.5`: a class metric compared with a number.
struct ScoreExpectation {
  enum class Op { kGreaterEqual, kGreater, kLessEqual, kLess };
  std::string text;  // as given, for the report
  std::string class_name;
  std::string metric;
  Op op = Op::kGreaterEqual;
  double value = 0.0;
};

struct ScoreRequest {
  std::filesystem::path detections_file;            // DETECTIONS.json (COCO results)
  std::filesystem::path dataset_dir;                // --dataset
  std::optional<std::string> camera;                // --camera; default: the dataset's only one
  std::optional<std::filesystem::path> report_dir;  // --out: score.json and score.png
  bool force = false;                               // --force: replace a non-empty --out
  std::vector<ScoreExpectation> expectations;       // --expect
};

}  // namespace corridorsim
