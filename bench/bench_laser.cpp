// Laser scanner speed on the default world (P1's 55 m corridor): the ray grid's build, and the rays
// per second of LaserScanner::Cast for a 720-beam sweep (-90 to 89.75 deg at 0.25 deg) from poses
// along the corridor's centre line, the robot driving at P1's 0.34 m/s during each sweep (each
// beam cast from where the scanner is when it fires), and Measure's cost per sweep; then the same
// rays through RayGrid::Nearest alone at several cell sizes (sim/ray_grid.h); in this thread's
// CPU time.
// Usage: bench_laser [sweeps, default 2000] [range_max_m, default 80]

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "sim/laser_scanner.h"
#include "sim/ray_grid.h"
#include "worlds/world.h"

namespace {

using namespace corridorsim;

// This thread's CPU time (s): steadier than the wall clock on a machine shared with other work.
double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  const int sweeps = argc > 1 ? std::max(10, std::atoi(argv[1])) : 2000;
  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 1);
  sim::LaserOptions options;
  options.resolution_deg = 0.25;
  options.angle_max_deg = 89.75;  // 720 beams
  if (argc > 2) options.range_max_m = std::atof(argv[2]);
  if (const auto problem = options.Check()) {
    std::fprintf(stderr, "bench_laser: %s: %s\n", problem->key.c_str(), problem->message.c_str());
    return 2;
  }
  double start = CpuSeconds();
  const sim::LaserScanner scanner(world, options, 1);
  const double build_s = CpuSeconds() - start;
  std::printf("default world: %zu meshes, %zu triangles; scanner (its ray grid) built in %.1f ms\n",
              world.meshes.size(), world.triangle_count(), 1e3 * build_s);

  // Sweeps evenly along the first corridor's centre line, 1 m from each end, facing along it.
  const worlds::CorridorSegment& corridor = world.segments.front();
  const Eigen::Vector2d along = corridor.direction();
  const double length_m = (corridor.end - corridor.start).norm() - 2.0;
  const double yaw = std::atan2(along.y(), along.x());
  constexpr double kSpeedMps = 0.34;  // P1's cruise speed
  const double beam_s = ToSeconds(scanner.time_increment_ns());
  std::vector<sim::BeamTruth> truths(static_cast<std::size_t>(scanner.beam_count()));
  double hits = 0.0, cast_s = 0.0, measure_s = 0.0, checksum = 0.0;
  for (int s = 0; s < sweeps; ++s) {
    const Eigen::Vector2d xy = corridor.start + (1.0 + length_m * s / (sweeps - 1)) * along;
    start = CpuSeconds();
    for (int i = 0; i < scanner.beam_count(); ++i) {
      const Eigen::Vector2d at = xy + kSpeedMps * beam_s * i * along;
      const SE3 pose = SE3::FromYawPitchRoll(yaw, 0.0, 0.0, {at.x(), at.y(), options.mount.z_m});
      truths[static_cast<std::size_t>(i)] = scanner.Cast(i, pose);
    }
    cast_s += CpuSeconds() - start;
    start = CpuSeconds();
    const LaserScan scan = scanner.Measure(0, static_cast<std::uint64_t>(s), truths);
    measure_s += CpuSeconds() - start;
    for (const sim::BeamTruth& t : truths) hits += t.range_m < options.range_max_m ? 1 : 0;
    checksum += scan.ranges_m[360];
  }
  const double rays = static_cast<double>(sweeps) * scanner.beam_count();
  std::printf("%d sweeps of %d beams: %.0f rays/s (%.2f us/ray, %.0f%% returns), %.3f ms/sweep\n",
              sweeps, scanner.beam_count(), rays / cast_s, 1e6 * cast_s / rays, 100.0 * hits / rays,
              1e3 * cast_s / sweeps);
  std::printf("Measure: %.1f us/sweep; at 40 Hz the scanner costs %.1f%% of one core\n",
              1e6 * measure_s / sweeps, 100.0 * 40.0 * (cast_s + measure_s) / sweeps);
  std::printf("(checksum %.3f)\n", checksum);

  // The same rays through the grid alone, at several cell sizes.
  std::vector<Eigen::Vector3d> corners, origins, directions;
  for (const worlds::Mesh& mesh : world.meshes) {
    for (const std::uint32_t index : mesh.indices) {
      corners.push_back(mesh.positions[index].cast<double>());
    }
  }
  for (int s = 0; s < sweeps; ++s) {
    const Eigen::Vector2d xy = corridor.start + (1.0 + length_m * s / (sweeps - 1)) * along;
    for (int i = 0; i < scanner.beam_count(); ++i) {
      const Eigen::Vector2d at = xy + kSpeedMps * beam_s * i * along;
      const double angle = yaw + scanner.BeamAngleRad(i);
      origins.emplace_back(at.x(), at.y(), options.mount.z_m);
      directions.emplace_back(std::cos(angle), std::sin(angle), 0.0);
    }
  }
  for (const double cell_m : {0.25, 0.5, 1.0, 2.0}) {
    start = CpuSeconds();
    const sim::RayGrid grid(corners, cell_m);
    const double grid_build_s = CpuSeconds() - start;
    double sum = 0.0;
    start = CpuSeconds();
    for (std::size_t r = 0; r < origins.size(); ++r) {
      const sim::RayHit hit = grid.Nearest(origins[r], directions[r], options.range_max_m);
      sum += hit.triangle >= 0 ? hit.t : 0.0;
    }
    const double grid_s = CpuSeconds() - start;
    std::printf(
        "  grid %.2f m: %d x %d cells, %.1f triangles per cell, built in %.1f ms; %.0f rays/s "
        "(mean range %.2f m)\n",
        grid.cell_m(), grid.columns(), grid.rows(),
        static_cast<double>(grid.entries()) / (grid.columns() * grid.rows()), 1e3 * grid_build_s,
        rays / grid_s, sum / rays);
  }
  return 0;
}
