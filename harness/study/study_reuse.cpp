// Studies that reuse renders (docs/studies.md, "Replay instead of rendering"): whether a study's
// points read one sensor stream, and the queue that records each seed once and replays it for
// the seed's other points.

#include <algorithm>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "harness/external/external_pipeline.h"
#include "harness/record/replay_scenario.h"
#include "harness/scenario/calibration.h"
#include "harness/study/study_internal.h"
#include "slam/registry.h"

namespace corridorsim::study_internal {

namespace {

// A run's recording in its folder (`run --record`).
constexpr const char* kRecordingName = "recording.mcap";

std::string CameraList(const std::set<std::string>& cameras) {
  if (cameras.empty()) return "none";
  std::string list;
  for (const std::string& c : cameras) list += (list.empty() ? "" : ", ") + c;
  return list;
}

// The cameras a point's pipelines read (what its run renders and a recording of it holds), by
// creating each shipped pipeline as the run does (harness/run/pipeline_runner.cpp) and asking
// it; an external program's are its options' `cameras` (creating it would start the program).
// A plugin's pipeline is not created in the study's process (its code runs in the runs, behind
// their process boundary): its cameras are known only to be the same where its options are the
// same at every point (`first_options`, by pipeline name, the first point's). `cache`: by type
// and options (as the resolved YAML echoes them), over the points. Nothing when they cannot be
// known: `why` says why.
std::optional<std::set<std::string>> PointCameras(
    const Scenario& scenario, const YAML::Node& pipelines_yaml, std::uint64_t seed,
    std::map<std::string, std::vector<std::string>>* cache,
    std::map<std::string, std::string>* first_options, std::string* why) {
  std::set<std::string> cameras;
  std::optional<slam::Calibration> calibration;
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (!entry.enabled || !entry.options) continue;
    if (&entry.options->table() == &external::ExternalPipelineOptionsTable()) {
      const auto* options =
          static_cast<const external::ExternalPipelineOptions*>(entry.options->options());
      cameras.insert(options->cameras.begin(), options->cameras.end());
      continue;
    }
    YAML::Emitter options_text;
    options_text << pipelines_yaml[entry.name];
    const std::string key = entry.type + "\n" + options_text.c_str();
    const std::optional<slam::PipelineType> type = slam::FindPipelineType(entry.type);
    if (!type || !type->library.empty()) {
      const auto [first, added] = first_options->emplace(entry.name, key);
      if (!added && first->second != key) {
        *why = "the options of the plugin pipeline '" + entry.name +
               "' differ, so might the cameras it reads (a plugin's code runs only in the runs)";
        return std::nullopt;
      }
      continue;
    }
    auto found = cache->find(key);
    if (found == cache->end()) {
      try {
        if (!calibration) calibration = CalibrationOf(scenario);
        const std::unique_ptr<slam::Pipeline> pipeline = entry.options->Create(*calibration, seed);
        if (!pipeline) throw std::runtime_error("its factory returned no pipeline");
        found = cache->emplace(key, pipeline->cameras_used()).first;
      } catch (const std::exception& e) {
        *why = "the pipeline '" + entry.name + "' cannot be created to ask its cameras (" +
               e.what() + ")";
        return std::nullopt;
      }
    }
    cameras.insert(found->second.begin(), found->second.end());
  }
  return cameras;
}

// How a run's status file says its stream was made (RecordRun's "stream"), or "".
std::string RecordedStream(const fs::path& status) {
  try {
    return json::parse(ReadRegularFile(status, kMaxPlanBytes)).value("stream", "");
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

StreamSharing DecideStreamSharing(const StudySpec& spec,
                                  const std::vector<std::string>& point_yaml) {
  if (spec.points.size() < 2) return {false, "a single point"};
  std::map<std::string, std::vector<std::string>> cache;
  std::map<std::string, std::string> plugin_options;
  std::optional<std::set<std::string>> first_cameras;
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    const std::string& id = spec.points[i].id;
    std::string why;
    std::optional<std::set<std::string>> cameras;
    try {
      if (i > 0) {
        const std::string difference = record::FirstStreamDifference(point_yaml[0], point_yaml[i]);
        if (!difference.empty()) {
          return {false, id + "'s sensor stream differs from " + spec.points[0].id + "'s at " +
                             difference};
        }
      }
      cameras = PointCameras(spec.points[i].scenario, YAML::Load(point_yaml[i])["pipelines"],
                             spec.first_seed, &cache, &plugin_options, &why);
    } catch (const YAML::Exception& e) {
      return {false, id + "'s resolved scenario cannot be compared (" + e.what() + ")"};
    }
    if (!cameras) return {false, "at " + id + ", " + why};
    if (!first_cameras) {
      first_cameras = cameras;
    } else if (*cameras != *first_cameras) {
      return {false, id + "'s pipelines read the cameras " + CameraList(*cameras) + ", " +
                         spec.points[0].id + "'s " + CameraList(*first_cameras)};
    }
  }
  return {true, ""};
}

std::string StreamText(const RunStream& stream, const fs::path& dir) {
  switch (stream.kind) {
    case RunStream::Kind::kRecord:
      return stream.record_requested ? "recorded" : "recorded for replay";
    case RunStream::Kind::kReplay:
      return "replayed from " + stream.recording.lexically_relative(dir).generic_string();
    case RunStream::Kind::kLive:
      break;
  }
  return stream.record_requested ? "recorded" : "live";
}

RunQueue::RunQueue(const StudySpec& spec, const fs::path& dir, const std::vector<PlannedRun>& todo,
                   bool share, bool record)
    : spec_(spec), dir_(dir) {
  for (const PlannedRun& run : todo) {
    Entry entry;
    entry.run = run;
    entry.stream.record_requested = record;
    entries_.push_back(entry);
  }
  if (!share) return;
  // The runs of each seed, in plan order.
  std::map<std::uint64_t, std::vector<std::size_t>> by_seed;
  for (std::size_t i = 0; i < entries_.size(); ++i) by_seed[entries_[i].run.seed].push_back(i);
  for (const auto& [seed, indices] : by_seed) {
    Group group;
    group.seed = seed;
    // A finished run of this seed whose recording is there (a resumed study): every run left
    // replays it. It is removed after them only when a study made it for replay.
    for (const StudyPoint& point : spec.points) {
      const fs::path recording = RunFolder(dir, point.id, seed) / kRecordingName;
      std::error_code error;
      if (fs::is_regular_file(RunFolder(dir, point.id, seed) / "metrics.json", error) &&
          fs::is_regular_file(recording, error)) {
        group.recording = recording;
        group.state = Group::State::kReady;
        group.remove_after =
            !record && RecordedStream(StatusFile(dir, point.id, seed)) == "recorded for replay";
        break;
      }
    }
    if (group.state != Group::State::kReady) {
      if (indices.size() < 2) continue;  // one run: nothing to share, it runs live
      Entry& recorder = entries_[indices[0]];
      recorder.stream.kind = RunStream::Kind::kRecord;
      group.recording = RunFolder(dir, spec.points[recorder.run.point].id, seed) / kRecordingName;
      group.state = Group::State::kWaiting;
      group.remove_after = !record;
    }
    const std::size_t g = groups_.size();
    for (std::size_t i : indices) {
      Entry& entry = entries_[i];
      entry.group = g;
      if (entry.stream.kind == RunStream::Kind::kRecord) continue;
      entry.stream.kind = RunStream::Kind::kReplay;
      entry.stream.recording = group.recording;
      ++group.replays_left;
    }
    groups_.push_back(std::move(group));
  }
}

std::optional<std::pair<PlannedRun, RunStream>> RunQueue::Next() {
  // Replays first, so that a seed's recording is done with (and removed) soon; then the runs
  // that render, in plan order.
  for (const bool replays : {true, false}) {
    for (Entry& entry : entries_) {
      if (entry.started) continue;
      const bool replay = entry.stream.kind == RunStream::Kind::kReplay;
      if (replay != replays) continue;
      if (replay && groups_[entry.group].state != Group::State::kReady) continue;
      entry.started = true;
      ++started_;
      return std::make_pair(entry.run, entry.stream);
    }
  }
  return std::nullopt;
}

void RunQueue::Ended(const PlannedRun& run, bool finished) {
  const auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) {
    return e.run.point == run.point && e.run.seed == run.seed;
  });
  if (it == entries_.end() || it->group == kNoGroup) return;
  Group& group = groups_[it->group];
  std::error_code error;
  if (it->stream.kind == RunStream::Kind::kRecord) {
    if (finished && fs::is_regular_file(group.recording, error)) {
      group.state = Group::State::kReady;
      return;
    }
    // No recording to replay: the seed's other runs render as they would without replay.
    group.state = Group::State::kLive;
    std::size_t live = 0;
    for (Entry& entry : entries_) {
      if (entry.group != it->group || entry.stream.kind != RunStream::Kind::kReplay) continue;
      entry.stream.kind = RunStream::Kind::kLive;
      entry.stream.recording.clear();
      ++live;
    }
    group.replays_left = 0;
    std::printf("study: seed %llu's recording run (%s) %s: its %zu other run(s) render live\n",
                static_cast<unsigned long long>(group.seed), spec_.points[run.point].id.c_str(),
                finished ? "wrote no recording" : "did not finish", live);
    std::fflush(stdout);
    return;
  }
  if (it->stream.kind != RunStream::Kind::kReplay || group.replays_left == 0) return;
  if (--group.replays_left == 0 && group.remove_after) {
    // Every replay of the seed is done: the study's folders hold what they hold without replay.
    fs::remove(group.recording, error);
  }
}

}  // namespace corridorsim::study_internal
