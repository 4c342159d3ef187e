#include "slam/features/door_plates.h"

#include <system_error>

#include <opencv2/core/persistence.hpp>

namespace corridorsim::slam {

ModelFileError::ModelFileError(std::filesystem::path path, const std::string& problem)
    : std::runtime_error("model file " + path.string() + ": " + problem), path_(std::move(path)) {}

std::filesystem::path DefaultModelsDir() { return std::filesystem::path(CORRIDORSIM_MODELS_DIR); }

namespace {

std::filesystem::path Dir(const std::filesystem::path& dir) {
  return dir.empty() ? DefaultModelsDir() : dir;
}

// Reads one cv::ml model; every failure of OpenCV's reader is the file's problem.
template <class Model>
cv::Ptr<Model> LoadModel(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw ModelFileError(path,
                         "missing (or not a regular file); `corridorsim train-detectors` "
                         "makes it");
  }
  // Model files are KBs to a few MB: a huge file is not one of ours.
  const auto bytes = std::filesystem::file_size(path, error);
  if (error || bytes > (std::uintmax_t{256} << 20)) {
    throw ModelFileError(path, "unreadable or larger than 256 MiB");
  }
  cv::Ptr<Model> model;
  try {
    cv::FileStorage fs(path.string(), cv::FileStorage::READ);
    if (!fs.isOpened()) throw ModelFileError(path, "not an OpenCV storage file");
    const cv::FileNode node = fs.getFirstTopLevelNode();
    if (node.empty()) throw ModelFileError(path, "holds no model");
    model = Model::create();
    model->read(node);
  } catch (const cv::Exception& e) {
    throw ModelFileError(path, std::string("corrupt: ") + e.what());
  }
  if (!model || !model->isTrained()) throw ModelFileError(path, "holds no trained model");
  return model;
}

}  // namespace

DoorPlateModels DoorPlateModels::Load(const std::filesystem::path& dir) {
  DoorPlateModels models;
  const std::filesystem::path svm_path = Dir(dir) / kDoorPlateSvmFile;
  models.svm = LoadModel<cv::ml::SVM>(svm_path);
  if (models.svm->getKernelType() != cv::ml::SVM::LINEAR || !models.svm->isClassifier()) {
    throw ModelFileError(svm_path, "not a linear SVM classifier");
  }
  const std::filesystem::path mlp_path = Dir(dir) / kRoomNumberMlpFile;
  models.mlp = LoadModel<cv::ml::ANN_MLP>(mlp_path);
  const cv::Mat layers = models.mlp->getLayerSizes();
  if (layers.total() < 2 || layers.at<int>(int(layers.total()) - 1) != 10) {
    throw ModelFileError(mlp_path, "not a network with 10 outputs (digits 0-9)");
  }
  return models;
}

const OptionTable<DoorPlateOptions>& DoorPlateOptionsTable() {
  return StaticOptionTable<DoorPlateOptions>([](OptionTable<DoorPlateOptions>& t) {
    t.AddSection("detector", &DoorPlateOptions::detector, DoorPlateDetectorOptionsTable(),
                 "P1 section 3.1 candidate segmentation and SVM patch",
                 &DoorPlateDetectorOptions::Check);
    t.AddSection("reader", &DoorPlateOptions::reader, RoomNumberReaderOptionsTable(),
                 "P1 section 3.2 digit segmentation and MLP", &RoomNumberReaderOptions::Check);
    t.Add("min_plate_score", &DoorPlateOptions::min_plate_score, "",
          "SVM margins above this are plates (P1 eq. 6: 0)")
        .Range(-100, 100);
  });
}

std::optional<OptionsProblem> DoorPlateOptions::Check() const {
  return CheckOptionBounds(DoorPlateOptionsTable(), *this);
}

void CheckModelsFit(const DoorPlateModels& models, const DoorPlateOptions& options,
                    const std::filesystem::path& dir) {
  CheckOrDie(models.svm && models.mlp, "slam::CheckModelsFit", "models are not loaded");
  const int patch = options.detector.patch_width_px * options.detector.patch_height_px;
  if (models.svm->getVarCount() != patch) {
    throw ModelFileError(Dir(dir) / kDoorPlateSvmFile,
                         "takes " + std::to_string(models.svm->getVarCount()) +
                             " features, the detector options give " + std::to_string(patch));
  }
  const cv::Mat layers = models.mlp->getLayerSizes();
  const int inputs = layers.total() > 0 ? layers.at<int>(0) : 0;
  if (inputs != DigitFeatureCount(options.reader)) {
    throw ModelFileError(Dir(dir) / kRoomNumberMlpFile,
                         "takes " + std::to_string(inputs) + " features, the reader options give " +
                             std::to_string(DigitFeatureCount(options.reader)));
  }
}

std::vector<DoorPlateDetection> DetectDoorPlates(const Image8& image, const DoorPlateModels& models,
                                                 const DoorPlateOptions& options) {
  CheckModelsFit(models, options);
  std::vector<DoorPlateDetection> out;
  for (const PlateCandidate& c : DetectPlateCandidates(image, *models.svm, options.detector)) {
    if (!(c.score > options.min_plate_score)) continue;
    DoorPlateDetection d;
    d.box_px = c.box_px;
    d.svm_score = c.score;
    d.reading = ReadRoomNumber(image, c.box_px, *models.mlp, options.reader);
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace corridorsim::slam
