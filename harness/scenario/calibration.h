#pragma once
// What the robot knows about itself, from a scenario: the calibration a real robot's file would
// hold (slam::Calibration). Nominal values only, never the simulator's real ones: the wheel
// geometry the encoders convert with (the real wheels follow robot.odometry's E_d and E_b), the
// encoders' resolution, and each enabled camera's model, mount and depth range.

#include "harness/scenario/scenario.h"
#include "slam/pipeline.h"

namespace corridorsim {

/// The calibration of `scenario`'s robot: wheelbase_m and wheel_diameter_m from `robot`,
/// ticks_per_revolution from `robot.odometry`, and per enabled camera (in the rig's order) its
/// model, Mount::RobotFromCamera() and, for depth cameras, the depth noise options' valid range
/// [min_m, max_m].
slam::Calibration CalibrationOf(const Scenario& scenario);

/// The enabled cameras' calibration (CalibrationOf's `cameras`) of a run folder's scenario.yaml,
/// the resolved echo `run` wrote, read without loading the scenario: only its `sensors:` section
/// is read (onto the defaults, checked as LoadScenario checks it); no `include:` is followed, no
/// `plugins:` library is loaded and no pipeline is read, so reading a run folder never runs code
/// from it. Throws InputError at file:line:column: key.
std::vector<slam::CameraCalibration> CamerasOfRunScenario(const std::string& path);

}  // namespace corridorsim
