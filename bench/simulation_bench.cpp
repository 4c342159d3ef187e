// Simulation speed on the default world (P1's 55 m corridor, the default round trip):
//   1. physics alone at 1 kHz (the Bullet robot driving at constant wheel speeds), as a
//      real-time factor;
//   2. the loop without cameras (physics + path follower + odometry + sensor clock);
//   3. the closed loop with the full rig (front RGB-D + lateral + upward, noise on) at 10 Hz,
//      with the time split between physics and rendering.
// Usage: bench_simulation [simulated seconds, default 60] [all|physics|loop|rig]

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "sim/robot.h"
#include "sim/simulation.h"
#include "worlds/world.h"

namespace {

using namespace corridorsim;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

int main(int argc, char** argv) {
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
    const auto t0 = Clock::now();
    for (long i = 0; i < steps; ++i) robot.Step();
    const double wall = Seconds(t0, Clock::now());
    std::printf("  physics alone (%.0f Hz):     %6.2f us/step   real-time factor %7.1fx\n",
                options.robot.physics_rate_hz, 1e6 * wall / static_cast<double>(steps),
                sim_s / wall);
  }

  // 2. The loop without cameras.
  if (run("loop")) {
    options.max_duration_ns = FromSeconds(sim_s);
    sim::Simulation simulation(world, options, sim::BuildRobotPath(world, options.robot_path));
    const auto t0 = Clock::now();
    std::size_t messages = 0;
    while (!simulation.finished()) messages += simulation.Step().odometry.size();
    const double wall = Seconds(t0, Clock::now());
    std::printf(
        "  loop without cameras:       %6.2f us/step   real-time factor %7.1fx  (%zu "
        "odometry messages)\n",
        1e6 * wall / (sim_s * options.robot.physics_rate_hz), sim_s / wall, messages);
  }

  // 3. The closed loop with the full rig at 10 Hz.
  if (run("rig")) {
    render::RigOptions rig_options = render::RigOptions::Default();
    for (render::CameraOptions& c : rig_options.cameras) c.rate_hz = 10.0;
    const render::Scene scene = render::BuildScene(world, rig_options.scene);
    std::unique_ptr<render::Backend> backend = render::CreateBackend(rig_options.backend);
    backend->Upload(scene);
    render::Rig rig(rig_options, scene, *backend);
    const double rig_s = sim_s / 4;  // rendering dominates: a shorter run gives the same rate
    options.max_duration_ns = FromSeconds(rig_s);
    sim::Simulation simulation(world, options, sim::BuildRobotPath(world, options.robot_path), &rig,
                               &rig_options);
    const auto t0 = Clock::now();
    std::size_t frames = 0;
    while (!simulation.finished()) frames += simulation.Step().frames.size();
    const double wall = Seconds(t0, Clock::now());
    std::printf(
        "  closed loop, full rig 10 Hz: %zu frames, real-time factor %6.2fx, %.1f ms "
        "per rig frame (physics and everything else included)\n",
        frames, rig_s / wall, 1e3 * wall / (static_cast<double>(frames) / 3.0));
  }
  return 0;
}
