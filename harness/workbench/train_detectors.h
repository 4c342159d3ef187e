#pragma once
// `corridorsim train-detectors`: trains P1's door-plate SVM and room-number MLP (slam/features/)
// on labelled lateral-camera views, evaluates both on held-out worlds and plate fonts, and writes
// the models and a training report (docs/detectors.md).
//
// The views come through `corridorsim dataset` (harness/workbench/dataset.h): by default rendered
// in memory by its generator from the built-in scenario (TrainingScenario, --poses plates), or read
// from dataset folders (--dataset, --eval-dataset). Either way the labels are the truth files'
// JSON, so training on a folder `dataset` wrote gives the models the in-memory path gives.
//
// Every random choice is seeded from `seed` (world seeds, poses, subsampling, OpenCV's RNG, the
// MLP's initial weights), OpenCV runs on one thread while training, so the same request writes
// byte-identical model files.
//
// The training and the command: train_detectors.cpp; the views: train_detectors_views.cpp; the
// held-out evaluation and its report: train_detectors_evaluation.cpp.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/image.h"
#include "harness/scenario/scenario.h"
#include "harness/workbench/train_detectors_request.h"
#include "slam/features/door_plates.h"

namespace corridorsim {

// From TrainingViews (train_detectors_request.h): seed; train_worlds, the built-in training
// worlds (seeds TrainingFirstWorldSeed(seed) + w); eval_worlds, the built-in held-out worlds (the
// seeds after the training ones); views_per_world, lateral views per built-in world; and
// train_dataset and eval_dataset, `corridorsim dataset` folders (with the lateral camera) used
// instead of the built-in training or evaluation set (their world seeds must not overlap).
struct TrainDetectorsOptions : TrainingViews {
  // Plates drawn in these fonts are left out of training (neither positives nor negatives, no
  // digits) and evaluated apart: the held-out-font figures of the report.
  std::vector<std::string> held_out_fonts{"hershey_triplex"};
  int max_negatives_per_view = 12;
  double svm_c = 0.05;               // C of the linear SVM
  int mlp_hidden = 48;               // hidden units of the MLP
  int mlp_iterations = 1000;         // RPROP iterations at most
  slam::DoorPlateOptions detection;  // what the models are trained for and evaluated with
};

/// The scenario the built-in views are rendered from; scenarios/datasets/train_detectors.yaml is
/// the same scenario as a file (a test keeps the two equal): the default corridor (plates, posters,
/// notice boards) and only the lateral camera, 640x480, 60 deg, level on a mast at (0, 0.12, 1.5) m
/// facing left (yaw 90 deg, pitch 0), with the rig's default noise.
Scenario TrainingScenario();

/// Seed of the first built-in training world for `seed`: a 48-bit number drawn from it, so that
/// the worlds of scenarios (small seeds) are not trained on. Training worlds are first + w,
/// evaluation worlds follow them.
std::uint64_t TrainingFirstWorldSeed(std::uint64_t seed);

struct TrainingResult {
  slam::DoorPlateModels models;
  std::string svm_bytes;  // the model files as written (cv::FileStorage YAML)
  std::string mlp_bytes;
  nlohmann::ordered_json report;  // training_report.json
  Image8 report_image;            // training_report.png
};

/// A linear SVM's model file without its uncompressed support vectors: cv::ml::SVM writes them
/// beside the one compressed weight vector that prediction uses (for C_SVC with a linear kernel),
/// and they are most of the file (443 vectors of 3780 features: 28 MB instead of 0.1 MB).
/// cv::ml::SVM::read treats them as optional. `yaml` is what cv::FileStorage wrote; the text is
/// returned unchanged when it holds none.
std::string WithoutUncompressedSupportVectors(const std::string& yaml);

/// Renders (the backend of CORRIDORSIM_RENDER_BACKEND, default OSMesa), trains and evaluates.
/// Progress lines go to stdout.
TrainingResult TrainDetectors(const TrainDetectorsOptions& options);

/// The options of a request: its seed, counts and dataset folders; the others at their defaults.
TrainDetectorsOptions TrainDetectorsOptionsOf(const TrainDetectorsRequest& request);

/// The command: TrainDetectors with TrainDetectorsOptionsOf(request), then the model files into
/// out_dir (each replaced atomically) and the report into report_dir. Returns the exit code.
int RunTrainDetectors(const TrainDetectorsRequest& request);

}  // namespace corridorsim
