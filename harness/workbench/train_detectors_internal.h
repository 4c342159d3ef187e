#pragma once
// What train-detectors' files share (train_detectors.cpp: the training and the command;
// train_detectors_views.cpp: the labelled views, rendered or read from dataset folders;
// train_detectors_evaluation.cpp: the held-out evaluation and its report): a labelled view, how
// a candidate is matched to a plate, and the evaluation's counters. Internal to
// harness/workbench/.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/image.h"
#include "common/io/stable_json.h"
#include "harness/workbench/train_detectors.h"
#include "render/frame_truth.h"
#include "slam/features/door_plates.h"

namespace corridorsim::train_detectors_internal {

// Report binning (P1 reads plates within 3 m and 30 deg).
inline constexpr std::array<double, 5> kDistanceEdges{0.0, 1.0, 2.0, 3.0, 4.0};
inline constexpr std::array<double, 6> kAngleEdges{0.0, 10.0, 20.0, 30.0, 45.0, 60.0};
inline constexpr double kMatchIou = 0.5;  // a candidate is the plate's number region (brief, P1)

inline slam::BoxPx NumberBox(const render::PlateTruth& p) {
  return slam::BoxPx{p.number_bbox_min_px.x(), p.number_bbox_min_px.y(), p.number_bbox_max_px.x(),
                     p.number_bbox_max_px.y()};
}

using Json = nlohmann::ordered_json;

// A labelled lateral view: the image and the door plates its truth file lists.
struct LabelledView {
  Image8 rgb;
  std::vector<render::PlateTruth> plates;
};
using PlateFonts = std::map<int, std::string>;  // plate id -> font, of one world

inline std::string FontOf(const PlateFonts& fonts, int id) {
  const auto it = fonts.find(id);
  return it == fonts.end() ? std::string() : it->second;
}

inline bool HeldOut(const TrainDetectorsOptions& o, const std::string& font) {
  return std::find(o.held_out_fonts.begin(), o.held_out_fonts.end(), font) !=
         o.held_out_fonts.end();
}

inline double Ratio(int a, int b) {
  return b > 0 ? RoundToStep(double(a) / b, json_steps::kRatio) : 0.0;
}

// The labelled views of one set (training or evaluation), world by world.
class ViewSet {
 public:
  virtual ~ViewSet() = default;
  virtual int worlds() const = 0;
  virtual std::uint64_t world_seed(int w) const = 0;
  /// Calls `each` with world w's views in frame order and the world's plate fonts.
  virtual void ForEachView(
      int w, const std::function<void(const LabelledView&, const PlateFonts&)>& each) const = 0;
  virtual Json Source() const = 0;
};

/// The views of the dataset folder `dataset` (refused at `option` when it does not fit), or
/// without one the built-in views: `worlds` worlds from `first_seed`, `views` each.
std::unique_ptr<ViewSet> MakeViewSet(const std::optional<std::filesystem::path>& dataset,
                                     const char* option, std::uint64_t first_seed, int worlds,
                                     int views);

// Counters of one bin of the evaluation.
struct Counts {
  int plates = 0, detected = 0, read = 0;
  nlohmann::ordered_json Json() const {
    return {{"plates", plates},
            {"detected", detected},
            {"read_correctly", read},
            {"recall", Ratio(detected, plates)},
            {"reading_accuracy", Ratio(read, plates)}};
  }
};

struct Evaluation {
  std::array<Counts, kDistanceEdges.size() - 1> by_distance;
  std::array<Counts, kAngleEdges.size() - 1> by_angle;
  Counts target, target_held_out;
  int views = 0, detections = 0, true_detections = 0, accepted = 0, false_accepted = 0;
  int plates_seen = 0, plates_detected = 0;
  std::array<std::array<int, 10>, 10> confusion{};  // [true][read]
  double correct_score_min = 1.0, wrong_score_max = 0.0;
  int digits_correct = 0, digits_wrong = 0;
};

/// Runs the models on one held-out view and adds what they found to `e`.
void EvaluateView(const LabelledView& view, const PlateFonts& fonts,
                  const slam::DoorPlateModels& models, const TrainDetectorsOptions& o,
                  Evaluation* e);
/// training_report.json's `evaluation`.
nlohmann::ordered_json EvaluationJson(const Evaluation& e);
/// training_report.png.
Image8 DrawReport(const Evaluation& e);

}  // namespace corridorsim::train_detectors_internal
