#pragma once
// `corridorsim score`: detections in COCO results format, from any program, matched against a
// dataset's COCO annotations (`corridorsim dataset`, docs/datasets.md) class by class, with
// COCO's evaluation (pycocotools COCOeval.evaluate / accumulate: greedy matching by descending
// score, 101-point interpolated AP over IoU 0.50:0.05:0.95), plus what a detector developer
// needs beside it: precision and recall at the best-F1 threshold, localisation error, the plates'
// reading accuracy, and recall by distance, viewing angle and appearance.
//
// The input read and checked: score_input.cpp; the evaluation: score_evaluation.cpp; the job and
// its report: score.cpp.

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/workbench/score_request.h"

namespace corridorsim {

/// Bounds of a detections file (read entry by entry: memory holds the text and the entries).
inline constexpr std::size_t kMaxDetections = 2'000'000;
inline constexpr std::uint64_t kMaxDetectionsFileBytes = std::uint64_t{256} << 20;  // 256 MiB
/// Bounds of a camera's annotations.json (parsed whole, at most kMaxJsonValues values).
inline constexpr std::uint64_t kMaxAnnotationsFileBytes = std::uint64_t{256} << 20;  // 256 MiB
/// Every coordinate, size and radius of a detection or label (pixels) lies in [-1e6, 1e6], and an
/// image's width and height in [1, kMaxScoreImageSide]: areas and distances stay finite.
inline constexpr double kMaxScoreCoordinatePx = 1e6;
inline constexpr int kMaxScoreImageSide = 65536;
/// Distinct keys of the images' `appearance` objects (score.png draws a panel per key).
inline constexpr std::size_t kMaxAppearanceKeys = 32;
/// pycocotools' maxDets: the best-scored detections kept per image and class.
inline constexpr int kMaxDetectionsPerImage = 100;
/// Matching thresholds, loosest first: IoU for boxes and circles, pixel distance for corners
/// (corner threshold k stands in for IoU threshold k).
inline constexpr int kThresholdCount = 10;
double IouThreshold(int k);       // 0.50, 0.55, ..., 0.95 (np.linspace(.5, .95, 10))
double CornerThresholdPx(int k);  // 10, 9, ..., 1 px

/// The image of a dataset camera, as annotations.json lists it.
struct ScoreImage {
  std::int64_t id = 0;
  int width = 0;
  int height = 0;
  std::map<std::string, double> appearance;  // numeric keys of the image's `appearance` object
};

/// A label: one annotation of the dataset (COCO pixels: (0, 0) is the top-left pixel's corner).
struct ScoreLabel {
  std::int64_t image_id = 0;
  int category_id = 0;
  std::array<double, 4> bbox{};                 // x, y, w, h
  std::optional<std::array<double, 3>> circle;  // lamps: cx, cy, r
  std::optional<std::array<double, 2>> point;   // corners: the keypoint
  std::string room_number;                      // plates
  std::optional<double> distance_m;
  std::optional<double> viewing_angle_deg;
};

struct ScoreDataset {
  std::string camera;
  std::map<std::int64_t, ScoreImage> images;
  std::vector<ScoreLabel> labels;  // in the file's order
};

/// One detection of a results file.
struct ScoreDetection {
  std::int64_t image_id = 0;
  int category_id = 0;
  double score = 0.0;
  std::optional<std::array<double, 4>> bbox;    // x, y, w, h
  std::optional<std::array<double, 3>> circle;  // cx, cy, r (lamps)
  std::optional<std::array<double, 2>> point;   // x, y (corners: `point` or `keypoints`)
  std::optional<std::string> room_number;       // plates
};

/// Parses a camera's annotations.json (`file` names it in messages). Throws InputError naming the
/// file and field.
ScoreDataset ParseScoreDataset(std::string_view text, const std::string& file);
/// DIR/<camera>/annotations.json; the camera defaults to the one of DIR/dataset.json when it has
/// one. Throws InputError for a missing or malformed folder or file, or an unknown camera.
ScoreDataset ReadScoreDataset(const std::filesystem::path& dir,
                              const std::optional<std::string>& camera);

/// Parses and checks a COCO results file against the dataset (docs/datasets.md): throws
/// InputError as `file: [index].field: problem` (or `file: problem` for the whole file).
std::vector<ScoreDetection> ParseDetections(std::string_view text, const std::string& file,
                                            const ScoreDataset& dataset);

/// IoU of two circles (cx, cy, r): the exact lens area over the union.
double CircleIou(const std::array<double, 3>& a, const std::array<double, 3>& b);

/// The evaluation of every class (score.json's content without the file names): per class
/// labels, detections, precision, recall, f1, score_threshold, ap50, ap, loc_error_px,
/// reading_accuracy (plates), the interpolated PR curve at the loosest threshold and the binned
/// recall. Undefined values are null.
nlohmann::ordered_json EvaluateDetections(const ScoreDataset& dataset,
                                          const std::vector<ScoreDetection>& detections);

/// The value of `expectation` in `evaluation` and whether it holds (null values fail).
struct ScoreExpectationResult {
  std::optional<double> value;
  bool passed = false;
};
ScoreExpectationResult CheckScoreExpectation(const nlohmann::ordered_json& evaluation,
                                             const ScoreExpectation& expectation);

/// Runs the job: returns 0, or 3 when an --expect failed. Throws InputError for bad input.
int RunScore(const ScoreRequest& request);

}  // namespace corridorsim
