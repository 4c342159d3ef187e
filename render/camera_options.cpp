#include "render/camera_options.h"

#include "common/io/input_text.h"
#include "common/io/options_yaml.h"
#include "common/options_checker.h"
#include "common/time.h"
#include "render/camera_budget.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace corridorsim::render {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr double kDegToRad = std::numbers::pi / 180.0;

const auto& Num = FormatNumber;

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

SE3 Mount::RobotFromBody() const {
  return SE3::FromYawPitchRoll(yaw_deg * kDegToRad, -pitch_deg * kDegToRad, roll_deg * kDegToRad,
                               Vector3d(x_m, y_m, z_m));
}

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

CameraOptions NewCameraOptions(const std::string& id) {
  CameraOptions camera = RigOptions::Default().cameras.front();
  camera.id = id;
  camera.depth = false;
  return camera;
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

const OptionTable<DepthNoiseOptions>& DepthNoiseOptionsTable() {
  return StaticOptionTable<DepthNoiseOptions>([](OptionTable<DepthNoiseOptions>& t) {
    using D = DepthNoiseOptions;
    t.Add("min_m", &D::min_m, "m", "nearest valid depth").AtLeast(0);
    t.Add("max_m", &D::max_m, "m", "farthest valid depth").Range(0, 1000).Note("> min_m");
    t.Add("quantise", &D::quantise, "", "disparity quantisation to 1 / subpixel px");
    t.Add("baseline_m", &D::baseline_m, "m", "projector-camera baseline").Greater(0).Range(0, 10);
    t.Add("subpixel", &D::subpixel, "", "disparity steps per px")
        .AtLeast(1, "must be at least 1 (got {})")
        .Range(1, 1024);
    t.Add("axial", &D::axial, "",
          "axial noise sigma_z = axial_a_m + axial_b (z - axial_z0_m)^2 (Nguyen 2012 eq. 6)");
    t.Add("axial_a_m", &D::axial_a_m, "m", "sigma at z = axial_z0_m").AtLeast(0);
    t.Add("axial_b", &D::axial_b, "1/m", "growth of sigma with (z - axial_z0_m)^2").AtLeast(0);
    t.Add("axial_z0_m", &D::axial_z0_m, "m", "depth of the smallest sigma").AtLeast(0);
    t.Add("lateral_sigma_px", &D::lateral_sigma_px, "px",
          "lateral noise: a pixel takes the depth of one displaced by round(N(0, sigma)); 0 = off")
        .Range(0, 10, "must lie in [0, 10] px (got {})");
    t.Add("grazing", &D::grazing, "", "dropouts at grazing incidence");
    t.Add("grazing_start_deg", &D::grazing_start_deg, "deg", "dropouts begin")
        .Range(0, 90, "must lie in [0, 90] deg (got {})");
    t.Add("grazing_max_deg", &D::grazing_max_deg, "deg", "everything beyond is invalid")
        .Note("[grazing_start_deg, 90]");
    t.Add("random_dropout", &D::random_dropout, "",
          "probability that any valid pixel becomes invalid")
        .Range(0, 1);
  });
}

const OptionTable<RgbNoiseOptions>& RgbNoiseOptionsTable() {
  return StaticOptionTable<RgbNoiseOptions>([](OptionTable<RgbNoiseOptions>& t) {
    using R = RgbNoiseOptions;
    t.Add("exposure", &R::exposure, "",
          "gain on the collected signal (exposure time ratio); 1 = off")
        .Greater(0)
        .Range(0, 100);
    t.Add("vignetting", &R::vignetting, "", "relative fall-off at the image corners; 0 = off")
        .Range(0, 1);
    t.Add("full_well_electrons", &R::full_well_electrons, "",
          "electrons at 255 DN (shot noise); 0 = off, e.g. 6000 for a web camera")
        .AtLeast(0)
        .Range(0, 1e7);
    t.Add("read_noise_electrons", &R::read_noise_electrons, "",
          "read noise (std, electrons); 0 = off")
        .AtLeast(0)
        .Range(0, 1e4)
        .Note("needs full_well_electrons > 0");
    t.Add("motion_blur_px", &R::motion_blur_px, "px", "length of the linear motion blur; 0 = off")
        .AtLeast(0)
        .Range(0, 64);
  });
}

const OptionTable<CameraOptions>& CameraOptionsTable() {
  return StaticOptionTable<CameraOptions>([](OptionTable<CameraOptions>& t) {
    using C = CameraOptions;
    AddSensorTypeKey(t, "camera");
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

}  // namespace corridorsim::render
