// slam/features/room_number_reader.cpp: P1 section 3.2 on rendered plates and a digit-bearing
// poster, with the shipped MLP; and the number region of the ground truth (render::PlateTruth)
// against the rendered plate's text pixels.
#include <catch2/catch.hpp>

#include "slam/features/door_plates.h"
#include "tests/support/door_plate_truth.h"
#include "tests/support/generated_worlds.h"
#include "tests/support/lateral_views.h"

namespace corridorsim {
namespace {

using slam::BoxPx;
using test::NumberBox;
using test::ShippedModels;
using test::TruthOf;

const worlds::World& TestWorld() { return test::GeneratedWorld(23); }

TEST_CASE("the projected number box holds the rendered plate's text pixels", "[plates][render]") {
  const worlds::World& world = TestWorld();
  test::UploadedRig rig(world, test::LevelLateralRig());
  const worlds::DoorPlate& plate = world.plates.front();
  // The region lies inside the plate face and is not empty.
  CHECK(plate.number_min_in_face.x() < plate.number_max_in_face.x());
  CHECK(plate.number_min_in_face.y() < plate.number_max_in_face.y());
  CHECK(plate.number_min_in_face.cwiseAbs().maxCoeff() <= plate.size_m.maxCoeff() / 2);
  CHECK(plate.number_max_in_face.x() <= plate.size_m.x() / 2);
  CHECK(plate.number_max_in_face.y() <= plate.size_m.y() / 2);

  render::RigOptions exact = test::LevelLateralRig();
  exact.cameras.front().noise = false;
  test::UploadedRig exact_rig(world, exact);
  const test::LateralView view =
      test::ViewTarget(world, exact_rig, plate.center, plate.normal, 0.7);
  const render::PlateTruth* truth = TruthOf(view, plate.id);
  REQUIRE(truth);
  REQUIRE(truth->fully_in_image);
  const BoxPx number = NumberBox(*truth);
  const BoxPx outline{truth->bbox_min_px.x(), truth->bbox_min_px.y(), truth->bbox_max_px.x(),
                      truth->bbox_max_px.y()};
  CHECK(number.width() < outline.width());
  CHECK(number.height() < outline.height());
  // Text pixels: inside the plate's outline (2 px in from its edge, clear of any border line),
  // far from the plate's own colour, taken as the median of the outline's inner ring.
  const Image8& rgb = view.frame.rgb;
  const auto grey = [&](int x, int y) {
    const std::uint8_t* p = rgb.Pixel(x, y);
    return (int(p[0]) + p[1] + p[2]) / 3;
  };
  std::vector<int> ring;
  const int x0 = int(std::ceil(outline.min_x)) + 2, x1 = int(std::floor(outline.max_x)) - 2;
  const int y0 = int(std::ceil(outline.min_y)) + 2, y1 = int(std::floor(outline.max_y)) - 2;
  const int border = int(std::round(outline.height() * (plate.border_px * 2 + 4) / 128.0));
  for (int x = x0 + border; x <= x1 - border; ++x) {
    ring.push_back(grey(x, y0 + border));
    ring.push_back(grey(x, y1 - border));
  }
  std::nth_element(ring.begin(), ring.begin() + ring.size() / 2, ring.end());
  const int background = ring[ring.size() / 2];
  int text = 0, outside = 0;
  for (int y = y0 + border; y <= y1 - border; ++y) {
    for (int x = x0 + border; x <= x1 - border; ++x) {
      if (std::abs(grey(x, y) - background) < 60) continue;
      ++text;
      // 1 px of slack for anti-aliasing at the region's edge.
      if (x < number.min_x - 1 || x > number.max_x + 1 || y < number.min_y - 1 ||
          y > number.max_y + 1) {
        ++outside;
      }
    }
  }
  INFO("plate " << plate.room_number << " font " << plate.font << " background " << background);
  CHECK(text > 100);
  CHECK(outside == 0);
  // And the region is tight: text reaches each of its sides.
  int left = 0, right = 0;
  for (int y = int(number.min_y); y <= int(number.max_y); ++y) {
    left += std::abs(grey(int(std::ceil(number.min_x + 1)), y) - background) >= 60;
    right += std::abs(grey(int(std::floor(number.max_x - 1)), y) - background) >= 60;
  }
  CHECK(left > 0);
  CHECK(right > 0);
}

TEST_CASE("the reader reads a rendered plate's truth box with every digit above threshold",
          "[plates][render]") {
  const worlds::World& world = TestWorld();
  test::UploadedRig rig(world, test::LevelLateralRig());
  const slam::RoomNumberReaderOptions options;
  int read = 0;
  for (std::size_t k = 1; k < world.plates.size(); k += 3) {
    const worlds::DoorPlate& plate = world.plates[k];
    const test::LateralView view = test::ViewTarget(world, rig, plate.center, plate.normal, 1.2);
    const render::PlateTruth* truth = TruthOf(view, plate.id);
    REQUIRE(truth);
    const slam::RoomNumberReading reading =
        slam::ReadRoomNumber(view.frame.rgb, NumberBox(*truth), *ShippedModels().mlp, options);
    INFO("plate " << plate.room_number << " font " << plate.font << " read " << reading.number);
    CHECK(reading.number == plate.room_number);
    CHECK(reading.accepted);
    CHECK(reading.min_score >= options.min_digit_score);
    for (const auto& d : reading.digits) CHECK(d.score >= options.min_digit_score);
    ++read;
  }
  CHECK(read >= 3);
}

TEST_CASE("a digit-bearing poster gives no accepted plate reading", "[plates][render]") {
  const worlds::World& world = TestWorld();
  test::UploadedRig rig(world, test::LevelLateralRig());
  int posters = 0;
  for (const worlds::Distractor& d : world.distractors) {
    if (d.semantic_class != worlds::SemanticClass::kPoster || d.text.empty()) continue;
    const test::LateralView view =
        test::ViewTarget(world, rig, d.center + d.normal * (d.size_m.y() / 2), d.normal, 1.5);
    if (!view.truth.plates.empty()) continue;  // a plate in view as well: not this test
    const auto detections =
        slam::DetectDoorPlates(view.frame.rgb, ShippedModels(), slam::DoorPlateOptions{});
    INFO("poster " << d.id << " text " << d.text);
    for (const auto& det : detections) {
      INFO("read " << det.reading.number << " svm score " << det.svm_score << " box "
                   << det.box_px.min_x << " " << det.box_px.min_y << " " << det.box_px.max_x << " "
                   << det.box_px.max_y);
      CHECK_FALSE(det.reading.accepted);
    }
    ++posters;
  }
  CHECK(posters >= 2);
}

TEST_CASE("reader options: defaults pass; digit bounds are checked", "[plates]") {
  slam::RoomNumberReaderOptions o;
  CHECK_FALSE(o.Check());
  o.max_digits = 1;
  REQUIRE(o.Check());
  CHECK(o.Check()->key == "max_digits");
  o = {};
  CHECK(slam::DigitFeatureCount(o) ==
        o.cell_width_px + o.cell_height_px + 1 + o.zone_cols * o.zone_rows);
  o.zone_cols = 0;
  REQUIRE(o.Check());
  CHECK(o.Check()->key == "zone_rows");
}

}  // namespace
}  // namespace corridorsim
