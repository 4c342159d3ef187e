#pragma once
// How a camera is drawn, known from its options before anything is planned or allocated: the
// model it is drawn with (supersampling draws it at n times its resolution), whether it is one
// exact pass, and what its passes and frames cost (RigOptions::Check and the Rig refuse a camera
// that needs more than a pass or a rig may have).

#include <cstdint>

#include "common/camera_models.h"
#include "render/camera_options.h"

namespace corridorsim::render {

/// What a camera costs, known from its options before anything is planned or allocated: the
/// largest pass it is drawn in (an undistorted pinhole: its image; a distorted pinhole: the
/// undistorted window its border reaches, from the border pixels alone; a fisheye: a cube face
/// with its 2 px crop border and rounding, cube_face_px + 7) and an upper bound of the bytes its
/// frames take (the GL targets and read-backs of up to six passes, the frame, the remap table and
/// what planning it needs at once).
struct CameraBudget {
  int pass_width_px = 0;
  int pass_height_px = 0;
  int passes = 0;  // at most this many passes (a fisheye: 6 cube faces)
  std::uint64_t bytes = 0;
};
/// `samples`: render.samples (the camera drawn at sqrt(samples) times its resolution).
CameraBudget CameraBudgetOf(const CameraOptions& camera, int samples = 1);

/// The largest pass side (px) a camera may need: every backend (llvmpipe's renderbuffers reach
/// 16384, but a 16384^2 R32F target is the 1 GiB llvmpipe refuses) draws it; RigOptions::Check
/// refuses more at the camera's key.
inline constexpr int kMaxPassPx = 8192;
/// The most bytes the enabled cameras of a rig may need together (CameraBudget::bytes): a
/// 8192 x 8192 depth camera needs 3 GB.
inline constexpr std::uint64_t kMaxRigBytes = std::uint64_t{6} << 30;

/// render.samples (1, 9, 25) as samples per pixel side (1, 3, 5).
int SamplesPerSide(int samples);

/// The model at n times the resolution: pixel centres u map to n u + (n - 1) / 2, so the centre
/// sample of output pixel (u, v) is drawn pixel (n u + (n - 1) / 2, n v + (n - 1) / 2).
CameraModel ScaledModel(const CameraModel& model, int n);

/// A pinhole without distortion: drawn in one exact pass with its own intrinsics.
bool IsUndistortedPinhole(const CameraModel& model);

}  // namespace corridorsim::render
