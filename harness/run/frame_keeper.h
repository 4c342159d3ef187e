#pragma once
// `corridorsim run --keep-frames`: downscaled JPEGs of the rendered frames, kept within a size
// budget, for viewer.html (docs/viewer.md). Deterministic: which frames are kept depends only on
// the frames' order and their JPEG bytes, never on timing.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "harness/run/sensor_bus.h"

namespace corridorsim {

class FrameKeeper : public BusConsumer {
 public:
  static constexpr int kMaxWidthPx = 320;  // a kept frame's width at most (aspect kept)
  static constexpr int kJpegQuality = 80;

  /// `budget_bytes`: the most the kept JPEGs may hold together (at least one frame's worth).
  explicit FrameKeeper(std::size_t budget_bytes);

  /// Keeps each camera's n-th frame when n is a multiple of the stride (1 at first); when the
  /// kept bytes pass the budget, the stride doubles and the frames it no longer keeps go.
  void OnCameraSet(const CameraSet& set) override;

  /// frames/<camera>_<stamp_ns>.jpg and frames/frames.csv
  /// (`camera,t_ns,file,scale,width,height`, one row per kept frame in stamp order) into `dir`.
  void Write(const std::filesystem::path& dir) const;

  std::size_t kept_bytes() const { return bytes_; }
  std::size_t kept_frames() const { return kept_.size(); }
  std::uint64_t stride() const { return stride_; }

 private:
  struct Kept {
    std::string camera;
    std::int64_t stamp_ns = 0;
    std::uint64_t index = 0;  // the camera's n-th frame
    int width = 0, height = 0;
    double scale = 1.0;
    std::string jpeg;
  };
  void Thin();

  std::size_t budget_;
  std::size_t bytes_ = 0;
  std::uint64_t stride_ = 1;
  std::map<std::string, std::uint64_t> seen_;  // frames per camera so far
  std::vector<Kept> kept_;                     // stamp order
};

}  // namespace corridorsim
