#include "harness/workbench/dataset.h"

#include <algorithm>
#include <cstdio>

#include "common/error.h"
#include "harness/run/frame_io.h"
#include "harness/run/simulation_setup.h"
#include "harness/workbench/dataset_internal.h"
#include "render/backend.h"

// `dataset`'s frames (dataset.h: DatasetWorld): one seeded world, its poses and its renderer,
// each frame's images with its truth file (the frame's ground truth, the drawn appearance, the
// front camera's vanishing point, the COCO annotations); the frames' file names.

namespace corridorsim {
namespace {

using dataset_internal::Fraction;
using dataset_internal::Px;
using Json = nlohmann::ordered_json;

int Digits(int n) { return n < 10 ? 1 : 1 + Digits(n / 10); }

}  // namespace

std::string DatasetWorldStem(int world_index, int worlds) {
  const std::string digits = std::to_string(world_index);
  const std::size_t width = static_cast<std::size_t>(std::max(3, Digits(std::max(worlds - 1, 0))));
  return "w" + std::string(width > digits.size() ? width - digits.size() : 0, '0') + digits;
}

std::string DatasetFrameStem(int world_index, int frame_index, int worlds, int frames_per_world) {
  const int frame_digits = std::max(4, Digits(std::max(frames_per_world - 1, 0)));
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "_f%0*d", frame_digits, frame_index);
  return DatasetWorldStem(world_index, worlds) + buffer;
}

DatasetWorld::DatasetWorld(const Scenario& scenario, const render::RigOptions& rig,
                           render::BackendKind backend, std::uint64_t world_seed, int world_index,
                           int worlds, DatasetPoseMode mode, int frames)
    : scenario_(scenario),
      rig_(rig),
      backend_(backend),
      world_index_(world_index),
      worlds_(worlds),
      frames_(frames),
      world_(GenerateWorld(scenario, world_seed)),
      poses_(DatasetPoses(scenario, world_, rig, mode, frames)) {}

DatasetWorld::~DatasetWorld() = default;

std::vector<DatasetFrame> DatasetWorld::Render(int f) {
  CheckOrDie(f >= 0 && f < frames_, "DatasetWorld::Render", "frame index out of range");
  if (!renderer_) renderer_ = std::make_unique<Renderer>(world_, rig_, backend_);
  const std::string stem = DatasetFrameStem(world_index_, f, worlds_, frames_);
  const SE3 world_from_robot = SE3::FromSE2(poses_[std::size_t(f)]);
  std::vector<render::CameraFrame> frames;
  renderer_->rig->Render(world_from_robot, world_.seed, static_cast<std::uint64_t>(f), &frames);
  std::vector<DatasetFrame> out;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const render::CameraOptions& options = renderer_->rig->cameras()[k].options();
    DatasetFrame d{std::move(frames[k]), options.depth, Json()};
    const render::CameraFrame& frame = d.frame;
    const int width = frame.rgb.width, height = frame.rgb.height;
    const render::FrameTruth truth = FrameTruthOf(world_, options, frame, world_from_robot);
    Json& j = d.truth;
    j["world_index"] = world_index_;
    j["frame_index"] = f;
    j["world_seed"] = world_.seed;
    j["file_name"] = "images/" + stem + ".png";
    j["width"] = width;
    j["height"] = height;
    if (scenario_.world.appearance.Any()) {
      // What the world's appearance randomisation drew, as numbers `score` bins recall by.
      const worlds::AppearanceDraw& a = world_.appearance;
      const auto mean = [](const Eigen::Vector3f& c) { return double(c.mean()); };
      j["appearance"] = {{"wall_brightness", Fraction(mean(a.wall))},
                         {"floor_brightness", Fraction(mean(a.floor))},
                         {"ceiling_brightness", Fraction(mean(a.ceiling))},
                         {"door_brightness", Fraction(mean(a.door))},
                         {"lamp_brightness", Fraction(a.lamp_brightness)},
                         {"lamp_temperature_k", Fraction(a.lamp_temperature_k)},
                         {"distractor_density", Fraction(a.distractor_density)},
                         {"camera_exposure", Fraction(a.camera_exposure)},
                         {"camera_noise", Fraction(a.camera_noise)},
                         {"camera_blur_px", Fraction(a.camera_blur_px)}};
    }
    const Json truth_json = render::FrameTruthJson(truth);
    for (const auto& [key, value] : truth_json.items()) j[key] = value;
    if (frame.camera_id == "front") {
      // The vanishing point of the corridor the camera stands in, COCO pixel convention.
      j["vanishing_point"] = nullptr;
      for (const render::VanishingPointTruth& vp : truth.vanishing_points) {
        if (!vp.camera_in_segment) continue;
        j["vanishing_point"] = Json::array({Px(vp.pixel.x() + 0.5), Px(vp.pixel.y() + 0.5)});
        break;
      }
    }
    j["annotations"] = FrameAnnotations(world_, truth, frame, width, height);
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace corridorsim
