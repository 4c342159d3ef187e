// slam/features/door_plate_detector.cpp and door_plates.cpp: P1 section 3.1 on rendered lateral
// frames with the shipped models (models/, `corridorsim train-detectors`).
#include <fstream>

#include <catch2/catch.hpp>

#include "slam/features/door_plates.h"
#include "tests/support/door_plate_truth.h"
#include "tests/support/generated_worlds.h"
#include "tests/support/lateral_views.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

using slam::BoxPx;
using test::NumberBox;
using test::ShippedModels;

const worlds::World& TestWorld() { return test::GeneratedWorld(11); }

TEST_CASE("box IoU: identical boxes 1, disjoint 0, half overlap 1/3", "[plates]") {
  const BoxPx a{0, 0, 10, 10};
  CHECK(slam::IntersectionOverUnion(a, a) == Approx(1.0));
  CHECK(slam::IntersectionOverUnion(a, BoxPx{20, 20, 30, 30}) == 0.0);
  CHECK(slam::IntersectionOverUnion(a, BoxPx{5, 0, 15, 10}) == Approx(1.0 / 3.0));
  CHECK(slam::IntersectionOverUnion(a, BoxPx{3, 3, 3, 3}) == 0.0);
}

TEST_CASE("detector options: defaults pass, a bad scale and a crossed range are refused",
          "[plates]") {
  slam::DoorPlateOptions options;
  CHECK_FALSE(options.Check());
  options.detector.scales = {1.0, 1.5};
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "detector.scales");
  options = {};
  options.detector.max_height_px = 3;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "detector.max_height_px");
  options = {};
  options.reader.min_digit_score = 1.5;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "reader.min_digit_score");
  // HOG cells must tile the patch: 7 px does not divide 60 x 30, 20 px leaves 1.5 rows of cells.
  for (const int cell : {7, 20, 1}) {
    options = {};
    options.detector.hog_cell_px = cell;
    REQUIRE(options.Check());
    CHECK(options.Check()->key == "detector.hog_cell_px");
  }
}

TEST_CASE("plate features: pixels, then HOG; the row length is PlateFeatureCount", "[plates]") {
  Image8 image;
  image.width = 120;
  image.height = 80;
  image.channels = 1;
  image.data.assign(std::size_t(120 * 80), 200);
  for (int y = 30; y < 50; ++y) {
    for (int x = 40; x < 80; x += 8) image.data[std::size_t(y * 120 + x)] = 20;  // digit strokes
  }
  const BoxPx box{38, 28, 82, 52};
  slam::DoorPlateDetectorOptions o;
  const cv::Mat with_hog = slam::PlatePatchFeatures(image, box, o);
  CHECK(with_hog.cols == slam::PlateFeatureCount(o));
  CHECK(with_hog.cols == 60 * 30 + 11 * 5 * 36);
  o.hog_cell_px = 0;
  const cv::Mat pixels = slam::PlatePatchFeatures(image, box, o);
  CHECK(pixels.cols == 60 * 30);
  CHECK(slam::PlateFeatureCount(o) == 60 * 30);
  // The pixels come first, unchanged; the HOG part describes the strokes (not all zero).
  CHECK(cv::norm(with_hog.colRange(0, pixels.cols), pixels, cv::NORM_INF) == 0.0);
  CHECK(cv::norm(with_hog.colRange(pixels.cols, with_hog.cols), cv::NORM_L1) > 1.0);
}

TEST_CASE("the detector finds the plate of a rendered lateral frame and reads its number",
          "[plates][render]") {
  const worlds::World& world = TestWorld();
  test::UploadedRig rig(world, test::LevelLateralRig());
  int plates_checked = 0;
  for (std::size_t k = 0; k < world.plates.size() && plates_checked < 3; k += 4) {
    const worlds::DoorPlate& plate = world.plates[k];
    for (const double distance_m : {0.8, 2.0}) {
      const test::LateralView view =
          test::ViewTarget(world, rig, plate.center, plate.normal, distance_m);
      const render::PlateTruth* truth = nullptr;
      for (const auto& p : view.truth.plates) {
        if (p.id == plate.id) truth = &p;
      }
      REQUIRE(truth);
      REQUIRE(truth->fully_in_image);
      const std::vector<slam::DoorPlateDetection> detections =
          slam::DetectDoorPlates(view.frame.rgb, ShippedModels(), slam::DoorPlateOptions{});
      const slam::DoorPlateDetection* found = nullptr;
      for (const auto& d : detections) {
        if (slam::IntersectionOverUnion(d.box_px, NumberBox(*truth)) >= 0.5) found = &d;
      }
      INFO("plate " << plate.room_number << " at " << distance_m << " m, font " << plate.font);
      REQUIRE(found);
      CHECK(found->svm_score > 0.0);
      // P1 section 3.2: every digit read with a score that clears the threshold.
      CHECK(found->reading.number == plate.room_number);
      CHECK(found->reading.accepted);
      REQUIRE(found->reading.digits.size() == plate.room_number.size());
      for (const slam::DigitReading& d : found->reading.digits) {
        CHECK(d.score >= slam::RoomNumberReaderOptions{}.min_digit_score);
        CHECK(d.box_px.min_x >= found->box_px.min_x - 0.3 * found->box_px.height());
        CHECK(d.box_px.max_x <= found->box_px.max_x + 0.3 * found->box_px.height());
      }
      for (std::size_t i = 1; i < found->reading.digits.size(); ++i) {
        CHECK(found->reading.digits[i].box_px.min_x > found->reading.digits[i - 1].box_px.min_x);
      }
    }
    ++plates_checked;
  }
  CHECK(plates_checked == 3);
}

TEST_CASE("the detector finds no plate on a bare wall", "[plates][render]") {
  const worlds::World& world = TestWorld();
  test::UploadedRig rig(world, test::LevelLateralRig());
  // A wall point 1 m from every plate, doorway and distractor.
  int walls_checked = 0;
  for (const worlds::Wall& wall : world.walls) {
    const Eigen::Vector2d d = (wall.end - wall.start);
    for (double s = 1.0; s + 1.0 < d.norm() && walls_checked < 3; s += 0.5) {
      const Eigen::Vector2d p2 = wall.start + d.normalized() * s;
      bool clear = true;
      for (const auto& p : world.plates) clear = clear && (p.center.head<2>() - p2).norm() > 2.0;
      for (const auto& x : world.distractors)
        clear = clear && (x.center.head<2>() - p2).norm() > 2.0;
      for (const auto& x : world.doors) {
        clear = clear && (x.column_a - p2).norm() > 2.0 && (x.column_b - p2).norm() > 2.0;
      }
      if (!clear) continue;
      const Eigen::Vector3d target(p2.x(), p2.y(), 1.5);
      const Eigen::Vector3d normal(wall.inward_normal.x(), wall.inward_normal.y(), 0.0);
      const test::LateralView view = test::ViewTarget(world, rig, target, normal, 1.0);
      if (!view.truth.plates.empty()) continue;
      const auto detections =
          slam::DetectDoorPlates(view.frame.rgb, ShippedModels(), slam::DoorPlateOptions{});
      INFO("wall " << wall.id << " at s = " << s << " m");
      CHECK(detections.empty());
      ++walls_checked;
      s += 3.0;
    }
  }
  CHECK(walls_checked == 3);
}

TEST_CASE("a missing or corrupt model file is a ModelFileError naming the file", "[plates]") {
  const test::ScratchDir dir("plate_models");
  // Missing.
  try {
    slam::DoorPlateModels::Load(dir.path());
    FAIL("no error");
  } catch (const slam::ModelFileError& e) {
    CHECK(e.path() == dir.path() / slam::kDoorPlateSvmFile);
    CHECK(std::string(e.what()).find(slam::kDoorPlateSvmFile) != std::string::npos);
  }
  // Corrupt: garbage, a truncated copy of the shipped model, a model of the wrong kind.
  const auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir.path() / name, std::ios::binary) << bytes;
  };
  std::string svm_text;
  {
    std::ifstream in(slam::DefaultModelsDir() / slam::kDoorPlateSvmFile, std::ios::binary);
    svm_text.assign(std::istreambuf_iterator<char>(in), {});
  }
  REQUIRE(svm_text.size() > 100);
  std::string mlp_text;
  {
    std::ifstream in(slam::DefaultModelsDir() / slam::kRoomNumberMlpFile, std::ios::binary);
    mlp_text.assign(std::istreambuf_iterator<char>(in), {});
  }
  for (const std::string& bad :
       {std::string("\x01\x02 not yaml {{{"), svm_text.substr(0, svm_text.size() / 2), mlp_text,
        std::string("%YAML:1.0\n---\nfoo: 1\n")}) {
    write(slam::kDoorPlateSvmFile, bad);
    write(slam::kRoomNumberMlpFile, mlp_text);
    try {
      slam::DoorPlateModels::Load(dir.path());
      FAIL("no error for an SVM file of " << bad.size() << " bytes");
    } catch (const slam::ModelFileError& e) {
      CHECK(e.path() == dir.path() / slam::kDoorPlateSvmFile);
    }
  }
  // A good SVM and a corrupt MLP: the MLP file is named.
  write(slam::kDoorPlateSvmFile, svm_text);
  write(slam::kRoomNumberMlpFile, svm_text);
  try {
    slam::DoorPlateModels::Load(dir.path());
    FAIL("no error");
  } catch (const slam::ModelFileError& e) {
    CHECK(e.path() == dir.path() / slam::kRoomNumberMlpFile);
  }
  // Both good: loads; models that do not fit the options are named too.
  write(slam::kRoomNumberMlpFile, mlp_text);
  const slam::DoorPlateModels models = slam::DoorPlateModels::Load(dir.path());
  slam::DoorPlateOptions options;
  options.detector.patch_width_px += 5;
  CHECK_THROWS_AS(slam::CheckModelsFit(models, options), slam::ModelFileError);
  options = {};
  options.detector.hog_cell_px = 0;  // pixels only: not what the shipped SVM was trained on
  CHECK_THROWS_AS(slam::CheckModelsFit(models, options), slam::ModelFileError);
}

}  // namespace
}  // namespace corridorsim
