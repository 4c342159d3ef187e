#include "harness/train_detectors.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "common/pose.h"
#include "common/random.h"
#include "harness/frame_io.h"
#include "harness/run_folder.h"
#include "harness/simulation_setup.h"
#include "render/frame_truth.h"
#include "worlds/image_io.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
constexpr double kDeg = std::numbers::pi / 180.0;

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
bool Seen(const render::PlateTruth& p) {
  return p.fully_in_image && p.visible_fraction >= kSeenFraction;
}

// The camera's optical centre must lie inside a corridor segment, 0.15 m from its walls and ends.
bool InsideCorridor(const worlds::World& world, const Vector2d& p) {
  for (const worlds::CorridorSegment& s : world.segments) {
    const Vector2d d = s.direction();
    const Vector2d n(-d.y(), d.x());
    const double along = (p - s.start).dot(d), across = (p - s.start).dot(n);
    if (along >= 0.15 && along <= (s.end - s.start).norm() - 0.15 &&
        std::abs(across) <= s.width_m / 2 - 0.15) {
      return true;
    }
  }
  return false;
}

struct View {
  SE3 world_from_robot;
};

// A lateral view of a target on a wall (centre, unit normal into the corridor): the camera at
// 0.4-3.5 m from it, off its normal by up to 50 deg, heading at it +-30 deg.
std::optional<View> ViewOf(const worlds::World& world, const Vector3d& target,
                           const Vector3d& normal, const render::CameraOptions& lateral,
                           RandomStream& rng) {
  const Vector2d n = normal.head<2>().normalized();
  const Vector2d t(-n.y(), n.x());
  for (int attempt = 0; attempt < 20; ++attempt) {
    const double d = rng.Uniform(0.4, 3.5);
    const double off = rng.Uniform(-50.0, 50.0) * kDeg;
    const Vector2d camera = target.head<2>() + d * (std::cos(off) * n + std::sin(off) * t);
    if (!InsideCorridor(world, camera)) continue;
    const Vector2d to_target = target.head<2>() - camera;
    const double camera_yaw =
        std::atan2(to_target.y(), to_target.x()) + rng.Uniform(-30.0, 30.0) * kDeg;
    // The camera looks along the robot's heading + mount yaw; its mount is at (x, y) on the robot.
    const double robot_yaw = camera_yaw - lateral.mount.yaw_deg * kDeg;
    const Vector2d mount(lateral.mount.x_m, lateral.mount.y_m);
    const Eigen::Rotation2Dd r(robot_yaw);
    const Vector2d robot = camera - r * mount;
    return View{SE3::FromSE2(SE2(robot.x(), robot.y(), robot_yaw))};
  }
  return std::nullopt;
}

struct RenderedView {
  Image8 rgb;
  render::FrameTruth truth;
};

// Renders `views` lateral views of one world; a quarter aim at posters and notice boards.
std::vector<RenderedView> RenderWorldViews(const worlds::World& world, int views,
                                           double distractor_fraction, RandomStream& rng,
                                           std::uint64_t noise_seed) {
  const render::RigOptions rig_options = TrainingRigOptions();
  const render::CameraOptions& lateral = rig_options.cameras.front();
  const Renderer renderer(world, rig_options, ChooseBackend(rig_options.backend));
  std::vector<const worlds::Distractor*> printed;
  for (const worlds::Distractor& d : world.distractors) {
    if (!d.text.empty()) printed.push_back(&d);
  }
  std::vector<RenderedView> out;
  for (int v = 0; v < views; ++v) {
    Vector3d target, normal;
    if (!printed.empty() && rng.Bernoulli(distractor_fraction)) {
      const worlds::Distractor& d =
          *printed[std::size_t(rng.UniformInt(0, std::int64_t(printed.size()) - 1))];
      target = d.center + d.normal * (d.size_m.y() / 2);
      normal = d.normal;
    } else {
      if (world.plates.empty()) continue;
      const worlds::DoorPlate& p =
          world.plates[std::size_t(rng.UniformInt(0, std::int64_t(world.plates.size()) - 1))];
      target = p.center;
      normal = p.normal;
    }
    const std::optional<View> view = ViewOf(world, target, normal, lateral, rng);
    if (!view) continue;
    render::CameraFrame frame;
    renderer.rig->RenderCamera(0, view->world_from_robot, noise_seed, std::uint64_t(v), &frame);
    render::FrameTruthInput input;
    input.world = &world;
    input.camera_id = frame.camera_id;
    input.model = lateral.model;
    input.world_from_camera = frame.world_from_camera;
    input.world_from_robot = view->world_from_robot;
    input.instance = &frame.instance;
    input.semantic = &frame.semantic;
    out.push_back(RenderedView{std::move(frame.rgb), render::ComputeFrameTruth(input)});
  }
  return out;
}

const worlds::DoorPlate* PlateById(const worlds::World& world, int id) {
  for (const worlds::DoorPlate& p : world.plates) {
    if (p.id == id) return &p;
  }
  return nullptr;
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

void AddTrainingView(const worlds::World& world, const RenderedView& view,
                     const TrainDetectorsOptions& o, RandomStream& rng, TrainingSet* set) {
  ++set->views;
  const slam::DoorPlateDetectorOptions& det = o.detection.detector;
  const std::vector<slam::BoxPx> candidates = slam::SegmentPlateCandidates(view.rgb, det);
  std::vector<slam::BoxPx> negatives;
  for (const slam::BoxPx& c : candidates) {
    double best = 0.0;
    int best_plate = -1;
    bool near_held_out = false;
    for (std::size_t k = 0; k < view.truth.plates.size(); ++k) {
      const render::PlateTruth& p = view.truth.plates[k];
      const worlds::DoorPlate* plate = PlateById(world, p.id);
      const bool held = plate && HeldOut(o, plate->font);
      if (held && slam::IntersectionOverUnion(c, PlateBox(p)) > 0.0) near_held_out = true;
      const double iou = slam::IntersectionOverUnion(c, NumberBox(p));
      if (iou > best) {
        best = iou;
        best_plate = static_cast<int>(k);
      }
    }
    if (near_held_out) continue;  // held-out fonts teach nothing, not even as negatives
    if (best >= kMatchIou) {
      const render::PlateTruth& p = view.truth.plates[std::size_t(best_plate)];
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

void EvaluateView(const worlds::World& world, const RenderedView& view,
                  const slam::DoorPlateModels& models, const TrainDetectorsOptions& o,
                  Evaluation* e) {
  ++e->views;
  const std::vector<slam::DoorPlateDetection> detections =
      slam::DetectDoorPlates(view.rgb, models, o.detection);
  // Detections against number regions: the best-overlapping plate of each.
  std::vector<int> plate_of(detections.size(), -1);
  for (std::size_t i = 0; i < detections.size(); ++i) {
    double best = 0.0;
    for (std::size_t k = 0; k < view.truth.plates.size(); ++k) {
      const double iou =
          slam::IntersectionOverUnion(detections[i].box_px, NumberBox(view.truth.plates[k]));
      if (iou >= kMatchIou && iou > best) {
        best = iou;
        plate_of[i] = static_cast<int>(k);
      }
    }
    ++e->detections;
    e->true_detections += plate_of[i] >= 0;
    const slam::RoomNumberReading& r = detections[i].reading;
    if (r.accepted) {
      ++e->accepted;
      const bool right =
          plate_of[i] >= 0 && r.number == view.truth.plates[std::size_t(plate_of[i])].room_number;
      e->false_accepted += !right;
    }
  }
  for (std::size_t k = 0; k < view.truth.plates.size(); ++k) {
    const render::PlateTruth& p = view.truth.plates[k];
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
      const worlds::DoorPlate* plate = PlateById(world, p.id);
      if (plate && HeldOut(o, plate->font)) add(e->target_held_out);
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
  target["met"] =
      e.target.plates > 0 && double(e.target.read) >= kTargetReadFraction * e.target.plates;
  j["read_within_3m_30deg"] = target;
  j["read_within_3m_30deg_held_out_fonts"] = e.target_held_out.Json();
  j["false_readings"] = {
      {"accepted", e.accepted},
      {"false", e.false_accepted},
      {"fraction", Ratio(e.false_accepted, e.accepted)},
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

std::vector<std::uint64_t> WorldSeeds(std::uint64_t seed, const char* what, int count) {
  RandomStream rng(seed, 0, what);
  std::vector<std::uint64_t> seeds;
  for (int k = 0; k < count; ++k) seeds.push_back(rng.NextU64() >> 16);  // readable, distinct
  return seeds;
}

}  // namespace

render::RigOptions TrainingRigOptions() {
  render::RigOptions rig = render::RigOptions::Default();
  std::vector<render::CameraOptions> cameras;
  for (const render::CameraOptions& c : rig.cameras) {
    if (c.id != "lateral") continue;
    render::CameraOptions lateral = c;
    lateral.enabled = true;
    lateral.mount = render::Mount{0.0, 0.12, 1.5, 90.0, 0.0, 0.0};  // level mast (the lead's)
    cameras.push_back(lateral);
  }
  rig.cameras = cameras;
  return rig;
}

TrainingResult TrainDetectors(const TrainDetectorsOptions& o) {
  CheckOrDie(!o.detection.Check(), "TrainDetectors", "the detection options fail their Check()");
  const auto t0 = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const worlds::WorldOptions world_options;  // the default corridor: plates and distractors
  TrainingSet set;
  RandomStream view_rng(o.seed, 0, "train_detectors.views");
  RandomStream sample_rng(o.seed, 0, "train_detectors.samples");
  const std::vector<std::uint64_t> train_seeds =
      WorldSeeds(o.seed, "train_detectors.train", o.train_worlds);
  for (std::size_t k = 0; k < train_seeds.size(); ++k) {
    const worlds::World world = worlds::Generate(world_options, train_seeds[k]);
    for (const RenderedView& v : RenderWorldViews(
             world, o.views_per_world, o.distractor_view_fraction, view_rng, train_seeds[k])) {
      AddTrainingView(world, v, o, sample_rng, &set);
    }
    std::printf(
        "train-detectors: training world %zu/%d (seed %llu): %d positives, %d negatives, "
        "%d digits (%.0f s)\n",
        k + 1, o.train_worlds, static_cast<unsigned long long>(train_seeds[k]), set.positives,
        set.negatives, set.digit_labels.rows, seconds());
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
    result.svm_bytes = ModelBytes(*svm);
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
  const std::vector<std::uint64_t> eval_seeds =
      WorldSeeds(o.seed, "train_detectors.eval", o.eval_worlds);
  RandomStream eval_rng(o.seed, 0, "train_detectors.eval_views");
  for (std::size_t k = 0; k < eval_seeds.size(); ++k) {
    const worlds::World world = worlds::Generate(world_options, eval_seeds[k]);
    for (const RenderedView& v : RenderWorldViews(
             world, o.views_per_world, o.distractor_view_fraction, eval_rng, eval_seeds[k])) {
      EvaluateView(world, v, result.models, o, &e);
    }
    std::printf(
        "train-detectors: evaluation world %zu/%d: within 3 m, 30 deg read %d/%d, false "
        "readings %d/%d accepted (%.0f s)\n",
        k + 1, o.eval_worlds, e.target.read, e.target.plates, e.false_accepted, e.accepted,
        seconds());
    std::fflush(stdout);
  }

  nlohmann::ordered_json& j = result.report;
  j["seed"] = o.seed;
  j["train_worlds"] = o.train_worlds;
  j["eval_worlds"] = o.eval_worlds;
  j["views_per_world"] = o.views_per_world;
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
  std::unique_ptr<StagedDirectory> report;
  if (request.report_dir)
    report = StageOutputFolder(*request.report_dir, "--report", request.force);
  TrainDetectorsOptions options;
  options.seed = request.seed;
  options.train_worlds = request.train_worlds;
  options.eval_worlds = request.eval_worlds;
  options.views_per_world = request.views_per_world;
  const TrainingResult result = TrainDetectors(options);
  std::error_code error;
  std::filesystem::create_directories(request.out_dir, error);
  if (error) {
    throw std::runtime_error("cannot create " + request.out_dir.string() + ": " + error.message());
  }
  WriteFileAtomic(request.out_dir / slam::kDoorPlateSvmFile, result.svm_bytes);
  WriteFileAtomic(request.out_dir / slam::kRoomNumberMlpFile, result.mlp_bytes);
  std::printf("wrote %s/{%s, %s}\n", request.out_dir.string().c_str(), slam::kDoorPlateSvmFile,
              slam::kRoomNumberMlpFile);
  if (report) {
    WriteFileAtomic(report->path() / "training_report.json", result.report.dump(2) + "\n");
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
