#include "render/camera_rig.h"

#include "render/lighting.h"

#include "common/io/options_yaml.h"
#include "common/options_checker.h"
#include "common/time.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>

namespace corridorsim::render {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDegToRad = std::numbers::pi / 180.0;

const auto& Num = FormatNumber;

bool IsUndistortedPinhole(const CameraModel& model) {
  const PinholeRadTan* p = model.pinhole();
  return p && p->k1 == 0 && p->k2 == 0 && p->p1 == 0 && p->p2 == 0 && p->k3 == 0;
}

// Rotation from a pass (cube face) frame to the camera frame whose optical axis is `axis`.
Matrix3d FaceRotation(int face) {
  // Columns: the face's x, y, z axes in the camera frame (x right, y down, z forward).
  Matrix3d r;
  switch (face) {
    case 0:
      r << 1, 0, 0, 0, 1, 0, 0, 0, 1;
      break;  // +z
    case 1:
      r << 0, 0, 1, 0, 1, 0, -1, 0, 0;
      break;  // +x: face z = cam x, face x = -cam z
    case 2:
      r << 0, 0, -1, 0, 1, 0, 1, 0, 0;
      break;  // -x
    case 3:
      r << 1, 0, 0, 0, 0, 1, 0, -1, 0;
      break;  // +y: face z = cam y, face y = -cam z
    case 4:
      r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      break;  // -y
    default:
      r << -1, 0, 0, 0, 1, 0, 0, 0, -1;
      break;  // -z
  }
  return r;
}

// What is wrong with a field of view for a model, or nothing. A pinhole's is horizontal, a
// fisheye's spans the smaller image side.
std::optional<std::string> FovProblem(bool pinhole, double fov_deg) {
  if (!(fov_deg > 0)) return "the field of view must be positive (got " + Num(fov_deg) + ")";
  if (pinhole && fov_deg >= 150.0) {
    return "a pinhole camera must see less than 150 degrees (got " + Num(fov_deg) +
           "); use model: kannala_brandt";
  }
  if (!pinhole && fov_deg >= 180.0) {
    return "a fisheye must see less than 180 degrees (got " + Num(fov_deg) + ")";
  }
  return std::nullopt;
}

// The model's field of view as its `fov_deg` key means it (FromFov's argument): a pinhole's
// horizontal one, a fisheye's across the smaller image side.
double FovKeyDegOf(const CameraModel& model) {
  const double rad = model.pinhole() ? model.HorizontalFovRad() : model.FieldOfViewRad();
  return rad / kDegToRad;
}

}  // namespace

SE3 Mount::RobotFromCamera() const {
  const double yaw = yaw_deg * kDegToRad, pitch = pitch_deg * kDegToRad,
               roll = roll_deg * kDegToRad;
  const Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                         std::sin(pitch));
  // Horizontal right of the heading (defined by yaw even when looking straight up).
  const Vector3d right0(std::sin(yaw), -std::cos(yaw), 0.0);
  const Vector3d down0 = forward.cross(right0);
  const Vector3d right = std::cos(roll) * right0 + std::sin(roll) * down0;
  const Vector3d down = forward.cross(right);
  Matrix3d r;
  r.col(0) = right;
  r.col(1) = down;
  r.col(2) = forward;
  return SE3(r, Vector3d(x_m, y_m, z_m));
}

RigOptions RigOptions::Default() {
  RigOptions rig;
  CameraOptions front;
  front.id = "front";
  front.model = PinholeRadTan::FromFov(640, 480, 58.0 * kDegToRad);
  front.mount = Mount{0.18, 0.0, 0.45, 0.0, 0.0, 0.0};
  front.depth = true;
  rig.cameras.push_back(front);

  CameraOptions lateral;
  lateral.id = "lateral";
  lateral.model = PinholeRadTan::FromFov(640, 480, 60.0 * kDegToRad);
  // P1's scenarios mount it level on a 1.5 m mast instead (scenarios/default.yaml,
  // docs/frames.md).
  lateral.mount = Mount{0.0, 0.12, 0.55, 90.0, 25.0, 0.0};
  rig.cameras.push_back(lateral);

  CameraOptions upward;
  upward.id = "upward";
  upward.model = KannalaBrandt::FromFov(640, 480, 110.0 * kDegToRad);
  upward.mount = Mount{-0.05, 0.0, 0.4, 0.0, 90.0, 0.0};
  upward.truth_depth = true;  // upward corners are scored against the point seen (docs/metrics.md)
  rig.cameras.push_back(upward);
  return rig;
}

const CameraOptions* RigOptions::Find(const std::string& id) const {
  for (const CameraOptions& c : cameras) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

namespace {

// The camera model's keys depend on each other (a size or a field of view rebuilds the
// intrinsics, explicit fx/fy/cx/cy override them, a model switch needs fov_deg), so one hook
// reads them. The model's parameters are built here and assigned to c.model once.
void ParseCameraModel(YamlMap& map, CameraOptions& c) {
  const CameraModel& current = c.model;
  const bool was_pinhole = current.pinhole() != nullptr;
  bool pinhole = was_pinhole;
  std::string model_name;
  if (map.ReadEnum("model", model_name,
                   {{"pinhole", std::string("pinhole")},
                    {"kannala_brandt", std::string("kannala_brandt")}})) {
    pinhole = model_name == "pinhole";
  }
  const CameraIntrinsics p = current.intrinsics();
  // Size and field of view rebuild the intrinsics; explicit fx/fy/cx/cy override them.
  int width = p.width, height = p.height;
  map.Read("width", width);
  map.Read("height", height);
  double fov_deg = 0.0;
  const bool has_fov = map.Read("fov_deg", fov_deg);
  const bool resized = width != p.width || height != p.height;
  const bool model_changed = pinhole != was_pinhole;
  if (model_changed && !has_fov) {
    // A pinhole's fov_deg is horizontal, a fisheye's spans the smaller image side: say which.
    map.Fail("model", "changing the camera model needs fov_deg as well");
  }
  PinholeRadTan pinhole_params = was_pinhole ? *current.pinhole() : PinholeRadTan{};
  KannalaBrandt fisheye_params = was_pinhole ? KannalaBrandt{} : *current.kannala_brandt();
  if (has_fov || resized || model_changed) {
    if (!has_fov) {
      // A resize keeps the field of view that fov_deg means (a portrait pinhole's larger,
      // vertical one taken as horizontal would widen it).
      fov_deg = FovKeyDegOf(current);
    }
    // An impossible field of view is reported here, at its key, before it shapes a model.
    if (auto problem = FovProblem(pinhole, fov_deg)) map.Fail("fov_deg", *problem);
    if (pinhole) {
      pinhole_params = PinholeRadTan::FromFov(width, height, fov_deg * kDegToRad);
    } else {
      fisheye_params = KannalaBrandt::FromFov(width, height, fov_deg * kDegToRad);
    }
  }
  auto read_intrinsics = [&](auto& m) {
    map.Read("fx", m.fx);
    map.Read("fy", m.fy);
    map.Read("cx", m.cx);
    map.Read("cy", m.cy);
  };
  std::vector<double> distortion;
  if (pinhole) {
    read_intrinsics(pinhole_params);
    if (map.Read("distortion", distortion)) {
      if (distortion.size() != 5) map.Fail("distortion", "a pinhole needs [k1, k2, p1, p2, k3]");
      PinholeRadTan& m = pinhole_params;
      m.k1 = distortion[0], m.k2 = distortion[1], m.p1 = distortion[2];
      m.p2 = distortion[3], m.k3 = distortion[4];
    }
    c.model = pinhole_params;
  } else {
    read_intrinsics(fisheye_params);
    if (map.Read("distortion", distortion)) {
      if (distortion.size() != 4) map.Fail("distortion", "a fisheye needs [k1, k2, k3, k4]");
      KannalaBrandt& m = fisheye_params;
      m.k1 = distortion[0], m.k2 = distortion[1], m.k3 = distortion[2], m.k4 = distortion[3];
    }
    c.model = fisheye_params;
  }
}

double FovDegOf(const CameraModel& model) { return model.FieldOfViewRad() / kDegToRad; }

// Every model key, so that the echo reads back as the same model (fov_deg first rebuilds it,
// then the explicit intrinsics and distortion set it exactly).
void EchoCameraModel(const CameraOptions& c, OptionsYamlWriter& out) {
  const CameraIntrinsics p = c.model.intrinsics();
  out.Scalar("model", c.model.pinhole() ? "pinhole" : "kannala_brandt");
  out.Scalar("width", std::to_string(p.width));
  out.Scalar("height", std::to_string(p.height));
  out.Scalar("fov_deg", YamlNumber(FovDegOf(c.model)));
  out.Scalar("fx", YamlNumber(p.fx));
  out.Scalar("fy", YamlNumber(p.fy));
  out.Scalar("cx", YamlNumber(p.cx));
  out.Scalar("cy", YamlNumber(p.cy));
  out.Scalar("distortion", YamlList(p.distortion));
}

std::vector<OptionDocRow> CameraModelDocRows(const CameraOptions& c) {
  const CameraIntrinsics p = c.model.intrinsics();
  const bool pinhole = c.model.pinhole() != nullptr;
  std::string distortion;
  for (const double k : p.distortion) distortion += (distortion.empty() ? "" : ", ") + Num(k);
  return {
      {"model", "", pinhole ? "`pinhole`" : "`kannala_brandt`", "`pinhole`, `kannala_brandt`",
       "`pinhole` (radial-tangential) or `kannala_brandt` (equidistant fisheye); a change needs "
       "`fov_deg` too"},
      {"width", "px", std::to_string(p.width), "(0, 8192]; the rig's cameras at most 6 GiB",
       "image width"},
      {"height", "px", std::to_string(p.height), "(0, 8192]", "image height"},
      {"fov_deg", "deg", Num(FovKeyDegOf(c.model)), "pinhole < 150, fisheye < 180",
       "pinhole: horizontal field of view; fisheye: across the smaller image dimension. Sets "
       "fx = fy and the principal point at the centre"},
      {"fx", "px", Num(p.fx), "> 0; fisheye <= 2048, pinhole <= 1e5",
       "explicit focal length, overriding the one from `fov_deg`"},
      {"fy", "px", Num(p.fy), "> 0", ""},
      {"cx", "px", Num(p.cx), "", "explicit principal point"},
      {"cy", "px", Num(p.cy), "", ""},
      {"distortion", "", "`[" + distortion + "]`", "its undistorted pass at most 8192 px a side",
       "pinhole `[k1, k2, p1, p2, k3]`, fisheye `[k1, k2, k3, k4]`"},
  };
}

const OptionTable<Mount>& MountOptionsTable() {
  return StaticOptionTable<Mount>([](OptionTable<Mount>& t) {
    t.Add("x_m", &Mount::x_m, "m", "position in the robot frame (x forward)");
    t.Add("y_m", &Mount::y_m, "m", "y left");
    t.Add("z_m", &Mount::z_m, "m", "z up; the camera must sit inside the corridor");
    t.Add("yaw_deg", &Mount::yaw_deg, "deg", "heading of the optical axis (0 forward, 90 left)");
    t.Add("pitch_deg", &Mount::pitch_deg, "deg", "elevation (0 horizontal, 90 straight up)");
    t.Add("roll_deg", &Mount::roll_deg, "deg", "turns the image about the optical axis");
  });
}

const OptionTable<ExposureOptions>& ExposureOptionsTable() {
  return StaticOptionTable<ExposureOptions>([](OptionTable<ExposureOptions>& t) {
    using E = ExposureOptions;
    t.AddEnum("mode", &E::mode, {{"fixed", ExposureMode::kFixed}, {"auto", ExposureMode::kAuto}},
              "`fixed`: the gain below; `auto`: metered per frame from the scene in view "
              "(deterministic: the pose decides)");
    t.Add("gain", &E::gain, "", "fixed exposure: scene radiance 1 / gain reaches full scale")
        .Range(0.01, 100, "must lie in [0.01, 100]");
    t.Add("target", &E::target, "", "auto exposure: the mean luminance it brings the scene to")
        .Range(0.01, 1, "must lie in [0.01, 1]");
    t.Add("min_gain", &E::min_gain, "", "auto exposure: the lowest gain")
        .Range(0.01, 100, "must lie in [0.01, 100]");
    t.Add("max_gain", &E::max_gain, "", "auto exposure: the highest gain (dark scenes stay dark)")
        .Range(0.01, 100, "must lie in [0.01, 100]");
  });
}

// `noise:` holds the camera's noise switch and its two noise models.
const OptionTable<CameraOptions>& CameraNoiseOptionsTable() {
  return StaticOptionTable<CameraOptions>([](OptionTable<CameraOptions>& t) {
    using C = CameraOptions;
    t.Add("enabled", &C::noise, "", "false gives exact images (depth still limited to its range)");
    t.AddSection("depth", &C::depth_noise, DepthNoiseOptionsTable(),
                 "structured-light depth noise (depth cameras)", &DepthNoiseOptions::Check);
    t.AddSection("rgb", &C::rgb_noise, RgbNoiseOptionsTable(), "colour camera noise",
                 &RgbNoiseOptions::Check);
  });
}

const OptionTable<SceneOptions>& SceneRenderOptionsTable() {
  return StaticOptionTable<SceneOptions>([](OptionTable<SceneOptions>& t) {
    using S = SceneOptions;
    t.Add("ambient", &S::ambient, "", "uniform ambient light").Range(0, 1, "must lie in [0, 1]");
    t.Add("light_intensity", &S::light_intensity, "", "scale of every lamp's point light")
        .AtLeast(0, "must not be negative");
    t.Add("light_falloff_m", &S::light_falloff_m, "m",
          "distance at which a lamp's light has halved")
        .Greater(0, "must be greater than 0");
    t.Add("lamp_radiance", &S::lamp_radiance, "",
          "brightness of the lamps' own emitting faces (1 = white at gain 1; 4 saturates a lamp "
          "of any colour at gains from 0.25, as lamps do on a camera)")
        .Range(0, 1000, "must lie in [0, 1000]");
    t.Add("shadows", &S::shadows, "",
          "baked light stops at solids: walls, door frames and leaves, furniture");
    t.Add("bounces", &S::bounces, "",
          "baked diffuse bounces between floor, walls and ceiling (radiosity over their patches)")
        .Range(0, 3, "must lie in [0, 3]");
    t.Add("bounce_range_m", &S::bounce_range_m, "m",
          "surfaces further apart exchange no bounced light")
        .Range(0.5, 30, "must lie in [0.5, 30] m (got {})");
    t.Add("bake_lighting", &S::bake_lighting, "",
          "lamps' light baked per vertex when the scene is built (every lamp within 15 m, no "
          "per-pixel cost); false lights each pixel from the nearest `max_lights` lamps");
    t.Add("max_lights", &S::max_lights, "",
          "per-pixel lighting only: lamps that light one pass (the nearest to the camera); each "
          "costs about 1.4 ms per 640x480 pass")
        .Range(0, 16, "must lie in [0, 16]");
    t.AddEnum(
        "texture_filter", &S::texture_filter,
        {{"trilinear", TextureFilter::kTrilinear}, {"nearest_mip", TextureFilter::kNearestMip}},
        "how textures are filtered where they are minified (below)");
  });
}

}  // namespace

const OptionTable<CameraOptions>& CameraOptionsTable() {
  return StaticOptionTable<CameraOptions>([](OptionTable<CameraOptions>& t) {
    using C = CameraOptions;
    t.Add("enabled", &C::enabled, "", "false leaves the camera out of the rig");
    // At most 100 Hz, the slowest physics rate: at most one frame per camera is in flight in a
    // physics step, so the rig's memory bound (kMaxRigBytes) holds. At least 1e-6 Hz: a period of
    // at most 1e6 s, the longest run.
    t.Add("rate_hz", &C::rate_hz, "Hz",
          "frames per second (P1: a 300 ms period); frames are stamped every 1 / rate_hz rounded "
          "to the nanosecond")
        .Range(kMinSensorRateHz, 100,
               "must lie in [1e-06, 100] Hz: at most one frame per physics step, a period of at "
               "most 1e+06 s (got {})");
    t.Add("phase_s", &C::phase_s, "s",
          "time of the first frame; frames are stamped at `phase_s + k / rate_hz`, rounded to the "
          "nanosecond")
        .Note("[0, 1 / rate_hz)");
    t.Add("drop_probability", &C::drop_probability, "",
          "each frame is lost with this probability: neither rendered nor delivered, and "
          "`events.json` records it (`frame_dropped`); one draw per stamp from the camera's own "
          "stream `sim.clock.drop.<camera>`")
        .RangeOpenHigh(0, 1);
    t.AddCustom("model", "the camera model and its intrinsics", &ParseCameraModel, &EchoCameraModel,
                &CameraModelDocRows);
    t.AddSection("mount", &C::mount, MountOptionsTable(),
                 "where the camera sits on the robot (docs/frames.md)");
    t.Add("depth", &C::depth, "", "a registered depth image").Note("pinhole only");
    t.Add("truth_depth", &C::truth_depth, "",
          "exact depth kept as frame truth only (any lens; never given to a pipeline): corner "
          "detections are scored against the point seen at their pixel")
        .Note("default true for the upward camera");
    t.Add("cube_face_px", &C::cube_face_px, "px",
          "fisheye: resolution of the cube faces it is drawn from (0 = matched to the model's "
          "centre)")
        .Range(0, 4096, "must lie in [0, 4096] (0 = automatic; got {})");
    t.AddSection("exposure", &C::exposure, ExposureOptionsTable(),
                 "the gain from scene radiance to the sensor's range, before it clips");
    t.AddSection(
        "noise", [](C& c) -> C& { return c; }, CameraNoiseOptionsTable(), "the noise models");
  });
}

const OptionTable<RigOptions>& SensorsOptionsTable() {
  return StaticOptionTable<RigOptions>([](OptionTable<RigOptions>& t) {
    t.AddNamedSections(
        "", &RigOptions::cameras, CameraOptionsTable(), [](const CameraOptions& c) { return c.id; },
        "the cameras, by id");
  });
}

const OptionTable<RigOptions>& RenderOptionsTable() {
  return StaticOptionTable<RigOptions>([](OptionTable<RigOptions>& t) {
    t.AddEnum("backend", &RigOptions::backend, kBackendKindNames,
              "`egl` renders on the first hardware EGL device, else Mesa surfaceless "
              "(`CORRIDORSIM_EGL_DEVICE`, docs/rendering.md); the environment variable "
              "`CORRIDORSIM_RENDER_BACKEND` overrides it");
    t.Add("samples", &RigOptions::samples, "",
          "supersampling: samples per pixel, 1 (off), 9 (3 x 3) or 25 (5 x 5); colour is their "
          "mean, labels and depth the centre sample's; costs about `samples` times the drawing")
        .Range(1, 25, "must be 1, 9 or 25 (got {})");
    t.AddSection("", &RigOptions::scene, SceneRenderOptionsTable(), "lighting and textures");
  });
}

std::optional<OptionsProblem> RigOptions::CheckRender() const {
  if (auto problem = CheckOptionBounds(RenderOptionsTable(), *this)) return problem;
  if (samples != 1 && samples != 9 && samples != 25) {
    return OptionsProblem{"samples",
                          "must be 1, 9 (3 x 3) or 25 (5 x 5) samples per pixel, so "
                          "that one sample sits at each pixel's centre (got " +
                              std::to_string(samples) + ")"};
  }
  return std::nullopt;
}

std::optional<OptionsProblem> RigOptions::Check() const {
  if (auto problem = CheckOptionBounds(SensorsOptionsTable(), *this)) return problem;
  for (const CameraOptions& c : cameras) {
    const std::string k = c.id + ".";
    if (!(c.phase_s >= 0 && c.phase_s * c.rate_hz < 1)) {
      return OptionsProblem{k + "phase_s",
                            "must lie in [0, 1 / rate_hz) (got " + FormatNumber(c.phase_s) + " s)"};
    }
    if (c.exposure.min_gain > c.exposure.max_gain) {
      return OptionsProblem{k + "exposure.min_gain", "must not exceed exposure.max_gain (got " +
                                                         FormatNumber(c.exposure.min_gain) + " > " +
                                                         FormatNumber(c.exposure.max_gain) + ")"};
    }
    const bool pinhole = c.model.pinhole() != nullptr;
    const CameraIntrinsics p = c.model.intrinsics();
    if (p.width <= 0 || p.height <= 0) {
      return OptionsProblem{k + (p.width <= 0 ? "width" : "height"),
                            "the image size must be positive (got " + std::to_string(p.width) +
                                "x" + std::to_string(p.height) + ")"};
    }
    if (p.width > 8192 || p.height > 8192) {
      return OptionsProblem{k + (p.width > 8192 ? "width" : "height"),
                            "images larger than 8192 px on a side are not supported (got " +
                                std::to_string(p.width) + "x" + std::to_string(p.height) + ")"};
    }
    // Fisheyes are drawn from cube faces of 2 fx pixels (up to 4096), pinholes in one pass.
    const double max_focal = pinhole ? 1e5 : 2048.0;
    for (const auto& [key, focal] : {std::pair{"fx", p.fx}, std::pair{"fy", p.fy}}) {
      if (!(focal > 0) || !std::isfinite(focal)) {
        return OptionsProblem{k + key, "the focal length must be positive (got " + Num(focal) +
                                           " px; fov_deg sets it from the field of view)"};
      }
      if (focal > max_focal) {
        return OptionsProblem{k + key, "focal lengths above " + Num(max_focal) +
                                           " px are not supported for this model (got " +
                                           Num(focal) + ")"};
      }
    }
    if (auto problem = FovProblem(pinhole, FovDegOf(c.model))) {
      return OptionsProblem{k + "fov_deg", *problem};
    }
    if (auto problem = c.model.Check()) return OptionsProblem{k + "distortion", *problem};
    if (c.depth && !pinhole) {
      return OptionsProblem{k + "depth", "depth images need a pinhole camera"};
    }
  }
  // What the enabled cameras need, before anything is planned or allocated.
  std::uint64_t rig_bytes = 0;
  for (const CameraOptions& c : cameras) {
    if (!c.enabled) continue;
    const CameraBudget budget = CameraBudgetOf(c, samples);
    const bool fisheye = c.model.kannala_brandt() != nullptr;
    if (budget.pass_width_px > kMaxPassPx || budget.pass_height_px > kMaxPassPx) {
      return OptionsProblem{
          c.id + (fisheye ? ".cube_face_px" : ".distortion"),
          "the camera is drawn from a pass of " + std::to_string(budget.pass_width_px) + " x " +
              std::to_string(budget.pass_height_px) + " px, more than the " +
              std::to_string(kMaxPassPx) +
              " px a pass may have on a side (a distorted pinhole's pass spans its undistorted "
              "view: narrow fov_deg or weaken the distortion)"};
    }
    rig_bytes += budget.bytes;
    if (rig_bytes > kMaxRigBytes) {
      return OptionsProblem{c.id + ".width",
                            "the enabled cameras need " + Num(double(rig_bytes) / (1 << 30)) +
                                " GiB up to this one, more than the " +
                                Num(double(kMaxRigBytes) / (1 << 30)) + " GiB a rig may use (got " +
                                std::to_string(c.model.width()) + "x" +
                                std::to_string(c.model.height()) + " px)"};
    }
  }
  return std::nullopt;
}

namespace {

// The model at n times the resolution: pixel centres u map to n u + (n - 1) / 2, so the centre
// sample of output pixel (u, v) is drawn pixel (n u + (n - 1) / 2, n v + (n - 1) / 2).
template <class Model>
Model Scaled(Model m, int n) {
  m.width *= n;
  m.height *= n;
  m.fx *= n;
  m.fy *= n;
  m.cx = n * m.cx + (n - 1) / 2.0;
  m.cy = n * m.cy + (n - 1) / 2.0;
  return m;
}

CameraModel ScaledModel(const CameraModel& model, int n) {
  if (n == 1) return model;
  if (const auto* p = model.pinhole()) return CameraModel(Scaled(*p, n));
  return CameraModel(Scaled(*model.kannala_brandt(), n));
}

// render.samples (1, 9, 25) as samples per pixel side.
int SamplesPerSide(int samples) { return samples >= 25 ? 5 : samples >= 9 ? 3 : 1; }

}  // namespace

CameraBudget CameraBudgetOf(const CameraOptions& camera, int samples) {
  if (SamplesPerSide(samples) > 1) {
    // Supersampled: the camera drawn at n times its resolution.
    CameraOptions drawn = camera;
    drawn.model = ScaledModel(camera.model, SamplesPerSide(samples));
    drawn.cube_face_px *= SamplesPerSide(samples);
    return CameraBudgetOf(drawn, 1);
  }
  const CameraModel& model = camera.model;
  const CameraIntrinsics p = model.intrinsics();
  const std::uint64_t pixels = std::uint64_t(std::max(p.width, 0)) * std::max(p.height, 0);
  CameraBudget b;
  if (IsUndistortedPinhole(model)) {
    b.pass_width_px = p.width, b.pass_height_px = p.height, b.passes = 1;
  } else if (model.kannala_brandt()) {
    // A face spans 90 degrees at face_px (PlanRemapPasses); its crop keeps a 2 px border, and
    // rounding the window's ends outwards adds up to 1 px each (a ray on a face's edge may lie
    // a rounding error beyond it).
    const double auto_face = 2 * std::ceil(std::max(p.fx, p.fy));
    const double face = camera.cube_face_px > 0 ? camera.cube_face_px : auto_face;
    b.pass_width_px = b.pass_height_px = int(std::min(face + 7, 1e9));
    b.passes = 6;
  } else {
    // A distorted pinhole passing its Check() is invertible up to its image corners, so every
    // pixel is valid and the undistorted window's extremes lie on the image border.
    double u0 = 1e30, u1 = -1e30, v0 = 1e30, v1 = -1e30;
    auto extend = [&](int u, int v) {
      const Vector3d q = model.Unproject(Vector2d(u, v));
      if (!q.allFinite() || q.norm() < 0.5 || !(q.z() > 1e-6)) return;
      const double x = p.fx * q.x() / q.z(), y = p.fy * q.y() / q.z();
      u0 = std::min(u0, x), u1 = std::max(u1, x), v0 = std::min(v0, y), v1 = std::max(v1, y);
    };
    for (int u = 0; u < p.width; ++u) extend(u, 0), extend(u, p.height - 1);
    for (int v = 0; v < p.height; ++v) extend(0, v), extend(p.width - 1, v);
    if (u0 <= u1 && v0 <= v1) {
      // The crop of PlanRemapPasses: the used window plus 2 px, both ends included.
      b.pass_width_px = int(std::min(std::ceil(u1) - std::floor(u0) + 5, 1e9));
      b.pass_height_px = int(std::min(std::ceil(v1) - std::floor(v0) + 5, 1e9));
    }
    b.passes = 1;
  }
  // Bytes per pass pixel: the GL targets (RGBA8, R32UI, R8UI, R32F, depth 32F) and the
  // read-back (RGB, instance, class, depth). Per output pixel: the frame (RGB, instance, class,
  // exact and noisy depth) and, for a remapped camera, its tables (lookup 12, remap 8, depth
  // scale 4) and the planning's bearings and faces (28).
  const std::uint64_t pass_pixels =
      std::uint64_t(b.pass_width_px) * std::uint64_t(b.pass_height_px) * std::uint64_t(b.passes);
  const bool depth = camera.ReadsDepth();
  const std::uint64_t per_pass_px = 17 + 8 + (depth ? 4 : 0);
  const std::uint64_t per_px =
      8 + (depth ? 8 : 0) + (IsUndistortedPinhole(model) ? 0 : 12 + 8 + (depth ? 4 : 0) + 28);
  b.bytes = pass_pixels * per_pass_px + pixels * per_px;
  return b;
}

void ParseSensors(YamlMap& sensors, RigOptions& rig) {
  ReadOptions(sensors, SensorsOptionsTable(), rig);
}

RigOptions WithAppearance(const RigOptions& rig, const worlds::AppearanceDraw& look) {
  RigOptions out = rig;
  for (CameraOptions& c : out.cameras) {
    c.exposure.gain *= look.camera_exposure;
    c.exposure.target = std::min(1.0, c.exposure.target * look.camera_exposure);
    if (!c.noise) continue;
    if (c.rgb_noise.full_well_electrons > 0) {
      c.rgb_noise.full_well_electrons /= look.camera_noise;
      c.rgb_noise.read_noise_electrons *= look.camera_noise;
    }
    c.rgb_noise.motion_blur_px += look.camera_blur_px;
  }
  return out;
}

namespace {

// Where a point is: inside the corridor or a room, or why not.
enum class Space { kInside, kBelowFloor, kAboveCeiling, kOutside };

// A corridor segment's floor rectangle runs half a width past an end that meets another
// segment's (the corner square of an L or a loop), else to the end wall (worlds/layout.cpp).
bool SharesEnd(const worlds::World& world, const worlds::CorridorSegment& seg,
               const Eigen::Vector2d& p) {
  return std::any_of(world.segments.begin(), world.segments.end(),
                     [&](const worlds::CorridorSegment& other) {
                       return other.id != seg.id &&
                              ((other.start - p).norm() < 1e-6 || (other.end - p).norm() < 1e-6);
                     });
}

Space Locate(const worlds::World& world, const Vector3d& p, double* ceiling_m) {
  Space space = Space::kOutside;
  const auto consider = [&](double height_m) {
    if (p.z() > 0 && p.z() < height_m) {
      space = Space::kInside;
    } else if (space != Space::kInside) {
      space = p.z() <= 0 ? Space::kBelowFloor : Space::kAboveCeiling;
      *ceiling_m = height_m;
    }
  };
  for (const worlds::CorridorSegment& seg : world.segments) {
    const Vector2d d = seg.direction(), q = p.head<2>() - seg.start;
    const double along = q.dot(d), across = q.dot(Vector2d(-d.y(), d.x()));
    const double len = (seg.end - seg.start).norm();
    const double before = SharesEnd(world, seg, seg.start) ? seg.width_m / 2 : 0.0;
    const double after = SharesEnd(world, seg, seg.end) ? seg.width_m / 2 : 0.0;
    if (along >= -before && along <= len + after && std::abs(across) <= seg.width_m / 2) {
      consider(seg.height_m);
    }
  }
  for (const worlds::Doorway& door : world.doors) {
    // The opening through the wall (a closed door's leaf is a solid of its own), and the room.
    const Vector2d u = (door.column_b - door.column_a).normalized();
    const Vector2d q = p.head<2>() - door.column_a;
    const double along = q.dot(u), depth = -q.dot(door.inward_normal);
    const double span = (door.column_b - door.column_a).norm();
    if (along >= door.column_width_m / 2 && along <= span - door.column_width_m / 2 && depth >= 0 &&
        depth <= world.options.wall_thickness_m) {
      consider(door.top_height_m);
    }
    if (door.room && door.room->footprint.contains(p.head<2>())) {
      consider(door.room->ceiling_height_m);
    }
  }
  return space;
}

std::string At(const Vector3d& p) {
  return "at (" + Num(p.x()) + ", " + Num(p.y()) + ", " + Num(p.z()) + ") m";
}

}  // namespace

std::optional<std::string> CameraSpaceProblem(const worlds::World& world,
                                              const Vector3d& p_in_world) {
  double ceiling_m = 0.0;
  switch (Locate(world, p_in_world, &ceiling_m)) {
    case Space::kInside:
      break;
    case Space::kAboveCeiling:
      return "above the ceiling (" + Num(ceiling_m) + " m high)";
    case Space::kBelowFloor:
      return std::string("below the floor");
    case Space::kOutside:
      return std::string("outside the corridor (in or behind a wall)");
  }
  // The corridor's walls, floor and ceilings are axis-aligned planes: the ball of the clearance
  // about the centre stays inside when its six extreme points do.
  const std::string near = "within " + Num(kCameraClearanceM) + " m (the near plane, " +
                           Num(kNearPlaneM) + " m, and 1 cm) of ";
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {-1.0, 1.0}) {
      Vector3d q = p_in_world;
      q[axis] += sign * kCameraClearanceM;
      if (Locate(world, q, &ceiling_m) == Space::kInside) continue;
      if (axis < 2) return near + "a wall: it would see through it";
      return near + (sign > 0 ? "the ceiling" : "the floor") + ": it would see through it";
    }
  }
  return std::nullopt;
}

std::optional<OptionsProblem> CheckCameraPlacement(const worlds::World& world,
                                                   const RigOptions& rig,
                                                   const SE3& world_from_robot) {
  for (const CameraOptions& c : rig.cameras) {
    if (!c.enabled) continue;
    const Vector3d p = (world_from_robot * c.mount.RobotFromCamera()).translation();
    for (const worlds::CollisionBox& box : world.collision_boxes) {
      const double gap = ((p - box.center).cwiseAbs() - box.half_extents).maxCoeff();
      if (gap < kCameraClearanceM) {
        return OptionsProblem{c.id + ".mount",
                              "the camera " + At(p) + " is " +
                                  (gap < 0 ? "inside a "
                                           : "within " + Num(kCameraClearanceM) +
                                                 " m (the near plane and 1 cm) of a ") +
                                  worlds::SemanticClassName(box.semantic_class) + " (instance " +
                                  std::to_string(box.instance_id) + ")"};
      }
    }
    if (auto problem = CameraSpaceProblem(world, p)) {
      return OptionsProblem{c.id + ".mount", "the camera " + At(p) + " is " + *problem};
    }
  }
  return std::nullopt;
}

// ---- CameraRenderer ----------------------------------------------------------------------------

CameraRenderer::CameraRenderer(const CameraOptions& options, int samples_per_side)
    : options_(options),
      n_(samples_per_side),
      draw_model_(ScaledModel(options.model, samples_per_side)) {
  if (n_ < 1 || n_ % 2 == 0 || n_ > 5) {
    throw std::invalid_argument("render: samples per pixel side must be 1, 3 or 5");
  }
  if (IsUndistortedPinhole(draw_model_)) {
    PlanPinholePass();
  } else {
    PlanRemapPasses();
  }
  rendered_.resize(passes_.size());
}

void CameraRenderer::PlanPinholePass() {
  const PinholeRadTan& p = *draw_model_.pinhole();
  Pass pass;
  pass.view.width = p.width;
  pass.view.height = p.height;
  pass.view.fx = p.fx;
  pass.view.fy = p.fy;
  pass.view.cx = p.cx;
  pass.view.cy = p.cy;
  passes_.push_back(pass);
}

void CameraRenderer::PlanRemapPasses() {
  const CameraIntrinsics p = draw_model_.intrinsics();
  const bool fisheye = draw_model_.kannala_brandt() != nullptr;
  const int w = p.width, h = p.height;
  // Unit bearings of every output pixel, and which face (or the single pass) each one uses.
  std::vector<Vector3d> bearings(static_cast<std::size_t>(w) * h);
  std::vector<int> face_of(bearings.size(), -1);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Vector3d b = draw_model_.Unproject(Vector2d(u, v));
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      bearings[i] = b;
      if (!b.allFinite() || b.norm() < 0.5) continue;
      if (!fisheye) {
        if (b.z() > 1e-6) face_of[i] = 0;
        continue;
      }
      int best = 0;
      double best_dot = -2;
      for (int f = 0; f < 6; ++f) {
        const double d = FaceRotation(f).col(2).dot(b);
        if (d > best_dot + 1e-12) best_dot = d, best = f;
      }
      face_of[i] = best;
    }
  }
  // Pass intrinsics: a fisheye face spans 90 degrees at `face_px`; a distorted pinhole's single
  // pass keeps the camera's focal length.
  int face_px = options_.cube_face_px * n_;
  if (face_px == 0) face_px = 2 * static_cast<int>(std::ceil(std::max(p.fx, p.fy)));
  const double f_face = face_px / 2.0;
  struct Extent {
    double u0 = 1e30, v0 = 1e30, u1 = -1e30, v1 = -1e30;
  };
  const int n_faces = fisheye ? 6 : 1;
  std::vector<Extent> extents(static_cast<std::size_t>(n_faces));
  auto project_in = [&](int f, const Vector3d& b) {
    const Vector3d q = FaceRotation(f).transpose() * b;
    const double fx = fisheye ? f_face : p.fx, fy = fisheye ? f_face : p.fy;
    return Vector2d(fx * q.x() / q.z(), fy * q.y() / q.z());  // relative to the principal point
  };
  for (std::size_t i = 0; i < bearings.size(); ++i) {
    if (face_of[i] < 0) continue;
    const Vector2d uv = project_in(face_of[i], bearings[i]);
    Extent& e = extents[static_cast<std::size_t>(face_of[i])];
    e.u0 = std::min(e.u0, uv.x()), e.u1 = std::max(e.u1, uv.x());
    e.v0 = std::min(e.v0, uv.y()), e.v1 = std::max(e.v1, uv.y());
  }
  std::vector<int> pass_of_face(static_cast<std::size_t>(n_faces), -1);
  std::vector<Vector2d> origin_of_face(static_cast<std::size_t>(n_faces));
  for (int f = 0; f < n_faces; ++f) {
    const Extent& e = extents[static_cast<std::size_t>(f)];
    if (e.u0 > e.u1) continue;
    // Crop to the used window plus a border of 2 px for bilinear sampling.
    const double u0 = std::floor(e.u0) - 2, v0 = std::floor(e.v0) - 2;
    const double u1 = std::ceil(e.u1) + 2, v1 = std::ceil(e.v1) + 2;
    Pass pass;
    pass.camera_from_pass = SE3(FaceRotation(f), Vector3d::Zero());
    pass.view.width = static_cast<int>(u1 - u0) + 1;
    pass.view.height = static_cast<int>(v1 - v0) + 1;
    pass.view.fx = fisheye ? f_face : p.fx;
    pass.view.fy = fisheye ? f_face : p.fy;
    pass.view.cx = -u0;  // pixel (0,0) of the crop is at offset (u0, v0) from the principal point
    pass.view.cy = -v0;
    pass_of_face[static_cast<std::size_t>(f)] = static_cast<int>(passes_.size());
    origin_of_face[static_cast<std::size_t>(f)] = Vector2d(u0, v0);
    passes_.push_back(pass);
  }
  lut_.resize(bearings.size());
  remap_.resize(bearings.size());
  if (options_.ReadsDepth()) depth_scale_.assign(bearings.size(), 0.0f);
  for (std::size_t i = 0; i < bearings.size(); ++i) {
    if (face_of[i] < 0) continue;
    const int f = face_of[i];
    const Vector3d q = FaceRotation(f).transpose() * bearings[i];
    const Vector2d uv = project_in(f, bearings[i]) - origin_of_face[static_cast<std::size_t>(f)];
    LutEntry& e = lut_[i];
    e.x = static_cast<float>(uv.x());
    e.y = static_cast<float>(uv.y());
    e.pass = static_cast<std::uint8_t>(pass_of_face[static_cast<std::size_t>(f)]);
    e.valid = true;
    const View& pv = passes_[e.pass].view;
    // The crop keeps a 2 px border, so the bilinear block and the nearest pixel stay inside.
    int x0 = std::clamp(static_cast<int>(std::floor(uv.x())), 0, pv.width - 2);
    int y0 = std::clamp(static_cast<int>(std::floor(uv.y())), 0, pv.height - 2);
    long wx = std::clamp(std::lround((uv.x() - x0) * 256.0), 0L, 256L);
    long wy = std::clamp(std::lround((uv.y() - y0) * 256.0), 0L, 256L);
    // A full weight on the right column (bottom row) is the next block's left column (top row)
    // with weight 0: the same sum, and the weights fit in 8 bits.
    if (wx == 256 && x0 + 2 < pv.width) ++x0, wx = 0;
    if (wy == 256 && y0 + 2 < pv.height) ++y0, wy = 0;
    const int nx = std::clamp(static_cast<int>(std::lround(uv.x())), 0, pv.width - 1);
    const int ny = std::clamp(static_cast<int>(std::lround(uv.y())), 0, pv.height - 1);
    if (wx > 255 || wy > 255 || nx < x0 || nx > x0 + 1 || ny < y0 || ny > y0 + 1) {
      std::abort();  // cannot happen with the 2 px border (the sample lies inside the crop)
    }
    RemapEntry& r = remap_[i];
    r.top_left = static_cast<std::uint32_t>(y0 * pv.width + x0);
    r.wx = static_cast<std::uint8_t>(wx);
    r.wy = static_cast<std::uint8_t>(wy);
    r.pass = e.pass;
    r.nearest = static_cast<std::uint8_t>((nx - x0) | (ny - y0) << 1);
    // Camera z of the point at pass depth 1 along this ray: camera z = pass z * b.z / q.z.
    if (options_.ReadsDepth()) depth_scale_[i] = static_cast<float>(bearings[i].z() / q.z());
  }
  PlanUnusedPixels();
}

void CameraRenderer::PlanUnusedPixels() {
  // The pass pixels Compose reads: each output pixel's bilinear block (its nearest pixel is one
  // of the four).
  std::vector<std::vector<bool>> used(passes_.size());
  for (std::size_t k = 0; k < passes_.size(); ++k) {
    used[k].assign(std::size_t(passes_[k].view.width) * passes_[k].view.height, false);
  }
  for (const RemapEntry& r : remap_) {
    if (r.nearest == RemapEntry::kInvalid) continue;
    std::vector<bool>& u = used[r.pass];
    const std::size_t w = std::size_t(passes_[r.pass].view.width);
    u[r.top_left] = u[r.top_left + 1] = u[r.top_left + w] = u[r.top_left + w + 1] = true;
  }
  // Unused blocks of kBlock x kBlock pixels (llvmpipe shades 4x4 blocks; a coarser grid keeps
  // the rectangles few), as runs along block rows merged with identical runs of the rows below.
  constexpr int kBlock = 8;
  unused_.assign(passes_.size(), {});
  for (std::size_t k = 0; k < passes_.size(); ++k) {
    const int w = passes_[k].view.width, h = passes_[k].view.height;
    auto block_unused = [&](int bx, int by) {
      for (int y = by * kBlock; y < std::min(h, (by + 1) * kBlock); ++y) {
        for (int x = bx * kBlock; x < std::min(w, (bx + 1) * kBlock); ++x) {
          if (used[k][std::size_t(y) * w + x]) return false;
        }
      }
      return true;
    };
    std::vector<PixelRect> open;  // runs of the previous block row, still growing downwards
    for (int by = 0; by * kBlock < h; ++by) {
      const int y0 = by * kBlock, y1 = std::min(h, y0 + kBlock);
      std::vector<PixelRect> runs;
      for (int bx = 0; bx * kBlock < w; ++bx) {
        if (!block_unused(bx, by)) continue;
        const int x0 = bx * kBlock, x1 = std::min(w, x0 + kBlock);
        if (!runs.empty() && runs.back().x1 == x0) {
          runs.back().x1 = x1;
        } else {
          runs.push_back({x0, y0, x1, y1});
        }
      }
      std::vector<PixelRect> next;
      for (PixelRect run : runs) {
        const auto same = std::find_if(open.begin(), open.end(), [&](const PixelRect& o) {
          return o.x0 == run.x0 && o.x1 == run.x1;
        });
        if (same != open.end()) {
          run.y0 = same->y0;
          open.erase(same);
        }
        next.push_back(run);
      }
      unused_[k].insert(unused_[k].end(), open.begin(), open.end());  // ended above this row
      open = std::move(next);
    }
    unused_[k].insert(unused_[k].end(), open.begin(), open.end());
  }
}

std::vector<View> CameraRenderer::Passes(const SE3& world_from_camera) const {
  std::vector<View> views;
  for (const Pass& pass : passes_) {
    View v = pass.view;
    v.world_from_camera = world_from_camera * pass.camera_from_pass;
    views.push_back(v);
  }
  return views;
}

std::size_t CameraRenderer::pass_pixel_count() const {
  std::size_t n = 0;
  for (const Pass& p : passes_) n += static_cast<std::size_t>(p.view.width) * p.view.height;
  return n;
}

std::optional<std::pair<int, Eigen::Vector2d>> CameraRenderer::Lookup(int u, int v) const {
  if (u < 0 || v < 0 || u >= options_.model.width() || v >= options_.model.height()) {
    return std::nullopt;
  }
  // The centre sample (supersampling).
  u = n_ * u + (n_ - 1) / 2;
  v = n_ * v + (n_ - 1) / 2;
  const int width = draw_model_.width();
  if (lut_.empty()) return std::make_pair(0, Vector2d(u, v));
  const LutEntry& e = lut_[static_cast<std::size_t>(v) * width + u];
  if (!e.valid) return std::nullopt;
  return std::make_pair(static_cast<int>(e.pass), Vector2d(e.x, e.y));
}

void CameraRenderer::Render(const Scene& scene, Backend& backend, const SE3& world_from_camera,
                            CameraFrame* frame) {
  Draw(scene, backend, world_from_camera);
  Finish(frame);
}

void CameraRenderer::Draw(const Scene& scene, Backend& backend, const SE3& world_from_camera) {
  world_from_camera_ = world_from_camera;
  std::vector<View> views = Passes(world_from_camera);
  // Baked lighting needs no per-pixel lights; otherwise the nearest few light each pass.
  const std::vector<int> lights =
      scene.options.bake_lighting
          ? std::vector<int>{}
          : NearestLights(scene, world_from_camera.translation(), scene.options.max_lights);
  // All passes in one batch: the backend submits the next pass while the last one rasterises.
  std::vector<std::vector<int>> visible(views.size());
  std::vector<DrawRequest> requests(views.size());
  for (std::size_t k = 0; k < views.size(); ++k) {
    views[k].read_depth = options_.ReadsDepth();
    visible[k] = VisibleDrawables(scene, views[k]);
  }
  const auto gain = static_cast<float>(ExposureGain(scene, world_from_camera, visible));
  for (std::size_t k = 0; k < views.size(); ++k) {
    requests[k] = DrawRequest{views[k], visible[k], lights, &rendered_[k], unused_pixels(k), gain};
  }
  backend.DrawPasses(requests);
}

double CameraRenderer::ExposureGain(const Scene& scene, const SE3& world_from_camera,
                                    std::span<const std::vector<int>> visible) const {
  const ExposureOptions& e = options_.exposure;
  if (e.mode == ExposureMode::kFixed) return e.gain;
  const double mean = MeteredLuminance(scene, world_from_camera.translation(), visible);
  if (!(mean > 0)) return e.max_gain;
  return std::clamp(e.target / mean, e.min_gain, e.max_gain);
}

void CameraRenderer::Finish(CameraFrame* frame) {
  frame->camera_id = options_.id;
  frame->world_from_camera = world_from_camera_;
  if (n_ > 1) {
    if (lut_.empty()) {
      std::swap(hires_.rgb, rendered_[0].rgb);
      std::swap(hires_.instance, rendered_[0].instance);
      std::swap(hires_.semantic, rendered_[0].semantic);
      if (options_.ReadsDepth()) std::swap(hires_.depth_m, rendered_[0].depth_m);
    } else {
      Compose(&hires_);
    }
    Downsample(hires_, frame);
  } else if (lut_.empty()) {
    // One exact pass: hand its buffers over (the frame's old buffers come back for reuse).
    RenderedView& r = rendered_[0];
    std::swap(frame->rgb, r.rgb);
    std::swap(frame->instance, r.instance);
    std::swap(frame->semantic, r.semantic);
    if (options_.ReadsDepth()) std::swap(frame->depth_m, r.depth_m);
  } else {
    Compose(frame);
  }
}

void CameraRenderer::Downsample(const CameraFrame& hires, CameraFrame* frame) const {
  const int width = options_.model.width(), height = options_.model.height(), n = n_;
  const std::size_t hw = static_cast<std::size_t>(width) * n;
  if (frame->rgb.width != width || frame->rgb.height != height || frame->rgb.channels != 3) {
    frame->rgb = Image8(width, height, 3);
  }
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  frame->instance.resize(pixels);
  frame->semantic.resize(pixels);
  if (options_.ReadsDepth()) {
    frame->depth_m.width = width;
    frame->depth_m.height = height;
    frame->depth_m.data.resize(pixels);
  }
  const unsigned count = static_cast<unsigned>(n * n);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const std::size_t out = static_cast<std::size_t>(v) * width + u;
      unsigned sum[3] = {0, 0, 0};
      for (int dy = 0; dy < n; ++dy) {
        const std::size_t row = (static_cast<std::size_t>(v) * n + dy) * hw;
        for (int dx = 0; dx < n; ++dx) {
          const std::uint8_t* px =
              &hires.rgb.data[(row + static_cast<std::size_t>(u) * n + dx) * 3];
          for (int c = 0; c < 3; ++c) sum[c] += px[c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        frame->rgb.data[out * 3 + c] = static_cast<std::uint8_t>((sum[c] + count / 2) / count);
      }
      const std::size_t centre = (static_cast<std::size_t>(v) * n + (n - 1) / 2) * hw +
                                 static_cast<std::size_t>(u) * n + (n - 1) / 2;
      frame->instance[out] = hires.instance[centre];
      frame->semantic[out] = hires.semantic[centre];
      if (options_.ReadsDepth()) frame->depth_m.data[out] = hires.depth_m.data[centre];
    }
  }
}

void CameraRenderer::Compose(CameraFrame* frame) const {
  const int width = draw_model_.width(), height = draw_model_.height();
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (frame->rgb.width != width || frame->rgb.height != height || frame->rgb.channels != 3) {
    frame->rgb = Image8(width, height, 3);
  }
  frame->instance.resize(n);
  frame->semantic.resize(n);
  if (options_.ReadsDepth()) {
    frame->depth_m.width = width;
    frame->depth_m.height = height;
    frame->depth_m.data.resize(n);
  }
  // Per pass: where its images start (up to 6 cube faces).
  std::array<detail::PassImages, 6> images{};
  for (std::size_t k = 0; k < rendered_.size() && k < images.size(); ++k) {
    const RenderedView& r = rendered_[k];
    images[k] = {r.rgb.data.data(), r.instance.data(), r.semantic.data(),
                 options_.ReadsDepth() ? r.depth_m.data.data() : nullptr, std::size_t(r.rgb.width)};
  }
  detail::NearestLabels(remap_, images, options_.ReadsDepth() ? depth_scale_.data() : nullptr,
                        frame->instance.data(), frame->semantic.data(),
                        options_.ReadsDepth() ? frame->depth_m.data.data() : nullptr);
  detail::BilinearRgb(remap_, images, frame->rgb.data.data());
}

// ---- Rig -------------------------------------------------------------------------------------

Rig::Rig(const RigOptions& options, const Scene& scene, Backend& backend)
    : scene_(scene), backend_(backend) {
  // The backend's own limit (a GPU driver may have less than kMaxPassPx), before the remap
  // tables are planned or a frame is drawn.
  for (const CameraOptions& c : options.cameras) {
    if (!c.enabled) continue;
    const CameraBudget budget = CameraBudgetOf(c, options.samples);
    if (budget.pass_width_px > backend.max_view_px() ||
        budget.pass_height_px > backend.max_view_px()) {
      throw RenderError("render: sensors." + c.id + ": the camera is drawn from a pass of " +
                        std::to_string(budget.pass_width_px) + " x " +
                        std::to_string(budget.pass_height_px) + " px; the " +
                        BackendName(backend.kind()) + " backend draws at most " +
                        std::to_string(backend.max_view_px()) + " px on a side");
    }
  }
  for (const CameraOptions& c : options.cameras) {
    if (c.enabled) cameras_.emplace_back(c, SamplesPerSide(options.samples));
  }
  started_.assign(cameras_.size(), false);
  // The cameras with the most CPU work after their draw start first in Render, so it overlaps
  // the most drawing of the others.
  for (std::size_t k = 0; k < cameras_.size(); ++k) draw_order_.push_back(k);
  std::stable_sort(draw_order_.begin(), draw_order_.end(), [&](std::size_t a, std::size_t b) {
    return cameras_[a].cpu_work() > cameras_[b].cpu_work();
  });
}

Rig::~Rig() { Abandon(); }  // the stages write frames the caller owns: let them end

void Rig::Render(const SE3& world_from_robot, std::uint64_t seed, std::uint64_t frame_index,
                 std::vector<CameraFrame>* frames) {
  frames->resize(cameras_.size());
  try {
    for (const std::size_t k : draw_order_) {
      StartCamera(k, world_from_robot, seed, frame_index, &(*frames)[k]);
    }
  } catch (...) {
    Abandon();  // the cameras already started write into *frames: let them end first
    throw;
  }
  Wait();
}

void Rig::RenderCamera(std::size_t index, const SE3& world_from_robot, std::uint64_t seed,
                       std::uint64_t frame_index, CameraFrame* frame) {
  StartCamera(index, world_from_robot, seed, frame_index, frame);
  Wait();
}

void Rig::StartCamera(std::size_t index, const SE3& world_from_robot, std::uint64_t seed,
                      std::uint64_t frame_index, CameraFrame* frame) {
  CameraRenderer& camera = cameras_.at(index);
  if (started_.at(index)) Wait();  // its last frame's CPU stages still read the buffers Draw writes
  camera.Draw(scene_, backend_, world_from_robot * camera.options().mount.RobotFromCamera());
  if (camera.cpu_work() == 0) {
    FinishCamera(index, seed, frame_index, frame);
    return;
  }
  started_[index] = true;
  worker_.Submit(
      [this, index, seed, frame_index, frame] { FinishCamera(index, seed, frame_index, frame); });
}

void Rig::Wait() {
  std::fill(started_.begin(), started_.end(), false);
  worker_.Drain();  // rethrows the first exception of a stage
}

void Rig::Abandon() noexcept {
  try {
    Wait();
  } catch (...) {  // NOLINT(bugprone-empty-catch): the caller reports its own error
  }
}

void Rig::FinishCamera(std::size_t index, std::uint64_t seed, std::uint64_t frame_index,
                       CameraFrame* frame) {
  CameraRenderer& camera = cameras_[index];
  camera.Finish(frame);
  const CameraOptions& options = camera.options();
  if (options.depth) {
    frame->noisy_depth_m = frame->depth_m;
    // The noise applies the range itself; without it the exact depth still obeys the range.
    if (!options.noise) ApplyDepthRange(options.depth_noise, &frame->noisy_depth_m);
  }
  if (options.noise) ApplyNoise(index, seed, frame_index, frame);
}

void Rig::ApplyNoise(std::size_t index, std::uint64_t seed, std::uint64_t frame_index,
                     CameraFrame* frame) const {
  const CameraOptions& camera = cameras_.at(index).options();
  // Truth, then noise (STYLE item 9): each camera and frame has its own stream.
  RandomStream rng =
      RandomStream(seed, 0, "render.noise." + camera.id).Derive(std::to_string(frame_index));
  RandomStream depth_rng = rng.Derive("depth"), rgb_rng = rng.Derive("rgb");
  if (camera.depth) {
    ApplyDepthNoise(camera.depth_noise, *camera.model.pinhole(), depth_rng, &frame->noisy_depth_m);
  }
  ApplyRgbNoise(camera.rgb_noise, rgb_rng, &frame->rgb);
}

}  // namespace corridorsim::render
