// libFuzzer target: a detections file through what `corridorsim score` does with it
// (docs/fuzzing.md, docs/datasets.md). ParseDetections reads the bytes as a COCO results file
// against a fixed dataset (two images of 64x48 px, a label of every class), and detections it
// accepts are evaluated (EvaluateDetections: the matching, AP, the binned recall) and checked
// against an expectation of every class and metric, as `score --expect` does.
//
// Bad input must end in an InputError (exit 2). Anything else escaping (another exception type),
// an evaluation that does not count every accepted detection, or a metric that is not a finite
// number or null is a bug: the target aborts, and libFuzzer saves the input.

#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "fuzz/fuzz_checks.h"
#include "harness/workbench/score.h"

namespace {

using corridorsim::fuzz::Bug;
using corridorsim::fuzz::CheckFinite;

// One label of each class over two images, with appearance keys (the binned recall's quartiles).
constexpr const char* kAnnotations = R"({
 "images": [
  {"id": 1, "width": 64, "height": 48, "appearance": {"wall_brightness": 0.4, "camera_noise": 1}},
  {"id": 2, "width": 64, "height": 48, "appearance": {"wall_brightness": 0.8}}],
 "annotations": [
  {"id": 1, "image_id": 1, "category_id": 1, "bbox": [5, 5, 20, 10], "room_number": "101",
   "distance_m": 3, "viewing_angle_deg": 20},
  {"id": 2, "image_id": 1, "category_id": 2, "bbox": [30, 0, 20, 40], "distance_m": 9},
  {"id": 3, "image_id": 2, "category_id": 3, "bbox": [10, 10, 10, 10], "circle": [15, 15, 5],
   "distance_m": 1.5, "viewing_angle_deg": 61},
  {"id": 4, "image_id": 2, "category_id": 4, "bbox": [40, 20, 1, 1], "keypoints": [40.5, 20.5, 2]}],
 "categories": []})";

const corridorsim::ScoreDataset& Dataset() {
  static const corridorsim::ScoreDataset dataset = [] {
    corridorsim::ScoreDataset d = corridorsim::ParseScoreDataset(kAnnotations, "annotations.json");
    d.camera = "upward";
    return d;
  }();
  return dataset;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<corridorsim::ScoreDetection> detections;
  try {
    detections = corridorsim::ParseDetections(text, "detections.json", Dataset());
  } catch (const corridorsim::InputError&) {
    return 0;  // bad input, reported as it should be
  } catch (const std::exception& e) {
    Bug(std::string("ParseDetections threw something other than InputError: ") + e.what());
  }
  nlohmann::ordered_json classes;
  try {
    classes = corridorsim::EvaluateDetections(Dataset(), detections);
  } catch (const std::exception& e) {
    Bug(std::string("EvaluateDetections threw: ") + e.what());
  }
  CheckFinite(classes, "classes");
  std::size_t counted = 0;
  for (const auto& [name, c] : classes.items()) {
    counted += c.at("detections").get<std::size_t>();
    for (const auto& [metric, value] : c.items()) {
      if (!value.is_number() && !value.is_null()) continue;
      corridorsim::ScoreExpectation e;
      e.class_name = name;
      e.metric = metric;
      e.op = corridorsim::ScoreExpectation::Op::kGreaterEqual;
      e.value = 0.0;
      e.text = name + "." + metric + ">=0";
      const corridorsim::ScoreExpectationResult r = corridorsim::CheckScoreExpectation(classes, e);
      if (r.value.has_value() != value.is_number()) Bug("expectation value of " + e.text);
    }
  }
  if (counted != detections.size()) Bug("the classes do not count every detection");
  return 0;
}
