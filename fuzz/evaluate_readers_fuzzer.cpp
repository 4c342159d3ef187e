// Fuzzes what `corridorsim evaluate` reads (docs/evaluation.md, docs/fuzzing.md): the input is
// read as a trajectory file (harness/evaluate/trajectory_file.h: TUM or ov_eval) and as a
// landmark map (landmark_file.h). A trajectory it accepts must hold what the reader promises
// (poses, increasing stamps within the bound, finite bounded numbers, unit quaternions, one
// covariance per ov_eval pose), and is then scored as the job scores it: against a fixed truth
// (a 10 s arc at 100 Hz) with every alignment, and through a camera mount (--frame); every
// number of the result must be finite. A map it accepts is aligned and must stay finite.
//
// InputError is the documented outcome for bad input (exit 2); any other exception, a crash, a
// sanitizer report or a broken promise is a bug: the target aborts and libFuzzer saves the input.
//
//   scripts/bootstrap.sh fuzz 60   (docs/fuzzing.md; builds build-fuzz/bin/evaluate_readers_fuzzer)

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "fuzz/fuzz_checks.h"
#include "harness/evaluate/evaluate.h"
#include "harness/evaluate/landmark_file.h"
#include "harness/evaluate/trajectory_file.h"

namespace {

namespace ev = corridorsim::evaluate;
using corridorsim::fuzz::Bug;
using corridorsim::fuzz::CheckFinite;

// A left arc at 1 m/s, radius 20 m, 10 s on the 100 Hz grid (stamps 0 ... 10 s).
const std::vector<corridorsim::TruthPose>& Truth() {
  static const std::vector<corridorsim::TruthPose> truth = [] {
    std::vector<corridorsim::TruthPose> out;
    for (int k = 0; k <= 1000; ++k) {
      const double s = 0.01 * k, yaw = s / 20.0;
      out.push_back({static_cast<corridorsim::TimeNs>(k) * 10'000'000,
                     corridorsim::SE2(20.0 * std::sin(yaw), 20.0 * (1.0 - std::cos(yaw)), yaw)});
    }
    return out;
  }();
  return truth;
}

bool Finite(const Eigen::MatrixXd& m) { return m.allFinite(); }

void CheckTrajectory(const ev::Trajectory& t) {
  if (t.poses.empty() || t.poses.size() > ev::kMaxTrajectoryPoses) Bug("pose count");
  const bool ov = t.format == ev::Trajectory::Format::kOvEval;
  if (t.covariances.size() != (ov ? t.poses.size() : 0)) Bug("covariance count");
  for (std::size_t i = 0; i < t.poses.size(); ++i) {
    const ev::TrajectoryPose& p = t.poses[i];
    if (i > 0 && p.stamp_ns <= t.poses[i - 1].stamp_ns) Bug("stamps not increasing");
    if (std::abs(corridorsim::ToSeconds(p.stamp_ns)) > ev::kMaxStampSeconds + 1) Bug("stamp bound");
    if (!Finite(p.position) || p.position.cwiseAbs().maxCoeff() > ev::kMaxCoordinateMetres) {
      Bug("position not finite or beyond the bound");
    }
    if (std::abs(p.orientation.norm() - 1.0) > 1e-9 || p.orientation.w() < 0.0) {
      Bug("quaternion not unit with qw >= 0");
    }
  }
  for (const ev::PoseCovariance& c : t.covariances) {
    if (!Finite(c.position) || !Finite(c.orientation)) Bug("covariance not finite");
  }
}

template <class F>
bool Expect(const char* what, F&& call) {
  try {
    call();
    return true;
  } catch (const corridorsim::InputError&) {
    return false;  // the documented outcome
  } catch (const std::exception& e) {
    Bug(std::string(what) + " threw something other than InputError: " + e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);

  ev::Trajectory trajectory;
  if (Expect("ParseTrajectory", [&] { trajectory = ev::ParseTrajectory(text, "estimate.tum"); })) {
    CheckTrajectory(trajectory);
    for (const ev::Alignment a : ev::kAllAlignments) {
      Expect("EvaluateTrajectory", [&] {
        const ev::TrajectoryEvaluation e =
            ev::EvaluateTrajectory(Truth(), trajectory, a, 0.01, "fuzz");
        CheckFinite(e.metrics, ev::AlignmentName(a));
        if (e.aligned.poses.size() != trajectory.poses.size()) Bug("aligned pose count");
      });
    }
    // --frame: a camera 0.2 m ahead, 0.5 m up, looking forward (optical z along robot x).
    Eigen::Matrix3d r;
    r << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    const corridorsim::SE3 robot_from_camera(Eigen::Quaterniond(r), Eigen::Vector3d(0.2, 0.0, 0.5));
    Expect("EvaluateTrajectory --frame", [&] {
      const ev::TrajectoryEvaluation e =
          ev::EvaluateTrajectory(Truth(), ev::ToRobotFrame(trajectory, robot_from_camera),
                                 ev::Alignment::kNone, 0.01, "fuzz");
      CheckFinite(e.metrics, "frame");
    });
  }

  std::vector<corridorsim::slam::LandmarkEstimate> map;
  if (Expect("ParseLandmarkMap", [&] { map = ev::ParseLandmarkMap(text, "map.json"); })) {
    if (map.size() > ev::kMaxLandmarks) Bug("landmark count");
    std::set<int> ids;
    for (const auto& l : map) {
      if (!ids.insert(l.id).second) Bug("duplicate id accepted");
      if (l.points.size() > ev::kMaxLandmarkPoints) Bug("point count");
    }
    ev::Similarity g;
    g.scale = 2.0;
    g.rotation = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    g.translation = Eigen::Vector3d(1.0, -2.0, 0.5);
    for (const auto& l : ev::AlignLandmarks(map, g)) {
      if (!Finite(l.position_in_world) || !Finite(l.covariance)) Bug("aligned map not finite");
    }
  }
  return 0;
}
