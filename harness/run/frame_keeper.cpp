#include "harness/run/frame_keeper.h"

#include <algorithm>
#include <cstdio>

#include "common/io/atomic_file.h"
#include "worlds/image_io.h"

namespace corridorsim {

FrameKeeper::FrameKeeper(std::size_t budget_bytes) : budget_(budget_bytes) {}

void FrameKeeper::OnCameraSet(const CameraSet& set) {
  for (const CameraSlot& slot : set.cameras) {
    if (slot.message == nullptr) continue;  // dropped: nothing was seen
    const std::uint64_t index = seen_[slot.camera_id]++;
    if (index % stride_ != 0) continue;
    const Image8& rgb = slot.message->frame.rgb;
    if (rgb.channels != 3 || rgb.empty()) continue;  // a depth-only camera: nothing to show
    Kept k;
    k.camera = slot.camera_id;
    k.stamp_ns = set.stamp_ns;
    k.index = index;
    k.jpeg = EncodeJpegShrunk(rgb, kMaxWidthPx, kJpegQuality, slot.camera_id + " frame", &k.scale);
    k.width = rgb.width;
    k.height = rgb.height;
    bytes_ += k.jpeg.size();
    kept_.push_back(std::move(k));
    Thin();
  }
}

void FrameKeeper::Thin() {
  // Bounded: each pass halves what is kept, and a single frame is never thinned away.
  while (bytes_ > budget_ && kept_.size() > 1) {
    stride_ *= 2;
    std::size_t bytes = 0;
    std::vector<Kept> kept;
    for (Kept& k : kept_) {
      if (k.index % stride_ != 0) continue;
      bytes += k.jpeg.size();
      kept.push_back(std::move(k));
    }
    kept_ = std::move(kept);
    bytes_ = bytes;
    if (stride_ > (std::uint64_t{1} << 40)) break;
  }
}

void FrameKeeper::Write(const std::filesystem::path& dir) const {
  std::filesystem::create_directories(dir);
  std::string csv = "camera,t_ns,file,scale,width,height\n";
  for (const Kept& k : kept_) {
    const std::string name = k.camera + "_" + std::to_string(k.stamp_ns) + ".jpg";
    WriteFileAtomic(dir / name, k.jpeg);
    char scale[32];
    std::snprintf(scale, sizeof(scale), "%.9g", k.scale);
    csv += k.camera + "," + std::to_string(k.stamp_ns) + "," + name + "," + scale + "," +
           std::to_string(k.width) + "," + std::to_string(k.height) + "\n";
  }
  WriteFileAtomic(dir / "frames.csv", csv);
}

}  // namespace corridorsim
