// Tests harness/workbench/score*.cpp (the input, the evaluation, the job): COCO's AP on
// hand-computed cases, matching thresholds for boxes, circles and corner points, reading accuracy,
// binned recall, expectations and every kind of bad detections file.
#include "harness/workbench/score.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "common/io/json_input.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

using Json = nlohmann::ordered_json;

// A dataset of `images` 100x80 images (ids 1..n) with the given annotations (COCO JSON objects).
ScoreDataset Dataset(int images, const std::vector<Json>& annotations,
                     const Json& appearance = Json()) {
  Json coco;
  coco["images"] = Json::array();
  for (int i = 1; i <= images; ++i) {
    Json image{{"id", i}, {"file_name", "x.png"}, {"width", 100}, {"height", 80}};
    if (!appearance.is_null()) image["appearance"] = appearance[i - 1];
    coco["images"].push_back(image);
  }
  coco["annotations"] = Json(annotations);
  coco["categories"] = Json::array();
  ScoreDataset dataset = ParseScoreDataset(coco.dump(), "annotations.json");
  dataset.camera = "upward";
  return dataset;
}

Json Box(int image, int category, double x, double y, double w, double h) {
  return {{"image_id", image}, {"category_id", category}, {"bbox", {x, y, w, h}}};
}

std::vector<ScoreDetection> Detections(const std::vector<Json>& detections,
                                       const ScoreDataset& dataset) {
  return ParseDetections(Json(detections).dump(), "d.json", dataset);
}

Json Scored(Json d, double score) {
  d["score"] = score;
  return d;
}

// The message ParseDetections throws ("" when none).
std::string ErrorOf(const std::string& text, const ScoreDataset& dataset) {
  try {
    ParseDetections(text, "d.json", dataset);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("perfect detections score AP 1, precision 1, recall 1", "[harness][score]") {
  const ScoreDataset dataset =
      Dataset(2, {Box(1, 1, 10, 10, 20, 10), Box(1, 1, 50, 10, 20, 10), Box(2, 1, 30, 30, 15, 15)});
  const Json result = EvaluateDetections(
      dataset,
      Detections({Scored(Box(1, 1, 10, 10, 20, 10), 0.9), Scored(Box(1, 1, 50, 10, 20, 10), 0.8),
                  Scored(Box(2, 1, 30, 30, 15, 15), 0.7)},
                 dataset));
  const Json& plates = result["door_plate"];
  CHECK(plates["labels"] == 3);
  CHECK(plates["detections"] == 3);
  CHECK(plates["ap50"].get<double>() == 1.0);
  CHECK(plates["ap"].get<double>() == 1.0);
  CHECK(plates["precision"].get<double>() == 1.0);
  CHECK(plates["recall"].get<double>() == 1.0);
  CHECK(plates["score_threshold"].get<double>() == 0.7);
  CHECK(plates["loc_error_px"].get<double>() == 0.0);
  // A class without labels has no AP or recall.
  CHECK(result["lamp"]["ap50"].is_null());
  CHECK(result["lamp"]["recall"].is_null());
}

TEST_CASE("half false positives: AP from COCO's 101-point interpolation", "[harness][score]") {
  // Two labels; ranked TP 0.9, FP 0.8, TP 0.7, FP 0.6: recall 0.5, 0.5, 1, 1 and precision
  // 1, 1/2, 2/3, 1/2, made non-increasing from the end: 1, 2/3, 2/3, 1/2. The 51 recall points
  // 0..0.50 take 1, the 50 points 0.51..1 take 2/3.
  const ScoreDataset dataset = Dataset(1, {Box(1, 3, 0, 0, 10, 10), Box(1, 3, 40, 40, 10, 10)});
  const Json result = EvaluateDetections(
      dataset,
      Detections({Scored(Box(1, 3, 0, 0, 10, 10), 0.9), Scored(Box(1, 3, 70, 0, 10, 10), 0.8),
                  Scored(Box(1, 3, 40, 40, 10, 10), 0.7), Scored(Box(1, 3, 70, 40, 10, 10), 0.6)},
                 dataset));
  const double expected = (51.0 + 50.0 * 2.0 / 3.0) / 101.0;
  CHECK(result["lamp"]["ap50"].get<double>() == Approx(expected).epsilon(1e-6));
  CHECK(result["lamp"]["ap"].get<double>() == Approx(expected).epsilon(1e-6));
  // Best F1 (0.8) at the cut 0.7: precision 2/3, recall 1 (the cut 0.6 has F1 2/3).
  CHECK(result["lamp"]["score_threshold"].get<double>() == 0.7);
  CHECK(result["lamp"]["precision"].get<double>() == Approx(2.0 / 3.0).epsilon(1e-6));
  CHECK(result["lamp"]["recall"].get<double>() == 1.0);
}

TEST_CASE("a known precision-recall curve over two images", "[harness][score]") {
  // Four labels; ranked TP .95, TP .9, FP .8, TP .6, FP .5 (one label never found): recall
  // .25 .5 .5 .75 .75, precision 1 1 2/3 3/4 3/5 -> non-increasing 1 1 3/4 3/4 3/5. Points
  // 0..0.50 (51) take 1, 0.51..0.75 (25) take 3/4, 0.76..1 (25) take 0.
  const ScoreDataset dataset = Dataset(2, {Box(1, 2, 0, 0, 10, 10), Box(1, 2, 20, 0, 10, 10),
                                           Box(2, 2, 0, 0, 10, 10), Box(2, 2, 20, 20, 10, 10)});
  const Json result = EvaluateDetections(
      dataset,
      Detections({Scored(Box(1, 2, 0, 0, 10, 10), 0.95), Scored(Box(2, 2, 0, 0, 10, 10), 0.9),
                  Scored(Box(1, 2, 60, 60, 10, 10), 0.8), Scored(Box(1, 2, 20, 0, 10, 10), 0.6),
                  Scored(Box(2, 2, 60, 0, 10, 10), 0.5)},
                 dataset));
  CHECK(result["door"]["ap50"].get<double>() == Approx((51.0 + 25.0 * 0.75) / 101.0).epsilon(1e-6));
  CHECK(result["door"]["score_threshold"].get<double>() == 0.6);
  CHECK(result["door"]["precision"].get<double>() == 0.75);
  CHECK(result["door"]["recall"].get<double>() == 0.75);
  const Json& curve = result["door"]["pr_curve_precision_at_recall_0_to_1"];
  REQUIRE(curve.size() == 101);
  CHECK(curve[50].get<double>() == 1.0);
  CHECK(curve[51].get<double>() == 0.75);
  CHECK(curve[75].get<double>() == 0.75);
  CHECK(curve[76].get<double>() == 0.0);
}

TEST_CASE("a box matches at the IoU thresholds it reaches", "[harness][score]") {
  // IoU 0.72: matched at 0.50 .. 0.70 (5 of 10 thresholds).
  const ScoreDataset dataset = Dataset(1, {Box(1, 1, 0, 0, 10, 10)});
  const Json result =
      EvaluateDetections(dataset, Detections({Scored(Box(1, 1, 0, 0, 10, 7.2), 0.5)}, dataset));
  CHECK(result["door_plate"]["ap50"].get<double>() == 1.0);
  CHECK(result["door_plate"]["ap"].get<double>() == Approx(0.5).epsilon(1e-9));
  CHECK(result["door_plate"]["loc_error_px"].get<double>() == Approx(1.4).epsilon(1e-9));
  // Below 0.5 it is a false positive and the label is missed.
  const Json miss =
      EvaluateDetections(dataset, Detections({Scored(Box(1, 1, 0, 0, 10, 4.9), 0.5)}, dataset));
  CHECK(miss["door_plate"]["ap50"].get<double>() == 0.0);
  CHECK(miss["door_plate"]["recall"].get<double>() == 0.0);
  CHECK(miss["door_plate"]["loc_error_px"].is_null());
}

TEST_CASE("greedy matching: the higher score takes the label", "[harness][score]") {
  // Two detections on one label: the better-scored one matches even with the lower IoU.
  const ScoreDataset dataset = Dataset(1, {Box(1, 1, 0, 0, 10, 10)});
  const Json result = EvaluateDetections(
      dataset,
      Detections({Scored(Box(1, 1, 0, 0, 10, 10), 0.4), Scored(Box(1, 1, 0, 0, 10, 8.2), 0.9)},
                 dataset));
  // IoU 0.82 for the 0.9 box: ranked TP 0.9 then FP 0.4 up to the threshold 0.80 (AP 1); above
  // it the 0.9 box misses and the 0.4 box (IoU 1) matches: precision 1/2 at recall 1.
  CHECK(result["door_plate"]["ap50"].get<double>() == 1.0);
  CHECK(result["door_plate"]["loc_error_px"].get<double>() == Approx(0.9).epsilon(1e-9));
  CHECK(result["door_plate"]["ap"].get<double>() == Approx((7 * 1.0 + 3 * 0.5) / 10).epsilon(1e-6));
}

TEST_CASE("lamp circles are matched by their exact IoU", "[harness][score]") {
  CHECK(CircleIou({0, 0, 2}, {0, 0, 2}) == Approx(1.0));
  CHECK(CircleIou({0, 0, 1}, {5, 0, 1}) == 0.0);
  CHECK(CircleIou({0, 0, 1}, {0, 0, 2}) == Approx(0.25));
  // Two unit circles one radius apart: the lens is 2 pi / 3 - sqrt(3) / 2.
  const double lens = 2.0 * std::numbers::pi / 3.0 - std::sqrt(3.0) / 2.0;
  CHECK(CircleIou({0, 0, 1}, {1, 0, 1}) == Approx(lens / (2.0 * std::numbers::pi - lens)));

  Json label = Box(1, 3, 40, 30, 20, 20);
  label["circle"] = {50, 40, 10};
  const ScoreDataset dataset = Dataset(1, {label});
  // A circle of radius 7.1 inside the label's: IoU 0.504 (matched at 0.5 only).
  const Json result = EvaluateDetections(
      dataset,
      Detections({{{"image_id", 1}, {"category_id", 3}, {"circle", {50, 40, 7.1}}, {"score", 1.0}}},
                 dataset));
  CHECK(result["lamp"]["ap50"].get<double>() == 1.0);
  CHECK(result["lamp"]["ap"].get<double>() == Approx(0.1).epsilon(1e-9));
}

TEST_CASE("corners match a keypoint within 10 .. 1 px", "[harness][score]") {
  Json label = Box(1, 4, 10, 10, 1, 1);
  label["keypoints"] = {10.5, 10.5, 2};
  const ScoreDataset dataset = Dataset(1, {label});
  // 5 px away: matched at 10, 9, 8, 7, 6 and 5 px (6 of 10 thresholds).
  const Json result = EvaluateDetections(
      dataset,
      Detections({{{"image_id", 1}, {"category_id", 4}, {"point", {13.5, 14.5}}, {"score", 0.3}}},
                 dataset));
  CHECK(result["ceiling_corner"]["ap50"].get<double>() == 1.0);
  CHECK(result["ceiling_corner"]["ap"].get<double>() == Approx(0.6).epsilon(1e-9));
  CHECK(result["ceiling_corner"]["loc_error_px"].get<double>() == 5.0);
  // `keypoints` works the same; 11 px away is a false positive.
  const Json far = EvaluateDetections(
      dataset,
      Detections(
          {{{"image_id", 1}, {"category_id", 4}, {"keypoints", {21.5, 10.5, 2}}, {"score", 0.3}}},
          dataset));
  CHECK(far["ceiling_corner"]["ap50"].get<double>() == 0.0);
  CHECK(far["ceiling_corner"]["precision"].get<double>() == 0.0);
}

TEST_CASE("reading accuracy counts matched plates that give a room number", "[harness][score]") {
  Json a = Box(1, 1, 0, 0, 20, 10), b = Box(1, 1, 30, 0, 20, 10), c = Box(1, 1, 60, 0, 20, 10);
  a["room_number"] = "101";
  b["room_number"] = "102";
  c["room_number"] = "103";
  const ScoreDataset dataset = Dataset(1, {a, b, c});
  Json right = Scored(Box(1, 1, 0, 0, 20, 10), 0.9), wrong = Scored(Box(1, 1, 30, 0, 20, 10), 0.8);
  right["room_number"] = "101";
  wrong["room_number"] = "108";
  Json unread = Scored(Box(1, 1, 60, 0, 20, 10), 0.7);
  Json unmatched = Scored(Box(1, 1, 0, 50, 20, 10), 0.6);
  unmatched["room_number"] = "101";
  const Json result =
      EvaluateDetections(dataset, Detections({right, wrong, unread, unmatched}, dataset));
  CHECK(result["door_plate"]["reading_accuracy"].get<double>() == 0.5);
  CHECK(result["door_plate"]["readings"] == 2);
}

TEST_CASE("recall is binned by distance, viewing angle and appearance quartiles",
          "[harness][score]") {
  Json near = Box(1, 3, 0, 0, 10, 10), far = Box(2, 3, 0, 0, 10, 10);
  near["distance_m"] = 1.0;
  near["viewing_angle_deg"] = 10.0;
  far["distance_m"] = 9.0;
  far["viewing_angle_deg"] = 70.0;
  const ScoreDataset dataset =
      Dataset(2, {near, far}, Json::array({{{"exposure", 1.0}}, {{"exposure", 3.0}}}));
  const Json result =
      EvaluateDetections(dataset, Detections({Scored(Box(1, 3, 0, 0, 10, 10), 1.0)}, dataset));
  const Json& by_distance = result["lamp"]["recall_by_distance_m"];
  REQUIRE(by_distance.size() == 4);
  CHECK(by_distance[0]["recall"].get<double>() == 1.0);
  CHECK(by_distance[1]["recall"].is_null());
  CHECK(by_distance[3]["labels"] == 1);
  CHECK(by_distance[3]["recall"].get<double>() == 0.0);
  const Json& by_angle = result["lamp"]["recall_by_viewing_angle_deg"];
  CHECK(by_angle[0]["recall"].get<double>() == 1.0);
  CHECK(by_angle[4]["recall"].get<double>() == 0.0);
  // Quartiles of 1 and 3: 1, 1.5, 2, 2.5; the bins [1, 1.5) and [2.5, 3].
  const Json& by_exposure = result["lamp"]["recall_by_appearance"]["exposure"];
  REQUIRE(by_exposure.size() == 4);
  CHECK(by_exposure[0]["bin"] == "1-1.5");
  CHECK(by_exposure[0]["recall"].get<double>() == 1.0);
  CHECK(by_exposure[3]["bin"] == "2.5-3");
  CHECK(by_exposure[3]["recall"].get<double>() == 0.0);
}

TEST_CASE("score's --expect checks pass, fail, and fail on undefined values", "[harness][score]") {
  const Json evaluation = {{"lamp", {{"ap50", 0.8}, {"recall", nullptr}}}};
  const auto check = [&](const char* metric, ScoreExpectation::Op op, double value) {
    ScoreExpectation e;
    e.class_name = "lamp";
    e.metric = metric;
    e.op = op;
    e.value = value;
    return CheckScoreExpectation(evaluation, e).passed;
  };
  CHECK(check("ap50", ScoreExpectation::Op::kGreaterEqual, 0.8));
  CHECK_FALSE(check("ap50", ScoreExpectation::Op::kGreater, 0.8));
  CHECK(check("ap50", ScoreExpectation::Op::kLess, 0.9));
  CHECK_FALSE(check("ap50", ScoreExpectation::Op::kLessEqual, 0.7));
  CHECK_FALSE(check("recall", ScoreExpectation::Op::kGreaterEqual, 0.0));
}

TEST_CASE("bad detections files name the file, the entry and the field", "[harness][score]") {
  const ScoreDataset dataset = Dataset(1, {});
  const auto entry = [](const std::string& fields) {
    return "[{\"image_id\": 1, \"category_id\": 1, \"score\": 0.5, \"bbox\": [1, 2, 3, 4]}, {" +
           fields + "}]";
  };
  CHECK(ErrorOf(entry("\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1,1]"),
                dataset) == "");
  CHECK_THAT(ErrorOf("[{\"image_id\": 1,", dataset),
             Catch::StartsWith("d.json: malformed JSON at byte 17: "));
  CHECK_THAT(ErrorOf("{}", dataset), Catch::StartsWith("d.json: expected a JSON array"));
  // JSON has no infinities: a number too large for a double is refused by the parser.
  CHECK_THAT(ErrorOf(entry("\"image_id\": 1, \"category_id\": 1, \"score\": 1e999"), dataset),
             Catch::StartsWith("d.json: malformed JSON: number overflow parsing '1e999'"));
  CHECK_THAT(ErrorOf("[{\"image_id\": 1, \"category_id\": 1, \"score\": 0.5, \"bbox\": [1, 2, 3, "
                     "4]}, 7]",
                     dataset),
             Catch::StartsWith("d.json: [1]: expected an object"));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"\"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1,1]", "d.json: [1].image_id: missing"},
      {"\"image_id\": \"1\", \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1,1]",
       "d.json: [1].image_id: expected an integer"},
      {"\"image_id\": 2, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1,1]",
       "d.json: [1].image_id: no image of the dataset's upward camera has id 2"},
      {"\"image_id\": 1, \"category_id\": 5, \"score\": 1, \"bbox\": [0,0,1,1]",
       "d.json: [1].category_id: unknown category 5"},
      {"\"image_id\": 1, \"category_id\": 1, \"bbox\": [0,0,1,1]", "d.json: [1].score: missing"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1", "d.json: [1].bbox: missing"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1]",
       "d.json: [1].bbox: expected an array of 4 numbers"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,\"1\",1]",
       "d.json: [1].bbox[2]: expected a number"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,-1,1]",
       "d.json: [1].bbox: a box with negative width or height"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [101,0,5,5]",
       "d.json: [1].bbox: the box lies outside the image"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [-10,-10,5,5]",
       "d.json: [1].bbox: the box lies outside the image"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"circle\": [5,5,1]",
       "d.json: [1].circle: only lamps"},
      {"\"image_id\": 1, \"category_id\": 3, \"score\": 1, \"circle\": [5,5,-1]",
       "d.json: [1].circle: a negative radius"},
      {"\"image_id\": 1, \"category_id\": 3, \"score\": 1, \"circle\": [200,5,1]",
       "d.json: [1].circle: the circle lies outside the image"},
      {"\"image_id\": 1, \"category_id\": 3, \"score\": 1",
       "d.json: [1].bbox: missing (a lamp gives `bbox` or `circle`)"},
      {"\"image_id\": 1, \"category_id\": 4, \"score\": 1, \"point\": [5]",
       "d.json: [1].point: expected an array of 2 numbers"},
      {"\"image_id\": 1, \"category_id\": 4, \"score\": 1, \"point\": [5, 90]",
       "d.json: [1].point: the point lies outside the image"},
      {"\"image_id\": 1, \"category_id\": 2, \"score\": 1, \"point\": [5, 5]",
       "d.json: [1].point: only ceiling corners"},
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1,1], \"room_number\": "
       "101",
       "d.json: [1].room_number: expected a string"},
      // Huge geometry that still overlaps the image: its area would overflow to inf.
      {"\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [-1e300,0,2e300,1]",
       "d.json: [1].bbox: a coordinate beyond +-1e+06 px"},
      {"\"image_id\": 1, \"category_id\": 3, \"score\": 1, \"circle\": [5,5,1e200]",
       "d.json: [1].circle: a coordinate beyond +-1e+06 px"},
  };
  for (const auto& [fields, message] : cases) {
    INFO(fields);
    CHECK_THAT(ErrorOf(entry(fields), dataset), Catch::StartsWith(message));
  }
}

TEST_CASE("a detections file's nesting and size are bounded before it is parsed",
          "[harness][score]") {
  const ScoreDataset dataset = Dataset(1, {});
  // 50 MB of `[` needed gigabytes: the nesting is refused at the 65th bracket, with its line.
  CHECK(ErrorOf("\n" + std::string(1000000, '['), dataset) ==
        "d.json:2:65: more than 64 nested arrays and objects");
  CHECK(ErrorOf("[{\"a\": " + std::string(70, '{'), dataset) ==
        "d.json:1:70: more than 64 nested arrays and objects");
  // Brackets inside strings are text.
  CHECK(ErrorOf("[{\"image_id\": 1, \"category_id\": 1, \"score\": 1, \"bbox\": [0,0,1,1], "
                "\"room_number\": \"" +
                    std::string(100, '[') + "\\\"\"}]",
                dataset) == "");
  // One entry holds at most kMaxJsonValues values.
  std::string big = "[[0";
  for (std::size_t i = 0; i < kMaxJsonValues; ++i) big += ",0";
  big += "]]";
  CHECK_THAT(ErrorOf(big, dataset),
             Catch::Contains("more than 10000000 values in one element of the top-level array"));
}

TEST_CASE("detections are read entry by entry, in order", "[harness][score]") {
  const ScoreDataset dataset = Dataset(2, {});
  std::vector<Json> entries;
  for (int i = 0; i < 3000; ++i) entries.push_back(Scored(Box(1 + i % 2, 1, i % 50, 1, 2, 2), i));
  const std::vector<ScoreDetection> d = Detections(entries, dataset);
  REQUIRE(d.size() == entries.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    CHECK(d[i].image_id == int(1 + i % 2));
    CHECK(d[i].score == double(i));
    CHECK((*d[i].bbox)[0] == double(i % 50));
  }
  // A bad entry after good ones is still named by its index.
  entries.push_back(Json::array());
  CHECK_THAT(ErrorOf(Json(entries).dump(), dataset),
             Catch::StartsWith("d.json: [3000]: expected an object"));
  CHECK_THAT(ErrorOf("7", dataset), Catch::StartsWith("d.json: expected a JSON array"));
}

TEST_CASE("bad annotations files name the file and the field", "[harness][score]") {
  const auto error = [](const std::string& images, const std::string& annotations) {
    try {
      ParseScoreDataset("{\"images\": [" + images + "], \"annotations\": [" + annotations + "]}",
                        "a.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string image = "{\"id\": 1, \"width\": 64, \"height\": 48}";
  CHECK(error(image, "") == "");
  // An int64 width wrapped to a small or negative int before.
  CHECK(error("{\"id\": 1, \"width\": 4294967360, \"height\": 48}", "") ==
        "a.json: images[0].width: outside [1, 65536] px");
  CHECK(error("{\"id\": 1, \"width\": 64, \"height\": 0}", "") ==
        "a.json: images[0].height: outside [1, 65536] px");
  CHECK(error(image, "{\"image_id\": 1, \"category_id\": 1, \"bbox\": [0, 0, 1e300, 1e300]}") ==
        "a.json: annotations[0].bbox: a coordinate beyond +-1e+06 px");
  CHECK(error(image, "{\"image_id\": 1, \"category_id\": 1, \"bbox\": [0, 0, -1, 1]}") ==
        "a.json: annotations[0].bbox: a box with negative width or height");
  CHECK(error(image,
              "{\"image_id\": 1, \"category_id\": 3, \"bbox\": [0, 0, 1, 1], "
              "\"circle\": [1, 1, -2]}") == "a.json: annotations[0].circle: a negative radius");
  // score.png draws a panel per appearance key: their number is bounded.
  std::string keys;
  for (int k = 0; k <= int(kMaxAppearanceKeys); ++k) {
    keys += (k ? ", \"k" : "\"k") + std::to_string(k) + "\": 1";
  }
  CHECK(error("{\"id\": 1, \"width\": 64, \"height\": 48, \"appearance\": {" + keys + "}}", "") ==
        "a.json: images[0].appearance: more than 32 distinct appearance keys in the "
        "file");
  CHECK_THAT(error(std::string(100, '['), ""), Catch::StartsWith("a.json:1:"));
}

TEST_CASE("score writes its report for a detections file whose name is not UTF-8",
          "[harness][score]") {
  const test::ScratchDir dir("score_odd_name");
  const auto write = [](const std::filesystem::path& path, const std::string& text) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
  };
  write(dir.path() / "ds" / "dataset.json",
        "{\"format\": \"corridorsim dataset\", \"cameras\": [\"upward\"]}");
  write(dir.path() / "ds" / "upward" / "annotations.json",
        "{\"images\": [{\"id\": 1, \"width\": 64, \"height\": 48}], \"annotations\": []}");
  ScoreRequest request;
  request.detections_file = dir.path() / "d\xff.json";  // score.json's dump threw: exit 1
  write(request.detections_file, "[]");
  request.dataset_dir = dir.path() / "ds";
  request.report_dir = dir.path() / "report";
  CHECK(RunScore(request) == 0);
  const Json report = Json::parse(test::FileBytes(dir.path() / "report" / "score.json"));
  CHECK(report["detections_file"] == "d\xef\xbf\xbd.json");  // U+FFFD in place of the byte
}

}  // namespace
}  // namespace corridorsim
