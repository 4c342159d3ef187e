#pragma once
// Sensor noise as pure functions on rendered images (STYLE item 9: truth, noise and sensing are
// separate stages). Each stage is optional and draws from the RandomStream the caller passes (one
// stream per camera and frame, STYLE item 8); with every stage off the output equals the input bit
// for bit. Stages that are off draw nothing; the depth stages draw from the one stream row by row
// (a row's lateral draws, then its axial draws, ...), so switching one stage on or off changes the
// numbers the others draw.

#include <optional>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/image.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "common/random.h"

namespace corridorsim::render {

/// Structured-light depth sensor noise. The defaults are an ASUS Xtion Pro Live / Kinect v1.
struct DepthNoiseOptions {
  // Valid range: depths outside [min_m, max_m] become 0 = invalid. Always applied, with the
  // camera's noise off too (ApplyDepthRange), so the depth matches what the Calibration says.
  double min_m = 0.5;  // m, nearest valid depth
  double max_m = 8.0;  // m, farthest valid depth

  // Disparity quantisation: d = fx * baseline_m / z (px) is rounded to 1 / subpixel px and the
  // depth recomputed as fx * baseline_m / d_q. A disparity that rounds to 0 is invalid.
  bool quantise = true;
  double baseline_m = 0.075;  // m, projector-camera baseline
  int subpixel = 8;           // disparity steps per px

  // Axial noise, Gaussian with sigma_z(z) = axial_a_m + axial_b * (z - axial_z0_m)^2
  // (Nguyen, Izadi, Lovell 2012, eq. 6, for incidence angles below 60 deg).
  bool axial = true;
  double axial_a_m = 0.0012;  // m, sigma at z = axial_z0_m
  double axial_b = 0.0019;    // 1/m, growth of sigma with (z - axial_z0_m)^2
  double axial_z0_m = 0.4;    // m, depth of the smallest sigma

  // Lateral noise: a pixel takes the depth of the pixel displaced by round(N(0, sigma)) in x and in
  // y (clamped to the image and to +-ceil(4 sigma) px; both shifts drawn by inversion from one
  // 64-bit draw). Nguyen et al. report 0.8 px below 60 deg.
  double lateral_sigma_px = 0.8;  // px, 0 = off

  // Dropouts at grazing incidence: with theta the angle between the viewing ray and the surface
  // normal, a pixel is kept below grazing_start_deg, dropped above grazing_max_deg, and dropped
  // with probability (theta - start) / (max - start) in between.
  bool grazing = true;
  double grazing_start_deg = 70.0;  // deg, dropouts begin
  double grazing_max_deg = 78.0;    // deg, everything beyond is invalid

  double random_dropout = 0.0;  // probability that any valid pixel becomes invalid, in [0, 1]

  /// The first invalid value (key relative to this struct and what is wrong), or nullopt.
  std::optional<OptionsProblem> Check() const;
};

/// The keys of `noise.depth` (parsing, bounds, echo, docs).
const OptionTable<DepthNoiseOptions>& DepthNoiseOptionsTable();

/// Reads the keys of DepthNoiseOptions present in `map` over `options`; unknown keys are errors.
void ParseDepthNoiseOptions(YamlMap& map, DepthNoiseOptions& options);

/// Applies depth noise in place. `depth_m` holds z along the optical axis (m), 0 = invalid.
/// `intrinsics` must match the image size; only its pinhole part (fx, fy, cx, cy) is used, to
/// back-project pixels for the normals and for the disparity: exact for an undistorted camera,
/// approximate towards the edges of a distorted one (whose depth image the rig remaps).
///
/// Per pixel, in this order (each stage runs over a whole row before the next; the axial noise is
/// Gaussian by the ziggurat method):
///   1. lateral: take the depth of the displaced pixel (the sensor's matching window lands on a
///      neighbouring surface, so edges fray); an invalid source makes the pixel invalid;
///   2. axial: add N(0, sigma_z(z)) (the disparity measurement's noise, before it is quantised);
///   3. quantisation of the disparity (the sensor reports quantised disparities, so its outputs
///      lie on the quantisation grid whatever the noise);
///   4. range: outside [min_m, max_m] -> 0 (the sensor's validity test is on what it reports);
///   5. grazing dropouts, decided on the noise-free surface at the source pixel of step 1 (its
///      normal from central differences of the back-projected input depth; a depth discontinuity
///      reads as a grazing surface, which mimics the invalid band real sensors leave around
///      object edges), then random dropouts.
/// Normals come from the input depth, not the noisy one: 1 mm of noise between pixels a few mm
/// apart would make every surface look grazing.
void ApplyDepthNoise(const DepthNoiseOptions& options, const PinholeRadTan& intrinsics,
                     RandomStream& rng, ImageF* depth_m);

/// Whether the sensor reports depth `z_m` (m): inside [min_m, max_m] (false for NaN). The range
/// test of ApplyDepthNoise (step 4) and of ApplyDepthRange.
inline bool InDepthRange(const DepthNoiseOptions& options, double z_m) {
  return z_m >= options.min_m && z_m <= options.max_m;
}

/// The valid range alone, in place: depths outside [min_m, max_m] become 0 (invalid), the others
/// stay bit for bit; draws nothing. What a depth camera with its noise off reports, so that its
/// depth holds what the calibration's range (harness/scenario/calibration.h) promises, as with
/// noise on.
void ApplyDepthRange(const DepthNoiseOptions& options, ImageF* depth_m);

/// Colour camera noise on an 8-bit image whose values are taken as linear in irradiance. The
/// defaults change nothing; typical webcam values are full_well_electrons 6000 and
/// read_noise_electrons 6.
struct RgbNoiseOptions {
  double exposure = 1.0;  // gain on the collected signal (exposure time ratio), > 0; 1 = off

  // Vignetting: the signal is multiplied by 1 - vignetting * (r / r_corner)^2, r the distance of a
  // pixel centre from the image centre and r_corner that of the corner pixel centres.
  double vignetting = 0.0;  // relative fall-off at the image corners, in [0, 1]; 0 = off

  // Poisson-Gaussian sensor noise: a value of 255 DN collects full_well_electrons electrons; the
  // count is Poisson, then read noise N(0, read_noise_electrons) is added. In DN:
  // var = DN * 255 / full_well + (read * 255 / full_well)^2.
  double full_well_electrons = 0.0;   // electrons at 255 DN, 0 = no shot noise
  double read_noise_electrons = 0.0;  // electrons (std), 0 = off; needs full_well_electrons > 0

  // Linear motion blur: each pixel averages the image along a segment of this length centred on
  // it, in the direction the caller passes (the image motion during the exposure).
  double motion_blur_px = 0.0;  // px, 0 = off

  /// Whether any stage is on (with none, ApplyRgbNoise leaves the image as it is).
  bool Active() const {
    return motion_blur_px > 0 || full_well_electrons > 0 || exposure != 1.0 || vignetting != 0.0;
  }

  /// The first invalid value (key relative to this struct and what is wrong), or nullopt.
  std::optional<OptionsProblem> Check() const;
};

/// The keys of `noise.rgb` (parsing, bounds, echo, docs).
const OptionTable<RgbNoiseOptions>& RgbNoiseOptionsTable();

/// Reads the keys of RgbNoiseOptions present in `map` over `options`; unknown keys are errors.
void ParseRgbNoiseOptions(YamlMap& map, RgbNoiseOptions& options);

/// Applies colour noise in place to every channel of `rgb`, in the order light meets the sensor:
/// motion blur (scene motion during the exposure), vignetting (lens), exposure gain, shot noise,
/// read noise, then rounding to the nearest DN and clamping to [0, 255]. `blur_direction` is
/// normalised here; a zero direction means no blur. Draws one Poisson and, with read noise, one
/// Normal per channel value, in row-major order.
void ApplyRgbNoise(const RgbNoiseOptions& options, RandomStream& rng, Image8* rgb,
                   Eigen::Vector2d blur_direction = {1, 0});

}  // namespace corridorsim::render
