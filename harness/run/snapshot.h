#pragma once
// `corridorsim snapshot`: the robot placed at one pose, every camera of the rig rendered, and
// per camera the image, labels, an overlay of the ground truth, depth, plus the frame's ground
// truth and the intrinsics.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "harness/scenario/job.h"

namespace corridorsim {

struct SnapshotRequest : JobRequest {
  // --pose x,y,yaw (ParsePoseArgument, harness/cli/cli.h): the robot's pose in the world frame.
  double x_m = 0.0;      // m
  double y_m = 0.0;      // m
  double yaw_deg = 0.0;  // degrees, 0 = along +x
};

/// Runs the snapshot; prints a summary. Throws InputError for bad input.
void RunSnapshot(const SnapshotRequest& request);

}  // namespace corridorsim
