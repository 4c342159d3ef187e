#pragma once
// Shared constructed cases of the metrics tests (tests/harness/metrics/*_test.cpp): truth on the
// 100 Hz grid, pipelines whose estimates are the truth mapped by a function, a small world of
// plates and a lamp, detections and frame truth, and ComputeMetrics on one pipeline.

#include <cmath>
#include <functional>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/metrics/metrics.h"

namespace corridorsim::test {

using Json = nlohmann::ordered_json;

inline constexpr TimeNs kGridNs = 10'000'000;  // the 100 Hz truth grid

// A left-turning arc at 1 m/s: radius 20 m, sampled on the truth grid for `seconds`.
inline std::vector<TruthPose> ArcTruth(double seconds) {
  std::vector<TruthPose> truth;
  const int n = static_cast<int>(std::lround(seconds * 100));
  for (int k = 0; k <= n; ++k) {
    const double s_m = 0.01 * k;
    const double yaw = s_m / 20.0;
    truth.push_back({k * kGridNs, SE2(20.0 * std::sin(yaw), 20.0 * (1.0 - std::cos(yaw)), yaw)});
  }
  return truth;
}

// Estimates at every other truth sample (50 Hz odometry), each pose mapped by `f`.
inline PipelineRecord Record(const std::string& name, const std::vector<TruthPose>& truth,
                             const std::function<SE2(const SE2&)>& f,
                             const Eigen::Matrix3d& covariance = Eigen::Matrix3d::Identity() *
                                                                 1e-2) {
  PipelineRecord record;
  record.name = name;
  for (std::size_t k = 0; k < truth.size(); k += 2) {
    record.estimates.push_back({truth[k].stamp_ns, f(truth[k].world_from_robot), covariance});
  }
  return record;
}

// A pipeline whose estimates are the truth (Record without error) and that used `cameras`.
inline PipelineRecord ExactRecord(const std::string& name, const std::vector<TruthPose>& truth,
                                  const std::vector<std::string>& cameras = {}) {
  PipelineRecord record = Record(name, truth, [](const SE2& p) { return p; });
  record.cameras_used = cameras;
  return record;
}

inline Json RunOne(const worlds::World& world, const std::vector<TruthPose>& truth,
                   const PipelineRecord& record, std::vector<FrameTruthSample> frames = {}) {
  MetricsInput input;
  input.world = &world;
  input.truth = truth;
  input.frames = std::move(frames);
  input.pipelines = {record};
  return ComputeMetrics(input)["pipelines"][record.name];
}

inline double Num(const Json& j) { return j.get<double>(); }

/// The whole-number fields of one metrics group (`m["detection"]["door_plate"]`, ...), each
/// checked, a failure naming its key.
inline void CheckCounts(const Json& group,
                        std::initializer_list<std::pair<const char*, int>> counts) {
  for (const auto& [key, expected] : counts) {
    INFO(key);
    CHECK(group.at(key) == expected);
  }
}

inline worlds::World PlateWorld() {
  worlds::World world;
  world.plates.resize(3);
  const std::vector<Eigen::Vector3d> centres = {{1, 1, 1.5}, {4, 1, 1.5}, {8, -1, 1.5}};
  for (int i = 0; i < 3; ++i) {
    world.plates[i].id = i + 1;
    world.plates[i].center = centres[i];
    world.plates[i].room_number = std::to_string(101 + i);
  }
  worlds::Lamp lamp;
  lamp.id = 4;
  lamp.center = Eigen::Vector3d(2, 0, 2.5);
  world.lamps.push_back(lamp);
  return world;
}

inline slam::LandmarkEstimate Landmark(int id, slam::LandmarkType type, const Eigen::Vector3d& p,
                                       const std::string& label = "") {
  slam::LandmarkEstimate l;
  l.id = id;
  l.type = type;
  l.position_in_world = p;
  l.label = label;
  return l;
}

/// A plate seen legibly (whole, 40 px high, head-on) centred at `center_px`.
inline render::PlateTruth PlateSeen(int id, const Eigen::Vector2d& center_px) {
  render::PlateTruth p;
  p.id = id;
  p.center_px = center_px;
  p.bbox_min_px = center_px - Eigen::Vector2d(40, 20);
  p.bbox_max_px = center_px + Eigen::Vector2d(40, 20);
  p.fully_in_image = true;
  p.visible_fraction = 1.0;
  return p;
}

/// A detection of a `type` landmark by `camera` at `stamp`, at `pixel`.
inline slam::Detection DetectionAt(TimeNs stamp, const std::string& camera, slam::LandmarkType type,
                                   const Eigen::Vector2d& pixel) {
  slam::Detection d;
  d.stamp_ns = stamp;
  d.camera_id = camera;
  d.type = type;
  d.pixel = pixel;
  return d;
}

inline FrameTruthSample Frame(const std::string& camera, TimeNs stamp) {
  FrameTruthSample f;
  f.stamp_ns = stamp;
  f.truth.camera_id = camera;
  return f;
}

}  // namespace corridorsim::test

// The metrics tests (tests/harness/metrics/*_test.cpp) live in this namespace: the helpers above
// and the types they use, named once here.
namespace corridorsim::metrics_tests {
using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector4d;
using slam::LandmarkType;
using test::ArcTruth;
using test::CheckCounts;
using test::DetectionAt;
using test::ExactRecord;
using test::Frame;
using test::Json;
using test::kGridNs;
using test::Landmark;
using test::Num;
using test::PlateSeen;
using test::PlateWorld;
using test::Record;
using test::RunOne;
}  // namespace corridorsim::metrics_tests
