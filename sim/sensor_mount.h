#pragma once
// Where a sensor that is not a camera (an IMU, a laser scanner) sits on the robot: the same
// render::Mount as a camera's, read as the sensor's body axes (render::Mount::RobotFromBody: x
// at heading yaw_deg and elevation pitch_deg, y to its left, z up at zero roll; REP 103).

#include "common/options_table.h"
#include "render/camera_options.h"

namespace corridorsim::sim {

/// The keys of such a sensor's `mount:` section (x_m, y_m, z_m, yaw_deg, pitch_deg, roll_deg),
/// documented for body axes (sim/sim_options.cpp).
const OptionTable<render::Mount>& BodyMountOptionsTable();

}  // namespace corridorsim::sim
