#include "harness/metrics/matching.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include "common/pose.h"

namespace corridorsim::metrics {

using Eigen::Vector2d;
using Eigen::Vector3d;
using slam::LandmarkType;

PipelineContext MakeContext(const MetricsInput& input, const PipelineRecord& pipeline) {
  PipelineContext context;
  context.world = input.world;
  context.options = &input.options;
  const std::set<std::string> cameras(pipeline.cameras_used.begin(), pipeline.cameras_used.end());
  for (const FrameTruthSample& f : input.frames) {
    if (cameras.count(f.truth.camera_id) != 0) {
      context.frames[{f.truth.camera_id, f.stamp_ns}] = &f.truth;
    }
  }
  return context;
}

bool HasDetections(const PipelineRecord& pipeline, LandmarkType type) {
  return std::any_of(pipeline.detections.begin(), pipeline.detections.end(),
                     [type](const slam::Detection& d) { return d.Is(type); });
}

bool HasType(const PipelineRecord& pipeline, LandmarkType type) {
  return std::any_of(pipeline.landmarks.begin(), pipeline.landmarks.end(),
                     [type](const slam::LandmarkEstimate& l) { return l.type == type; }) ||
         HasDetections(pipeline, type);
}

std::vector<std::pair<std::size_t, std::size_t>> GreedyMatch(std::vector<Candidate> candidates,
                                                             std::size_t a_count,
                                                             std::size_t b_count) {
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.cost, x.a, x.b) < std::tie(y.cost, y.a, y.b);
  });
  std::vector<bool> a_used(a_count, false);
  std::vector<bool> b_used(b_count, false);
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (const Candidate& c : candidates) {
    if (a_used[c.a] || b_used[c.b]) continue;
    a_used[c.a] = true;
    b_used[c.b] = true;
    matches.emplace_back(c.a, c.b);
  }
  return matches;
}

std::vector<TruthLandmark> TruthLandmarks(const worlds::World& world, LandmarkType type) {
  std::vector<TruthLandmark> out;
  switch (type) {
    case LandmarkType::kDoorPlate:
      for (const worlds::DoorPlate& p : world.plates)
        out.push_back({p.id, p.center, p.room_number});
      break;
    case LandmarkType::kCorner:
      for (const worlds::CornerPoint& c : world.corner_points)
        out.push_back({c.id, c.position, ""});
      break;
    case LandmarkType::kLamp:
      for (const worlds::Lamp& l : world.lamps) out.push_back({l.id, l.center, ""});
      for (const worlds::Reflector& r : world.reflectors) {
        out.push_back({r.id, r.apparent_lamp_center, ""});
      }
      break;
    case LandmarkType::kDoor:
      for (const worlds::Doorway& d : world.doors) {
        const Vector2d mid = 0.5 * (d.column_a + d.column_b);
        out.push_back({d.id, Vector3d(mid.x(), mid.y(), d.top_height_m), ""});
      }
      break;
    case LandmarkType::kVanishingPoint:
      break;
  }
  return out;
}

std::vector<TruthPixel> FrameTruthPixels(const render::FrameTruth& truth, LandmarkType type) {
  std::vector<TruthPixel> out;
  switch (type) {
    case LandmarkType::kDoorPlate:
      for (const render::PlateTruth& p : truth.plates) out.push_back({p.id, p.center_px});
      break;
    case LandmarkType::kCorner:
      for (const render::CornerTruth& c : truth.corners) out.push_back({c.id, c.pixel});
      break;
    case LandmarkType::kLamp:
      for (const render::LampTruth& l : truth.lamps) out.push_back({l.id, l.center_px});
      break;
    case LandmarkType::kDoor:
      for (const render::DoorTruth& d : truth.doors) {
        if (d.visible) out.push_back({d.id, 0.5 * (d.column_a_px + d.column_b_px)});
      }
      break;
    case LandmarkType::kVanishingPoint:
      break;
  }
  return out;
}

Vector2d DetectionPixel(const slam::Detection& d) {
  if (d.type == LandmarkType::kDoor) return 0.5 * (d.box_px.head<2>() + d.box_px.tail<2>());
  return d.pixel;
}

std::optional<double> DoorBearingError(const slam::Detection& d, const render::DoorTruth& t) {
  if (!d.column_bearings_rad.allFinite()) return std::nullopt;
  const auto error = [](double a, double b) { return std::abs(NormalizeAngle(a - b)); };
  const Vector2d& b = d.column_bearings_rad;
  const double straight = std::max(error(b(0), t.bearing_a_rad), error(b(1), t.bearing_b_rad));
  const double crossed = std::max(error(b(0), t.bearing_b_rad), error(b(1), t.bearing_a_rad));
  return std::min(straight, crossed);
}

std::optional<int> DoorIdentity(const slam::Detection& d, const render::FrameTruth& frame,
                                double gate_rad, double gate_px) {
  std::optional<int> identity;
  const bool by_bearing = d.column_bearings_rad.allFinite();
  double best = by_bearing ? gate_rad : gate_px;
  for (const render::DoorTruth& t : frame.doors) {
    if (!t.visible) continue;
    const double e = by_bearing
                         ? *DoorBearingError(d, t)
                         : (0.5 * (t.column_a_px + t.column_b_px) - DetectionPixel(d)).norm();
    if (e <= best) {
      best = e;
      identity = t.id;
    }
  }
  return identity;
}

}  // namespace corridorsim::metrics
