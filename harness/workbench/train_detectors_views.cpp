#include "harness/workbench/train_detectors_internal.h"

#include <algorithm>
#include <limits>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "harness/run/frame_io.h"
#include "harness/run/simulation_setup.h"
#include "harness/workbench/dataset.h"
#include "harness/workbench/detect.h"
#include "worlds/world.h"

// train-detectors' labelled views (MakeViewSet): rendered in memory by the dataset's generator
// (BuiltInViews), or read from a folder `corridorsim dataset` wrote (DatasetFolderViews); the
// plates of either come from the truth files' JSON.

namespace corridorsim::train_detectors_internal {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector2d;

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

}  // namespace

std::unique_ptr<ViewSet> MakeViewSet(const std::optional<fs::path>& dataset, const char* option,
                                     std::uint64_t first_seed, int worlds, int views) {
  if (dataset) return std::make_unique<DatasetFolderViews>(*dataset, option);
  return std::make_unique<BuiltInViews>(first_seed, worlds, views);
}

}  // namespace corridorsim::train_detectors_internal
