// The workbench's subcommands, for developing detectors: detect, train-detectors, dataset, score.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "harness/cli/options.h"
#include "harness/cli/subcommands.h"

namespace corridorsim::cli {
namespace {

class DetectCommand final : public Subcommand {
 public:
  explicit DetectCommand(CLI::App* app)
      : Subcommand(app, "detect",
                   "Run the detectors (vanishing point, door plates, lamps, "
                   "corners) on an image; JSON on stdout") {
    AddOption(job_, "image", image_, "PNG image (8-bit grey, RGB or RGBA, or 16-bit)", "IMAGE.png")
        ->required();
    AddOption(job_, "--camera", camera_,
              "The camera the image comes from: front (vanishing point and corners; P1's "
              "RGB-D sensor), lateral (door plates and corners) or upward (P3's circular "
              "lamps and corners)",
              "front|lateral|upward")
        ->capture_default_str();
    AddOption(job_, "--depth", depth_,
              "Depth registered to the image (front only): 16-bit PNG at 5000 per metre, "
              "0 = invalid (TUM RGB-D; snapshot's front_depth.png); gives each corner "
              "its depth",
              "D.png");
    AddOption(job_, "--intrinsics", intrinsics_,
              "The upward camera's model as intrinsics.json holds it (docs/frames.md; a "
              "dataset's upward/intrinsics.json, or snapshot's intrinsics.json, whose "
              "\"upward\" entry is used); default: the default rig's upward "
              "camera (Kannala-Brandt, 640x480, 110 deg)",
              "FILE.json");
    AddOption(job_, "--out", out_, "Also write the image with what was found drawn on it",
              "overlay.png");
    SetFooter(job_,
              "Prints one JSON document on stdout (docs/detectors.md): the image, the camera, "
              "then one section per detector: vanishing_point (front: the point, its lines and "
              "quality, or the status saying why there is none), door_plates (lateral), lamps "
              "(upward: circular lamps and the rejected bright regions, P3 section II) and "
              "corners (pixel, depth_m, response). Images are at most 8192 px a side and 256 "
              "MiB.\n",
              FolderFooter::kNone,
              "0 success (also when nothing was found), 2 bad input (a missing, unreadable "
              "or non-PNG file, an image too large, a depth image of another size; one message "
              "naming the file, nothing is printed or written), 1 other failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kDetect;
    DetectRequest& r = parsed->detect;
    if (image_.given()) FileName(image_.text, "image");
    r.image_file = image_.text;
    if (camera_ == "front") {
      r.camera = DetectCamera::kFront;
    } else if (camera_ == "lateral") {
      r.camera = DetectCamera::kLateral;
    } else if (camera_ == "upward") {
      r.camera = DetectCamera::kUpward;
    } else {
      Fail("--camera", "expected front, lateral or upward " + Got(camera_));
    }
    if (intrinsics_.given()) {
      FileName(intrinsics_.text, "--intrinsics");
      if (r.camera != DetectCamera::kUpward) {
        Fail("--intrinsics", "only for --camera upward (got --camera " + camera_ + ")");
      }
      r.intrinsics_file = intrinsics_.text;
    }
    if (depth_.given()) {
      FileName(depth_.text, "--depth");
      if (r.camera != DetectCamera::kFront) {
        Fail("--depth", "only the front camera has a depth sensor (got --camera " + camera_ + ")");
      }
      r.depth_file = depth_.text;
    }
    if (out_.given()) r.overlay_file = FileName(out_.text, "--out");
  }

 private:
  std::string camera_ = "front";
  OptionalArgument image_, depth_, out_, intrinsics_;
};

class TrainDetectorsCommand final : public Subcommand {
 public:
  explicit TrainDetectorsCommand(CLI::App* app)
      : Subcommand(app, "train-detectors",
                   "Render labelled lateral views of seeded worlds, train P1's door-plate SVM and "
                   "room-number MLP, evaluate them on held-out worlds and fonts") {
    AddOutFolder(job_, out_, "Folder of the two model files (replaced atomically)");
    AddOption(job_, "--report", report_,
              "Also write training_report.json and training_report.png into "
              "this folder (staged and replaced like every output folder)");
    AddOption(job_, "--seed", seed_, "Seed of every random choice (default 1)", "UINT64");
    AddOption(job_, "--train-worlds", train_worlds_, "Training worlds, 1-200 (default 24)", "N");
    AddOption(job_, "--eval-worlds", eval_worlds_, "Held-out evaluation worlds, 1-200 (default 8)",
              "N");
    AddOption(job_, "--views", views_, "Lateral views per world, 1-500 (default 48)", "N");
    AddOption(job_, "--dataset", train_dataset_,
              "Train on this folder of `corridorsim dataset` (its lateral camera; e.g. "
              "--poses plates, appearance randomisation) instead of the built-in views",
              "DIR");
    AddOption(job_, "--eval-dataset", eval_dataset_,
              "Evaluate on this dataset folder instead of the built-in held-out worlds", "DIR");
    AddSwitch(job_, "--force", force_, "Replace a non-empty --report folder");
    SetFooter(job_,
              "The built-in views are the frames of `corridorsim dataset "
              "scenarios/datasets/train_detectors.yaml "
              "--cameras lateral --poses plates`, rendered in memory (training worlds from a "
              "seed drawn from --seed, the held-out worlds after them).\n"
              "Writes <out>/door_plate_svm.yml and <out>/room_number_mlp.yml (cv::ml YAML, "
              "docs/detectors.md); with --report also training_report.json (detection "
              "precision and recall, reading accuracy by distance and viewing angle, the digit "
              "confusion matrix, the P1 targets) and training_report.png. The same arguments "
              "write byte-identical models.\n",
              FolderFooter::kNone,
              "0 success, 2 bad input (nothing is written), 1 other failures (e.g. no GL "
              "context).");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kTrainDetectors;
    TrainDetectorsRequest& r = parsed->train_detectors;
    r.out_dir = FolderName(out_, "--out");
    if (report_.given()) r.report_dir = FolderName(report_.text, "--report");
    r.force = force_;
    if (seed_.given()) r.seed = ParseSeedArgument(seed_.text, "--seed");
    if (train_worlds_.given())
      r.train_worlds = WholeArgument(train_worlds_.text, kMaxTrainWorlds, "--train-worlds");
    if (eval_worlds_.given())
      r.eval_worlds = WholeArgument(eval_worlds_.text, kMaxTrainWorlds, "--eval-worlds");
    if (views_.given())
      r.views_per_world = WholeArgument(views_.text, kMaxViewsPerWorld, "--views");
    if (train_dataset_.given()) {
      r.train_dataset = std::filesystem::path(FolderName(train_dataset_.text, "--dataset"));
      if (train_worlds_.given())
        Fail("--train-worlds", "the --dataset folder decides the training worlds");
    }
    if (eval_dataset_.given()) {
      r.eval_dataset = std::filesystem::path(FolderName(eval_dataset_.text, "--eval-dataset"));
      if (eval_worlds_.given())
        Fail("--eval-worlds", "the --eval-dataset folder decides the evaluation worlds");
    }
    if (r.train_dataset && r.eval_dataset && views_.given())
      Fail("--views", "both sets are dataset folders, whose frames decide the views");
  }

 private:
  std::string out_ = "models";
  OptionalArgument report_, seed_, train_worlds_, eval_worlds_, views_;
  OptionalArgument train_dataset_, eval_dataset_;
  bool force_ = false;
};

class DatasetCommand final : public Subcommand {
 public:
  explicit DatasetCommand(CLI::App* app)
      : Subcommand(app, "dataset",
                   "Render labelled images of seeded worlds (images, labels, depth, truth, COCO "
                   "annotations) for developing detectors"),
        options_(job_, "out/dataset",
                 std::string("Scenario YAML (world, sensors, path) ") + kDefaultScenarioHelp,
                 "Seed of world 0 (world w uses seed + w; default: the scenario's `seed`)",
                 "Dataset folder (filled in place and resumable; docs/datasets.md)") {
    AddOption(job_, "--worlds", worlds_, "Number of worlds, 1-100000", "N")->capture_default_str();
    AddOption(job_, "--frames-per-world", frames_, "Poses rendered per world, 1-100000", "M")
        ->capture_default_str();
    AddOption(job_, "--cameras", cameras_,
              "Comma-separated cameras to render, each enabled in the scenario "
              "(default: every enabled camera)",
              "front,lateral,upward");
    AddOption(job_, "--poses", poses_,
              "random: uniform in the corridor, yaw uniform, collisions redrawn; path: evenly "
              "spaced along the scenario's path; plates: the lateral camera aimed at door "
              "plates (a quarter at posters and notice boards), 0.4-3.5 m, up to 50 deg off "
              "their normal (what train-detectors learns from)",
              "path|random|plates")
        ->capture_default_str();
    SetFooter(job_,
              "Writes DIR/dataset.json (the manifest), per camera "
              "DIR/<camera>/{images,labels,depth,truth}/"
              "w<WWW>_f<FFFF>.{png,json}, DIR/<camera>/intrinsics.json and "
              "DIR/<camera>/annotations.json "
              "(COCO: door_plate 1, door 2, lamp 3, ceiling_corner 4), and "
              "DIR/worlds/w<WWW>/ground_truth.json (docs/datasets.md).\n"
              "Output folder: filled in place, every file atomically. Rerunning the same command "
              "over a folder whose dataset.json matches resumes it (frames with a truth file are "
              "skipped); a folder with another dataset.json is refused (exit 2) unless --force, "
              "which clears it; a folder with files but no dataset.json is never touched.\n",
              FolderFooter::kNone,
              "0 success, 2 bad input, 1 other failures (e.g. no GL context).");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kDataset;
    DatasetRequest& r = parsed->dataset;
    options_.Resolve(&r);
    r.worlds = WholeArgument(worlds_, kMaxDatasetWorlds, "--worlds");
    r.frames_per_world = WholeArgument(frames_, kMaxDatasetFramesPerWorld, "--frames-per-world");
    if (cameras_.given()) {
      const std::string& cameras = cameras_.text;
      std::size_t start = 0;
      for (;;) {
        const std::size_t comma = cameras.find(',', start);
        const std::string id =
            cameras.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (id.empty()) Fail("--cameras", "an empty camera name " + Got(cameras));
        r.cameras.push_back(id);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
    if (poses_ == "random") {
      r.poses = DatasetPoseMode::kRandom;
    } else if (poses_ == "path") {
      r.poses = DatasetPoseMode::kPath;
    } else if (poses_ == "plates") {
      r.poses = DatasetPoseMode::kPlates;
    } else {
      Fail("--poses", "expected path, random or plates " + Got(poses_));
    }
  }

 private:
  JobOptions options_;
  std::string worlds_ = "1", frames_ = "1", poses_ = "random";
  OptionalArgument cameras_;
};

class ScoreCommand final : public Subcommand {
 public:
  explicit ScoreCommand(CLI::App* app)
      : Subcommand(app, "score",
                   "Score detections (COCO results JSON) against a dataset's annotations") {
    AddOption(job_, "detections", detections_,
              "COCO results: [{image_id, category_id, bbox | circle | point | keypoints, "
              "score, room_number?}, ...]",
              "DETECTIONS.json")
        ->required();
    AddOption(job_, "--dataset", dataset_, "Dataset folder (corridorsim dataset --out)", "DIR")
        ->required();
    AddOption(job_, "--camera", camera_,
              "The camera the detections are for (default: the dataset's only "
              "one)");
    AddOutFolder(job_, out_,
                 "Also write score.json and score.png into this folder (staged and "
                 "replaced like every output folder)",
                 "REPORT_DIR");
    AddSwitch(job_, "--force", force_, "Replace a non-empty --out folder");
    AddOption(job_, "--expect", expect_,
              "A check such as lamp.ap50>=0.8 or door_plate.recall>=0.5 (repeatable)",
              "CLASS.METRIC>=VALUE");
    SetFooter(job_,
              "Matches detections to annotations per class (COCO's greedy matching by score; IoU "
              "of boxes, of circles for lamps, pixel distance for corners) and reports labels, "
              "detections, precision and recall at the best-F1 threshold, AP50, AP50:95 "
              "(101-point), localisation error, reading accuracy (plates) and recall by "
              "distance, viewing angle and appearance (docs/datasets.md).\n",
              FolderFooter::kNone,
              "0 success, 3 an --expect check failed, 2 bad input (the file and field are "
              "named), 1 other failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kScore;
    ScoreRequest& r = parsed->score;
    r.detections_file = FileName(detections_, "detections");
    r.dataset_dir = FolderName(dataset_, "--dataset");
    if (camera_.given()) {
      if (camera_.text.empty()) Fail("--camera", "an empty camera name");
      r.camera = camera_.text;
    }
    if (out_.given()) r.report_dir = FolderName(out_.text, "--out");
    r.force = force_;
    for (const std::string& e : expect_) {
      r.expectations.push_back(ParseScoreExpectation(e, "--expect"));
    }
  }

 private:
  std::string detections_, dataset_;
  OptionalArgument camera_, out_;
  bool force_ = false;
  std::vector<std::string> expect_;
};

}  // namespace

std::unique_ptr<Subcommand> AddDetectCommand(CLI::App* app) {
  return std::make_unique<DetectCommand>(app);
}
std::unique_ptr<Subcommand> AddTrainDetectorsCommand(CLI::App* app) {
  return std::make_unique<TrainDetectorsCommand>(app);
}
std::unique_ptr<Subcommand> AddDatasetCommand(CLI::App* app) {
  return std::make_unique<DatasetCommand>(app);
}
std::unique_ptr<Subcommand> AddScoreCommand(CLI::App* app) {
  return std::make_unique<ScoreCommand>(app);
}

}  // namespace corridorsim::cli
