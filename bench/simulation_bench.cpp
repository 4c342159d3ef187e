// Simulation speed on the default world (P1's 55 m corridor, the default round trip):
//   1. physics alone at 1 kHz (the Bullet robot driving at constant wheel speeds), as a
//      real-time factor;
//   2. the loop without cameras (physics + path follower + odometry + sensor clock);
//   3. the loop without cameras with a 1 kHz IMU and a 720-beam laser scanner at 40 Hz, against
//      the plain loop (docs/sensors.md, "Cost"), in wall-clock time and in this thread's CPU time
//      (steadier on a shared machine: the loop runs on this thread alone);
//   4. the closed loop with the full rig (front RGB-D + lateral + upward, noise on) at 10 Hz,
//      with the time split between physics and rendering.
// Usage: bench_simulation [simulated seconds, default 60] [all|physics|loop|motion|rig]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "render/camera_rig.h"
#include "render/software_rasterizer.h"
#include "sim/robot.h"
#include "sim/simulation.h"
#include "tests/support/uploaded_rig.h"
#include "worlds/world.h"

namespace {

using namespace corridorsim;
using Clock = std::chrono::steady_clock;

// Wall-clock seconds that `work()` takes.
template <class F>
double WallSeconds(F&& work) {
  const auto start = Clock::now();
  work();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// This thread's CPU time (s).
double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// What DriveTimed measured: wall-clock and CPU seconds of the steps, and what they delivered.
struct TimedDrive {
  double wall_s = 0.0;
  double cpu_s = 0.0;
  std::size_t odometry_messages = 0;
  std::size_t frames = 0;
  std::size_t imu_samples = 0;
  std::size_t sweeps = 0;
};

// Drives the world's default path for `simulated_s` (with `rig` drawing, if given), timing the
// steps only.
TimedDrive DriveTimed(const worlds::World& world, sim::SimulationOptions options,
                      double simulated_s, render::Rig* rig = nullptr,
                      const render::RigOptions* rig_options = nullptr) {
  options.max_duration_ns = FromSeconds(simulated_s);
  sim::Simulation simulation(world, options, sim::BuildRobotPath(world, options.robot_path), rig,
                             rig_options);
  TimedDrive drive;
  const double cpu_start = CpuSeconds();
  drive.wall_s = WallSeconds([&] {
    while (!simulation.finished()) {
      const sim::StepOutput& out = simulation.Step();
      drive.odometry_messages += out.odometry.size();
      drive.frames += out.frames.size();
      drive.imu_samples += out.imu.size();
      drive.sweeps += out.scans.size();
    }
  });
  drive.cpu_s = CpuSeconds() - cpu_start;
  return drive;
}

}  // namespace

int main(int argc, char** argv) {
  render::PinSoftwareRasterizer();  // Mesa's environment, before any thread
  const double sim_s = argc > 1 ? std::max(5.0, std::atof(argv[1])) : 60.0;
  const std::string only = argc > 2 ? argv[2] : "all";
  auto run = [&](const char* part) { return only == "all" || only == part; };
  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 1);
  sim::SimulationOptions options;
  std::printf("default world, %zu collision boxes; %.0f s simulated per figure\n",
              world.collision_boxes.size(), sim_s);

  // 1. Physics alone.
  if (run("physics")) {
    sim::RobotPhysics robot(world, options.robot, SE2(1.0, 0.0, 0.0));
    robot.SetWheelSpeeds(3.4, 3.4);
    const auto steps = static_cast<long>(sim_s * options.robot.physics_rate_hz);
    const double wall = WallSeconds([&] {
      for (long i = 0; i < steps; ++i) robot.Step();
    });
    std::printf("  physics alone (%.0f Hz):     %6.2f us/step   real-time factor %7.1fx\n",
                options.robot.physics_rate_hz, 1e6 * wall / static_cast<double>(steps),
                sim_s / wall);
  }

  // 2. The loop without cameras.
  if (run("loop")) {
    const TimedDrive drive = DriveTimed(world, options, sim_s);
    std::printf(
        "  loop without cameras:       %6.2f us/step   real-time factor %7.1fx  (%zu "
        "odometry messages)\n",
        1e6 * drive.wall_s / (sim_s * options.robot.physics_rate_hz), sim_s / drive.wall_s,
        drive.odometry_messages);
  }

  // 3. The loop without cameras, plus a 1 kHz IMU and a 720-beam scanner at 40 Hz (the issue's
  //    figure: what they add to a camera-less run), alternated with the plain loop three times;
  //    the medians' ratio.
  if (run("motion")) {
    sim::SimulationOptions with = options;
    sim::ImuOptions imu;
    imu.id = "imu";
    imu.rate_hz = 1000;
    sim::LaserOptions laser;
    laser.id = "laser";
    laser.rate_hz = 40;
    laser.angle_min_deg = -135;
    laser.angle_max_deg = 134.625;
    laser.resolution_deg = 0.375;  // 720 beams over 270 deg, like a Hokuyo UTM-30LX
    laser.range_max_m = 30;
    with.imus = {imu};
    with.lasers = {laser};
    std::vector<double> plain_s, with_s, plain_cpu_s, with_cpu_s;
    TimedDrive last;
    for (int k = 0; k < 3; ++k) {
      const TimedDrive plain = DriveTimed(world, options, sim_s);
      plain_s.push_back(plain.wall_s);
      plain_cpu_s.push_back(plain.cpu_s);
      last = DriveTimed(world, with, sim_s);
      with_s.push_back(last.wall_s);
      with_cpu_s.push_back(last.cpu_s);
    }
    for (std::vector<double>* v : {&plain_s, &with_s, &plain_cpu_s, &with_cpu_s}) {
      std::sort(v->begin(), v->end());
    }
    std::printf(
        "  loop + 1 kHz IMU + 720-beam 40 Hz scanner: %zu samples, %zu sweeps; median %.3f s "
        "against %.3f s without: +%.0f %% (CPU time: %.3f s against %.3f s, +%.0f %%)\n",
        last.imu_samples, last.sweeps, with_s[1], plain_s[1],
        100.0 * (with_s[1] / plain_s[1] - 1.0), with_cpu_s[1], plain_cpu_s[1],
        100.0 * (with_cpu_s[1] / plain_cpu_s[1] - 1.0));
  }

  // 4. The closed loop with the full rig at 10 Hz.
  if (run("rig")) {
    render::RigOptions rig_options = render::RigOptions::Default();
    for (render::CameraOptions& c : rig_options.cameras) c.rate_hz = 10.0;
    test::UploadedRig uploaded(world, rig_options);
    const double rig_s = sim_s / 4;  // rendering dominates: a shorter run gives the same rate
    const TimedDrive drive = DriveTimed(world, options, rig_s, &uploaded.rig(), &rig_options);
    std::printf(
        "  closed loop, full rig 10 Hz: %zu frames, real-time factor %6.2fx, %.1f ms "
        "per rig frame (physics and everything else included)\n",
        drive.frames, rig_s / drive.wall_s,
        1e3 * drive.wall_s / (static_cast<double>(drive.frames) / 3.0));
  }
  return 0;
}
