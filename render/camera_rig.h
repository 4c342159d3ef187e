#pragma once
// The sensor rig: the enabled cameras of RigOptions (render/camera_options.h), each drawn by its
// CameraRenderer (render/camera_renderer.h), scheduled frame by frame: the GL passes on the
// calling thread, the CPU stages after them (remap, noise) on the rig's worker thread.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/io/serial_worker.h"
#include "common/pose.h"
#include "render/backend.h"
#include "render/camera_options.h"
#include "render/camera_renderer.h"
#include "render/scene.h"

namespace corridorsim::render {

/// The whole rig on one robot.
///
/// The GL passes run on the calling thread; what follows them on the CPU (a fisheye's remap,
/// the noise models) runs on the rig's worker thread while the next cameras draw: llvmpipe
/// leaves a core idle while the calling thread transforms and bins triangles. Those stages read
/// and write only their own camera's buffers and frame and draw from their own streams, so the
/// bytes never depend on the overlap.
class Rig {
 public:
  Rig(const RigOptions& options, const Scene& scene, Backend& backend);
  ~Rig();
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  /// Renders every enabled camera at `world_from_robot`, then applies each camera's noise from
  /// the stream (seed, 0, "render.noise.<camera>") derived for `frame_index` (the same bytes as
  /// RenderCamera gives each camera).
  void Render(const SE3& world_from_robot, std::uint64_t seed, std::uint64_t frame_index,
              std::vector<CameraFrame>* frames);
  /// Renders the enabled camera `index` (in cameras() order) alone, with the same noise
  /// streams as Render(): a camera's frame does not depend on which other cameras render.
  void RenderCamera(std::size_t index, const SE3& world_from_robot, std::uint64_t seed,
                    std::uint64_t frame_index, CameraFrame* frame);
  /// RenderCamera in two halves: draws the camera now and leaves its CPU stages running;
  /// `*frame` must stay where it is, untouched, until Wait() (or the next StartCamera of the
  /// same camera, which waits for the last one) returns.
  void StartCamera(std::size_t index, const SE3& world_from_robot, std::uint64_t seed,
                   std::uint64_t frame_index, CameraFrame* frame);
  /// Waits for every started camera; rethrows the first exception of their stages.
  void Wait();
  /// Waits for every started camera and drops their exceptions: for a caller unwinding from an
  /// error of its own, whose started frames must not go away under the worker.
  void Abandon() noexcept;
  const std::vector<CameraRenderer>& cameras() const { return cameras_; }

 private:
  // After camera `index` drew: its frame, then its noise.
  void FinishCamera(std::size_t index, std::uint64_t seed, std::uint64_t frame_index,
                    CameraFrame* frame);
  // The camera's noise models on `frame`, from its stream for `frame_index`.
  void ApplyNoise(std::size_t index, std::uint64_t seed, std::uint64_t frame_index,
                  CameraFrame* frame) const;

  const Scene& scene_;
  Backend& backend_;
  std::vector<CameraRenderer> cameras_;
  std::vector<std::size_t> draw_order_;  // Render's order: most CPU work after the draw first
  // The CPU stages after the draws, in the order the cameras started (one thread: the other
  // core is llvmpipe's); a bound of 64 queued frames is never reached by one rig frame.
  SerialWorker worker_{64};
  std::vector<bool> started_;  // per camera: a frame whose stages may still run
};

}  // namespace corridorsim::render
