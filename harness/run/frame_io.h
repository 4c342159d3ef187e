#pragma once
// Camera frames as files: the encodings `snapshot`, `drive --save-frames` and the dataset export
// share (PNG images, 16-bit labels and depth, overlays of the ground truth, intrinsics JSON).

#include <string>

#include <nlohmann/json.hpp>

#include "common/image.h"
#include "common/io/stable_json.h"  // PoseJson: the one pose convention of every JSON file
#include "common/pose.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "worlds/world.h"

namespace corridorsim {

inline constexpr double kDepthScale = 5000.0;  // TUM RGB-D convention: 16-bit depth, 5000 per m

/// Backend named by CORRIDORSIM_RENDER_BACKEND, else the scenario's `render.backend`. Throws
/// InputError for an unknown name.
render::BackendKind ChooseBackend(render::BackendKind from_scenario);

/// Labels as a 16-bit RGB PNG: R = semantic class, G = instance id >> 16, B = instance id & 0xffff.
std::string EncodeLabels(const render::CameraFrame& frame, int width, int height);

/// Metric depth as a 16-bit PNG at kDepthScale per metre; 0 = invalid or beyond 13.1 m.
std::string EncodeDepth(const ImageF& depth, const std::string& what);

/// The ground truth drawn on the image, for a person to check at a glance.
Image8 DrawOverlay(const Image8& rgb, const render::FrameTruth& truth);

/// The ground truth of a rendered frame (render::ComputeFrameTruth with the frame's label images
/// for occlusion): what `snapshot` and `dataset` write beside each image.
render::FrameTruth FrameTruthOf(const worlds::World& world, const render::CameraOptions& options,
                                const render::CameraFrame& frame, const SE3& world_from_robot);

/// Model, size, fx, fy, cx, cy, distortion, robot_from_camera, and depth_scale for depth cameras.
nlohmann::ordered_json IntrinsicsJson(const render::CameraOptions& options);

}  // namespace corridorsim
