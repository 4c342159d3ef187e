#pragma once
// What `corridorsim train-detectors` is asked to do (harness/cli/cli.h parses it; the job is
// harness/workbench/train_detectors.h). Plain data, so that the command-line parser needs no
// OpenCV.

#include <cstdint>
#include <filesystem>
#include <optional>

namespace corridorsim {

/// Which views train and evaluate the detectors: the command's flags and the first fields of
/// TrainDetectorsOptions (harness/workbench/train_detectors.h), which derives from it.
struct TrainingViews {
  std::uint64_t seed = 1;                              // --seed
  int train_worlds = 24;                               // --train-worlds, in [1, kMaxTrainWorlds]
  int eval_worlds = 8;                                 // --eval-worlds, in [1, kMaxTrainWorlds]
  int views_per_world = 48;                            // --views, in [1, kMaxViewsPerWorld]
  std::optional<std::filesystem::path> train_dataset;  // --dataset: train on this folder
  std::optional<std::filesystem::path> eval_dataset;   // --eval-dataset: evaluate on this one
};

struct TrainDetectorsRequest : TrainingViews {
  std::filesystem::path out_dir = "models";         // --out: the two model files
  std::optional<std::filesystem::path> report_dir;  // --report: staged like every output folder
  bool force = false;                               // --force: replace a non-empty --report
};

}  // namespace corridorsim
