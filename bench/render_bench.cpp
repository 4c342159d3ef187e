// Rendering speed on the default world: frames per second of each camera and of the whole rig
// (front RGB-D + lateral + upward, noise included), and the rig's time against a bare draw of
// the same passes (the same views and drawables straight to the backend: no culling, remap,
// copies or noise). Usage: bench_render [frames] [osmesa|egl]

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "worlds/world.h"

namespace {

using namespace corridorsim;
using Clock = std::chrono::steady_clock;

double Ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// CPU time of the whole process (llvmpipe's threads included), ms: the work done, which the
// other users of a shared machine disturb far less than the wall clock.
double CpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

// Robot poses driving down the corridor's centre line.
SE3 PoseAt(int i) { return SE3::FromSE2(SE2(3.0 + 0.1 * (i % 480), 0.0, 0.0)); }

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  const std::string backend_name = argc > 2 ? argv[2] : "osmesa";
  const render::BackendKind kind =
      backend_name == "egl" ? render::BackendKind::kEgl : render::BackendKind::kOsMesa;

  const worlds::World world = worlds::Generate(worlds::WorldSpec{}, 7);
  const render::RigSpec spec = render::RigSpec::Default();
  const render::Scene scene = render::BuildScene(world, spec.scene);
  auto backend = render::CreateBackend(kind);
  backend->Upload(scene);
  std::printf("backend %s, default world: %zu triangles, %zu drawables, %d frames per figure\n",
              backend_name.c_str(), scene.triangle_count(), scene.drawables.size(), frames);

  // Each camera alone (exact frames, no noise).
  for (const render::CameraSpec& camera_spec : spec.cameras) {
    render::CameraRenderer camera(camera_spec);
    render::CameraFrame frame;
    camera.Render(scene, *backend, PoseAt(0) * camera_spec.mount.RobotFromCamera(), &frame);
    const double c0 = CpuMs();
    const auto t0 = Clock::now();
    for (int i = 0; i < frames; ++i) {
      camera.Render(scene, *backend, PoseAt(i) * camera_spec.mount.RobotFromCamera(), &frame);
    }
    const double ms = Ms(t0, Clock::now()) / frames;
    const double cpu = (CpuMs() - c0) / frames;
    std::printf(
        "  %-8s %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (%zu pass pixels in %zu passes)\n",
        camera_spec.id.c_str(), ms, 1000.0 / ms, cpu, camera.pass_pixel_count(),
        camera.Passes(SE3()).size());
  }

  // The whole rig, noise included.
  render::Rig rig(spec, scene, *backend);
  std::vector<render::CameraFrame> rig_frames;
  rig.Render(PoseAt(0), 1, 0, &rig_frames);
  double c0 = CpuMs();
  auto t0 = Clock::now();
  for (int i = 0; i < frames; ++i)
    rig.Render(PoseAt(i), 1, static_cast<std::uint64_t>(i), &rig_frames);
  const double rig_ms = Ms(t0, Clock::now()) / frames;
  const double rig_cpu = (CpuMs() - c0) / frames;

  // The bare draw of the same passes: views and drawable lists prepared outside the timing.
  struct Prepared {
    render::View view;
    std::vector<int> drawables;
    std::vector<int> lights;
  };
  std::vector<std::vector<Prepared>> prepared(static_cast<std::size_t>(frames));
  for (int i = 0; i < frames; ++i) {
    for (const render::CameraRenderer& camera : rig.cameras()) {
      const SE3 world_from_camera = PoseAt(i) * camera.spec().mount.RobotFromCamera();
      const auto lights = scene.options.bake_lighting
                              ? std::vector<int>{}
                              : render::NearestLights(scene, world_from_camera.translation(),
                                                      scene.options.max_lights);
      for (render::View view : camera.Passes(world_from_camera)) {
        view.read_depth = camera.spec().depth;
        prepared[static_cast<std::size_t>(i)].push_back(
            {view, render::VisibleDrawables(scene, view), lights});
      }
    }
  }
  render::RenderedView out;
  c0 = CpuMs();
  t0 = Clock::now();
  for (const auto& frame_passes : prepared) {
    for (const Prepared& p : frame_passes) backend->Draw(p.view, p.drawables, p.lights, &out);
  }
  const double bare_ms = Ms(t0, Clock::now()) / frames;
  const double bare_cpu = (CpuMs() - c0) / frames;
  std::printf(
      "  rig      %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (front RGB-D + lateral + upward, "
      "noise on)\n",
      rig_ms, 1000.0 / rig_ms, rig_cpu);
  std::printf(
      "  bare     %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (the same passes drawn and read "
      "back)\n",
      bare_ms, 1000.0 / bare_ms, bare_cpu);

  // The same rig with exact images (no noise models), to split the harness's share.
  render::RigSpec exact = spec;
  for (render::CameraSpec& c : exact.cameras) c.noise = false;
  render::Rig exact_rig(exact, scene, *backend);
  exact_rig.Render(PoseAt(0), 1, 0, &rig_frames);
  c0 = CpuMs();
  t0 = Clock::now();
  for (int i = 0; i < frames; ++i) {
    exact_rig.Render(PoseAt(i), 1, static_cast<std::uint64_t>(i), &rig_frames);
  }
  const double exact_ms = Ms(t0, Clock::now()) / frames;
  const double exact_cpu = (CpuMs() - c0) / frames;
  std::printf(
      "  rig      %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (noise off: exact images)\n",
      exact_ms, 1000.0 / exact_ms, exact_cpu);
  std::printf("  harness overhead: rig / bare = %.2f with noise, %.2f without (target <= 1.25)\n",
              rig_ms / bare_ms, exact_ms / bare_ms);
  std::printf("  same in cpu time:              %.2f with noise, %.2f without\n",
              rig_cpu / bare_cpu, exact_cpu / bare_cpu);

  // Culling: the same rig in the middle of a 1 km corridor.
  worlds::WorldSpec km_spec;
  km_spec.length_m = 1000;
  km_spec.doors.count = 290;
  km_spec.plates.count = 254;
  const worlds::World km = worlds::Generate(km_spec, 7);
  const render::Scene km_scene = render::BuildScene(km, spec.scene);
  backend->Upload(km_scene);
  render::Rig km_rig(spec, km_scene, *backend);
  auto km_pose = [](int i) { return SE3::FromSE2(SE2(480.0 + 0.1 * (i % 400), 0.0, 0.0)); };
  km_rig.Render(km_pose(0), 1, 0, &rig_frames);
  c0 = CpuMs();
  t0 = Clock::now();
  for (int i = 0; i < frames; ++i) {
    km_rig.Render(km_pose(i), 1, static_cast<std::uint64_t>(i), &rig_frames);
  }
  const double km_ms = Ms(t0, Clock::now()) / frames;
  const double km_cpu = (CpuMs() - c0) / frames;
  std::printf(
      "  rig      %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (1 km corridor, %zu triangles, "
      "noise on)\n",
      km_ms, 1000.0 / km_ms, km_cpu, km_scene.triangle_count());
  return 0;
}
