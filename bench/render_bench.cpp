// Rendering speed on the default world: frames per second of each camera and of the whole rig
// (front RGB-D + lateral + upward, noise included), and the rig's time against a bare draw of
// the same passes (the same views and drawables straight to the backend, a camera's passes in
// one batch: no culling, remap, copies or noise). Usage: bench_render [frames] [osmesa|egl]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/noise.h"
#include "render/scene.h"
#include "render/software_rasterizer.h"
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
  render::PinSoftwareRasterizer();  // Mesa's environment, before any thread
  const int frames = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  const std::string backend_name = argc > 2 ? argv[2] : "osmesa";
  const render::BackendKind kind =
      backend_name == "egl" ? render::BackendKind::kEgl : render::BackendKind::kOsMesa;

  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 7);
  const render::RigOptions rig_options = render::RigOptions::Default();
  // The light is baked when the scene is built (render/lighting.h): what shadows and the bounce
  // cost there, once per run, against the direct light alone.
  auto build_ms = [&](const worlds::World& w, const render::SceneOptions& o) {
    const auto t = Clock::now();
    const render::Scene built = render::BuildScene(w, o);
    return std::make_pair(Ms(t, Clock::now()), built.vertices.size());
  };
  render::SceneOptions direct_only = rig_options.scene;
  direct_only.shadows = false;
  direct_only.bounces = 0;
  const auto [direct_ms, vertex_count] = build_ms(world, direct_only);
  const double baked_ms = build_ms(world, rig_options.scene).first;
  std::printf(
      "scene build: %.0f ms with shadows and %d bounce(s), %.0f ms direct light only "
      "(%zu vertices)\n",
      baked_ms, rig_options.scene.bounces, direct_ms, vertex_count);
  const render::Scene scene = render::BuildScene(world, rig_options.scene);
  auto backend = render::CreateBackend(kind);
  backend->Upload(scene);
  // Set in main() unless the user set it; a GPU ignores it.
  const std::string gallivm_perf = render::GallivmPerfInEffect(backend.get()).value_or("");
  std::printf(
      "backend %s (GALLIVM_PERF=%s), default world: %zu triangles, %zu drawables, %d frames per "
      "figure\n",
      backend_name.c_str(), gallivm_perf.c_str(), scene.triangle_count(), scene.drawables.size(),
      frames);
  // Which device the figures are of: the EGL backend takes a GPU when there is one.
  std::printf("device: %s; GL_RENDERER %s\n", backend->info().device.c_str(),
              backend->info().renderer.c_str());

  // Each camera alone (exact frames, no noise).
  for (const render::CameraOptions& camera_options : rig_options.cameras) {
    render::CameraRenderer camera(camera_options);
    render::CameraFrame frame;
    camera.Render(scene, *backend, PoseAt(0) * camera_options.mount.RobotFromCamera(), &frame);
    const double c0 = CpuMs();
    const auto t0 = Clock::now();
    for (int i = 0; i < frames; ++i) {
      camera.Render(scene, *backend, PoseAt(i) * camera_options.mount.RobotFromCamera(), &frame);
    }
    const double ms = Ms(t0, Clock::now()) / frames;
    const double cpu = (CpuMs() - c0) / frames;
    std::printf(
        "  %-8s %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (%zu pass pixels in %zu passes)\n",
        camera_options.id.c_str(), ms, 1000.0 / ms, cpu, camera.pass_pixel_count(),
        camera.Passes(SE3()).size());
  }

  // The whole rig with noise, the same rig with exact images, and the bare draw of the same
  // passes, measured in interleaved rounds (median per figure), so that a shared machine's
  // changing speed hits all three alike and their ratios stay meaningful.
  render::Rig rig(rig_options, scene, *backend);
  render::RigOptions exact_options = rig_options;
  for (render::CameraOptions& c : exact_options.cameras) c.noise = false;
  render::Rig exact_rig(exact_options, scene, *backend);
  std::vector<render::CameraFrame> rig_frames;
  rig.Render(PoseAt(0), 1, 0, &rig_frames);
  exact_rig.Render(PoseAt(0), 1, 0, &rig_frames);

  // The bare draw: views and drawable lists prepared outside the timing, each camera's passes
  // handed to the backend in one batch as the rig does; no culling, remap, copies or noise.
  struct Prepared {
    std::vector<render::View> views;
    std::vector<std::vector<int>> drawables;
    std::vector<std::span<const render::PixelRect>> unused;
  };
  std::vector<std::vector<Prepared>> prepared(static_cast<std::size_t>(frames));
  for (int i = 0; i < frames; ++i) {
    for (const render::CameraRenderer& camera : rig.cameras()) {
      const SE3 world_from_camera = PoseAt(i) * camera.options().mount.RobotFromCamera();
      Prepared p;
      for (render::View view : camera.Passes(world_from_camera)) {
        view.read_depth = camera.options().depth;
        p.drawables.push_back(render::VisibleDrawables(scene, view));
        p.unused.push_back(camera.unused_pixels(p.views.size()));
        p.views.push_back(view);
      }
      prepared[static_cast<std::size_t>(i)].push_back(std::move(p));
    }
  }
  std::vector<render::RenderedView> outs(8);
  auto bare_frame = [&](int i) {
    for (const Prepared& p : prepared[static_cast<std::size_t>(i)]) {
      std::vector<render::DrawRequest> requests;
      for (std::size_t k = 0; k < p.views.size(); ++k) {
        requests.push_back({p.views[k], p.drawables[k], {}, &outs[k], p.unused[k]});
      }
      backend->DrawPasses(requests);
    }
  };
  if (!scene.options.bake_lighting) {
    std::printf("  (the bare draw assumes baked lighting; this scene lights per pixel)\n");
  }

  constexpr int kRounds = 5;
  const int per_round = std::max(2, frames / kRounds);
  struct Figure {
    std::vector<double> ms, cpu;
    double Median(std::vector<double> v) const {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    }
  };
  // The same rig with textures filtered in the nearest mip level (render.texture_filter:
  // nearest_mip), on a backend of its own so that its rounds interleave with the others.
  render::SceneOptions fast_options = rig_options.scene;
  fast_options.texture_filter = render::TextureFilter::kNearestMip;
  const render::Scene fast_scene = render::BuildScene(world, fast_options);
  const std::unique_ptr<render::Backend> fast_backend = render::CreateBackend(kind);
  fast_backend->Upload(fast_scene);
  render::Rig fast_rig(rig_options, fast_scene, *fast_backend);
  fast_rig.Render(PoseAt(0), 1, 0, &rig_frames);

  Figure noisy, bare, exact, fast;
  auto time = [&](Figure* figure, const std::function<void(int)>& frame) {
    const double c0 = CpuMs();
    const auto t0 = Clock::now();
    for (int i = 0; i < per_round; ++i) frame(i);
    figure->ms.push_back(Ms(t0, Clock::now()) / per_round);
    figure->cpu.push_back((CpuMs() - c0) / per_round);
  };
  for (int round = 0; round < kRounds; ++round) {
    const int offset = round * per_round;
    time(&noisy, [&](int i) {
      rig.Render(PoseAt(offset + i), 1, static_cast<std::uint64_t>(offset + i), &rig_frames);
    });
    time(&bare, [&](int i) { bare_frame((offset + i) % frames); });
    time(&exact, [&](int i) {
      exact_rig.Render(PoseAt(offset + i), 1, static_cast<std::uint64_t>(offset + i), &rig_frames);
    });
    time(&fast, [&](int i) {
      fast_rig.Render(PoseAt(offset + i), 1, static_cast<std::uint64_t>(offset + i), &rig_frames);
    });
  }
  const double rig_ms = noisy.Median(noisy.ms), rig_cpu = noisy.Median(noisy.cpu);
  const double bare_ms = bare.Median(bare.ms), bare_cpu = bare.Median(bare.cpu);
  const double exact_ms = exact.Median(exact.ms), exact_cpu = exact.Median(exact.cpu);
  std::printf(
      "  rig      %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (front RGB-D + lateral + upward, "
      "noise on; median of %d rounds)\n",
      rig_ms, 1000.0 / rig_ms, rig_cpu, kRounds);
  std::printf(
      "  bare     %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (the same passes drawn and read "
      "back)\n",
      bare_ms, 1000.0 / bare_ms, bare_cpu);
  std::printf(
      "  rig      %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (noise off: exact images)\n",
      exact_ms, 1000.0 / exact_ms, exact_cpu);
  const double fast_ms = fast.Median(fast.ms), fast_cpu = fast.Median(fast.cpu);
  std::printf(
      "  rig      %6.2f ms/frame  %6.1f frames/s  cpu %6.2f ms  (noise on, texture_filter "
      "nearest_mip)\n",
      fast_ms, 1000.0 / fast_ms, fast_cpu);
  std::printf("  harness overhead: rig / bare = %.2f with noise, %.2f without (target <= 1.25)\n",
              rig_ms / bare_ms, exact_ms / bare_ms);
  std::printf("  same in cpu time:              %.2f with noise, %.2f without\n",
              rig_cpu / bare_cpu, exact_cpu / bare_cpu);

  // The front camera's depth noise alone, on one thread.
  {
    const render::CameraOptions& front = rig_options.cameras[0];
    render::CameraRenderer camera(front);
    render::CameraFrame frame;
    camera.Render(scene, *backend, PoseAt(0) * front.mount.RobotFromCamera(), &frame);
    std::vector<double> ms;
    for (int i = 0; i < std::max(10, frames / 2); ++i) {
      ImageF depth = frame.depth_m;
      RandomStream rng(1, 0, "bench.depth_noise");
      const auto t0 = Clock::now();
      render::ApplyDepthNoise(front.depth_noise, *front.model.pinhole(), rng, &depth);
      ms.push_back(Ms(t0, Clock::now()));
    }
    std::printf("  depth noise %5.2f ms per front frame (median, one thread)\n",
                Figure{}.Median(ms));
  }

  // Supersampling (render.samples 9: each camera drawn at 3 x its resolution), a few frames.
  {
    render::RigOptions supersampled = rig_options;
    supersampled.samples = 9;
    render::Rig ss_rig(supersampled, scene, *backend);
    ss_rig.Render(PoseAt(0), 1, 0, &rig_frames);
    const int n = std::max(3, frames / 10);
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i)
      ss_rig.Render(PoseAt(i), 1, static_cast<std::uint64_t>(i), &rig_frames);
    std::printf("  rig      %6.2f ms/frame  (render.samples 9, noise on, %d frames)\n",
                Ms(t0, Clock::now()) / n, n);
  }

  // Culling: the same rig in the middle of a 1 km corridor.
  worlds::WorldOptions km_options;
  km_options.length_m = 1000;
  km_options.doors.count = 290;
  km_options.plates.count = 254;
  const worlds::World km = worlds::Generate(km_options, 7);
  const auto t_km = Clock::now();
  const render::Scene km_scene = render::BuildScene(km, rig_options.scene);
  std::printf("  scene build of the 1 km corridor: %.0f ms (%zu vertices)\n",
              Ms(t_km, Clock::now()), km_scene.vertices.size());
  backend->Upload(km_scene);
  render::Rig km_rig(rig_options, km_scene, *backend);
  auto km_pose = [](int i) { return SE3::FromSE2(SE2(480.0 + 0.1 * (i % 400), 0.0, 0.0)); };
  km_rig.Render(km_pose(0), 1, 0, &rig_frames);
  const double c0 = CpuMs();
  const auto t0 = Clock::now();
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
