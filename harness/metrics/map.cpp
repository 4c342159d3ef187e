#include "harness/metrics/map.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "harness/metrics/detection.h"
#include "harness/metrics/stats.h"

namespace corridorsim::metrics {

using slam::LandmarkType;

namespace {

// The seen point of each corner landmark: the point its creating detection's pixel showed.
std::map<int, const SeenPoint*> SeenPointsOfLandmarks(const PipelineRecord& pipeline) {
  std::map<int, const SeenPoint*> out;
  for (const auto& [index, seen] : pipeline.seen_points) {
    const slam::Detection& d = pipeline.detections[index];
    if (d.new_landmark && d.landmark_id >= 0) out.emplace(d.landmark_id, &seen);
  }
  return out;
}

// Corner landmarks made from detections in frames with exact depth (P1 Harris, P2/P3 upward):
// each is scored against the world point seen at its creating detection's pixel, exact from the
// rendered depth, not against the nearest tile crossing (every estimate in a tiled ceiling has one
// within 1 m).
void SeenPointMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                         const std::map<int, const SeenPoint*>& seen, const MetricWriter& m) {
  Stats error;
  Stats z_error;
  std::size_t estimated = 0;
  std::size_t matched = 0;
  for (const slam::LandmarkEstimate& l : pipeline.landmarks) {
    if (l.type != LandmarkType::kCorner) continue;
    ++estimated;
    const auto it = seen.find(l.id);
    if (it == seen.end()) continue;
    const Eigen::Vector3d& truth = it->second->p_in_world;
    const double d = (l.position_in_world.head<2>() - truth.head<2>()).norm();
    if (d > context.options->landmark_gate_m) continue;
    ++matched;
    error.Add(d);
    z_error.Add(std::abs(l.position_in_world.z() - truth.z()));
  }
  m.Count("estimated", estimated);
  m.Count("matched", matched);
  m.Count("spurious", estimated - matched);
  m.Null("observed");  // the seen points are what was observed; nothing else can be missed
  m.Null("missed");
  m.Set("mean_error_m", error.mean());
  m.Set("rmse_m", error.rms());
  m.Set("max_error_m", error.maximum());
  m.Set("z_rmse_m", z_error.rms());
}

// Doors as P3 states them (eq. 11): two column positions, matched one-to-one to the doorways
// (greedy by the larger column error, either order, within door_column_gate_m). Beyond the
// common map.<type> figures: which doorways the registered doors are (open, closed, none: a
// cabinet, a bookshelf, a wall) and how many open doorways that were seen got registered.
MapMatch DoorMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                        const MetricWriter& m) {
  const std::vector<worlds::Doorway>& doors = context.world->doors;
  std::vector<const slam::LandmarkEstimate*> estimates;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> columns;
  for (const slam::LandmarkEstimate& l : pipeline.landmarks) {
    if (l.type != LandmarkType::kDoor) continue;
    Eigen::Vector2d a = l.position_in_world.head<2>(), b = a;
    for (const slam::LandmarkPoint& p : l.points) {
      if (p.role == "column_a") a = p.position_in_world.head<2>();
      if (p.role == "column_b") b = p.position_in_world.head<2>();
    }
    estimates.push_back(&l);
    columns.emplace_back(a, b);
  }
  const auto error = [&](std::size_t e, const worlds::Doorway& d) {
    const auto& [a, b] = columns[e];
    return std::min(std::max((a - d.column_a).norm(), (b - d.column_b).norm()),
                    std::max((a - d.column_b).norm(), (b - d.column_a).norm()));
  };
  const double gate = context.options->door_column_gate_m;
  std::vector<Candidate> candidates;
  for (std::size_t e = 0; e < estimates.size(); ++e) {
    for (std::size_t t = 0; t < doors.size(); ++t) {
      const double d = error(e, doors[t]);
      if (d <= gate) candidates.push_back({d, e, t});
    }
  }
  const auto matches = GreedyMatch(std::move(candidates), estimates.size(), doors.size());
  MapMatch result;
  Stats column_error;
  Stats open_column_error;
  std::set<std::size_t> matched_estimates;
  std::set<int> matched_open;
  std::size_t open_registered = 0, closed_registered = 0;
  for (const auto& [e, t] : matches) {
    result.truth_of_estimate[estimates[e]->id] = doors[t].id;
    matched_estimates.insert(e);
    const auto& [a, b] = columns[e];
    const bool straight =
        std::max((a - doors[t].column_a).norm(), (b - doors[t].column_b).norm()) <=
        std::max((a - doors[t].column_b).norm(), (b - doors[t].column_a).norm());
    for (const auto& [est, truth] :
         {std::pair(a, straight ? doors[t].column_a : doors[t].column_b),
          std::pair(b, straight ? doors[t].column_b : doors[t].column_a)}) {
      column_error.Add((est - truth).norm());
      if (doors[t].state != worlds::DoorState::kClosed) open_column_error.Add((est - truth).norm());
    }
    if (doors[t].state == worlds::DoorState::kClosed) {
      ++closed_registered;
    } else {
      ++open_registered;
      matched_open.insert(doors[t].id);
    }
  }
  std::size_t duplicates = 0, non_door = 0;
  for (std::size_t e = 0; e < estimates.size(); ++e) {
    if (matched_estimates.count(e) != 0) continue;
    const bool near_a_doorway =
        std::any_of(doors.begin(), doors.end(), [&](const auto& d) { return error(e, d) <= gate; });
    ++(near_a_doorway ? duplicates : non_door);
  }
  m.Count("estimated", estimates.size());
  m.Count("matched", matches.size());
  m.Count("spurious", estimates.size() - matches.size());
  std::set<int> observed, open_seen;
  for (const auto& [key, frame] : context.frames) {
    for (const render::DoorTruth& t : frame->doors) {
      if (!t.visible) continue;
      observed.insert(t.id);
      if (t.state != worlds::DoorState::kClosed) open_seen.insert(t.id);
    }
  }
  if (context.frames.empty()) {
    m.Null("observed");
    m.Null("missed");
  } else {
    std::size_t missed = 0;
    for (const int id : observed) {
      missed += std::none_of(result.truth_of_estimate.begin(), result.truth_of_estimate.end(),
                             [id](const auto& kv) { return kv.second == id; });
    }
    m.Count("observed", observed.size());
    m.Count("missed", missed);
  }
  m.Set("mean_error_m", column_error.mean());
  m.Set("rmse_m", column_error.rms());
  m.Set("max_error_m", column_error.maximum());
  m.Count("open_registered", open_registered);
  m.Count("closed_registered", closed_registered);
  m.Count("non_door_registered", non_door);
  m.Count("duplicates", duplicates);
  m.Count("open_seen", open_seen.size());
  std::size_t open_found = 0;
  for (const int id : open_seen) open_found += matched_open.count(id);
  m.Count("open_found", open_found);
  m.Fraction("open_precision", open_registered, estimates.size());
  m.Fraction("open_recall", open_found, open_seen.size());
  m.Set("open_column_rmse_m", open_column_error.rms());
  return result;
}

}  // namespace

MapMatch AddMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                       LandmarkType type, const MetricWriter& out) {
  if (type == LandmarkType::kCorner) {
    const std::map<int, const SeenPoint*> seen = SeenPointsOfLandmarks(pipeline);
    if (!seen.empty()) {
      SeenPointMapMetrics(pipeline, context, seen, out.Sub("map").Sub("corner"));
      return {};
    }
  }
  if (type == LandmarkType::kDoor) {
    return DoorMapMetrics(pipeline, context, out.Sub("map").Sub("door"));
  }
  const std::vector<TruthLandmark> truth = TruthLandmarks(*context.world, type);
  std::vector<const slam::LandmarkEstimate*> estimates;
  for (const slam::LandmarkEstimate& l : pipeline.landmarks) {
    if (l.type == type) estimates.push_back(&l);
  }
  // Horizontal distance: P1's plates and P2/P3's doors are planar states.
  std::vector<Candidate> candidates;
  for (std::size_t a = 0; a < estimates.size(); ++a) {
    for (std::size_t b = 0; b < truth.size(); ++b) {
      const double d =
          (estimates[a]->position_in_world.head<2>() - truth[b].position_in_world.head<2>()).norm();
      if (d <= context.options->landmark_gate_m) candidates.push_back({d, a, b});
    }
  }
  const auto matches = GreedyMatch(std::move(candidates), estimates.size(), truth.size());

  MapMatch result;
  Stats error;
  Stats z_error;
  std::size_t labels_agree = 0;
  std::set<int> matched_truth;
  for (const auto& [a, b] : matches) {
    result.truth_of_estimate[estimates[a]->id] = truth[b].id;
    matched_truth.insert(truth[b].id);
    error.Add(
        (estimates[a]->position_in_world.head<2>() - truth[b].position_in_world.head<2>()).norm());
    z_error.Add(std::abs(estimates[a]->position_in_world.z() - truth[b].position_in_world.z()));
    if (estimates[a]->label == truth[b].label) ++labels_agree;
  }

  const MetricWriter m = out.Sub("map").Sub(slam::LandmarkTypeName(type));
  m.Count("estimated", estimates.size());
  m.Count("matched", matches.size());
  m.Count("spurious", estimates.size() - matches.size());
  // Observed: ground truth that appears in a frame the pipeline processed; only these can be
  // missed (the rest of the world was never in view).
  if (context.frames.empty()) {
    m.Null("observed");
    m.Null("missed");
  } else {
    std::set<int> observed;
    for (const auto& [key, frame] : context.frames) {
      if (type == LandmarkType::kDoorPlate) {
        // A plate is observed where it was legible (a dot 20 m ahead is not).
        for (const render::PlateTruth& t : frame->plates) {
          if (PlateLegible(t, *context.options)) observed.insert(t.id);
        }
        continue;
      }
      for (const TruthPixel& t : FrameTruthPixels(*frame, type)) observed.insert(t.id);
    }
    std::size_t missed = 0;
    for (const int id : observed) missed += matched_truth.count(id) == 0 ? 1 : 0;
    m.Count("observed", observed.size());
    m.Count("missed", missed);
  }
  m.Set("mean_error_m", error.mean());
  m.Set("rmse_m", error.rms());
  m.Set("max_error_m", error.maximum());
  if (type == LandmarkType::kCorner || type == LandmarkType::kLamp) {
    m.Set("z_rmse_m", z_error.rms());
  }
  if (type == LandmarkType::kDoorPlate) {
    m.Fraction("room_number_accuracy", labels_agree, matches.size());
  }
  return result;
}

void AddAreaMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                    const std::map<LandmarkType, MapMatch>& matches, const MetricWriter& out) {
  const worlds::World& world = *context.world;
  // The doorway a point's true position is in the room of (-1: none, the corridor).
  const auto doorway_of = [&](const Eigen::Vector3d& p) {
    for (const worlds::Doorway& d : world.doors) {
      if (d.room && d.room->footprint.contains(p.head<2>())) return d.id;
    }
    return -1;
  };
  const auto truth_of = [&](LandmarkType type, int estimate_id) -> int {
    const auto m = matches.find(type);
    if (m == matches.end()) return -1;
    const auto it = m->second.truth_of_estimate.find(estimate_id);
    return it == m->second.truth_of_estimate.end() ? -1 : it->second;
  };
  // The room area of each doorway (through the door landmark's match), and each landmark's area.
  std::map<int, int> area_of_doorway;
  std::map<int, int> area_of_landmark;
  std::size_t rooms = 0, rooms_open = 0;
  for (const slam::MapArea& area : pipeline.areas) {
    for (const int id : area.landmark_ids) area_of_landmark[id] = area.id;
    if (area.kind != slam::AreaKind::kRoom) continue;
    ++rooms;
    const int doorway = truth_of(LandmarkType::kDoor, area.door_landmark_id);
    if (doorway < 0) continue;
    const auto d = std::find_if(world.doors.begin(), world.doors.end(),
                                [&](const worlds::Doorway& w) { return w.id == doorway; });
    if (d != world.doors.end() && d->state != worlds::DoorState::kClosed) ++rooms_open;
    area_of_doorway.emplace(doorway, area.id);
  }
  // The truth of each scored point landmark: corners their seen point, lamps their match.
  std::map<int, Eigen::Vector3d> lamp_truth;
  for (const TruthLandmark& t : TruthLandmarks(world, LandmarkType::kLamp)) {
    lamp_truth.emplace(t.id, t.position_in_world);
  }
  const std::map<int, const SeenPoint*> seen = SeenPointsOfLandmarks(pipeline);
  std::size_t scored = 0, unregistered = 0, correct = 0, in_rooms = 0, in_rooms_found = 0;
  for (const slam::LandmarkEstimate& l : pipeline.landmarks) {
    std::optional<Eigen::Vector3d> truth;
    if (l.type == LandmarkType::kCorner) {
      if (const auto it = seen.find(l.id); it != seen.end()) truth = it->second->p_in_world;
    } else if (l.type == LandmarkType::kLamp) {
      if (const auto it = lamp_truth.find(truth_of(LandmarkType::kLamp, l.id));
          it != lamp_truth.end()) {
        truth = it->second;
      }
    }
    const auto assigned = area_of_landmark.find(l.id);
    if (!truth || assigned == area_of_landmark.end()) continue;
    ++scored;
    const int doorway = doorway_of(*truth);
    int expected = 0;  // the corridor
    if (doorway >= 0) {
      const auto room = area_of_doorway.find(doorway);
      if (room == area_of_doorway.end()) {
        ++unregistered;
        continue;
      }
      expected = room->second;
      ++in_rooms;
      in_rooms_found += assigned->second == expected;
    }
    correct += assigned->second == expected;
  }
  const MetricWriter m = out.Sub("map").Sub("area");
  m.Count("rooms", rooms);
  m.Count("rooms_behind_open_doors", rooms_open);
  m.Count("landmarks_scored", scored);
  m.Count("in_unregistered_room", unregistered);
  m.Count("assigned_correctly", correct);
  m.Fraction("assignment_accuracy", correct, scored - unregistered);
  m.Count("room_landmarks", in_rooms);
  m.Count("room_landmarks_found", in_rooms_found);
}

}  // namespace corridorsim::metrics
