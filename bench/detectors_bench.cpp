// Detector speed and accuracy on rendered frames: the default world's front camera (640x480,
// noise included) at poses along the corridor with headings of +-20 degrees, each detector timed
// per frame (median over the frames, wall clock and process CPU), and the vanishing point against
// the frame's truth (render::FrameTruth) for both Hough transforms.
// Usage: bench_detectors [frames] [osmesa|egl]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numbers>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "render/scene.h"
#include "render/software_rasterizer.h"
#include "slam/features/harris_corners.h"
#include "slam/features/vanishing_point.h"
#include "worlds/world.h"

namespace {

using namespace corridorsim;
using Clock = std::chrono::steady_clock;

double CpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Robot poses down the default corridor's centre line, offset and turned by a fixed pattern.
SE2 PoseAt(int i, int n) {
  const double x = 4.0 + 46.0 * i / std::max(1, n - 1);
  const double y = 0.3 * std::sin(1.7 * i);
  const double yaw_deg = 20.0 * std::sin(0.9 * i + 0.4);
  return SE2(x, y, yaw_deg * std::numbers::pi / 180.0);
}

struct Timed {
  std::vector<double> wall_ms, cpu_ms;
  template <class F>
  void Run(F&& f) {
    const double c0 = CpuMs();
    const auto t0 = Clock::now();
    f();
    wall_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    cpu_ms.push_back(CpuMs() - c0);
  }
};

}  // namespace

int main(int argc, char** argv) {
  render::PinSoftwareRasterizer();  // Mesa's environment, before any thread
  const int frames = argc > 1 ? std::clamp(std::atoi(argv[1]), 1, 10000) : 60;
  const std::string backend_name = argc > 2 ? argv[2] : "osmesa";
  const render::BackendKind kind =
      backend_name == "egl" ? render::BackendKind::kEgl : render::BackendKind::kOsMesa;

  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 1);
  render::RigOptions rig_options = render::RigOptions::Default();
  for (render::CameraOptions& c : rig_options.cameras) c.enabled = c.id == "front";
  const render::Scene scene = render::BuildScene(world, rig_options.scene);
  auto backend = render::CreateBackend(kind);
  backend->Upload(scene);
  render::Rig rig(rig_options, scene, *backend);

  slam::VanishingPointOptions probabilistic;
  slam::VanishingPointOptions standard;
  standard.hough = slam::HoughMethod::kStandard;
  standard.hough_votes = 120;  // the standard transform's best threshold on these frames
  const slam::HarrisCornerOptions harris;

  struct Score {
    const char* name;
    const slam::VanishingPointOptions* options;
    Timed time;
    std::vector<double> errors_px;
    int truth_in_image = 0, found = 0, missed = 0, false_points = 0;
  };
  Score scores[2] = {{"probabilistic (HoughLinesP)", &probabilistic, {}, {}},
                     {"standard (HoughLines)", &standard, {}, {}}};
  Timed harris_time, harris_depth_time;
  std::size_t corner_total = 0, corner_with_depth = 0;

  for (int i = 0; i < frames; ++i) {
    const SE3 world_from_robot = SE3::FromSE2(PoseAt(i, frames));
    std::vector<render::CameraFrame> rendered;
    rig.Render(world_from_robot, 1, static_cast<std::uint64_t>(i), &rendered);
    const render::CameraFrame& frame = rendered.at(0);
    render::FrameTruthInput input;
    input.world = &world;
    input.camera_id = frame.camera_id;
    input.model = rig.cameras()[0].options().model;
    input.world_from_camera = frame.world_from_camera;
    input.world_from_robot = world_from_robot;
    input.instance = &frame.instance;
    input.semantic = &frame.semantic;
    const render::FrameTruth truth = render::ComputeFrameTruth(input);
    const render::VanishingPointTruth* true_vp = nullptr;
    for (const auto& vp : truth.vanishing_points) {
      if (vp.camera_in_segment && vp.in_image) true_vp = &vp;
    }
    for (Score& s : scores) {
      std::optional<slam::VanishingPoint> vp;
      s.time.Run([&] { vp = slam::DetectVanishingPoint(frame.rgb, *s.options); });
      s.truth_in_image += true_vp != nullptr;
      if (vp) ++s.found;
      if (true_vp && !vp) ++s.missed;
      if (vp && true_vp) {
        const double e = (vp->pixel_px - true_vp->pixel).norm();
        s.errors_px.push_back(e);
        // A point farther than 10 px from the truth is a false point, not an inaccurate one.
        if (e > 10.0) ++s.false_points;
      } else if (vp) {
        ++s.false_points;
      }
    }
    std::vector<slam::HarrisCorner> corners;
    harris_time.Run([&] { corners = slam::DetectHarrisCorners(frame.rgb, nullptr, harris); });
    harris_depth_time.Run(
        [&] { corners = slam::DetectHarrisCorners(frame.rgb, &frame.noisy_depth_m, harris); });
    corner_total += corners.size();
    for (const auto& c : corners) corner_with_depth += c.depth_m.has_value();
  }

  std::printf("bench_detectors: %d front frames (640x480, noisy), default world seed 1, %s\n",
              frames, backend_name.c_str());
  for (Score& s : scores) {
    std::vector<double> accurate;
    for (double e : s.errors_px) {
      if (e <= 10.0) accurate.push_back(e);
    }
    std::printf(
        "  vanishing point, %-28s %6.2f ms/frame (cpu %6.2f)  truth in image %d, found %d, "
        "missed %d, false %d; error median %.2f px, max %.2f px (of %zu within 10 px)\n",
        s.name, Median(s.time.wall_ms), Median(s.time.cpu_ms), s.truth_in_image, s.found, s.missed,
        s.false_points, Median(accurate),
        accurate.empty() ? 0.0 : *std::max_element(accurate.begin(), accurate.end()),
        accurate.size());
  }
  std::printf("  harris corners                          %6.2f ms/frame (cpu %6.2f)\n",
              Median(harris_time.wall_ms), Median(harris_time.cpu_ms));
  std::printf(
      "  harris corners + depth                  %6.2f ms/frame (cpu %6.2f)  %.1f "
      "corners/frame, %.1f with depth\n",
      Median(harris_depth_time.wall_ms), Median(harris_depth_time.cpu_ms),
      static_cast<double>(corner_total) / frames, static_cast<double>(corner_with_depth) / frames);
  return 0;
}
