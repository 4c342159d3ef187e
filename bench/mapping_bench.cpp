// OctoMap insertion cost per keyframe (P1 section 5) with the project's own 640x480 front depth
// frames: the default world, the default front RGB-D camera driven down the corridor's centre line,
// one keyframe every 0.5 m, for each resolution, pixel stride, voxel-grid leaf and maximum range.
// The target is <= 30 ms per keyframe. Usage: bench_mapping [keyframes]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "render/software_rasterizer.h"
#include "slam/mapping/occupancy_mapper.h"
#include "slam/mapping/voxel_filter.h"
#include "worlds/world.h"

namespace {

using namespace corridorsim;

// CPU time of this thread, ms: the work done, which the other users of a shared machine disturb
// far less than the wall clock (OctoMap runs on the calling thread).
double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

SE3 RobotAt(int i) { return SE3::FromSE2(SE2(2.0 + 0.5 * i, 0.0, 0.0)); }

}  // namespace

int main(int argc, char** argv) {
  render::PinSoftwareRasterizer();  // Mesa's environment, before any thread
  const int keyframes = argc > 1 ? std::clamp(std::atoi(argv[1]), 2, 200) : 40;
  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 7);
  const render::RigOptions rig_options = render::RigOptions::Default();
  const render::Scene scene = render::BuildScene(world, rig_options.scene);
  auto backend = render::CreateBackend(render::BackendKind::kOsMesa);
  backend->Upload(scene);
  const render::CameraOptions& front = rig_options.cameras[0];
  render::CameraRenderer camera(front);

  slam::CameraCalibration calibration{
      front.id, front.model, front.mount.RobotFromCamera(),
      slam::DepthRange{front.depth_noise.min_m, front.depth_noise.max_m}};
  std::vector<ImageF> depths;
  std::vector<SE3> poses;
  std::size_t valid = 0;
  for (int i = 0; i < keyframes; ++i) {
    render::CameraFrame frame;
    const SE3 world_from_camera = RobotAt(i) * front.mount.RobotFromCamera();
    camera.Render(scene, *backend, world_from_camera, &frame);
    for (float d : frame.depth_m.data) valid += d > 0;
    depths.push_back(frame.depth_m);
    poses.push_back(world_from_camera);
  }
  std::printf(
      "front depth %dx%d, range [%.2f, %.2f] m, %d keyframes 0.5 m apart, %.0f valid "
      "pixels per frame\n",
      front.model.width(), front.model.height(), front.depth_noise.min_m, front.depth_noise.max_m,
      keyframes, static_cast<double>(valid) / keyframes);

  // The full cloud through the voxel-grid filter (P1 Fig. 12b's ~300k -> ~20k).
  {
    slam::DepthCloudProjector projector(slam::DepthCloudOptions{}, front.model, *calibration.depth);
    std::vector<Eigen::Vector3d> points;
    projector.PointsInWorld(depths[keyframes / 2], poses[keyframes / 2], &points);
    for (double leaf : {0.05, 0.10}) {
      const double c0 = ThreadCpuMs();
      const slam::VoxelFilterResult filtered = slam::VoxelFilter(points, {leaf});
      std::printf("voxel filter %.2f m: %zu -> %zu points in %.1f ms cpu\n", leaf, points.size(),
                  filtered.points.size(), ThreadCpuMs() - c0);
    }
  }

  std::printf("%-6s %-6s %-6s %-6s | %9s %9s %9s %9s %8s\n", "res_m", "stride", "leaf_m", "range",
              "cpu_ms/kf", "wall_ms/kf", "max_wall", "pts/kf", "leaves");
  struct Config {
    double resolution, leaf, range;
    int stride;
  };
  std::vector<Config> configs;
  for (double resolution : {0.05, 0.10}) {
    for (double range : {3.0, 4.0, 5.0, 8.0}) {
      for (int stride : {2, 4, 8}) configs.push_back({resolution, 0.0, range, stride});
    }
    configs.push_back({resolution, resolution, 5.0, 1});
    configs.push_back({resolution, 0.0, 5.0, 1});
  }
  for (const Config& c : configs) {
    slam::OccupancyMapperOptions options;
    options.resolution_m = c.resolution;
    options.max_range_m = c.range;
    options.pixel_stride = c.stride;
    options.voxel_leaf_m = c.leaf;
    slam::OccupancyMapper mapper(options, calibration);
    const double c0 = ThreadCpuMs();
    for (int i = 0; i < keyframes; ++i) mapper.Insert(depths[i], poses[i]);
    const double cpu_ms = (ThreadCpuMs() - c0) / keyframes;
    const slam::OccupancyMapperStats& s = mapper.stats();
    std::printf("%-6.2f %-6d %-6.2f %-6.1f | %9.2f %10.2f %9.2f %9.0f %8zu\n", c.resolution,
                c.stride, c.leaf, c.range, cpu_ms, s.ms_per_keyframe(),
                1e3 * s.max_keyframe_seconds, static_cast<double>(s.points_inserted) / s.keyframes,
                mapper.octree().getNumLeafNodes());
  }
  return 0;
}
