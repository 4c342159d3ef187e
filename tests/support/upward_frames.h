// The default rig's upward camera alone, drawing a world's frames with their frame truth (tests
// of the upward detectors on rendered images: lamps, door candidates).
#pragma once

#include <cstdint>
#include <vector>

#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "tests/support/uploaded_rig.h"
#include "worlds/world.h"

namespace corridorsim::test {

class UpwardFrames {
 public:
  explicit UpwardFrames(const worlds::World& world)
      : world_(world), options_(UpwardOnly()), rig_(world, options_) {}

  const CameraModel& model() const { return options_.cameras[0].model; }

  /// Renders the upward camera at `world_from_robot` (noise seed 7, frame `index`) into `frame`
  /// and returns its frame truth.
  render::FrameTruth Render(const SE3& world_from_robot, std::uint64_t index,
                            render::CameraFrame* frame) {
    rig_.rig().RenderCamera(0, world_from_robot, 7, index, frame);
    render::FrameTruthInput input;
    input.world = &world_;
    input.camera_id = frame->camera_id;
    input.model = model();
    input.world_from_camera = frame->world_from_camera;
    input.world_from_robot = world_from_robot;
    input.instance = &frame->instance;
    input.semantic = &frame->semantic;
    return render::ComputeFrameTruth(input);
  }

 private:
  static render::RigOptions UpwardOnly() {
    render::RigOptions options = render::RigOptions::Default();
    std::vector<render::CameraOptions> cameras;
    for (render::CameraOptions c : options.cameras) {
      if (c.id != "upward") continue;
      c.enabled = true;
      cameras.push_back(c);
    }
    options.cameras = cameras;
    return options;
  }

  const worlds::World& world_;
  render::RigOptions options_;
  UploadedRig rig_;  // after options_: built from it
};

}  // namespace corridorsim::test
