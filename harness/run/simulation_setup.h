#pragma once
// The build step of every job that simulates (docs/architecture.md, "How a run is made"):
// scenario + seed -> world, robot path, placement check along the path; then, for the cameras
// somebody reads, the render scene, GL backend and rig; then the Simulation. `drive`, `run` and
// `study` build through it and differ only in the consumers they put on the sensor bus.

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "harness/scenario/scenario.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "sim/placement.h"
#include "sim/robot_path.h"
#include "sim/simulation.h"
#include "worlds/world.h"

namespace corridorsim {

/// The render scene of a world, uploaded once to a GL backend, and the rig of the enabled
/// cameras of `rig_options` (snapshot renders through it; SimulationSetup::Start builds one).
struct Renderer {
  Renderer(const worlds::World& world, const render::RigOptions& rig_options,
           render::BackendKind backend_kind);
  render::Scene scene;
  std::unique_ptr<render::Backend> backend;
  std::unique_ptr<render::Rig> rig;
};

/// The robot standing at `pose`, checked as a path of one pose (sim::CheckPathPlacement): the
/// chassis against the world's solids and each enabled camera of `rig` inside the corridor or a
/// room. `snapshot --pose` and `dataset --poses random` place the robot through it.
std::optional<sim::PlacementProblem> CheckPosePlacement(const worlds::World& world,
                                                        const Scenario& scenario,
                                                        const render::RigOptions& rig,
                                                        const SE2& pose);

class SimulationSetup {
 public:
  /// Generates the world and the robot path of `scenario` with `seed` and sweeps the robot's
  /// chassis along the whole path against the world's solids (sim::CheckPathPlacement); with
  /// `check_camera_placement`, also every enabled camera of the scenario (inside the corridor or a
  /// room, below the ceiling, in no solid, anywhere along the path). Problems are InputErrors at
  /// the scenario line that caused them (robot.body_*, sensors.<camera>.mount, path).
  /// `scenario` must outlive the setup; the simulation keeps references to the world and rig.
  SimulationSetup(const Scenario& scenario, std::uint64_t seed, bool check_camera_placement);
  SimulationSetup(const SimulationSetup&) = delete;
  SimulationSetup& operator=(const SimulationSetup&) = delete;
  ~SimulationSetup();

  /// Builds the renderer for the enabled cameras named in `render_cameras` (none: no GL context
  /// is created) and the Simulation. Call once.
  void Start(const std::set<std::string>& render_cameras);

  std::uint64_t seed() const { return seed_; }
  const worlds::World& world() const { return world_; }
  /// The robot path (before Start; afterwards the simulation's).
  const sim::RobotPath& robot_path() const;
  sim::Simulation& simulation() { return *simulation_; }
  const sim::Simulation& simulation() const { return *simulation_; }
  /// The scenario's rig with only the rendered cameras enabled (valid after Start).
  const render::RigOptions& rig_options() const { return rig_options_; }
  /// The GL backend of the rendered cameras (valid after Start), or null when nothing renders.
  const render::Backend* backend() const { return renderer_ ? renderer_->backend.get() : nullptr; }
  /// Ids of the rendered cameras in the rig's order: CameraMessage::camera indexes them.
  const std::vector<std::string>& camera_ids() const { return camera_ids_; }

 private:
  const Scenario& scenario_;
  std::uint64_t seed_;
  render::BackendKind backend_kind_;
  worlds::World world_;
  std::optional<sim::RobotPath> robot_path_;  // until Start moves it into the simulation
  render::RigOptions rig_options_;
  std::vector<std::string> camera_ids_;
  std::optional<Renderer> renderer_;
  std::unique_ptr<sim::Simulation> simulation_;
};

}  // namespace corridorsim
