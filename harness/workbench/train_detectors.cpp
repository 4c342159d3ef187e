#include "harness/workbench/train_detectors.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string_view>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "common/io/stable_json.h"
#include "common/random.h"
#include "harness/run/frame_io.h"
#include "harness/run/run_folder.h"
#include "harness/run/simulation_setup.h"
#include "harness/workbench/dataset.h"
#include "harness/workbench/detect.h"
#include "render/frame_truth.h"
#include "worlds/image_io.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector2d;

// Report binning (P1 reads plates within 3 m and 30 deg).
constexpr std::array<double, 5> kDistanceEdges{0.0, 1.0, 2.0, 3.0, 4.0};
constexpr std::array<double, 6> kAngleEdges{0.0, 10.0, 20.0, 30.0, 45.0, 60.0};
constexpr double kTargetDistanceM = 3.0;
constexpr double kTargetAngleDeg = 30.0;
constexpr double kTargetReadFraction = 0.98;
constexpr double kTargetFalseFraction = 0.005;
constexpr double kMatchIou = 0.5;       // a candidate is the plate's number region (brief, P1)
constexpr double kNegativeIou = 0.3;    // below this against every number region: a negative
constexpr double kSeenFraction = 0.95;  // a plate counts as seen: whole and unoccluded

slam::BoxPx NumberBox(const render::PlateTruth& p) {
  return slam::BoxPx{p.number_bbox_min_px.x(), p.number_bbox_min_px.y(), p.number_bbox_max_px.x(),
                     p.number_bbox_max_px.y()};
}
slam::BoxPx PlateBox(const render::PlateTruth& p) {
  return slam::BoxPx{p.bbox_min_px.x(), p.bbox_min_px.y(), p.bbox_max_px.x(), p.bbox_max_px.y()};
}
// The part of a box inside the image, [0, width] x [0, height] (as detections' boxes lie).
slam::BoxPx InImage(const slam::BoxPx& b, const Image8& image) {
  return slam::BoxPx{std::max(b.min_x, 0.0), std::max(b.min_y, 0.0),
                     std::min(b.max_x, double(image.width)),
                     std::min(b.max_y, double(image.height))};
}
// The fraction of b's area that a covers.
double Coverage(const slam::BoxPx& a, const slam::BoxPx& b) {
  const double ix = std::min(a.max_x, b.max_x) - std::max(a.min_x, b.min_x);
  const double iy = std::min(a.max_y, b.max_y) - std::max(a.min_y, b.min_y);
  const double area = b.width() * b.height();
  return ix > 0 && iy > 0 && area > 0 ? ix * iy / area : 0.0;
}
bool Seen(const render::PlateTruth& p) {
  return p.fully_in_image && p.visible_fraction >= kSeenFraction;
}

using Json = nlohmann::ordered_json;

// A labelled lateral view: the image and the door plates its truth file lists.
struct LabelledView {
  Image8 rgb;
  std::vector<render::PlateTruth> plates;
};
using PlateFonts = std::map<int, std::string>;  // plate id -> font, of one world

// A plate id of a truth or ground-truth file: a non-negative int.
int PlateId(const JsonField& plate) {
  const std::int64_t id = plate.At("id").Integer();
  if (id < 0 || id > std::numeric_limits<int>::max()) plate.At("id").Fail("out of range");
  return static_cast<int>(id);
}

// The plates of a dataset truth file as FrameTruthJson wrote them (docs/datasets.md). Both view
// sets read them from this JSON, so that a model trained in memory equals one trained from the
// folder `dataset` writes.
std::vector<render::PlateTruth> PlatesOfTruth(const Json& truth, const std::string& file) {
  const JsonField plates = JsonField{file, "", truth}.At("plates");
  const auto pixel = [](const JsonField& f) {
    const std::array<double, 2> p = f.Numbers<2>();
    return Vector2d(p[0], p[1]);
  };
  std::vector<render::PlateTruth> out;
  for (std::size_t i = 0; i < plates.ArraySize(); ++i) {
    const JsonField p = plates.At(i);
    render::PlateTruth t;
    t.id = PlateId(p);
    t.room_number = p.At("room_number").String();
    if (t.room_number.empty() || t.room_number.size() > 16 ||
        !std::all_of(t.room_number.begin(), t.room_number.end(),
                     [](char c) { return c >= '0' && c <= '9'; })) {
      p.At("room_number").Fail("expected 1 to 16 digits");
    }
    t.bbox_min_px = pixel(p.At("bbox_px").At("min"));
    t.bbox_max_px = pixel(p.At("bbox_px").At("max"));
    t.number_bbox_min_px = pixel(p.At("number_bbox_px").At("min"));
    t.number_bbox_max_px = pixel(p.At("number_bbox_px").At("max"));
    t.distance_m = p.At("distance_m").Number();
    t.viewing_angle_deg = p.At("viewing_angle_deg").Number();
    t.visible_fraction = p.At("visible_fraction").Number();
    t.fully_in_image = p.At("fully_in_image").Bool();
    out.push_back(std::move(t));
  }
  return out;
}

// The labelled views of one set (training or evaluation), world by world.
class ViewSet {
 public:
  virtual ~ViewSet() = default;
  virtual int worlds() const = 0;
  virtual std::uint64_t world_seed(int w) const = 0;
  /// Calls `each` with world w's views in frame order and the world's plate fonts.
  virtual void ForEachView(
      int w, const std::function<void(const LabelledView&, const PlateFonts&)>& each) const = 0;
  virtual Json Source() const = 0;
};

// Rendered in memory through the dataset's generator (DatasetWorld, --poses plates): the frames
// `corridorsim dataset scenarios/datasets/train_detectors.yaml --cameras lateral --poses plates`
// writes.
class BuiltInViews : public ViewSet {
 public:
  BuiltInViews(std::uint64_t first_seed, int worlds, int views)
      : scenario_(TrainingScenario()),
        backend_(ChooseBackend(scenario_.rig.backend)),
        first_seed_(first_seed),
        worlds_(worlds),
        views_(views) {}
  int worlds() const override { return worlds_; }
  std::uint64_t world_seed(int w) const override { return first_seed_ + std::uint64_t(w); }
  void ForEachView(int w, const std::function<void(const LabelledView&, const PlateFonts&)>& each)
      const override {
    DatasetWorld world(scenario_, scenario_.rig, backend_, world_seed(w), w, worlds_,
                       DatasetPoseMode::kPlates, views_);
    PlateFonts fonts;
    for (const worlds::DoorPlate& p : world.world().plates) fonts[p.id] = p.font;
    for (int f = 0; f < views_; ++f) {
      std::vector<DatasetFrame> frames = world.Render(f);
      CheckOrDie(frames.size() == 1, "BuiltInViews", "the training rig has one camera");
      LabelledView view{std::move(frames[0].frame.rgb),
                        PlatesOfTruth(frames[0].truth, "the built-in training scenario")};
      each(view, fonts);
    }
  }
  Json Source() const override {
    return {{"scenario", "scenarios/datasets/train_detectors.yaml (built in)"},
            {"poses", "plates"},
            {"seed", first_seed_},
            {"worlds", worlds_},
            {"frames_per_world", views_}};
  }

 private:
  Scenario scenario_;
  render::BackendKind backend_;
  std::uint64_t first_seed_;
  int worlds_, views_;
};

// A folder `corridorsim dataset` wrote (any scenario and pose mode): its lateral camera's images
// and truth files, and each world's plate fonts from its ground_truth.json.
class DatasetFolderViews : public ViewSet {
 public:
  DatasetFolderViews(const fs::path& dir, const char* option) : dir_(dir) {
    std::error_code error;
    if (!fs::is_directory(dir, error)) {
      throw InputError(SourceLocation{"command line", 0, 0}, option,
                       dir.string() + " is not a folder");
    }
    const DatasetManifest manifest = ReadDatasetManifest(dir);
    const JsonField top{manifest.file, "", manifest.json};
    if (top.At("format_version").Integer() != 1) top.At("format_version").Fail("expected 1");
    if (std::find(manifest.cameras.begin(), manifest.cameras.end(), "lateral") ==
        manifest.cameras.end()) {
      top.At("cameras").Fail("the dataset has no lateral camera (dataset --cameras lateral)");
    }
    const std::int64_t worlds = top.At("worlds").Integer();
    const std::int64_t frames = top.At("frames_per_world").Integer();
    if (worlds < 1 || worlds > kMaxDatasetWorlds) {
      top.At("worlds").Fail("outside [1, " + std::to_string(kMaxDatasetWorlds) + "]");
    }
    if (frames < 1 || frames > kMaxDatasetFramesPerWorld) {
      top.At("frames_per_world")
          .Fail("outside [1, " + std::to_string(kMaxDatasetFramesPerWorld) + "]");
    }
    worlds_ = static_cast<int>(worlds);
    frames_ = static_cast<int>(frames);
    seed_ = top.At("seed").Unsigned();
    poses_ = top.At("poses").String();
  }
  int worlds() const override { return worlds_; }
  std::uint64_t world_seed(int w) const override { return seed_ + std::uint64_t(w); }
  void ForEachView(int w, const std::function<void(const LabelledView&, const PlateFonts&)>& each)
      const override {
    const fs::path world_file =
        dir_ / "worlds" / DatasetWorldStem(w, worlds_) / "ground_truth.json";
    const std::string world_name = world_file.string();
    const Json world = ParseJsonInput(ReadRegularFile(world_file, kMaxJsonBytes), world_name);
    const JsonField plates = JsonField{world_name, "", world}.At("door_plates");
    PlateFonts fonts;
    for (std::size_t i = 0; i < plates.ArraySize(); ++i) {
      const JsonField p = plates.At(i);
      fonts[PlateId(p)] = p.Has("font") ? p.At("font").String() : "";
    }
    for (int f = 0; f < frames_; ++f) {
      const std::string stem = DatasetFrameStem(w, f, worlds_, frames_);
      const fs::path truth_file = dir_ / "lateral" / "truth" / (stem + ".json");
      const std::string truth_name = truth_file.string();
      std::error_code error;
      if (!fs::exists(truth_file, error)) {
        throw InputError(SourceLocation{truth_name, 0, 0}, "",
                         "missing: the dataset is not finished (rerun its dataset command, "
                         "which resumes it)");
      }
      const Json truth = ParseJsonInput(ReadRegularFile(truth_file, kMaxJsonBytes), truth_name);
      const JsonField top{truth_name, "", truth};
      LabelledView view{ReadRgbPng(dir_ / "lateral" / "images" / (stem + ".png"), "an image"),
                        PlatesOfTruth(truth, truth_name)};
      if (view.rgb.width != top.At("width").Integer() ||
          view.rgb.height != top.At("height").Integer()) {
        top.At("width").Fail("the image " + stem + ".png is " + std::to_string(view.rgb.width) +
                             "x" + std::to_string(view.rgb.height) + " px");
      }
      each(view, fonts);
    }
  }
  Json Source() const override {
    return {{"dataset", dir_.string()},
            {"poses", poses_},
            {"seed", seed_},
            {"worlds", worlds_},
            {"frames_per_world", frames_}};
  }

 private:
  static constexpr std::uint64_t kMaxJsonBytes = std::uint64_t{64} << 20;
  fs::path dir_;
  int worlds_ = 0, frames_ = 0;
  std::uint64_t seed_ = 0;
  std::string poses_;
};

std::unique_ptr<ViewSet> MakeViewSet(const std::optional<fs::path>& dataset, const char* option,
                                     std::uint64_t first_seed, int worlds, int views) {
  if (dataset) return std::make_unique<DatasetFolderViews>(*dataset, option);
  return std::make_unique<BuiltInViews>(first_seed, worlds, views);
}

std::string FontOf(const PlateFonts& fonts, int id) {
  const auto it = fonts.find(id);
  return it == fonts.end() ? std::string() : it->second;
}

bool HeldOut(const TrainDetectorsOptions& o, const std::string& font) {
  return std::find(o.held_out_fonts.begin(), o.held_out_fonts.end(), font) !=
         o.held_out_fonts.end();
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

double Ratio(int a, int b) { return b > 0 ? RoundToStep(double(a) / b, json_steps::kRatio) : 0.0; }

// The Wilson score 95 % interval of a proportion k / n: what a held-out figure from a hundred
// plates can claim (one plate moves 127 plates' figure by 0.8 points). [0, 1] when n = 0.
nlohmann::ordered_json WilsonInterval(int k, int n) {
  if (n <= 0) return nlohmann::ordered_json::array({0.0, 1.0});
  constexpr double z = 1.959963984540054;
  const double p = double(k) / n, z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4 * n)) / (1 + z2n);
  return nlohmann::ordered_json::array(
      {RoundToStep(std::max(0.0, centre - half), json_steps::kRatio),
       RoundToStep(std::min(1.0, centre + half), json_steps::kRatio)});
}

// Counters of one bin of the evaluation.
struct Counts {
  int plates = 0, detected = 0, read = 0;
  nlohmann::ordered_json Json() const {
    return {{"plates", plates},
            {"detected", detected},
            {"read_correctly", read},
            {"recall", Ratio(detected, plates)},
            {"reading_accuracy", Ratio(read, plates)}};
  }
};

int Bin(double v, const double* edges, std::size_t n) {
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (v < edges[k + 1]) return static_cast<int>(k);
  }
  return static_cast<int>(n) - 2;  // the last bin takes what lies beyond
}

struct Evaluation {
  std::array<Counts, kDistanceEdges.size() - 1> by_distance;
  std::array<Counts, kAngleEdges.size() - 1> by_angle;
  Counts target, target_held_out;
  int views = 0, detections = 0, true_detections = 0, accepted = 0, false_accepted = 0;
  int plates_seen = 0, plates_detected = 0;
  std::array<std::array<int, 10>, 10> confusion{};  // [true][read]
  double correct_score_min = 1.0, wrong_score_max = 0.0;
  int digits_correct = 0, digits_wrong = 0;
};

void EvaluateView(const LabelledView& view, const PlateFonts& fonts,
                  const slam::DoorPlateModels& models, const TrainDetectorsOptions& o,
                  Evaluation* e) {
  ++e->views;
  const std::vector<slam::DoorPlateDetection> detections =
      slam::DetectDoorPlates(view.rgb, models, o.detection);
  // Detections against number regions: the best-overlapping plate of each. A region the image
  // border cuts is matched by its part inside the image, where a detection can lie (a number
  // read whole beside the border is not a false reading).
  std::vector<int> plate_of(detections.size(), -1);
  for (std::size_t i = 0; i < detections.size(); ++i) {
    double best = 0.0;
    for (std::size_t k = 0; k < view.plates.size(); ++k) {
      const double iou = slam::IntersectionOverUnion(detections[i].box_px,
                                                     InImage(NumberBox(view.plates[k]), view.rgb));
      if (iou >= kMatchIou && iou > best) {
        best = iou;
        plate_of[i] = static_cast<int>(k);
      }
    }
    ++e->detections;
    e->true_detections += plate_of[i] >= 0;
    const slam::RoomNumberReading& r = detections[i].reading;
    if (r.accepted) {
      // A false reading is a wrong number accepted: right when it is the number of a plate whose
      // number region (inside the image) the detection covers at least half of, also when the
      // box holds more than the number (a plate's frame beside the image border).
      ++e->accepted;
      bool right = false;
      for (const render::PlateTruth& p : view.plates) {
        right = right || (r.number == p.room_number &&
                          Coverage(detections[i].box_px, InImage(NumberBox(p), view.rgb)) >= 0.5);
      }
      e->false_accepted += !right;
    }
  }
  for (std::size_t k = 0; k < view.plates.size(); ++k) {
    const render::PlateTruth& p = view.plates[k];
    if (!Seen(p)) continue;
    ++e->plates_seen;
    // The plate's detection: the highest-scoring one matched to it.
    const slam::DoorPlateDetection* best = nullptr;
    for (std::size_t i = 0; i < detections.size(); ++i) {
      if (plate_of[i] == int(k) && (!best || detections[i].svm_score > best->svm_score)) {
        best = &detections[i];
      }
    }
    const bool detected = best != nullptr;
    const bool read = detected && best->reading.accepted && best->reading.number == p.room_number;
    e->plates_detected += detected;
    const auto add = [&](Counts& c) {
      ++c.plates;
      c.detected += detected;
      c.read += read;
    };
    add(e->by_distance[std::size_t(
        Bin(p.distance_m, kDistanceEdges.data(), kDistanceEdges.size()))]);
    add(e->by_angle[std::size_t(Bin(p.viewing_angle_deg, kAngleEdges.data(), kAngleEdges.size()))]);
    if (p.distance_m <= kTargetDistanceM && p.viewing_angle_deg <= kTargetAngleDeg) {
      add(e->target);
      if (HeldOut(o, FontOf(fonts, p.id))) add(e->target_held_out);
    }
    if (detected && best->reading.digits.size() == p.room_number.size()) {
      for (std::size_t i = 0; i < p.room_number.size(); ++i) {
        const slam::DigitReading& d = best->reading.digits[i];
        const int truth = p.room_number[i] - '0', got = d.digit - '0';
        if (truth < 0 || truth > 9 || got < 0 || got > 9) continue;
        ++e->confusion[std::size_t(truth)][std::size_t(got)];
        if (truth == got) {
          ++e->digits_correct;
          e->correct_score_min = std::min(e->correct_score_min, d.score);
        } else {
          ++e->digits_wrong;
          e->wrong_score_max = std::max(e->wrong_score_max, d.score);
        }
      }
    }
  }
}

nlohmann::ordered_json EvaluationJson(const Evaluation& e) {
  nlohmann::ordered_json j;
  j["views"] = e.views;
  j["plates_seen"] = e.plates_seen;
  j["detection"] = {{"detections", e.detections},
                    {"true", e.true_detections},
                    {"precision", Ratio(e.true_detections, e.detections)},
                    {"recall", Ratio(e.plates_detected, e.plates_seen)}};
  nlohmann::ordered_json target = e.target.Json();
  target["max_distance_m"] = kTargetDistanceM;
  target["max_viewing_angle_deg"] = kTargetAngleDeg;
  target["required"] = kTargetReadFraction;
  target["reading_accuracy_ci95"] = WilsonInterval(e.target.read, e.target.plates);
  target["met"] =
      e.target.plates > 0 && double(e.target.read) >= kTargetReadFraction * e.target.plates;
  j["read_within_3m_30deg"] = target;
  j["read_within_3m_30deg_held_out_fonts"] = e.target_held_out.Json();
  j["false_readings"] = {
      {"accepted", e.accepted},
      {"false", e.false_accepted},
      {"fraction", Ratio(e.false_accepted, e.accepted)},
      {"fraction_ci95", WilsonInterval(e.false_accepted, e.accepted)},
      {"required_below", kTargetFalseFraction},
      {"met", e.accepted > 0 && double(e.false_accepted) < kTargetFalseFraction * e.accepted}};
  j["by_distance"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < e.by_distance.size(); ++k) {
    nlohmann::ordered_json b = e.by_distance[k].Json();
    b["min_m"] = kDistanceEdges[k];
    b["max_m"] = kDistanceEdges[k + 1];
    j["by_distance"].push_back(b);
  }
  j["by_viewing_angle"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < e.by_angle.size(); ++k) {
    nlohmann::ordered_json b = e.by_angle[k].Json();
    b["min_deg"] = kAngleEdges[k];
    b["max_deg"] = kAngleEdges[k + 1];
    j["by_viewing_angle"].push_back(b);
  }
  j["digits"] = {{"correct", e.digits_correct},
                 {"wrong", e.digits_wrong},
                 {"correct_score_min", RoundToStep(e.correct_score_min, json_steps::kRatio)},
                 {"wrong_score_max", RoundToStep(e.wrong_score_max, json_steps::kRatio)}};
  j["digit_confusion_rows_true_cols_read"] = nlohmann::ordered_json::array();
  for (const auto& row : e.confusion) j["digit_confusion_rows_true_cols_read"].push_back(row);
  return j;
}

// training_report.png: reading accuracy and recall by distance and by viewing angle (bars),
// and the digit confusion matrix.
Image8 DrawReport(const Evaluation& e) {
  const int w = 1200, h = 480;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto text = [&](const std::string& s, int x, int y, double scale = 0.45) {
    cv::putText(img, s, {x, y}, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  };
  const auto bars = [&](int x0, const std::string& title, const std::vector<std::string>& labels,
                        const std::vector<const Counts*>& bins) {
    const int top = 60, bottom = 400, width = 360;
    text(title, x0, 30, 0.55);
    cv::rectangle(img, {x0, top}, {x0 + width, bottom}, cv::Scalar(0, 0, 0), 1);
    for (int f : {0, 50, 90, 100}) {
      const int y = bottom - (bottom - top) * f / 100;
      cv::line(img, {x0, y}, {x0 + width, y}, cv::Scalar(200, 200, 200), 1);
      text(std::to_string(f) + "%", x0 - 38, y + 4, 0.35);
    }
    const int n = static_cast<int>(bins.size());
    const int slot = width / n;
    for (int k = 0; k < n; ++k) {
      const Counts& c = *bins[std::size_t(k)];
      const double recall = c.plates ? double(c.detected) / c.plates : 0;
      const double read = c.plates ? double(c.read) / c.plates : 0;
      const int xa = x0 + k * slot + 6, bw = (slot - 12) / 2;
      cv::rectangle(img, {xa, bottom - int((bottom - top) * recall)}, {xa + bw, bottom},
                    cv::Scalar(60, 120, 220), cv::FILLED);
      cv::rectangle(img, {xa + bw, bottom - int((bottom - top) * read)}, {xa + 2 * bw, bottom},
                    cv::Scalar(40, 160, 60), cv::FILLED);
      text(labels[std::size_t(k)], xa, bottom + 18, 0.38);
      text("n=" + std::to_string(c.plates), xa, bottom + 34, 0.35);
    }
  };
  std::vector<std::string> dl, al;
  std::vector<const Counts*> db, ab;
  for (std::size_t k = 0; k < e.by_distance.size(); ++k) {
    char s[32];
    std::snprintf(s, sizeof s, "%.0f-%.0fm", kDistanceEdges[k], kDistanceEdges[k + 1]);
    dl.push_back(s);
    db.push_back(&e.by_distance[k]);
  }
  for (std::size_t k = 0; k < e.by_angle.size(); ++k) {
    char s[32];
    std::snprintf(s, sizeof s, "%.0f-%.0f", kAngleEdges[k], kAngleEdges[k + 1]);
    al.push_back(s);
    ab.push_back(&e.by_angle[k]);
  }
  bars(50, "by distance", dl, db);
  text("blue: detected, green: read correctly (held-out worlds, seen plates)", 50, 465, 0.45);
  bars(460, "by viewing angle (deg)", al, ab);
  // Confusion matrix: rows true digit, columns read digit; shade by row fraction.
  const int cx = 880, cy = 60, cell = 30;
  text("digit confusion (rows true, cols read)", cx - 20, 30, 0.5);
  for (int t = 0; t < 10; ++t) {
    int row = 0;
    for (int r = 0; r < 10; ++r) row += e.confusion[std::size_t(t)][std::size_t(r)];
    text(std::to_string(t), cx - 16, cy + t * cell + 20);
    text(std::to_string(t), cx + t * cell + 10, cy - 6);
    for (int r = 0; r < 10; ++r) {
      const int v = e.confusion[std::size_t(t)][std::size_t(r)];
      const double f = row ? double(v) / row : 0.0;
      const int shade = 255 - int(200 * f);
      cv::rectangle(img, {cx + r * cell, cy + t * cell}, {cx + (r + 1) * cell, cy + (t + 1) * cell},
                    t == r ? cv::Scalar(shade, 255, shade) : cv::Scalar(255, shade, shade),
                    cv::FILLED);
      cv::rectangle(img, {cx + r * cell, cy + t * cell}, {cx + (r + 1) * cell, cy + (t + 1) * cell},
                    cv::Scalar(180, 180, 180), 1);
      if (v > 0) text(std::to_string(v), cx + r * cell + 2, cy + t * cell + 19, 0.32);
    }
  }
  Image8 out(w, h, 3);
  for (int y = 0; y < h; ++y) std::memcpy(out.Pixel(0, y), img.ptr(y), std::size_t(w) * 3);
  return out;
}

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
  TrainDetectorsOptions options;
  options.seed = request.seed;
  options.train_worlds = request.train_worlds;
  options.eval_worlds = request.eval_worlds;
  options.views_per_world = request.views_per_world;
  options.train_dataset = request.train_dataset;
  options.eval_dataset = request.eval_dataset;
  const TrainingResult result = TrainDetectors(options);
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
