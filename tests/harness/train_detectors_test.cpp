// harness/train_detectors.cpp: the same request trains byte-identical model files; the models
// load back through slam::DoorPlateModels.
#include <catch2/catch.hpp>

#include "common/io/atomic_file.h"
#include "harness/train_detectors.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

TrainDetectorsOptions Small(std::uint64_t seed) {
  TrainDetectorsOptions o;
  o.seed = seed;
  o.train_worlds = 2;
  o.eval_worlds = 1;
  o.views_per_world = 10;
  o.mlp_iterations = 60;
  return o;
}

TEST_CASE("train-detectors: the same seed writes byte-identical models, another seed others",
          "[plates][render][slow]") {
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
  const auto& confusion = a.report["evaluation"]["digit_confusion_rows_true_cols_read"];
  REQUIRE(confusion.size() == 10);
  for (const auto& row : confusion) CHECK(row.size() == 10);
}

}  // namespace
}  // namespace corridorsim

#include "harness/cli.h"

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
                                             {"train-detectors", "--out", ""}}) {
    CHECK_THROWS_AS(ParseCommandLine(bad), InputError);
  }
}

}  // namespace
}  // namespace corridorsim
