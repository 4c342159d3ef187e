#pragma once
// The renderer that turns the GL backend's pinhole passes into one camera's image through its
// model.
//
// Every camera is drawn as one or more undistorted pinhole passes: an undistorted pinhole camera
// is one pass drawn with its own intrinsics (exact); a distorted pinhole is one wider pass
// remapped through the distortion; a Kannala-Brandt fisheye is drawn as the cube faces its field
// of view needs, each cropped to the part it uses, and remapped per pixel through the model
// (bilinear colour, nearest labels and depth). The remap table is built once per camera.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/image.h"
#include "common/pose.h"
#include "render/backend.h"
#include "render/camera_options.h"
#include "render/remap_kernel.h"
#include "render/scene.h"

namespace corridorsim::render {

/// One camera's rendered frame. Rows top-down; pixel (0,0) is the centre of the top-left pixel.
struct CameraFrame {
  std::string camera_id;
  SE3 world_from_camera;
  Image8 rgb;            // with noise when the camera's noise is on
  ImageF depth_m;        // exact z along the optical axis (ReadsDepth() only)
  ImageF noisy_depth_m;  // depth cameras: after the noise model, or (noise off) its range alone
  std::vector<std::uint32_t> instance;  // per pixel instance id (World ids), 0 = nothing
  std::vector<std::uint8_t> semantic;   // per pixel worlds::SemanticClass
};

/// Draws one camera: its pinhole passes and the remap table through its model.
class CameraRenderer {
 public:
  /// `samples_per_side` n: the camera is drawn at n times its resolution (n x n samples per
  /// pixel, n odd); colour is their mean, labels and depth the centre sample's.
  explicit CameraRenderer(const CameraOptions& options, int samples_per_side = 1);

  const CameraOptions& options() const { return options_; }
  /// The pinhole passes for a camera at `world_from_camera`.
  std::vector<View> Passes(const SE3& world_from_camera) const;
  /// The exposure gain of a frame at `world_from_camera` (ExposureOptions; `visible`: the
  /// drawables in view, as the passes cull them).
  double ExposureGain(const Scene& scene, const SE3& world_from_camera,
                      std::span<const std::vector<int>> visible) const;
  /// Renders the exact (noise-free) frame: Draw, then Finish.
  void Render(const Scene& scene, Backend& backend, const SE3& world_from_camera,
              CameraFrame* frame);
  /// Draws the passes (GL work) into this renderer's buffers.
  void Draw(const Scene& scene, Backend& backend, const SE3& world_from_camera);
  /// Turns the last Draw's passes into the frame (CPU only: the remap through the model, or a
  /// hand-over of the one exact pass); may run on another thread than Draw, not beside it.
  void Finish(CameraFrame* frame);
  /// Rough CPU work after Draw (depth noise 3, colour noise 2, a remap 1 per pixel), 0 for
  /// none: the rig draws the cameras with the most of it first, so it overlaps the most drawing.
  int cpu_work() const {
    const bool noise = options_.noise;
    return (noise && options_.depth ? 3 : 0) + (noise && options_.rgb_noise.Active() ? 2 : 0) +
           (lut_.empty() ? 0 : 1);
  }
  std::size_t pass_pixel_count() const;
  /// Pixels of pass `pass` that no output pixel samples (empty for a direct pinhole camera):
  /// drawn, they would be shaded for nothing.
  std::span<const PixelRect> unused_pixels(std::size_t pass) const {
    return pass < unused_.size() ? std::span<const PixelRect>(unused_[pass])
                                 : std::span<const PixelRect>();
  }
  /// Where output pixel (u, v) is sampled: the pass index and the continuous pixel position in
  /// that pass, or nothing outside the model's valid angle (for tests and tools).
  std::optional<std::pair<int, Eigen::Vector2d>> Lookup(int u, int v) const;

 private:
  struct Pass {
    SE3 camera_from_pass;  // rotation only
    View view;             // intrinsics of the (cropped) pass; pose filled per frame
  };
  // Where one output pixel samples its pass (kept for Lookup): the pass and the continuous pixel
  // position in it.
  struct LutEntry {
    float x = 0, y = 0;  // continuous pixel position in the pass image
    std::uint8_t pass = 0;
    bool valid = false;  // false outside the model's valid angle
  };
  using RemapEntry = detail::RemapEntry;
  void PlanPinholePass();
  void PlanUnusedPixels();
  void PlanRemapPasses();
  void Compose(CameraFrame* frame) const;
  /// Supersampling: `hires` (n times the size) into `frame`.
  void Downsample(const CameraFrame& hires, CameraFrame* frame) const;

  CameraOptions options_;
  int n_ = 1;               // samples per pixel side
  CameraModel draw_model_;  // the model drawn: options_.model, or n times its resolution
  CameraFrame hires_;       // supersampling: the frame at the drawn resolution
  SE3 world_from_camera_;   // of the last Draw
  std::vector<Pass> passes_;
  std::vector<LutEntry> lut_;       // empty for a direct (undistorted pinhole) camera
  std::vector<RemapEntry> remap_;   // per output pixel, alongside lut_
  std::vector<float> depth_scale_;  // camera z per pass z along each pixel's ray (depth cameras)
  std::vector<RenderedView> rendered_;
  std::vector<std::vector<PixelRect>> unused_;  // per pass, see unused_pixels()
};

}  // namespace corridorsim::render
