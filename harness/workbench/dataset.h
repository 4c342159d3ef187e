#pragma once
// `corridorsim dataset`: labelled images of seeded worlds for developing detectors and scoring
// them with `corridorsim score` (docs/datasets.md). N worlds (world w has seed + w) are each
// rendered at M poses (drawn inside the corridor, or evenly spaced along the scenario's path);
// per camera and frame it writes the image, the 16-bit labels, depth, the frame's ground truth
// with its COCO annotations, and at the end one COCO file per camera built from the truth files.
// The folder is filled in place, file by file (atomically), so that a killed job resumes: a frame
// whose truth files exist is done.
//
// The job and its folder: dataset.cpp; the poses: dataset_poses.cpp; a world's frames:
// dataset_world.cpp; the COCO annotations: dataset_coco.cpp.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "harness/run/simulation_setup.h"
#include "harness/scenario/scenario.h"
#include "harness/workbench/dataset_request.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "worlds/world.h"

namespace corridorsim {

/// Draws per random pose before the world is declared too tight for the robot.
inline constexpr int kMaxPoseTries = 1000;
/// `--poses plates`: the fraction of views aimed at printed distractors instead of plates.
inline constexpr double kAimDistractorFraction = 0.25;
/// Doors with fewer pixels than this in the instance image get no annotation.
inline constexpr int kMinDoorPixels = 20;

/// The fixed COCO categories of every dataset (ids never change: detections refer to them).
enum DatasetCategory : int {
  kCategoryDoorPlate = 1,
  kCategoryDoor = 2,
  kCategoryLamp = 3,
  kCategoryCeilingCorner = 4,
};
inline constexpr int kDatasetCategoryCount = 4;
/// "door_plate", "door", "lamp", "ceiling_corner" for ids 1..4; "" otherwise.
std::string DatasetCategoryName(int category_id);
/// COCO's `categories` array: id, name, supercategory.
nlohmann::ordered_json DatasetCategoriesJson();

/// The robot's poses in `world` for `mode` (`count` of them). Random poses come from the stream
/// (world.seed, 0, "dataset.poses") and are checked against the world with the enabled cameras of
/// `rig`. Throws InputError at `--poses` when no clear pose is found in kMaxPoseTries draws or
/// the scenario's path is a script (it has no legs to space poses along), and at the scenario's
/// `path:` when the path does not fit.
std::vector<SE2> DatasetPoses(const Scenario& scenario, const worlds::World& world,
                              const render::RigOptions& rig, DatasetPoseMode mode, int count);

/// The COCO annotations of one frame (without `id` and `image_id`, which the camera's
/// annotations.json assigns): the visible landmarks of `truth` inside the image, in COCO's pixel
/// convention (docs/datasets.md). `frame` gives the instance image (door boxes) and the pose.
nlohmann::ordered_json FrameAnnotations(const worlds::World& world, const render::FrameTruth& truth,
                                        const render::CameraFrame& frame, int width, int height);

/// Frame file stem `w<WWW>_f<FFFF>`: zero-padded to 3 and 4 digits, or to the digits of the
/// largest index when that is wider, so that names sort in frame order.
std::string DatasetFrameStem(int world_index, int frame_index, int worlds, int frames_per_world);

/// World folder name `w<WWW>` (worlds/w<WWW>/ground_truth.json, the first part of its frames'
/// stems): zero-padded as DatasetFrameStem pads the world index.
std::string DatasetWorldStem(int world_index, int worlds);

/// Rebuilds `dir/<camera>/annotations.json` from the camera's truth files (all of them must
/// exist; one that cannot be read or parsed, or lacks a key, is an InputError naming it). Image ids
/// are world_index * frames_per_world + frame_index + 1.
void WriteDatasetAnnotations(const std::filesystem::path& dir, const std::string& camera,
                             int worlds, int frames_per_world);

/// One camera's frame of a dataset: what `dataset` writes for it.
struct DatasetFrame {
  render::CameraFrame frame;     // image, labels (instance, semantic), depth
  bool depth = false;            // the camera has a depth image (a depth/ file is written)
  nlohmann::ordered_json truth;  // the truth file (docs/datasets.md), COCO annotations included
};

/// One world of a dataset (world_index of `worlds`, seeded `world_seed`) and its `frames` poses:
/// renders its frames as `dataset` writes them. `dataset` and `train-detectors` share it, so a
/// model trained in memory sees the frames a dataset folder holds. The world and its poses are
/// made by the constructor (InputError as DatasetPoses); the renderer on the first Render.
/// `scenario` and `rig` (cameras enabled as selected) must outlive it.
class DatasetWorld {
 public:
  DatasetWorld(const Scenario& scenario, const render::RigOptions& rig, render::BackendKind backend,
               std::uint64_t world_seed, int world_index, int worlds, DatasetPoseMode mode,
               int frames);
  ~DatasetWorld();
  DatasetWorld(const DatasetWorld&) = delete;
  DatasetWorld& operator=(const DatasetWorld&) = delete;

  const worlds::World& world() const { return world_; }
  /// Frame `frame_index` of every enabled camera, in the rig's order.
  std::vector<DatasetFrame> Render(int frame_index);

 private:
  const Scenario& scenario_;
  const render::RigOptions& rig_;
  render::BackendKind backend_;
  int world_index_, worlds_, frames_;
  worlds::World world_;
  std::vector<SE2> poses_;
  std::unique_ptr<Renderer> renderer_;
};

/// A dataset folder's manifest (`DIR/dataset.json`) as its readers (`score`, `train-detectors`)
/// take it: the whole document, and its camera names.
struct DatasetManifest {
  std::string file;  // DIR/dataset.json, for messages
  nlohmann::ordered_json json;
  std::vector<std::string> cameras;
};
/// Bounds of the dataset files its readers parse: the manifest and a frame's truth file.
inline constexpr std::uint64_t kMaxDatasetManifestBytes = std::uint64_t{1} << 20;  // 1 MiB
inline constexpr std::uint64_t kMaxDatasetTruthBytes = std::uint64_t{64} << 20;    // 64 MiB
/// Reads DIR/dataset.json (at most kMaxDatasetManifestBytes): an object whose `format` is
/// "corridorsim dataset", with a `cameras` array of names. Throws InputError naming the file and
/// field otherwise.
DatasetManifest ReadDatasetManifest(const std::filesystem::path& dir);

/// Runs the job; returns the exit code. Throws InputError for bad input.
int RunDataset(const DatasetRequest& request);

}  // namespace corridorsim
