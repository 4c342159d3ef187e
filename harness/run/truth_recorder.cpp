#include "harness/run/truth_recorder.h"

#include <algorithm>
#include <sstream>
#include <utility>

#include "common/error.h"
#include "common/io/stable_json.h"
#include "harness/run/run_io.h"

namespace corridorsim {

TruthRecorder::TruthRecorder(std::set<std::string> frame_cameras)
    : frame_cameras_(std::move(frame_cameras)) {}

void TruthRecorder::Record(const sim::TruthSample& truth) {
  CheckOrDie(poses_.empty() || truth.stamp_ns > poses_.back().stamp_ns, "TruthRecorder",
             "truth out of stamp order");
  poses_.push_back({truth.stamp_ns, truth.world_from_robot_2d});
  poses_3d_.push_back(truth.state.world_from_robot);
}

void TruthRecorder::OnStart(const sim::TruthSample& truth) { Record(truth); }

void TruthRecorder::OnTruth(const sim::TruthSample& truth) { Record(truth); }

void TruthRecorder::OnCameraSet(const CameraSet& set) {
  for (const CameraSlot& slot : set.cameras) {
    if (slot.message && frame_cameras_.count(slot.camera_id)) {
      frames_.push_back({slot.message->stamp_ns, slot.message->truth});
    }
  }
}

const TruthPose* TruthRecorder::At(TimeNs stamp) const {
  auto it = std::upper_bound(poses_.begin(), poses_.end(), stamp,
                             [](TimeNs t, const TruthPose& p) { return t < p.stamp_ns; });
  return it == poses_.begin() ? nullptr : &*(it - 1);
}

std::string TruthRecorder::PlanarTum() const {
  std::ostringstream tum;
  tum << "# ground truth: planar world_from_robot (x, y, yaw; z = 0, no roll or pitch) at "
         "100 Hz and every odometry stamp\n# timestamp tx ty tz qx qy qz qw\n";
  for (const TruthPose& p : poses_) {
    tum << sim::TumLine(p.stamp_ns, SE3::FromSE2(p.world_from_robot)) << "\n";
  }
  return tum.str();
}

std::string TruthRecorder::FullPoseTum() const {
  std::ostringstream tum;
  tum << "# ground truth: world_from_robot in 3D (robot frame R: floor, between the wheels) at "
         "100 Hz and every odometry stamp\n# timestamp tx ty tz qx qy qz qw\n";
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    tum << sim::TumLine(poses_[i].stamp_ns, poses_3d_[i]) << "\n";
  }
  return tum.str();
}

void EventLog::OnEvent(const sim::Event& event) {
  events_.push_back(EventJson(event));
  kinds_.push_back(event.kind);
}

void EventLog::AddPipelineFailure(TimeNs stamp_ns, const std::string& pipeline,
                                  const std::string& call, const std::string& what) {
  nlohmann::ordered_json j;
  j["t"] = RoundToStep(ToSeconds(stamp_ns), json_steps::kSeconds);
  j["t_ns"] = stamp_ns;
  j["type"] = "pipeline_failed";
  j["pipeline"] = pipeline;
  j["call"] = call;
  j["reason"] = what;
  failures_.emplace_back(stamp_ns, std::move(j));
}

int EventLog::count(sim::EventKind kind) const {
  return static_cast<int>(std::count(kinds_.begin(), kinds_.end(), kind));
}

std::string EventLog::Json(std::uint64_t seed, TimeNs duration_ns) const {
  nlohmann::ordered_json j;
  j["seed"] = seed;
  j["duration_s"] = RoundToStep(ToSeconds(duration_ns), json_steps::kSeconds);
  if (failures_.empty()) {
    j["events"] = events_;
    return JsonFileText(j);
  }
  // The failures among the simulation's events by stamp: stable, so equal stamps keep the
  // simulation's events first and the failures in the order they were added (scenario order).
  std::vector<std::pair<TimeNs, nlohmann::ordered_json>> failures = failures_;
  std::stable_sort(failures.begin(), failures.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  nlohmann::ordered_json merged = nlohmann::ordered_json::array();
  std::size_t f = 0;
  for (const nlohmann::ordered_json& e : events_) {
    const TimeNs t = e.value("t_ns", TimeNs{0});
    while (f < failures.size() && failures[f].first < t) merged.push_back(failures[f++].second);
    merged.push_back(e);
  }
  while (f < failures.size()) merged.push_back(failures[f++].second);
  j["events"] = std::move(merged);
  return JsonFileText(j);
}

}  // namespace corridorsim
