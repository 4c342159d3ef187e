#include "harness/workbench/train_detectors.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <set>
#include <string_view>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "common/random.h"
#include "harness/run/job_inputs.h"
#include "harness/run/run_folder.h"
#include "harness/workbench/train_detectors_internal.h"
#include "worlds/image_io.h"

// train-detectors' training (TrainDetectors: the views' candidates labelled, the SVM and the MLP
// trained deterministically, the model files' bytes) and the command (RunTrainDetectors). The
// views: train_detectors_views.cpp; the held-out evaluation and its report:
// train_detectors_evaluation.cpp.

namespace corridorsim {
namespace {

using train_detectors_internal::DrawReport;
using train_detectors_internal::EvaluateView;
using train_detectors_internal::Evaluation;
using train_detectors_internal::EvaluationJson;
using train_detectors_internal::FontOf;
using train_detectors_internal::HeldOut;
using train_detectors_internal::kMatchIou;
using train_detectors_internal::LabelledView;
using train_detectors_internal::MakeViewSet;
using train_detectors_internal::NumberBox;
using train_detectors_internal::PlateFonts;
using train_detectors_internal::Ratio;
using train_detectors_internal::ViewSet;

constexpr double kNegativeIou = 0.3;  // below this against every number region: a negative

slam::BoxPx PlateBox(const render::PlateTruth& p) {
  return slam::BoxPx{p.bbox_min_px.x(), p.bbox_min_px.y(), p.bbox_max_px.x(), p.bbox_max_px.y()};
}

// The SVM and MLP samples of the training views.
struct TrainingSet {
  cv::Mat plate_features, plate_labels;  // CV_32F rows, CV_32S +1 / -1
  cv::Mat digit_features, digit_labels;  // CV_32F rows, CV_32S 0-9
  int views = 0, positives = 0, negatives = 0, plates_skipped_digits = 0;
};

void AddTrainingView(const LabelledView& view, const PlateFonts& fonts,
                     const TrainDetectorsOptions& o, RandomStream& rng, TrainingSet* set) {
  ++set->views;
  const slam::DoorPlateDetectorOptions& det = o.detection.detector;
  const std::vector<slam::BoxPx> candidates = slam::SegmentPlateCandidates(view.rgb, det);
  std::vector<slam::BoxPx> negatives;
  for (const slam::BoxPx& c : candidates) {
    double best = 0.0;
    int best_plate = -1;
    bool near_held_out = false;
    for (std::size_t k = 0; k < view.plates.size(); ++k) {
      const render::PlateTruth& p = view.plates[k];
      const bool held = HeldOut(o, FontOf(fonts, p.id));
      if (held && slam::IntersectionOverUnion(c, PlateBox(p)) > 0.0) near_held_out = true;
      const double iou = slam::IntersectionOverUnion(c, NumberBox(p));
      if (iou > best) {
        best = iou;
        best_plate = static_cast<int>(k);
      }
    }
    if (near_held_out) continue;  // held-out fonts teach nothing, not even as negatives
    if (best >= kMatchIou) {
      const render::PlateTruth& p = view.plates[std::size_t(best_plate)];
      set->plate_features.push_back(slam::PlatePatchFeatures(view.rgb, c, det));
      set->plate_labels.push_back(1);
      ++set->positives;
      if (!p.fully_in_image) continue;
      // Digits, labelled by position from the true number (P1 Fig. 7).
      const std::vector<slam::DigitSegment> digits =
          slam::SegmentDigits(view.rgb, c, o.detection.reader);
      if (digits.size() != p.room_number.size()) {
        ++set->plates_skipped_digits;
        continue;
      }
      for (std::size_t i = 0; i < digits.size(); ++i) {
        set->digit_features.push_back(digits[i].features);
        set->digit_labels.push_back(int(p.room_number[i] - '0'));
      }
    } else if (best < kNegativeIou) {
      negatives.push_back(c);
    }
  }
  rng.Shuffle(negatives);
  if (static_cast<int>(negatives.size()) > o.max_negatives_per_view) {
    negatives.resize(std::size_t(o.max_negatives_per_view));
  }
  for (const slam::BoxPx& c : negatives) {
    set->plate_features.push_back(slam::PlatePatchFeatures(view.rgb, c, det));
    set->plate_labels.push_back(-1);
    ++set->negatives;
  }
}

// cv::ml writes a model as `<default name>: { ... }` (what StatModel::save writes), in memory.
std::string ModelBytes(const cv::ml::StatModel& model) {
  cv::FileStorage fs(
      ".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs << model.getDefaultName() << "{";
  model.write(fs);
  fs << "}";
  return fs.releaseAndGetString();
}

}  // namespace

std::string WithoutUncompressedSupportVectors(const std::string& yaml) {
  // cv::FileStorage's YAML puts the model's keys at one indent, three spaces, each value's lines
  // deeper: the two keys are dropped with every line up to the next key at that indent.
  std::string out;
  out.reserve(yaml.size());
  bool dropping = false;
  std::size_t begin = 0;
  while (begin < yaml.size()) {
    std::size_t end = yaml.find('\n', begin);
    end = end == std::string::npos ? yaml.size() : end + 1;
    const std::string_view line(yaml.data() + begin, end - begin);
    const bool key = line.size() > 3 && line.substr(0, 3) == "   " && line[3] != ' ';
    if (key) {
      dropping = line.starts_with("   uncompressed_sv_total:") ||
                 line.starts_with("   uncompressed_support_vectors:");
    }
    if (!dropping) out.append(line);
    begin = end;
  }
  return out;
}

namespace {

template <class Model>
cv::Ptr<Model> ModelFromBytes(const std::string& bytes) {
  cv::FileStorage fs(bytes, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  cv::Ptr<Model> model = Model::create();
  model->read(fs.getFirstTopLevelNode());
  return model;
}

// OpenCV's RNG seeded and its threads held at one while training; restored afterwards.
class DeterministicOpenCv {
 public:
  explicit DeterministicOpenCv(std::uint64_t seed) : threads_(cv::getNumThreads()) {
    cv::setNumThreads(1);
    cv::theRNG().state = seed == 0 ? 1 : seed;  // state 0 is OpenCV's degenerate stream
  }
  ~DeterministicOpenCv() { cv::setNumThreads(threads_); }

 private:
  int threads_;
};

}  // namespace

Scenario TrainingScenario() {
  Scenario scenario;
  scenario.file = "scenarios/datasets/train_detectors.yaml";
  scenario.name = "train_detectors";
  scenario.description = "the views train-detectors learns from: default corridor, lateral camera";
  for (render::CameraOptions& c : scenario.rig.cameras) {
    c.enabled = c.id == "lateral";
    // Level on a 1.5 m mast, facing left: P1's scenarios' mount (scenarios/default.yaml).
    if (c.id == "lateral") c.mount = render::Mount{0.0, 0.12, 1.5, 90.0, 0.0, 0.0};
  }
  return scenario;
}

std::uint64_t TrainingFirstWorldSeed(std::uint64_t seed) {
  // 48 bits: readable, and far from the small seeds scenarios use (their worlds stay unseen).
  return RandomStream(seed, 0, "train_detectors.worlds").NextU64() >> 16;
}

TrainingResult TrainDetectors(const TrainDetectorsOptions& o) {
  CheckOrDie(!o.detection.Check(), "TrainDetectors", "the detection options fail their Check()");
  const auto t0 = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const std::uint64_t first_seed = TrainingFirstWorldSeed(o.seed);
  const std::unique_ptr<ViewSet> train =
      MakeViewSet(o.train_dataset, "--dataset", first_seed, o.train_worlds, o.views_per_world);
  const std::unique_ptr<ViewSet> eval =
      MakeViewSet(o.eval_dataset, "--eval-dataset", first_seed + std::uint64_t(o.train_worlds),
                  o.eval_worlds, o.views_per_world);
  std::vector<std::uint64_t> train_seeds, eval_seeds;
  for (int w = 0; w < train->worlds(); ++w) train_seeds.push_back(train->world_seed(w));
  for (int w = 0; w < eval->worlds(); ++w) eval_seeds.push_back(eval->world_seed(w));
  {
    // Held-out worlds must be held out: no world seed in both sets.
    const std::set<std::uint64_t> trained(train_seeds.begin(), train_seeds.end());
    for (const std::uint64_t s : eval_seeds) {
      if (!trained.count(s)) continue;
      throw InputError(SourceLocation{"command line", 0, 0},
                       o.eval_dataset ? "--eval-dataset" : "--dataset",
                       "world seed " + std::to_string(s) +
                           " is in both the training and the evaluation set (write the "
                           "evaluation dataset with another --seed)");
    }
  }
  TrainingSet set;
  RandomStream sample_rng(o.seed, 0, "train_detectors.samples");
  for (int w = 0; w < train->worlds(); ++w) {
    train->ForEachView(w, [&](const LabelledView& view, const PlateFonts& fonts) {
      AddTrainingView(view, fonts, o, sample_rng, &set);
    });
    std::printf(
        "train-detectors: training world %d/%d (seed %llu): %d positives, %d negatives, "
        "%d digits (%.0f s)\n",
        w + 1, train->worlds(), static_cast<unsigned long long>(train->world_seed(w)),
        set.positives, set.negatives, set.digit_labels.rows, seconds());
    std::fflush(stdout);
  }
  if (set.positives == 0 || set.negatives == 0 || set.digit_labels.rows == 0) {
    throw std::runtime_error(
        "train-detectors: the training views gave no positives, negatives "
        "or digits (more worlds or views?)");
  }
  std::vector<int> digit_classes(10, 0);
  for (int r = 0; r < set.digit_labels.rows; ++r)
    ++digit_classes[std::size_t(set.digit_labels.at<int>(r))];

  TrainingResult result;
  {
    const DeterministicOpenCv deterministic(o.seed);
    // P1 eq. 6: linear SVM on the patches.
    cv::Ptr<cv::ml::SVM> svm = cv::ml::SVM::create();
    svm->setType(cv::ml::SVM::C_SVC);
    svm->setKernel(cv::ml::SVM::LINEAR);
    svm->setC(o.svm_c);
    svm->setTermCriteria(
        cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, 20000, 1e-6));
    svm->train(cv::ml::TrainData::create(set.plate_features, cv::ml::ROW_SAMPLE, set.plate_labels));
    result.svm_bytes = WithoutUncompressedSupportVectors(ModelBytes(*svm));
    // P1 section 3.2: MLP on the digits' projections, targets -1 / +1.
    cv::Mat targets(set.digit_labels.rows, 10, CV_32F, cv::Scalar(-1.0f));
    for (int r = 0; r < set.digit_labels.rows; ++r)
      targets.at<float>(r, set.digit_labels.at<int>(r)) = 1.0f;
    cv::Ptr<cv::ml::ANN_MLP> mlp = cv::ml::ANN_MLP::create();
    mlp->setLayerSizes(std::vector<int>{set.digit_features.cols, o.mlp_hidden, 10});
    mlp->setActivationFunction(cv::ml::ANN_MLP::SIGMOID_SYM, 0, 0);
    mlp->setTrainMethod(cv::ml::ANN_MLP::RPROP, 0.1, FLT_EPSILON);
    mlp->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS,
                                          o.mlp_iterations, 1e-6));
    mlp->train(cv::ml::TrainData::create(set.digit_features, cv::ml::ROW_SAMPLE, targets));
    result.mlp_bytes = ModelBytes(*mlp);
  }
  // The models as they will be loaded (the written bytes, not the objects trained).
  result.models.svm = ModelFromBytes<cv::ml::SVM>(result.svm_bytes);
  result.models.mlp = ModelFromBytes<cv::ml::ANN_MLP>(result.mlp_bytes);
  int svm_right = 0, mlp_right = 0;
  for (int r = 0; r < set.plate_features.rows; ++r) {
    const double s = slam::PlateScore(*result.models.svm, set.plate_features.row(r));
    svm_right += (s > 0) == (set.plate_labels.at<int>(r) > 0);
  }
  for (int r = 0; r < set.digit_features.rows; ++r) {
    mlp_right += slam::ClassifyDigit(*result.models.mlp, set.digit_features.row(r)).digit - '0' ==
                 set.digit_labels.at<int>(r);
  }
  const double train_s = seconds();
  std::printf("train-detectors: trained (SVM %d/%d, MLP %d/%d right on the training set; %.0f s)\n",
              svm_right, set.plate_features.rows, mlp_right, set.digit_features.rows, train_s);

  Evaluation e;
  for (int w = 0; w < eval->worlds(); ++w) {
    eval->ForEachView(w, [&](const LabelledView& view, const PlateFonts& fonts) {
      EvaluateView(view, fonts, result.models, o, &e);
    });
    std::printf(
        "train-detectors: evaluation world %d/%d: within 3 m, 30 deg read %d/%d, false "
        "readings %d/%d accepted (%.0f s)\n",
        w + 1, eval->worlds(), e.target.read, e.target.plates, e.false_accepted, e.accepted,
        seconds());
    std::fflush(stdout);
  }

  nlohmann::ordered_json& j = result.report;
  j["seed"] = o.seed;
  j["training_set"] = train->Source();
  j["evaluation_set"] = eval->Source();
  j["held_out_fonts"] = o.held_out_fonts;
  j["train_world_seeds"] = train_seeds;
  j["eval_world_seeds"] = eval_seeds;
  j["training"] = {{"views", set.views},
                   {"positives", set.positives},
                   {"negatives", set.negatives},
                   {"digits", set.digit_labels.rows},
                   {"digits_per_class", digit_classes},
                   {"plates_skipped_digit_count", set.plates_skipped_digits},
                   {"svm_training_accuracy", Ratio(svm_right, set.plate_features.rows)},
                   {"mlp_training_accuracy", Ratio(mlp_right, set.digit_features.rows)}};
  j["evaluation"] = EvaluationJson(e);
  j["seconds"] = {{"training", RoundToStep(train_s, 10)}, {"total", RoundToStep(seconds(), 10)}};
  result.report_image = DrawReport(e);
  return result;
}

TrainDetectorsOptions TrainDetectorsOptionsOf(const TrainDetectorsRequest& request) {
  TrainDetectorsOptions options;
  static_cast<TrainingViews&>(options) = request;
  return options;
}

int RunTrainDetectors(const TrainDetectorsRequest& request) {
  std::vector<JobInput> inputs;
  if (request.train_dataset) inputs.push_back({*request.train_dataset, "the --dataset folder"});
  if (request.eval_dataset) inputs.push_back({*request.eval_dataset, "the --eval-dataset folder"});
  RefuseOutputOverInputs(request.out_dir, "--out", inputs);
  std::unique_ptr<StagedDirectory> report;
  if (request.report_dir)
    report = StageOutputFolder(*request.report_dir, "--report", request.force, inputs);
  // The models' folder is checked before minutes of training: one that cannot be made or written
  // (a file of that name, no permission) is bad input.
  try {
    EnsureWritableDirectory(request.out_dir);
  } catch (const std::exception& e) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--out", e.what());
  }
  const TrainingResult result = TrainDetectors(TrainDetectorsOptionsOf(request));
  WriteFileAtomic(request.out_dir / slam::kDoorPlateSvmFile, result.svm_bytes);
  WriteFileAtomic(request.out_dir / slam::kRoomNumberMlpFile, result.mlp_bytes);
  std::printf("wrote %s/{%s, %s}\n", request.out_dir.string().c_str(), slam::kDoorPlateSvmFile,
              slam::kRoomNumberMlpFile);
  if (report) {
    WriteFileAtomic(report->path() / "training_report.json", JsonFileText(result.report));
    WriteFileAtomic(report->path() / "training_report.png",
                    EncodePng(result.report_image, "training_report.png"));
    report->Commit();
    std::printf("wrote %s/{training_report.json, training_report.png}\n",
                request.report_dir->string().c_str());
  }
  const nlohmann::ordered_json& ev = result.report["evaluation"];
  std::printf(
      "train-detectors: within 3 m and 30 deg read %s (target >= 0.98), false readings "
      "%s of accepted (target < 0.005)\n",
      ev["read_within_3m_30deg"]["reading_accuracy"].dump().c_str(),
      ev["false_readings"]["fraction"].dump().c_str());
  return 0;
}

}  // namespace corridorsim
