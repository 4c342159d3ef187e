#pragma once
// Camera models as JSON, in the form of the per-camera entries of intrinsics.json
// (docs/frames.md), which OpenCV- and Kalibr-style tools read:
//   {"model": "pinhole_radtan" | "kannala_brandt", "width": px, "height": px, "fx": px,
//    "fy": px, "cx": px, "cy": px, "distortion": [k1, k2, p1, p2, k3] | [k1, k2, k3, k4]}

#include <string>

#include <nlohmann/json.hpp>

#include "common/camera_models.h"

namespace corridorsim {

/// The model as the object above, keys in that order.
nlohmann::ordered_json CameraModelToJson(const CameraModel& model);

/// The model an object of the form above describes. An intrinsics.json entry as corridorsim
/// writes it (harness/run/frame_io.h's IntrinsicsJson) reads as it is: its `robot_from_camera` (an
/// object) and `depth_scale` (a positive number) describe the mount and the depth images, not the
/// model, and are passed over. Throws OptionsError naming the key (a missing, unknown or
/// mistyped key, a distortion of the wrong length, an unknown model name) or, with the key
/// "model", what CameraModel::Check() finds wrong with the parameters.
CameraModel CameraModelFromJson(const nlohmann::ordered_json& json);
CameraModel CameraModelFromJson(const nlohmann::json& json);

/// The model of `camera` in an intrinsics.json as corridorsim writes it: one camera's entry (an
/// object with `model`: `dataset`'s <camera>/intrinsics.json), or every camera's entry under its
/// id (`snapshot`'s intrinsics.json, `drive`'s frames/intrinsics.json). Throws OptionsError as
/// CameraModelFromJson, with the key `camera` when the file holds no entry of that camera.
CameraModel CameraModelFromIntrinsicsJson(const nlohmann::ordered_json& json,
                                          const std::string& camera);

}  // namespace corridorsim
