#pragma once
// `corridorsim drive`: the scenario's robot drives its path closed loop (physics, path follower,
// sensor clock) and the run's trajectories, odometry and events are written; with
// `--save-frames` the cameras are rendered at their rates and every frame is written too.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "harness/scenario/job.h"

namespace corridorsim {

struct DriveRequest : JobRequest {
  bool save_frames = false;
};

/// Runs the drive; prints progress and a summary. Throws InputError for bad input.
void RunDrive(const DriveRequest& request);

}  // namespace corridorsim
