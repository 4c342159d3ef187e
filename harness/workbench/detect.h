#pragma once
// `corridorsim detect IMAGE.png`: the robot's detectors (slam/features/) run on any image, what
// they found printed as JSON on stdout (docs/detectors.md) and, with --out, drawn on an overlay
// PNG. Each detector is one section of the JSON and one function below: a new detector (the door
// plates) is one more section function called from RunDetect.

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/camera_models.h"
#include "common/image.h"

namespace corridorsim {

/// The camera an image comes from: which detectors run (P1: the vanishing point on the front
/// RGB-D sensor's image, door plates on the lateral camera's; P3: lamps on the upward camera's;
/// corners on each) and whether a depth image can be registered.
enum class DetectCamera { kFront, kLateral, kUpward };
std::string DetectCameraName(DetectCamera camera);

/// Bounds on the inputs: larger files or images are refused (exit 2) before they are decoded.
inline constexpr std::size_t kMaxDetectFileBytes = std::size_t{256} << 20;  // 256 MiB
inline constexpr int kMaxDetectImageSide = 8192;                            // px, each side

/// A PNG file (8-bit grey, RGB or RGBA; 16-bit too) as 8-bit RGB, within the bounds above. A
/// missing, unreadable, non-PNG or too large file throws InputError naming it (`what` says which
/// input it is).
Image8 ReadRgbPng(const std::filesystem::path& path, const std::string& what);

struct DetectRequest {
  std::filesystem::path image_file;                   // PNG (8-bit grey, RGB or RGBA; 16-bit too)
  DetectCamera camera = DetectCamera::kFront;         // --camera
  std::optional<std::filesystem::path> depth_file;    // --depth: 16-bit PNG, 5000 per metre (TUM)
  std::optional<std::filesystem::path> overlay_file;  // --out: the overlay PNG to write
  // --intrinsics (upward): the camera model as intrinsics.json holds it (docs/frames.md)
  std::optional<std::filesystem::path> intrinsics_file;
};

/// The decoded inputs of one detection.
struct DetectInput {
  std::string image_name;  // as given on the command line
  DetectCamera camera = DetectCamera::kFront;
  Image8 rgb;                     // RGB, row 0 on top
  std::optional<ImageF> depth_m;  // registered to rgb: metres, 0 = invalid
  // Upward: the calibrated model (--intrinsics, else the default rig's upward camera).
  std::optional<CameraModel> model;
};

/// Reads and checks the request's files. Throws InputError naming the file for a file that is
/// missing, unreadable, not a regular file, larger than kMaxDetectFileBytes, not a PNG, larger
/// than kMaxDetectImageSide, a depth image that is not one 16-bit channel or not the image's size,
/// an intrinsics file that is not a valid camera model of the image's size (or, without one, an
/// upward image of another size than the default rig's upward camera).
DetectInput LoadDetectInput(const DetectRequest& request);

/// The `vanishing_point` section (P1 section 2): the point, its lines and quality, or why there
/// is none. Draws the candidate lines, the used lines and the point on `overlay` (RGB, the
/// image's size) when given.
nlohmann::ordered_json VanishingPointSection(const DetectInput& input, Image8* overlay);

/// The `corners` section (Harris, P1 section 6's baseline): each corner with its depth when a
/// depth image was given. Draws the corners on `overlay` when given.
nlohmann::ordered_json CornersSection(const DetectInput& input, Image8* overlay);

/// The `door_plates` section (P1 section 3, lateral camera): each candidate the SVM accepted with
/// its number-region box, SVM margin s(x) and reading (digits with scores; accepted when every
/// digit clears the threshold), with the shipped models. Throws slam::ModelFileError for a
/// missing or corrupt model file. Draws the boxes (green: accepted, with the number).
nlohmann::ordered_json PlatesSection(const DetectInput& input, Image8* overlay);

/// The `lamps` section (P3 section II, upward camera): each bright region tested, circular lamps
/// first (centre, radius, sigma1, sigma2 of the three-point centres, cut by the border), then the
/// rejected ones with the reason. Draws lamps green, rejected regions red.
nlohmann::ordered_json LampsSection(const DetectInput& input, Image8* overlay);

/// The whole document: the input's description, then one section per detector the camera runs.
/// `overlay` (optional) gets the image with every section's drawing.
nlohmann::ordered_json RunDetect(const DetectInput& input, Image8* overlay);

/// The job: loads the input, prints the JSON on stdout and writes the overlay when asked.
/// Throws InputError for bad input (nothing is printed or written then).
void RunDetectJob(const DetectRequest& request);

}  // namespace corridorsim
