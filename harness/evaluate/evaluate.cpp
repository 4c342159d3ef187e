#include "harness/evaluate/evaluate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string_view>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "harness/evaluate/landmark_file.h"
#include "harness/metrics/consistency.h"
#include "harness/metrics/expectations.h"
#include "harness/metrics/map.h"
#include "harness/metrics/matching.h"
#include "harness/metrics/registry.h"
#include "harness/metrics/stats.h"
#include "harness/metrics/trajectory.h"
#include "harness/run/run.h"
#include "harness/run/run_folder.h"
#include "harness/scenario/calibration.h"
#include "harness/scenario/scenario.h"
#include "sim/simulation.h"
#include "worlds/ground_truth_reader.h"

namespace corridorsim::evaluate {
namespace {

using Json = nlohmann::ordered_json;
using metrics::MetricScope;
using metrics::MetricWriter;

const SourceLocation kCommandLine{"command line", 0, 0};
// evaluation.json's "nees" of an aligned ov_eval estimate, then the alignment's name.
const std::string kNeesLeftOut =
    "left out: the covariances do not describe the error left after --align ";
constexpr std::uint64_t kMaxWorldFileBytes = 256ull << 20;

double Yaw(const Eigen::Matrix3d& rotation) { return std::atan2(rotation(1, 0), rotation(0, 0)); }

// The index of the truth stamp nearest `stamp` (truth non-empty, stamps increasing).
std::size_t NearestTruth(const std::vector<TruthPose>& truth, TimeNs stamp) {
  const auto it = std::lower_bound(truth.begin(), truth.end(), stamp,
                                   [](const TruthPose& p, TimeNs t) { return p.stamp_ns < t; });
  if (it == truth.end()) return truth.size() - 1;
  if (it == truth.begin()) return 0;
  const auto before = it - 1;
  return static_cast<std::size_t>((stamp - before->stamp_ns <= it->stamp_ns - stamp ? before : it) -
                                  truth.begin());
}

// Stable text of a number for the table.
std::string Cell(const Json& object, const char* key, int decimals) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return "-";
  return FormatFixed(it->get<double>(), decimals);
}

// Writes `path` as `write` hands it its text piece by piece (into the staging folder, which the
// commit makes whole: no file of its own needs a rename). Throws std::runtime_error naming it.
void WriteStreamed(const std::filesystem::path& path,
                   const std::function<void(const std::function<void(std::string_view)>&)>& write) {
  std::FILE* file = std::fopen(path.c_str(), "wbe");
  if (file == nullptr) throw std::runtime_error("cannot write '" + path.string() + "'");
  bool ok = true;
  try {
    write([&](std::string_view text) {
      ok = ok && std::fwrite(text.data(), 1, text.size(), file) == text.size();
    });
  } catch (...) {
    std::fclose(file);
    throw;
  }
  ok = std::fflush(file) == 0 && ok;
  ok = std::fclose(file) == 0 && ok;
  if (!ok) throw std::runtime_error("cannot write '" + path.string() + "'");
}

}  // namespace

void WriteEstimateFiles(const std::filesystem::path& out, const std::string& name,
                        Alignment alignment, const TrajectoryEvaluation& evaluation) {
  WriteStreamed(out / (name + "_aligned.tum"), [&](const auto& sink) {
    sink("# " + name + ": estimate after " + AlignmentName(alignment) +
         " alignment\n# timestamp tx ty tz qx qy qz qw\n");
    for (const TrajectoryPose& p : evaluation.aligned.poses) {
      sink(sim::TumLine(p.stamp_ns, SE3(p.orientation, p.position)) + "\n");
    }
  });
  WriteStreamed(out / (name + "_errors.csv"),
                [&](const auto& sink) { WriteErrorSeriesCsv(evaluation.matched, sink); });
}

std::vector<TruthPose> TruthOfTrajectory(const Trajectory& truth) {
  std::vector<TruthPose> out;
  out.reserve(truth.poses.size());
  for (const TrajectoryPose& p : truth.poses) {
    out.push_back(
        {p.stamp_ns, SE2(p.position.x(), p.position.y(), Yaw(p.orientation.toRotationMatrix()))});
  }
  return out;
}

TrajectoryEvaluation EvaluateTrajectory(const std::vector<TruthPose>& truth, Trajectory estimate,
                                        Alignment alignment, double max_dt_s,
                                        const std::string& name) {
  CheckOrDie(!truth.empty(), "evaluate::EvaluateTrajectory", "no truth");
  const auto max_dt_ns = static_cast<TimeNs>(std::llround(max_dt_s * 1e9));
  const std::size_t poses = estimate.poses.size();
  const bool has_covariance = estimate.format == Trajectory::Format::kOvEval;
  CheckOrDie(!has_covariance || estimate.covariances.size() == poses,
             "evaluate::EvaluateTrajectory", "one covariance per ov_eval pose");
  // Association: a truth stamp within max_dt of the pose's; the truth at the pose's own stamp.
  // Each associated pose becomes a matched sample at once (its estimate set after the alignment):
  // one compact record per pose, no intermediate list (docs/evaluation.md, "Memory").
  TrajectoryEvaluation out;
  metrics::MatchedTrajectory& matched = out.matched;
  std::vector<std::size_t> associated;  // the index of each sample's pose
  for (std::size_t i = 0; i < poses; ++i) {
    const TimeNs t = estimate.poses[i].stamp_ns;
    const TimeNs dt = std::abs(truth[NearestTruth(truth, t)].stamp_ns - t);
    if (dt > max_dt_ns) continue;
    if (!metrics::TruthAt(truth, t)) continue;
    associated.push_back(i);
  }
  matched.samples.reserve(associated.size());
  for (const std::size_t i : associated) {
    const TimeNs t = estimate.poses[i].stamp_ns;
    matched.samples.push_back({t, SE2(), *metrics::TruthAt(truth, t), Eigen::Matrix3d::Zero()});
  }
  std::string why;
  const std::optional<Similarity> fit = [&] {
    std::vector<Eigen::Vector3d> from, to;  // freed once fitted
    from.reserve(associated.size());
    to.reserve(associated.size());
    for (std::size_t k = 0; k < associated.size(); ++k) {
      const SE2& at = matched.samples[k].truth;
      from.push_back(estimate.poses[associated[k]].position);
      to.push_back(Eigen::Vector3d(at.x(), at.y(), 0.0));
    }
    return Align(alignment, from, to, &why);
  }();
  if (!fit) {
    throw InputError(kCommandLine, "--estimate",
                     name + ": " + why + " (" + std::to_string(poses) + " poses, --max-dt " +
                         FormatFixed(max_dt_s, 3) + " s)");
  }
  out.alignment = *fit;
  const Eigen::Matrix3d& r = fit->rotation;
  // Aligned in place: the estimate is this evaluation's own (no second copy of a long file).
  for (TrajectoryPose& p : estimate.poses) {
    p.position = (*fit)(p.position);
    p.orientation = Eigen::Quaterniond(r * p.orientation.toRotationMatrix()).normalized();
    if (p.orientation.w() < 0.0) p.orientation.coeffs() = -p.orientation.coeffs();
  }
  for (PoseCovariance& c : estimate.covariances) {
    c.position = fit->scale * fit->scale * r * c.position * r.transpose();
    c.orientation = r * c.orientation * r.transpose();
  }
  out.aligned = std::move(estimate);
  const Trajectory& aligned = out.aligned;
  // NEES only without alignment: a fitted alignment takes out the part of the error that the
  // covariance describes (an SE(2) fit removes a drift the filter was right to be unsure of, or
  // moves a trajectory whose covariance was about another frame), so error and covariance no
  // longer belong together (docs/evaluation.md, "NEES").
  const bool nees = has_covariance && alignment == Alignment::kNone;
  metrics::Stats error_3d, rotation_error;
  for (std::size_t k = 0; k < associated.size(); ++k) {
    const TrajectoryPose& a = aligned.poses[associated[k]];
    const Eigen::Matrix3d rotation = a.orientation.toRotationMatrix();
    metrics::MatchedSample& sample = matched.samples[k];
    sample.estimate = SE2(a.position.x(), a.position.y(), Yaw(rotation));
    if (nees) {
      // (x, y, yaw): the position block's x-y and the orientation's z entry; the format has no
      // cross terms between position and orientation.
      const PoseCovariance& c = aligned.covariances[associated[k]];
      sample.covariance.topLeftCorner<2, 2>() = c.position.topLeftCorner<2, 2>();
      sample.covariance(2, 2) = c.orientation(2, 2);
    }
    const SE3 t3 = SE3::FromSE2(sample.truth);
    error_3d.Add((a.position - t3.translation()).norm());
    rotation_error.Add(Eigen::AngleAxisd(t3.rotation().transpose() * rotation).angle());
  }
  // The reader's bounds keep every aligned pose and covariance finite (MatchToTruth would count
  // the others; none can occur here).
  matched.without_truth = poses - associated.size();
  std::vector<std::size_t>().swap(associated);

  Json& object = out.metrics;
  object["format"] = FormatName(aligned.format);
  const MetricWriter evaluation(object, MetricScope::kEvaluation);
  evaluation.Count("poses", poses);
  const MetricWriter align = evaluation.Sub("align");
  align.Set("scale", fit->scale);
  align.Set("x_m", fit->translation.x());
  align.Set("y_m", fit->translation.y());
  align.Set("z_m", fit->translation.z());
  align.Set("angle_rad", Eigen::AngleAxisd(r).angle());
  const MetricWriter shared(object, MetricScope::kPipeline);
  metrics::AddTrajectoryMetrics(matched, shared);
  if (!matched.samples.empty()) {
    evaluation.Set("ate_3d_rmse_m", error_3d.rms());
    evaluation.Set("rotation_rmse_rad", rotation_error.rms());
  }
  if (nees) metrics::AddNeesMetrics(matched, shared);
  if (has_covariance && !nees) object["nees"] = kNeesLeftOut + AlignmentName(alignment);
  return out;
}

Trajectory ToRobotFrame(Trajectory estimate, const SE3& robot_from_camera) {
  const SE3 camera_from_robot = robot_from_camera.Inverse();
  const bool has_covariance = !estimate.covariances.empty();  // ov_eval: one per pose
  for (std::size_t i = 0; i < estimate.poses.size(); ++i) {
    TrajectoryPose& p = estimate.poses[i];
    if (has_covariance) {
      // p_robot = p_camera + R_camera t: a world-frame rotation error d_theta moves it by
      // -[R_camera t]x d_theta.
      const Eigen::Vector3d arm = p.orientation * camera_from_robot.translation();
      Eigen::Matrix3d skew;
      skew << 0, -arm.z(), arm.y(), arm.z(), 0, -arm.x(), -arm.y(), arm.x(), 0;
      PoseCovariance& c = estimate.covariances[i];
      c.position += skew * c.orientation * skew.transpose();
    }
    const SE3 world_from_robot = SE3(p.orientation, p.position) * camera_from_robot;
    p.position = world_from_robot.translation();
    p.orientation = world_from_robot.quaternion();
    if (p.orientation.w() < 0.0) p.orientation.coeffs() = -p.orientation.coeffs();
  }
  return estimate;
}

std::vector<slam::LandmarkEstimate> AlignLandmarks(std::vector<slam::LandmarkEstimate> landmarks,
                                                   const Similarity& alignment) {
  const Eigen::Matrix3d& r = alignment.rotation;
  const double s2 = alignment.scale * alignment.scale;
  for (slam::LandmarkEstimate& l : landmarks) {
    l.position_in_world = alignment(l.position_in_world);
    l.covariance = s2 * r * l.covariance * r.transpose();
    for (slam::LandmarkPoint& p : l.points) {
      p.position_in_world = alignment(p.position_in_world);
      p.covariance = s2 * r * p.covariance * r.transpose();
    }
  }
  return landmarks;
}

void AddLandmarkMapMetrics(const worlds::World& world,
                           const std::vector<slam::LandmarkEstimate>& landmarks,
                           nlohmann::ordered_json& object) {
  PipelineRecord record;
  record.landmarks = landmarks;
  const MetricsOptions options;
  metrics::PipelineContext context;
  context.world = &world;
  context.options = &options;
  const MetricWriter out(object, MetricScope::kPipeline);
  for (const slam::LandmarkType type : metrics::kMapTypes) {
    if (metrics::HasType(record, type)) metrics::AddMapMetrics(record, context, type, out);
  }
}

int RunEvaluate(const EvaluateRequest& request) {
  std::error_code error;
  if (!std::filesystem::is_directory(request.run_dir, error)) {
    throw InputError(kCommandLine, "RUN_DIR",
                     "no such folder '" + request.run_dir.string() +
                         "' (a run folder: " + "corridorsim run --out)");
  }
  // Every expectation names an estimate or map of this evaluation and one of its metrics.
  std::set<std::string> names;
  for (const auto& e : request.estimates) names.insert(e.name);
  for (const auto& l : request.landmarks) names.insert(l.name);
  std::vector<Expectation> expectations;
  for (const std::string& text : request.expectations) {
    Expectation e;
    if (const auto problem = ParseExpectation(text, &e, EvaluationMetricNames())) {
      throw InputError(kCommandLine, "--expect", *problem);
    }
    if (names.count(e.pipeline) == 0) {
      throw InputError(
          kCommandLine, "--expect",
          "'" + e.pipeline + "' is no --estimate or --landmarks name (in '" + text + "')");
    }
    expectations.push_back(e);
  }
  const std::filesystem::path out_dir =
      request.out_dir.empty() ? request.run_dir / "evaluation" : request.out_dir;
  // Inputs: the run folder's files (its default output, RUN_DIR/evaluation, holds none of them)
  // and every estimate and map file.
  std::vector<JobInput> inputs;
  for (const char* file : {"ground_truth.tum", "world.json", "scenario.yaml"}) {
    inputs.push_back({request.run_dir / file, "a file of RUN_DIR"});
  }
  for (const auto& e : request.estimates) inputs.push_back({e.file, "--estimate " + e.name});
  for (const auto& l : request.landmarks) inputs.push_back({l.file, "--landmarks " + l.name});
  const std::unique_ptr<StagedDirectory> folder =
      StageOutputFolder(out_dir, "--out", request.force, inputs);

  // Every input is read and checked before the folder is committed (the staging folder holds
  // the estimates' files meanwhile; a bad input removes it, the target stays as it was).
  const std::vector<TruthPose> truth =
      TruthOfTrajectory(ReadTrajectory((request.run_dir / "ground_truth.tum").string()));
  Json estimates = Json::object();
  std::map<std::string, SE3> robot_from_camera;  // by estimate name, for --frame
  if (!request.frames.empty()) {
    // The mounts are the run's: its resolved scenario.yaml's `sensors:` alone, read only when a
    // --frame asks (never loaded: its plugins and pipelines stay unread, nothing of the folder
    // runs).
    const std::filesystem::path scenario_file = request.run_dir / "scenario.yaml";
    const std::vector<slam::CameraCalibration> cameras =
        CamerasOfRunScenario(scenario_file.string());
    for (const EvaluateRequest::Frame& f : request.frames) {
      std::string known;
      for (const slam::CameraCalibration& c : cameras) {
        if (c.id == f.camera) robot_from_camera[f.name] = c.robot_from_camera;
        known += (known.empty() ? "" : ", ") + c.id;
      }
      if (robot_from_camera.count(f.name) == 0) {
        throw InputError(kCommandLine, "--frame",
                         "camera '" + f.camera + "' is not enabled in " + scenario_file.string() +
                             " (its cameras: " + (known.empty() ? "none" : known) + ")");
      }
    }
  }
  // One estimate at a time: read, scored, its two files written into the staging folder (the
  // target is replaced only at the commit, after every input is read), then let go; only its
  // metrics and alignment stay (docs/evaluation.md, "Memory").
  std::map<std::string, Similarity> alignments;
  for (const EvaluateRequest::NamedFile& e : request.estimates) {
    Trajectory trajectory = ReadTrajectory(e.file.string());
    if (const auto it = robot_from_camera.find(e.name); it != robot_from_camera.end()) {
      trajectory = ToRobotFrame(std::move(trajectory), it->second);
    }
    TrajectoryEvaluation evaluation = EvaluateTrajectory(
        truth, std::move(trajectory), request.alignment, request.max_dt_s, e.name);
    Json object;
    object["file"] = e.file.string();
    for (const EvaluateRequest::Frame& f : request.frames) {
      if (f.name == e.name) object["frame"] = f.camera;
    }
    for (auto& [key, value] : evaluation.metrics.items()) object[key] = value;
    estimates[e.name] = std::move(object);
    alignments.emplace(e.name, evaluation.alignment);
    WriteEstimateFiles(folder->path(), e.name, request.alignment, evaluation);
  }
  if (!request.landmarks.empty()) {
    const std::filesystem::path world_file = request.run_dir / "world.json";
    const worlds::World world = worlds::ParseGroundTruthJson(
        ReadRegularFile(world_file, kMaxWorldFileBytes), world_file.string());
    for (const EvaluateRequest::NamedFile& l : request.landmarks) {
      std::vector<slam::LandmarkEstimate> map = ReadLandmarkMap(l.file.string());
      // A map is in its trajectory's frame: the estimate of the same name moves it too.
      const auto it = alignments.find(l.name);
      if (it != alignments.end()) map = AlignLandmarks(std::move(map), it->second);
      Json& object = estimates[l.name];
      object["landmarks_file"] = l.file.string();
      object["landmarks"] = map.size();
      AddLandmarkMapMetrics(world, map, object);
    }
  }
  Json document;
  document["schema_version"] = 1;
  document["run"] = request.run_dir.string();
  document["alignment"] = AlignmentName(request.alignment);
  document["max_dt_s"] = RoundToStep(request.max_dt_s, json_steps::kSeconds);
  document["estimates"] = std::move(estimates);
  const std::vector<ExpectationResult> results =
      CheckExpectations(document, expectations, "estimates");

  const auto write_results = [&](const std::filesystem::path& out) {
    WriteFileAtomic(out / "evaluation.json", JsonFileText(document));
  };
  std::vector<RunExtra> extras;
  if (request.plots && !alignments.empty()) {
    extras.push_back(
        {"plots/", [&] {
           if (const auto problem = RunPlotScript(
                   "plot_evaluation.py", {folder->path().string(), request.run_dir.string()})) {
             throw std::runtime_error(*problem);
           }
         }});
  }
  const int extras_failed = CommitResultsThenExtras(*folder, write_results, extras);

  std::printf("%-22s %8s %8s %10s %10s %10s %10s %10s %8s\n", "estimate", "format", "samples",
              "ATE rmse m", "ATE 3D m", "RPE 1m m", "final m", "NEES mean", "scale");
  for (const auto& [name, m] : document["estimates"].items()) {
    const std::string samples =
        m.contains("samples") ? std::to_string(m["samples"].get<int>()) : std::string("-");
    const std::string scale =
        m.contains("align") ? FormatFixed(m["align"]["scale"].get<double>(), 4) : "-";
    std::printf("%-22s %8s %8s %10s %10s %10s %10s %10s %8s\n", name.c_str(),
                m.value("format", std::string("-")).c_str(), samples.c_str(),
                Cell(m, "ate_rmse_m", 3).c_str(), Cell(m, "ate_3d_rmse_m", 3).c_str(),
                Cell(m, "rpe_1m_trans_rmse_m", 3).c_str(),
                Cell(m, "final_position_error_m", 3).c_str(), Cell(m, "nees_mean", 2).c_str(),
                scale.c_str());
  }
  bool all_passed = true;
  if (!results.empty()) std::printf("\nexpectations:\n");
  for (const ExpectationResult& r : results) {
    all_passed = all_passed && r.passed;
    const std::string measured = r.measured ? FormatFixed(*r.measured, 4) : "missing";
    std::printf("  %s  %-45s measured %s\n", r.passed ? "PASS" : "FAIL", r.expectation.text.c_str(),
                measured.c_str());
  }
  std::printf("wrote %s/{evaluation.json, <estimate>_aligned.tum, <estimate>_errors.csv%s}\n",
              folder->path().string().c_str(), extras.empty() ? "" : ", plots/");
  if (!all_passed) return kExitExpectationsFailed;
  return extras_failed > 0 ? kExitExtraFailed : 0;
}

}  // namespace corridorsim::evaluate
