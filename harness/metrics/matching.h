#pragma once
// What one pipeline is measured against (the world and the frame truth of the cameras it used)
// and the matching steps the map, association and detector metrics share.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "harness/metrics/input.h"

namespace corridorsim::metrics {

using FrameKey = std::pair<std::string, TimeNs>;  // camera id, stamp

struct PipelineContext {
  const worlds::World* world = nullptr;
  const MetricsOptions* options = nullptr;
  std::map<FrameKey, const render::FrameTruth*> frames;  // of the cameras the pipeline used
};

/// The context of `pipeline` within `input`.
PipelineContext MakeContext(const MetricsInput& input, const PipelineRecord& pipeline);

/// The pipeline mapped or detected `type` / detected it.
bool HasType(const PipelineRecord& pipeline, slam::LandmarkType type);
bool HasDetections(const PipelineRecord& pipeline, slam::LandmarkType type);

/// One-to-one greedy matching: candidates in ascending cost (ties by indices), each side used once.
struct Candidate {
  double cost = 0.0;
  std::size_t a = 0;
  std::size_t b = 0;
};
std::vector<std::pair<std::size_t, std::size_t>> GreedyMatch(std::vector<Candidate> candidates,
                                                             std::size_t a_count,
                                                             std::size_t b_count);

/// A ground-truth landmark in the world frame.
struct TruthLandmark {
  int id = 0;
  Eigen::Vector3d position_in_world;
  std::string label;  // door plates: room number
};
/// Door: the midpoint of its two columns on the wall face, at the underside of the top bar.
/// Lamps: lit or not, plus the apparent (mirrored) lamp of each reflector (P3 treats it as a lamp).
std::vector<TruthLandmark> TruthLandmarks(const worlds::World& world, slam::LandmarkType type);

/// Truth of one frame of `type`: id and the pixel a detection of it is compared with.
struct TruthPixel {
  int id = 0;
  Eigen::Vector2d pixel;
};
std::vector<TruthPixel> FrameTruthPixels(const render::FrameTruth& truth, slam::LandmarkType type);

/// Where a detection is in its image: doors by the centre of their box, the rest by their pixel.
Eigen::Vector2d DetectionPixel(const slam::Detection& detection);

/// The larger bearing error of a door detection's two columns against a truth door's (P3 eq.
/// 17), the columns taken in the order that fits better; nullopt when the detection has no
/// bearings.
std::optional<double> DoorBearingError(const slam::Detection& detection,
                                       const render::DoorTruth& truth);

/// The visible truth door of the frame a door detection shows: the nearest by DoorBearingError
/// within `gate_rad`, or (a detection without bearings) the nearest column midpoint within
/// `gate_px`.
std::optional<int> DoorIdentity(const slam::Detection& detection, const render::FrameTruth& frame,
                                double gate_rad, double gate_px);

}  // namespace corridorsim::metrics
