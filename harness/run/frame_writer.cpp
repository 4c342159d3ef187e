#include "harness/run/frame_writer.h"
#include "harness/run/run_io.h"

#include <cstdio>
#include <string>

#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "harness/run/frame_io.h"
#include "worlds/image_io.h"

namespace corridorsim {

FrameWriter::FrameWriter(const std::filesystem::path& dir, const render::RigOptions& rig) {
  nlohmann::ordered_json intrinsics = nlohmann::ordered_json::object();
  for (const render::CameraOptions& options : rig.cameras) {
    if (!options.enabled) continue;
    Camera camera{dir / options.id, options};
    for (const char* sub : {"rgb", "labels", "depth"}) {
      if (std::string(sub) != "depth" || options.depth) {
        std::filesystem::create_directories(camera.dir / sub);
      }
    }
    intrinsics[options.id] = IntrinsicsJson(options);
    cameras_.push_back(std::move(camera));
  }
  WriteFileAtomic(dir / "intrinsics.json", JsonFileText(intrinsics));
}

void FrameWriter::OnCameraSet(const CameraSet& set) {
  for (const CameraSlot& slot : set.cameras) {
    if (!slot.message) continue;
    const sim::CameraMessage& m = *slot.message;
    Camera& camera = cameras_.at(slot.camera);
    const std::string stamp = StampSeconds(m.stamp_ns);
    const std::string name = stamp + ".png";
    const render::CameraFrame& f = m.frame;
    WriteFileAtomic(camera.dir / "rgb" / name, EncodePng(f.rgb, name));
    WriteFileAtomic(camera.dir / "labels" / name, EncodeLabels(f, f.rgb.width, f.rgb.height));
    if (camera.options.depth) {
      WriteFileAtomic(camera.dir / "depth" / name, EncodeDepth(f.noisy_depth_m, name));
    }
    nlohmann::ordered_json j;
    j["t"] = stamp;
    j["frame_index"] = m.frame_index;
    j["world_from_camera"] = PoseJson(f.world_from_camera);
    j["truth"] = render::FrameTruthJson(m.truth);
    camera.truth.push_back(std::move(j));
    ++frames_;
  }
}

void FrameWriter::Finish() const {
  for (const Camera& camera : cameras_) {
    WriteFileAtomic(camera.dir / "frames.json", JsonFileText(camera.truth, 1));
  }
}

}  // namespace corridorsim
