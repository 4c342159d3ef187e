#pragma once
// `corridorsim train-detectors`: renders labelled lateral-camera views of seeded worlds, trains
// P1's door-plate SVM and room-number MLP on them (slam/features/), evaluates both on held-out
// worlds and plate fonts, and writes the models and a training report (docs/detectors.md).
//
// Every random choice is seeded from `seed` (world seeds, poses, subsampling, OpenCV's RNG, the
// MLP's initial weights), OpenCV runs on one thread while training, so the same request writes
// byte-identical model files.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/image.h"
#include "harness/train_detectors_request.h"
#include "render/camera_rig.h"
#include "slam/features/door_plates.h"

namespace corridorsim {

struct TrainDetectorsOptions {
  std::uint64_t seed = 1;
  int train_worlds = 24;     // worlds rendered for training
  int eval_worlds = 8;       // held-out worlds (other seeds) for the report
  int views_per_world = 48;  // lateral views per world
  // Plates drawn in these fonts are left out of training (neither positives nor negatives, no
  // digits) and evaluated apart: the held-out-font figures of the report.
  std::vector<std::string> held_out_fonts{"hershey_triplex"};
  double distractor_view_fraction = 0.25;  // views aimed at posters and notice boards
  int max_negatives_per_view = 12;
  double svm_c = 0.05;               // C of the linear SVM
  int mlp_hidden = 48;               // hidden units of the MLP
  int mlp_iterations = 1000;         // RPROP iterations at most
  slam::DoorPlateOptions detection;  // what the models are trained for and evaluated with
};

/// The lateral camera the views are rendered with: 640x480, 60 deg, level mast at
/// (0, 0.12, 1.5) m facing left (yaw 90 deg, pitch 0), with the rig's default noise.
render::RigOptions TrainingRigOptions();

struct TrainingResult {
  slam::DoorPlateModels models;
  std::string svm_bytes;  // the model files as written (cv::FileStorage YAML)
  std::string mlp_bytes;
  nlohmann::ordered_json report;  // training_report.json
  Image8 report_image;            // training_report.png
};

/// Renders (the backend of CORRIDORSIM_RENDER_BACKEND, default OSMesa), trains and evaluates.
/// Progress lines go to stdout.
TrainingResult TrainDetectors(const TrainDetectorsOptions& options);

/// The command: TrainDetectors with the request's counts and seed (the other options at their
/// defaults), then the model files into out_dir (each replaced atomically) and the report into
/// report_dir. Returns the exit code.
int RunTrainDetectors(const TrainDetectorsRequest& request);

}  // namespace corridorsim
