#pragma once
// `drive --save-frames` as a bus consumer: every rendered frame's images are written as they
// come (frames/<camera>/{rgb,labels,depth}/<t>.png), each camera's per-frame truth and the
// intrinsics at the end (frames/<camera>/frames.json, frames/intrinsics.json; docs/frames.md).

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/run/sensor_bus.h"
#include "render/camera_rig.h"

namespace corridorsim {

class FrameWriter : public BusConsumer {
 public:
  /// Creates the folders of the enabled cameras of `rig` under `dir` and writes intrinsics.json.
  FrameWriter(const std::filesystem::path& dir, const render::RigOptions& rig);

  void OnCameraSet(const CameraSet& set) override;
  /// Writes every camera's frames.json.
  void Finish() const;
  int frames_written() const { return frames_; }

 private:
  struct Camera {
    std::filesystem::path dir;
    render::CameraOptions options;
    nlohmann::ordered_json truth = nlohmann::ordered_json::array();
  };
  std::vector<Camera> cameras_;  // the rig's enabled cameras, in order
  int frames_ = 0;
};

}  // namespace corridorsim
