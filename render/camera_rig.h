#pragma once
// The sensor rig: cameras mounted on the robot (front RGB-D like P1's ASUS Xtion Pro Live, a
// lateral web camera tilted up to read door plates (P1), a wide-angle upward camera (P2/P3)),
// their options as parsed from a scenario's `sensors:` section, and the renderer that turns the
// GL backend's pinhole passes into each camera's image through its model.
//
// Every camera is drawn as one or more undistorted pinhole passes: an undistorted pinhole camera
// is one pass drawn with its own intrinsics (exact); a distorted pinhole is one wider pass
// remapped through the distortion; a Kannala-Brandt fisheye is drawn as the cube faces its field
// of view needs, each cropped to the part it uses, and remapped per pixel through the model
// (bilinear colour, nearest labels and depth). The remap table is built once per camera.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/image.h"
#include "common/io/serial_worker.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "render/backend.h"
#include "render/noise.h"
#include "render/remap_kernel.h"
#include "render/scene.h"
#include "worlds/world.h"

namespace corridorsim::render {

/// Where a camera sits on the robot. Position in the robot frame R (x forward, y left, z up);
/// the optical axis points at heading `yaw_deg` (0 forward, 90 left) and elevation `pitch_deg`
/// (0 horizontal, 90 straight up); `roll_deg` turns the image about the optical axis. At zero
/// roll the image x axis is horizontal (for an upward camera: towards the robot's right).
struct Mount {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double yaw_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  SE3 RobotFromCamera() const;
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
  std::string id;  // "front", "lateral", "upward"
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
  std::vector<CameraOptions> cameras;  // in a fixed order: front, lateral, upward
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

/// How far (m) a camera's optical centre must stay from every solid and from the boundary of the
/// corridor and the rooms (walls, floor, ceiling): the near plane of its views (kNearPlaneM),
/// within which a surface is clipped and the camera sees through it, plus 1 cm for the path
/// follower's tracking (it arrives within 2 mm of a waypoint, sim/robot_path.h).
inline constexpr double kCameraClearanceM = kNearPlaneM + 0.01;

/// Why a camera whose optical centre is at `p_in_world` would see through the world's boundary:
/// outside the corridor and the rooms ("outside the corridor (in or behind a wall)", "above the
/// ceiling (... m high)", "below the floor") or within kCameraClearanceM of a wall, the floor or a
/// ceiling; nullopt when clear. Solids (boxes) are not looked at (see CheckCameraPlacement).
std::optional<std::string> CameraSpaceProblem(const worlds::World& world,
                                              const Eigen::Vector3d& p_in_world);

/// A problem when a camera at `world_from_robot` would sit inside a solid or closer to one than
/// kCameraClearanceM, or where CameraSpaceProblem finds one (key "<camera>.mount"). One pose:
/// sim::CheckPathPlacement sweeps the same rules along a whole path.
std::optional<OptionsProblem> CheckCameraPlacement(const worlds::World& world,
                                                   const RigOptions& rig,
                                                   const SE3& world_from_robot);

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
