#pragma once
// P1 section 3 in one call: door-plate candidates (slam/features/door_plate_detector.h) scored
// by the SVM, and the room number of every candidate with a positive score read by the MLP
// (slam/features/room_number_reader.h), with the trained models loaded from one folder.
//
// Models: `door_plate_svm.yml` (cv::ml::SVM, LINEAR, two classes -1 / +1) and
// `room_number_mlp.yml` (cv::ml::ANN_MLP, outputs 0-9) as cv::ml writes them (cv::FileStorage
// YAML), in the folder `models/` of the data folder (common/installation.h: the checkout's models/
// from a build tree, <prefix>/share/corridorsim/models installed) or one given by the caller;
// `corridorsim train-detectors` makes them (docs/detectors.md).

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/ml.hpp>

#include "common/image.h"
#include "slam/features/door_plate_detector.h"
#include "slam/features/room_number_reader.h"

namespace corridorsim::slam {

inline constexpr const char* kDoorPlateSvmFile = "door_plate_svm.yml";
inline constexpr const char* kRoomNumberMlpFile = "room_number_mlp.yml";

/// A model file that is missing, unreadable, corrupt or of the wrong kind or size. Callers turn
/// it into exit code 2; what() names the file.
class ModelFileError : public std::runtime_error {
 public:
  ModelFileError(std::filesystem::path path, const std::string& problem);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// DataDir()/models (common/installation.h).
std::filesystem::path DefaultModelsDir();

struct DoorPlateModels {
  cv::Ptr<cv::ml::SVM> svm;      // P1 eq. 6, linear, trained
  cv::Ptr<cv::ml::ANN_MLP> mlp;  // P1 section 3.2, trained

  /// Loads both files from `dir` (empty: DefaultModelsDir()). Throws ModelFileError.
  static DoorPlateModels Load(const std::filesystem::path& dir = {});
};

struct DoorPlateOptions {
  DoorPlateDetectorOptions detector;
  RoomNumberReaderOptions reader;
  // SVM margins above this are plates (P1: s(x) > 0; 0.3 keeps posters' headlines out, the
  // measured figures of docs/detectors.md use it).
  double min_plate_score = 0.3;
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<DoorPlateOptions>& DoorPlateOptionsTable();

struct DoorPlateDetection {
  BoxPx box_px;               // the number region
  double svm_score = 0.0;     // s(x) > min_plate_score
  RoomNumberReading reading;  // accepted or not (see RoomNumberReading::accepted)
};

/// Every plate of `image` (score > min_plate_score), by decreasing score, each with its
/// reading. Throws ModelFileError when the models do not fit `options` (feature sizes).
std::vector<DoorPlateDetection> DetectDoorPlates(const Image8& image, const DoorPlateModels& models,
                                                 const DoorPlateOptions& options);

/// Throws ModelFileError (naming the model file) when a model's input or output size does not
/// match `options`.
void CheckModelsFit(const DoorPlateModels& models, const DoorPlateOptions& options,
                    const std::filesystem::path& dir = {});

}  // namespace corridorsim::slam
