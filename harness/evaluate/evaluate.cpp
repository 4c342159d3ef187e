#include "harness/evaluate/evaluate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

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

}  // namespace

std::vector<TruthPose> TruthOfTrajectory(const Trajectory& truth) {
  std::vector<TruthPose> out;
  out.reserve(truth.poses.size());
  for (const TrajectoryPose& p : truth.poses) {
    out.push_back(
        {p.stamp_ns, SE2(p.position.x(), p.position.y(), Yaw(p.orientation.toRotationMatrix()))});
  }
  return out;
}

TrajectoryEvaluation EvaluateTrajectory(const std::vector<TruthPose>& truth,
                                        const Trajectory& estimate, Alignment alignment,
                                        double max_dt_s, const std::string& name) {
  CheckOrDie(!truth.empty(), "evaluate::EvaluateTrajectory", "no truth");
  const auto max_dt_ns = static_cast<TimeNs>(std::llround(max_dt_s * 1e9));
  // Association: a truth stamp within max_dt of the pose's; the truth at the pose's own stamp.
  std::vector<std::size_t> associated;
  std::vector<SE2> truth_at;
  for (std::size_t i = 0; i < estimate.poses.size(); ++i) {
    const TimeNs t = estimate.poses[i].stamp_ns;
    const TimeNs dt = std::abs(truth[NearestTruth(truth, t)].stamp_ns - t);
    if (dt > max_dt_ns) continue;
    const std::optional<SE2> at = metrics::TruthAt(truth, t);
    if (!at) continue;
    associated.push_back(i);
    truth_at.push_back(*at);
  }
  std::vector<Eigen::Vector3d> from, to;
  for (std::size_t k = 0; k < associated.size(); ++k) {
    from.push_back(estimate.poses[associated[k]].position);
    to.push_back(Eigen::Vector3d(truth_at[k].x(), truth_at[k].y(), 0.0));
  }
  std::string why;
  const std::optional<Similarity> fit = Align(alignment, from, to, &why);
  if (!fit) {
    throw InputError(kCommandLine, "--estimate",
                     name + ": " + why + " (" + std::to_string(estimate.poses.size()) +
                         " poses, --max-dt " + FormatFixed(max_dt_s, 3) + " s)");
  }
  TrajectoryEvaluation out;
  out.alignment = *fit;
  const Eigen::Matrix3d& r = fit->rotation;
  const bool has_covariance = estimate.format == Trajectory::Format::kOvEval;
  for (const TrajectoryPose& p : estimate.poses) {
    TrajectoryPose a = p;
    a.position = (*fit)(p.position);
    a.orientation = Eigen::Quaterniond(r * p.orientation.toRotationMatrix()).normalized();
    if (a.orientation.w() < 0.0) a.orientation.coeffs() = -a.orientation.coeffs();
    a.position_covariance = fit->scale * fit->scale * r * p.position_covariance * r.transpose();
    a.orientation_covariance = r * p.orientation_covariance * r.transpose();
    out.aligned.push_back(a);
  }
  metrics::Stats error_3d, rotation_error;
  for (std::size_t k = 0; k < associated.size(); ++k) {
    const TrajectoryPose& a = out.aligned[associated[k]];
    const Eigen::Matrix3d rotation = a.orientation.toRotationMatrix();
    EstimateSample sample;
    sample.stamp_ns = a.stamp_ns;
    sample.world_from_robot = SE2(a.position.x(), a.position.y(), Yaw(rotation));
    if (has_covariance) {
      // (x, y, yaw): the position block's x-y and the orientation's z entry; the format has no
      // cross terms between position and orientation.
      sample.covariance.topLeftCorner<2, 2>() = a.position_covariance.topLeftCorner<2, 2>();
      sample.covariance(2, 2) = a.orientation_covariance(2, 2);
    }
    out.associated.push_back(sample);
    const SE3 t3 = SE3::FromSE2(truth_at[k]);
    error_3d.Add((a.position - t3.translation()).norm());
    rotation_error.Add(Eigen::AngleAxisd(t3.rotation().transpose() * rotation).angle());
  }
  metrics::MatchedTrajectory matched = metrics::MatchToTruth(truth, out.associated);
  matched.without_truth += estimate.poses.size() - associated.size();

  Json& object = out.metrics;
  object["format"] = FormatName(estimate.format);
  const MetricWriter evaluation(object, MetricScope::kEvaluation);
  evaluation.Count("poses", estimate.poses.size());
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
  if (has_covariance) metrics::AddNeesMetrics(matched, shared);
  return out;
}

Trajectory ToRobotFrame(Trajectory estimate, const SE3& robot_from_camera) {
  const SE3 camera_from_robot = robot_from_camera.Inverse();
  for (TrajectoryPose& p : estimate.poses) {
    const SE3 world_from_robot = SE3(p.orientation, p.position) * camera_from_robot;
    // p_robot = p_camera + R_camera t: a world-frame rotation error d_theta moves it by
    // -[R_camera t]x d_theta.
    const Eigen::Vector3d arm = p.orientation * camera_from_robot.translation();
    Eigen::Matrix3d skew;
    skew << 0, -arm.z(), arm.y(), arm.z(), 0, -arm.x(), -arm.y(), arm.x(), 0;
    p.position_covariance += skew * p.orientation_covariance * skew.transpose();
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
  const std::unique_ptr<StagedDirectory> folder =
      StageOutputFolder(out_dir, "--out", request.force);

  // Inputs: every file is read and checked before anything is written.
  const std::vector<TruthPose> truth =
      TruthOfTrajectory(ReadTrajectory((request.run_dir / "ground_truth.tum").string()));
  Json estimates = Json::object();
  std::map<std::string, TrajectoryEvaluation> evaluations;
  std::map<std::string, SE3> robot_from_camera;  // by estimate name, for --frame
  if (!request.frames.empty()) {
    // The mounts are the run's: its resolved scenario.yaml, loaded only when a --frame asks.
    const std::filesystem::path scenario_file = request.run_dir / "scenario.yaml";
    const slam::Calibration calibration = CalibrationOf(LoadScenario(scenario_file.string()));
    for (const EvaluateRequest::Frame& f : request.frames) {
      std::string known;
      for (const slam::CameraCalibration& c : calibration.cameras) {
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
  for (const EvaluateRequest::NamedFile& e : request.estimates) {
    Trajectory trajectory = ReadTrajectory(e.file.string());
    if (const auto it = robot_from_camera.find(e.name); it != robot_from_camera.end()) {
      trajectory = ToRobotFrame(std::move(trajectory), it->second);
    }
    TrajectoryEvaluation evaluation =
        EvaluateTrajectory(truth, trajectory, request.alignment, request.max_dt_s, e.name);
    Json object;
    object["file"] = e.file.string();
    for (const EvaluateRequest::Frame& f : request.frames) {
      if (f.name == e.name) object["frame"] = f.camera;
    }
    for (auto& [key, value] : evaluation.metrics.items()) object[key] = value;
    estimates[e.name] = std::move(object);
    evaluations.emplace(e.name, std::move(evaluation));
  }
  if (!request.landmarks.empty()) {
    const std::filesystem::path world_file = request.run_dir / "world.json";
    const worlds::World world = worlds::ParseGroundTruthJson(
        ReadRegularFile(world_file, kMaxWorldFileBytes), world_file.string());
    for (const EvaluateRequest::NamedFile& l : request.landmarks) {
      std::vector<slam::LandmarkEstimate> map = ReadLandmarkMap(l.file.string());
      // A map is in its trajectory's frame: the estimate of the same name moves it too.
      const auto it = evaluations.find(l.name);
      if (it != evaluations.end()) map = AlignLandmarks(std::move(map), it->second.alignment);
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
    for (const auto& [name, evaluation] : evaluations) {
      std::string tum = "# " + name + ": estimate after " + AlignmentName(request.alignment) +
                        " alignment\n# timestamp tx ty tz qx qy qz qw\n";
      for (const TrajectoryPose& p : evaluation.aligned) {
        tum += sim::TumLine(p.stamp_ns, SE3(p.orientation, p.position)) + "\n";
      }
      WriteFileAtomic(out / (name + "_aligned.tum"), tum);
      PipelineRecord record;
      record.name = name;
      record.estimates = evaluation.associated;
      WriteFileAtomic(out / (name + "_errors.csv"), ErrorSeriesCsv(truth, record));
    }
  };
  std::vector<RunExtra> extras;
  if (request.plots && !evaluations.empty()) {
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
