#pragma once
// The sensor rig's options: cameras mounted on the robot (front RGB-D like P1's ASUS Xtion Pro
// Live, a lateral web camera tilted up to read door plates (P1), a wide-angle upward camera
// (P2/P3)) as parsed from a scenario's `sensors:` section, and the `render:` keys (backend,
// supersampling, lighting). What a camera costs is render/camera_budget.h; how it is drawn,
// render/camera_renderer.h; the rig that renders them, render/camera_rig.h.

#include <optional>
#include <string>
#include <vector>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/io/input_text.h"
#include "common/io/options_yaml.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "render/backend.h"
#include "render/noise.h"
#include "render/scene.h"
#include "worlds/world.h"

namespace corridorsim::render {

/// Where a sensor sits on the robot. Position in the robot frame R (x forward, y left, z up);
/// a camera's optical axis (another sensor's x axis) points at heading `yaw_deg` (0 forward, 90
/// left) and elevation `pitch_deg` (0 horizontal, 90 straight up); `roll_deg` turns the image
/// (the sensor) about that axis. At zero roll a camera's image x axis is horizontal (for an
/// upward camera: towards the robot's right).
struct Mount {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double yaw_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  /// The camera's optical frame (z along the optical axis, x right and y down in the image).
  SE3 RobotFromCamera() const;
  /// The frame of a sensor that is not a camera (an IMU, a laser scanner: sim/sensor_options.h),
  /// REP 103's body axes: x at heading `yaw_deg` and elevation `pitch_deg`, y to its left and z
  /// up at zero roll; `roll_deg` turns it about x. Rz(yaw) Ry(-pitch) Rx(roll).
  SE3 RobotFromBody() const;
};

/// The camera's exposure: the gain from scene radiance to the sensor's full scale, applied before
/// the sensor clips (lamps saturate, as on a real camera). `fixed` uses `gain`; `auto` meters each
/// frame from the scene before drawing it (the mean luminance of the surfaces in view, weighted by
/// the solid angle each covers, lamps left out) and sets gain = target / mean, within
/// [min_gain, max_gain]. Both are deterministic: a frame's gain depends on its pose alone.
enum class ExposureMode { kFixed, kAuto };
struct ExposureOptions {
  ExposureMode mode = ExposureMode::kFixed;
  double gain = 1.0;       // fixed: the gain; auto: unused
  double target = 0.45;    // auto: the mean luminance the metered scene is brought to
  double min_gain = 0.25;  // auto: bounds of the gain
  double max_gain = 4.0;
};

struct CameraOptions {
  std::string id;  // "front", "lateral", "upward" or a name of the scenario's
  bool enabled = true;
  double rate_hz = 10.0 / 3.0;    // frames per second (P1: a 300 ms sensor period)
  double phase_s = 0.0;           // first frame at this time; then every 1 / rate_hz (sim clock)
  double drop_probability = 0.0;  // each frame is lost with this probability (sim clock)
  CameraModel model;
  Mount mount;
  bool depth = false;  // a registered depth image (front RGB-D sensor)
  // Exact depth rendered as frame truth only (any lens; pipelines never get it): the metrics score
  // corner detections against the point seen at their pixel. Implied by `depth`.
  bool truth_depth = false;
  bool noise = true;  // apply the noise models below (false: exact images)
  DepthNoiseOptions depth_noise;
  RgbNoiseOptions rgb_noise;
  int cube_face_px = 0;  // fisheye: cube face resolution (0 = matched to the model's centre)
  ExposureOptions exposure;
  bool ReadsDepth() const { return depth || truth_depth; }
};

/// Samples per pixel that `render.samples` allows: n x n per pixel with n odd, so one sample
/// sits at the pixel's centre (labels and depth come from it; colour is the mean of all).
inline constexpr int kSupersampleChoices[] = {1, 9, 25};

struct RigOptions {
  // front, lateral, upward, then the scenario's own in the order they are first named
  std::vector<CameraOptions> cameras;
  BackendKind backend = BackendKind::kOsMesa;
  int samples = 1;  // supersampling: 1, 9 (3 x 3) or 25 (5 x 5) samples per pixel
  SceneOptions scene;

  /// The defaults: front RGB-D (640x480, 58 x 45 deg), lateral web camera (640x480, 60 deg,
  /// facing left, 25 deg up), upward Kannala-Brandt fisheye (640x480, 110 deg, P3).
  static RigOptions Default();
  const CameraOptions* Find(const std::string& id) const;
  /// The first problem (key relative to `sensors`, e.g. "upward.fov_deg"), or nothing.
  std::optional<OptionsProblem> Check() const;
  /// The first problem of the `render:` keys (key relative to `render`), or nothing.
  std::optional<OptionsProblem> CheckRender() const;
};

/// The `type` key every sensor's table starts with (`camera`, `imu`, `laser`):
/// harness/scenario/scenario_sensors.cpp makes a new sensor of its kind where it is first named;
/// the sensor's map may say its kind again, and nothing else. Echoed always, so that a resolved
/// scenario names its new sensors' kinds.
template <class T>
void AddSensorTypeKey(OptionTable<T>& t, const char* kind) {
  const std::string k = kind;
  t.AddCustom(
      "type", "",
      [k](YamlMap& map, T& sensor) {
        std::string type;
        if (map.Read("type", type) && type != k) {
          map.Fail("type", "'" + InputExcerpt(type) + "': '" + InputExcerpt(sensor.id) +
                               "' is a sensor of type " + k +
                               " (a sensor's type is fixed where it is first named)");
        }
      },
      [k](const T&, OptionsYamlWriter& out) { out.Scalar("type", k); },
      [k](const T&) {
        return std::vector<OptionDocRow>{
            {"type", "", "`" + k + "`", "`camera`, `imu`, `laser`",
             "the sensor's kind, required where a new sensor is first named (front, lateral "
             "and upward are cameras); docs/sensors.md"}};
      });
}

/// A camera named `id` that the defaults do not have (`sensors.<id>: {type: camera, ...}`): the
/// front camera's defaults without depth (640x480 pinhole, 58 deg, at the front camera's mount).
CameraOptions NewCameraOptions(const std::string& id);

/// The keys of one camera (`sensors.<id>`), of the `sensors:` map (the cameras by id) and of the
/// `render:` map (backend, lighting): parsing, bounds, echo, docs.
const OptionTable<CameraOptions>& CameraOptionsTable();
const OptionTable<RigOptions>& SensorsOptionsTable();
const OptionTable<RigOptions>& RenderOptionsTable();

/// Reads a `sensors:` map onto `rig` (cameras by id; unknown ids are errors).
void ParseSensors(YamlMap& sensors, RigOptions& rig);

/// The rig as a world's appearance randomisation draws it (worlds::AppearanceDraw): every
/// camera's exposure gain times camera_exposure; cameras with shot noise get read noise times and
/// full well divided by camera_noise; colour cameras with noise on get camera_blur_px more motion
/// blur. Without randomisation the rig itself.
RigOptions WithAppearance(const RigOptions& rig, const worlds::AppearanceDraw& look);

}  // namespace corridorsim::render
