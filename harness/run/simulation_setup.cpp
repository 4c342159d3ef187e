#include "harness/run/simulation_setup.h"

#include <algorithm>

#include "common/error.h"
#include "harness/run/frame_io.h"
#include "harness/run/run_io.h"
#include "sim/placement.h"

namespace corridorsim {

Renderer::Renderer(const worlds::World& world, const render::RigOptions& rig_options,
                   render::BackendKind backend_kind)
    : scene(render::BuildScene(world, rig_options.scene)),
      backend(render::CreateBackend(backend_kind)) {
  backend->Upload(scene);
  // The cameras as the world's appearance randomisation drew them (the rig itself without it).
  rig = std::make_unique<render::Rig>(render::WithAppearance(rig_options, world.appearance), scene,
                                      *backend);
}

std::optional<sim::PlacementProblem> CheckPosePlacement(const worlds::World& world,
                                                        const Scenario& scenario,
                                                        const render::RigOptions& rig,
                                                        const SE2& pose) {
  sim::RobotPath at_pose;
  at_pose.kind = sim::PathKind::kScript;
  at_pose.world_from_start = pose;
  return sim::CheckPathPlacement(world, scenario.robot, at_pose, &rig);
}

SimulationSetup::SimulationSetup(const Scenario& scenario, std::uint64_t seed,
                                 bool check_camera_placement)
    : scenario_(scenario),
      seed_(seed),
      backend_kind_(ChooseBackend(scenario.rig.backend)),  // a bad override fails before the world
      world_(GenerateWorld(scenario, seed)) {
  robot_path_.emplace(BuildScenarioRobotPath(scenario, world_));
  // Physical sanity along the whole path: the body and the scanners always, the cameras when
  // they are checked.
  if (auto problem = sim::CheckPathPlacement(world_, scenario.robot, *robot_path_,
                                             check_camera_placement ? &scenario.rig : nullptr,
                                             scenario.lasers)) {
    throw LocateProblem(scenario, problem->section, problem->problem);
  }
}

SimulationSetup::~SimulationSetup() = default;

const sim::RobotPath& SimulationSetup::robot_path() const {
  return simulation_ ? simulation_->path() : *robot_path_;
}

void SimulationSetup::Start(const std::set<std::string>& render_cameras) {
  CheckOrDie(!simulation_, "SimulationSetup::Start", "called twice");
  // Render only what somebody reads.
  rig_options_ = scenario_.rig;
  for (render::CameraOptions& c : rig_options_.cameras) {
    c.enabled = c.enabled && render_cameras.count(c.id) > 0;
  }
  const bool render_any = std::any_of(rig_options_.cameras.begin(), rig_options_.cameras.end(),
                                      [](const render::CameraOptions& c) { return c.enabled; });
  if (render_any) {
    renderer_.emplace(world_, rig_options_, backend_kind_);
    for (const render::CameraRenderer& c : renderer_->rig->cameras()) {
      camera_ids_.push_back(c.options().id);
    }
  }
  sim::SimulationOptions options;
  options.robot = scenario_.robot;
  options.robot_path = scenario_.robot_path;
  options.seed = seed_;
  options.imus = scenario_.imus;
  options.lasers = scenario_.lasers;
  options.max_duration_ns = FromSeconds(scenario_.duration_s);
  options.truth_rate_hz = kTruthFileRateHz;
  simulation_ =
      std::make_unique<sim::Simulation>(world_, options, std::move(*robot_path_),
                                        renderer_ ? renderer_->rig.get() : nullptr, &rig_options_);
  robot_path_.reset();
}

}  // namespace corridorsim
