#pragma once
// `corridorsim snapshot`: the robot placed at one pose, every camera of the rig rendered, and
// per camera the image, labels, an overlay of the ground truth, depth, plus the frame's ground
// truth and the intrinsics.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "common/pose.h"

#include "harness/job.h"

namespace corridorsim {

struct SnapshotRequest : JobRequest {
  std::string pose_text;  // "x,y,yaw_deg" as given on the command line
};

/// Parses "x,y,yaw" (metres, metres, degrees). Throws InputError naming `--pose`.
SE2 ParsePose(const std::string& text);

/// Runs the snapshot; prints a summary. Throws InputError for bad input.
void RunSnapshot(const SnapshotRequest& request);

}  // namespace corridorsim
