#pragma once
// What `corridorsim dataset` is asked for (harness/workbench/dataset.h runs it): plain data, so
// that the command-line parser (harness/cli/cli.h) needs nothing else of the job.

#include <string>
#include <vector>

#include "common/enum_names.h"
#include "harness/scenario/job.h"

namespace corridorsim {

/// Where the robot stands in each world.
enum class DatasetPoseMode {
  kRandom,  // uniform inside the corridor segments, yaw uniform; poses that collide are redrawn
  kPath,    // evenly spaced along the scenario's path (BuildRobotPath), heading along the leg
  kPlates,  // the lateral camera aimed at door plates and printed distractors (train-detectors)
};
inline constexpr EnumName<DatasetPoseMode> kDatasetPoseModeNames[] = {
    {DatasetPoseMode::kRandom, "random"},
    {DatasetPoseMode::kPath, "path"},
    {DatasetPoseMode::kPlates, "plates"}};
inline std::string DatasetPoseModeName(DatasetPoseMode mode) {
  return NameOf(kDatasetPoseModeNames, mode);
}

/// Bounds of --worlds and --frames-per-world.
inline constexpr int kMaxDatasetWorlds = 100000;
inline constexpr int kMaxDatasetFramesPerWorld = 100000;

struct DatasetRequest : JobRequest {
  int worlds = 1;                    // --worlds
  int frames_per_world = 1;          // --frames-per-world
  std::vector<std::string> cameras;  // --cameras, as given; empty: the scenario's enabled ones
  DatasetPoseMode poses = DatasetPoseMode::kRandom;
};

}  // namespace corridorsim
