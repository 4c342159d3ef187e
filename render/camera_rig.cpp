#include "render/camera_rig.h"

#include <algorithm>
#include <string>

#include "common/random.h"
#include "render/camera_budget.h"
#include "render/noise.h"

namespace corridorsim::render {

Rig::Rig(const RigOptions& options, const Scene& scene, Backend& backend)
    : scene_(scene), backend_(backend) {
  // The backend's own limit (a GPU driver may have less than kMaxPassPx), before the remap
  // tables are planned or a frame is drawn.
  for (const CameraOptions& c : options.cameras) {
    if (!c.enabled) continue;
    const CameraBudget budget = CameraBudgetOf(c, options.samples);
    if (budget.pass_width_px > backend.max_view_px() ||
        budget.pass_height_px > backend.max_view_px()) {
      throw RenderError("render: sensors." + c.id + ": the camera is drawn from a pass of " +
                        std::to_string(budget.pass_width_px) + " x " +
                        std::to_string(budget.pass_height_px) + " px; the " +
                        BackendName(backend.kind()) + " backend draws at most " +
                        std::to_string(backend.max_view_px()) + " px on a side");
    }
  }
  for (const CameraOptions& c : options.cameras) {
    if (c.enabled) cameras_.emplace_back(c, SamplesPerSide(options.samples));
  }
  started_.assign(cameras_.size(), false);
  // The cameras with the most CPU work after their draw start first in Render, so it overlaps
  // the most drawing of the others.
  for (std::size_t k = 0; k < cameras_.size(); ++k) draw_order_.push_back(k);
  std::stable_sort(draw_order_.begin(), draw_order_.end(), [&](std::size_t a, std::size_t b) {
    return cameras_[a].cpu_work() > cameras_[b].cpu_work();
  });
}

Rig::~Rig() { Abandon(); }  // the stages write frames the caller owns: let them end

void Rig::Render(const SE3& world_from_robot, std::uint64_t seed, std::uint64_t frame_index,
                 std::vector<CameraFrame>* frames) {
  frames->resize(cameras_.size());
  try {
    for (const std::size_t k : draw_order_) {
      StartCamera(k, world_from_robot, seed, frame_index, &(*frames)[k]);
    }
  } catch (...) {
    Abandon();  // the cameras already started write into *frames: let them end first
    throw;
  }
  Wait();
}

void Rig::RenderCamera(std::size_t index, const SE3& world_from_robot, std::uint64_t seed,
                       std::uint64_t frame_index, CameraFrame* frame) {
  StartCamera(index, world_from_robot, seed, frame_index, frame);
  Wait();
}

void Rig::StartCamera(std::size_t index, const SE3& world_from_robot, std::uint64_t seed,
                      std::uint64_t frame_index, CameraFrame* frame) {
  CameraRenderer& camera = cameras_.at(index);
  if (started_.at(index)) Wait();  // its last frame's CPU stages still read the buffers Draw writes
  camera.Draw(scene_, backend_, world_from_robot * camera.options().mount.RobotFromCamera());
  if (camera.cpu_work() == 0) {
    FinishCamera(index, seed, frame_index, frame);
    return;
  }
  started_[index] = true;
  worker_.Submit(
      [this, index, seed, frame_index, frame] { FinishCamera(index, seed, frame_index, frame); });
}

void Rig::Wait() {
  std::fill(started_.begin(), started_.end(), false);
  worker_.Drain();  // rethrows the first exception of a stage
}

void Rig::Abandon() noexcept {
  try {
    Wait();
  } catch (...) {  // NOLINT(bugprone-empty-catch): the caller reports its own error
  }
}

void Rig::FinishCamera(std::size_t index, std::uint64_t seed, std::uint64_t frame_index,
                       CameraFrame* frame) {
  CameraRenderer& camera = cameras_[index];
  camera.Finish(frame);
  const CameraOptions& options = camera.options();
  if (options.depth) {
    frame->noisy_depth_m = frame->depth_m;
    // The noise applies the range itself; without it the exact depth still obeys the range.
    if (!options.noise) ApplyDepthRange(options.depth_noise, &frame->noisy_depth_m);
  }
  if (options.noise) ApplyNoise(index, seed, frame_index, frame);
}

void Rig::ApplyNoise(std::size_t index, std::uint64_t seed, std::uint64_t frame_index,
                     CameraFrame* frame) const {
  const CameraOptions& camera = cameras_.at(index).options();
  // Truth, then noise (STYLE item 9): each camera and frame has its own stream.
  RandomStream rng =
      RandomStream(seed, 0, "render.noise." + camera.id).Derive(std::to_string(frame_index));
  RandomStream depth_rng = rng.Derive("depth"), rgb_rng = rng.Derive("rgb");
  if (camera.depth) {
    ApplyDepthNoise(camera.depth_noise, *camera.model.pinhole(), depth_rng, &frame->noisy_depth_m);
  }
  ApplyRgbNoise(camera.rgb_noise, rgb_rng, &frame->rgb);
}

}  // namespace corridorsim::render
