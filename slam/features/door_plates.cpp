#include "slam/features/door_plates.h"

#include <algorithm>
#include <numeric>
#include <system_error>

#include <opencv2/core/persistence.hpp>

#include "common/installation.h"

namespace corridorsim::slam {

ModelFileError::ModelFileError(std::filesystem::path path, const std::string& problem)
    : std::runtime_error("model file " + path.string() + ": " + problem), path_(std::move(path)) {}

std::filesystem::path DefaultModelsDir() { return DataDir() / "models"; }

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

std::optional<OptionsProblem> DoorPlateOptions::Check() const {
  return CheckOptionBounds(DoorPlateOptionsTable(), *this);
}

void CheckModelsFit(const DoorPlateModels& models, const DoorPlateOptions& options,
                    const std::filesystem::path& dir) {
  CheckOrDie(models.svm && models.mlp, "slam::CheckModelsFit", "models are not loaded");
  const int patch = PlateFeatureCount(options.detector);
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

namespace {

// Whether the number read in `box` goes on beyond it: a part of a longer number was found ("725"
// of a poster's "1725", "19" of "119"). The box is segmented again widened by one box height on
// each side; a digit-like segment outside the box, on the read digits' rows and of their height,
// is more of the number. A plate's frame is taller than its digits and is no such segment.
bool NumberGoesOn(const Image8& image, const BoxPx& box, const RoomNumberReading& reading,
                  const RoomNumberReaderOptions& options) {
  if (reading.digits.empty()) return false;
  double top = 0.0, bottom = 0.0, height = 0.0;
  for (const DigitReading& d : reading.digits) {
    top += d.box_px.min_y;
    bottom += d.box_px.max_y;
    height += d.box_px.height();
  }
  const double n = static_cast<double>(reading.digits.size());
  top /= n;
  bottom /= n;
  height /= n;
  const BoxPx wide{box.min_x - box.height(), box.min_y, box.max_x + box.height(), box.max_y};
  for (const DigitSegment& s : SegmentDigits(image, wide, options)) {
    const BoxPx& b = s.box_px;
    const double centre = 0.5 * (b.min_x + b.max_x);
    if (centre >= box.min_x && centre <= box.max_x) continue;  // the number itself
    const double overlap = std::min(b.max_y, bottom) - std::max(b.min_y, top);
    if (overlap >= 0.5 * height && b.height() >= 0.7 * height && b.height() <= 1.3 * height) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<DoorPlateDetection> DetectDoorPlates(const Image8& image, const DoorPlateModels& models,
                                                 const DoorPlateOptions& options) {
  CheckModelsFit(models, options);
  // Every candidate the SVM takes for a plate (P1 eq. 6) is read (P1 section 3.2).
  std::vector<DoorPlateDetection> read;
  for (const PlateCandidate& c : ScorePlateCandidates(image, *models.svm, options.detector)) {
    if (!(c.score > options.min_plate_score)) continue;
    DoorPlateDetection d;
    d.box_px = c.box_px;
    d.svm_score = c.score;
    d.reading = ReadRoomNumber(image, c.box_px, *models.mlp, options.reader);
    // A number the image border cuts may go on beyond it ("4760" read "476"): with the reader's
    // margin its box must lie inside the image for the reading to count.
    const double margin = options.reader.margin * c.box_px.height();
    if (c.box_px.min_x - margin < 0.0 || c.box_px.min_y - margin < 0.0 ||
        c.box_px.max_x + margin > image.width || c.box_px.max_y + margin > image.height) {
      d.reading.accepted = false;
    }
    if (d.reading.accepted && NumberGoesOn(image, c.box_px, d.reading, options.reader)) {
      d.reading.accepted = false;
    }
    read.push_back(std::move(d));
  }
  // Non-maximum suppression over overlapping candidates (one plate found at several scales, or a
  // part of its number: "19" of "119"): a candidate whose reading is accepted wins over ones
  // whose reading is not, then the higher score wins.
  std::vector<std::size_t> order(read.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return read[a].reading.accepted > read[b].reading.accepted;
  });
  std::vector<BoxPx> boxes;
  for (const std::size_t i : order) boxes.push_back(read[i].box_px);
  std::vector<std::size_t> kept;
  for (const std::size_t j : SuppressOverlapping(boxes, options.detector.suppression_iou)) {
    kept.push_back(order[j]);
  }
  std::sort(kept.begin(), kept.end());  // by decreasing score again (`read`'s order)
  std::vector<DoorPlateDetection> out;
  for (const std::size_t i : kept) out.push_back(std::move(read[i]));
  return out;
}

}  // namespace corridorsim::slam
