#pragma once
// `corridorsim drive`: the scenario's robot drives its path closed loop (physics, path follower,
// sensor clock) and the run's trajectories, odometry and events are written; with
// `--save-frames` the cameras are rendered at their rates and every frame is written too.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace corridorsim {

struct DriveRequest {
  std::string scenario_file;
  std::optional<std::uint64_t> seed;  // overrides the scenario's seed
  std::filesystem::path out_dir = "out/drive";
  bool save_frames = false;
};

/// Runs the drive; prints progress and a summary. Throws InputError for bad input.
void RunDrive(const DriveRequest& request);

}  // namespace corridorsim
