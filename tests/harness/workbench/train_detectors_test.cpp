// harness/workbench/train_detectors*.cpp: the same request trains byte-identical model files; the
// models load back through slam::DoorPlateModels; the views come through `dataset` (a folder it
// wrote trains the models the in-memory path trains); dataset folders that do not fit are refused.
#include <catch2/catch.hpp>

#include <fstream>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/options_yaml.h"
#include "harness/workbench/dataset.h"
#include "harness/workbench/train_detectors.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

// A small request's options, as the command makes them, with a short MLP training.
TrainDetectorsOptions Small(std::uint64_t seed) {
  TrainDetectorsRequest request;
  request.seed = seed;
  request.train_worlds = 2;
  request.eval_worlds = 1;
  request.views_per_world = 10;
  TrainDetectorsOptions o = TrainDetectorsOptionsOf(request);
  o.mlp_iterations = 60;
  return o;
}

TEST_CASE("train-detectors: the same seed writes byte-identical models, another seed others",
          "[plates][render][slow][heavy]") {
  const TrainingResult a = TrainDetectors(Small(5));
  const TrainingResult b = TrainDetectors(Small(5));
  REQUIRE(a.svm_bytes.size() > 1000);
  REQUIRE(a.mlp_bytes.size() > 1000);
  CHECK(a.svm_bytes == b.svm_bytes);
  CHECK(a.mlp_bytes == b.mlp_bytes);
  CHECK(a.report["training"] == b.report["training"]);
  CHECK(a.report["evaluation"] == b.report["evaluation"]);
  const TrainingResult c = TrainDetectors(Small(6));
  CHECK(c.svm_bytes != a.svm_bytes);

  // The written files load as the shipped ones do.
  const test::ScratchDir dir("train_detectors");
  WriteFileAtomic(dir.path() / slam::kDoorPlateSvmFile, a.svm_bytes);
  WriteFileAtomic(dir.path() / slam::kRoomNumberMlpFile, a.mlp_bytes);
  const slam::DoorPlateModels models = slam::DoorPlateModels::Load(dir.path());
  CHECK_NOTHROW(slam::CheckModelsFit(models, slam::DoorPlateOptions{}));
  // The targets' figures carry their Wilson 95 % intervals, which bracket them.
  const auto& target = a.report["evaluation"]["read_within_3m_30deg"];
  REQUIRE(target["plates"].get<int>() > 0);
  const double read = target["reading_accuracy"], read_lo = target["reading_accuracy_ci95"][0],
               read_hi = target["reading_accuracy_ci95"][1];
  CHECK(0.0 <= read_lo);
  CHECK(read_lo < read_hi);
  CHECK(read_hi <= 1.0);
  CHECK(read_lo <= read);
  CHECK(read <= read_hi);
  const auto& false_readings = a.report["evaluation"]["false_readings"];
  CHECK(false_readings["fraction_ci95"][0].get<double>() <=
        false_readings["fraction"].get<double>());
  CHECK(false_readings["fraction"].get<double>() <=
        false_readings["fraction_ci95"][1].get<double>());
  const auto& confusion = a.report["evaluation"]["digit_confusion_rows_true_cols_read"];
  REQUIRE(confusion.size() == 10);
  for (const auto& row : confusion) CHECK(row.size() == 10);
}

TEST_CASE("train-detectors: the SVM file drops the uncompressed support vectors, not the model",
          "[plates]") {
  // A linear SVM on two noisy Gaussian classes: many support vectors, one weight vector.
  cv::RNG rng(7);
  cv::Mat features(400, 30, CV_32F), labels(400, 1, CV_32S);
  rng.fill(features, cv::RNG::NORMAL, 0.0, 1.0);
  for (int r = 0; r < features.rows; ++r) {
    labels.at<int>(r) = r % 2 == 0 ? 1 : -1;
    features.at<float>(r, 0) += labels.at<int>(r) > 0 ? 0.8f : -0.8f;
  }
  cv::Ptr<cv::ml::SVM> svm = cv::ml::SVM::create();
  svm->setKernel(cv::ml::SVM::LINEAR);
  svm->setC(1.0);
  svm->train(cv::ml::TrainData::create(features, cv::ml::ROW_SAMPLE, labels));
  cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  out << svm->getDefaultName() << "{";
  svm->write(out);
  out << "}";
  const std::string full = out.releaseAndGetString();
  REQUIRE(full.find("uncompressed_support_vectors") != std::string::npos);
  const std::string compact = WithoutUncompressedSupportVectors(full);
  CHECK(compact.find("uncompressed") == std::string::npos);
  CHECK(compact.size() * 5 < full.size());
  CHECK(WithoutUncompressedSupportVectors(compact) == compact);
  const auto load = [](const std::string& yaml) {
    cv::FileStorage in(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    cv::Ptr<cv::ml::SVM> m = cv::ml::SVM::create();
    m->read(in.getFirstTopLevelNode());
    return m;
  };
  const cv::Ptr<cv::ml::SVM> a = load(full), b = load(compact);
  REQUIRE(b->isTrained());
  CHECK(b->getVarCount() == 30);
  for (int r = 0; r < features.rows; ++r) {
    CHECK(slam::PlateScore(*b, features.row(r)) == slam::PlateScore(*a, features.row(r)));
  }
}

// `corridorsim dataset scenarios/datasets/train_detectors.yaml --cameras lateral --poses plates`
// into dir.
void WriteTrainingDataset(const std::filesystem::path& dir, std::uint64_t seed, int worlds,
                          int frames) {
  DatasetRequest r;
  r.scenario_file = CORRIDORSIM_SOURCE_DIR "/scenarios/datasets/train_detectors.yaml";
  r.seed = seed;
  r.out_dir = dir;
  r.worlds = worlds;
  r.frames_per_world = frames;
  r.cameras = {"lateral"};
  r.poses = DatasetPoseMode::kPlates;
  REQUIRE(RunDataset(r) == 0);
}

TEST_CASE(
    "train-detectors: scenarios/datasets/train_detectors.yaml is the built-in training scenario",
    "[plates]") {
  const Scenario file =
      LoadScenario(CORRIDORSIM_SOURCE_DIR "/scenarios/datasets/train_detectors.yaml");
  const Scenario built_in = TrainingScenario();
  CHECK(file.name == built_in.name);
  CHECK(OptionsYaml(ScenarioOptionsTable(), file) == OptionsYaml(ScenarioOptionsTable(), built_in));
}

TEST_CASE("train-detectors: dataset folders train the models the built-in views train",
          "[plates][render][slow][heavy]") {
  TrainDetectorsOptions o = Small(5);
  o.views_per_world = 6;
  const TrainingResult in_memory = TrainDetectors(o);
  const std::uint64_t first = TrainingFirstWorldSeed(o.seed);
  CHECK(in_memory.report["train_world_seeds"] == nlohmann::ordered_json::array({first, first + 1}));
  CHECK(in_memory.report["eval_world_seeds"] == nlohmann::ordered_json::array({first + 2}));

  const test::ScratchDir dir("train_detectors_datasets");
  WriteTrainingDataset(dir.path() / "train", first, 2, 6);
  WriteTrainingDataset(dir.path() / "eval", first + 2, 1, 6);
  TrainDetectorsOptions from_folders = o;
  from_folders.train_dataset = dir.path() / "train";
  from_folders.eval_dataset = dir.path() / "eval";
  const TrainingResult folders = TrainDetectors(from_folders);
  CHECK(folders.svm_bytes == in_memory.svm_bytes);
  CHECK(folders.mlp_bytes == in_memory.mlp_bytes);
  CHECK(folders.report["training"] == in_memory.report["training"]);
  CHECK(folders.report["evaluation"] == in_memory.report["evaluation"]);
  CHECK(folders.report["training_set"]["dataset"] == (dir.path() / "train").string());
}

TEST_CASE("train-detectors: dataset folders that do not fit are refused, naming file and field",
          "[plates][render]") {
  const test::ScratchDir dir("train_detectors_bad_datasets");
  WriteTrainingDataset(dir.path() / "train", 7, 2, 2);
  TrainDetectorsOptions o = Small(5);
  o.train_dataset = dir.path() / "train";

  // A training world that is also an evaluation world.
  TrainDetectorsOptions same = o;
  same.eval_dataset = dir.path() / "train";
  CHECK_THROWS_WITH(TrainDetectors(same),
                    Catch::Contains("--eval-dataset") &&
                        Catch::Contains("world seed 7 is in both the training and the evaluation"));
  // A folder that is not a dataset.
  TrainDetectorsOptions none = o;
  none.train_dataset = dir.path() / "nothing";
  std::filesystem::create_directories(*none.train_dataset);
  CHECK_THROWS_WITH(TrainDetectors(none), Catch::Contains("dataset.json"));
  // An unfinished dataset: a frame's truth file is missing.
  std::filesystem::remove(dir.path() / "train" / "lateral" / "truth" / "w001_f0001.json");
  CHECK_THROWS_WITH(TrainDetectors(o),
                    Catch::Contains("w001_f0001.json") && Catch::Contains("not finished"));
  // A truth file whose plate has no valid room number.
  std::ofstream(dir.path() / "train" / "lateral" / "truth" / "w000_f0000.json")
      << R"({"width": 640, "height": 480, "plates": [{"id": 1, "room_number": "4a"}]})";
  CHECK_THROWS_WITH(TrainDetectors(o), Catch::Contains("w000_f0000.json") &&
                                           Catch::Contains(".plates[0].room_number") &&
                                           Catch::Contains("expected 1 to 16 digits"));
}

}  // namespace
}  // namespace corridorsim

#include "harness/cli/cli.h"

namespace corridorsim {
namespace {

TEST_CASE("train-detectors command line: defaults, counts bounded, bad numbers refused",
          "[plates]") {
  const CommandLine plain = ParseCommandLine({"train-detectors"});
  REQUIRE(plain.job == CommandLine::Job::kTrainDetectors);
  CHECK(plain.train_detectors.out_dir == "models");
  CHECK_FALSE(plain.train_detectors.report_dir);
  CHECK(plain.train_detectors.seed == 1);
  const CommandLine set =
      ParseCommandLine({"train-detectors", "--out", "m", "--report", "r", "--seed", "9",
                        "--train-worlds", "3", "--eval-worlds", "2", "--views", "5"});
  CHECK(set.train_detectors.out_dir == "m");
  REQUIRE(set.train_detectors.report_dir);
  CHECK(*set.train_detectors.report_dir == "r");
  CHECK(set.train_detectors.seed == 9);
  CHECK(set.train_detectors.train_worlds == 3);
  CHECK(set.train_detectors.eval_worlds == 2);
  CHECK(set.train_detectors.views_per_world == 5);
  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"train-detectors", "--views", "501"},
                                             {"train-detectors", "--train-worlds", "0"},
                                             {"train-detectors", "--eval-worlds", "1.5"},
                                             {"train-detectors", "--views", "1e9"},
                                             {"train-detectors", "--seed", "-1"},
                                             {"train-detectors", "--out", ""},
                                             {"train-detectors", "--dataset", ""}}) {
    CHECK_THROWS_AS(ParseCommandLine(bad), InputError);
  }
  CHECK_FALSE(plain.train_detectors.train_dataset);
  CHECK_FALSE(plain.train_detectors.eval_dataset);
  const CommandLine folders =
      ParseCommandLine({"train-detectors", "--dataset", "d", "--eval-dataset", "e"});
  REQUIRE(folders.train_detectors.train_dataset);
  CHECK(*folders.train_detectors.train_dataset == "d");
  REQUIRE(folders.train_detectors.eval_dataset);
  CHECK(*folders.train_detectors.eval_dataset == "e");
  // What a dataset folder decides cannot be asked for as well.
  CHECK_THROWS_WITH(ParseCommandLine({"train-detectors", "--dataset", "d", "--train-worlds", "3"}),
                    Catch::StartsWith("command line: --train-worlds: the --dataset folder"));
  CHECK_THROWS_WITH(
      ParseCommandLine({"train-detectors", "--eval-dataset", "e", "--eval-worlds", "3"}),
      Catch::StartsWith("command line: --eval-worlds: the --eval-dataset folder"));
  CHECK_THROWS_WITH(ParseCommandLine({"train-detectors", "--dataset", "d", "--eval-dataset", "e",
                                      "--views", "3"}),
                    Catch::StartsWith("command line: --views: both sets are dataset folders"));
  // One folder and built-in views for the other set: --views applies to the built-in set.
  CHECK(ParseCommandLine({"train-detectors", "--dataset", "d", "--views", "3"})
            .train_detectors.views_per_world == 3);
}

}  // namespace
}  // namespace corridorsim
