#include "harness/metrics.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <tuple>
#include <utility>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>

#include "common/io/stable_json.h"

namespace corridorsim {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector4d;
using Json = nlohmann::ordered_json;
using slam::LandmarkType;

// Two-sided 95 % interval of the chi-square tests (NEES, NIS).
constexpr double kBandLowerTail = 0.025;
constexpr double kBandUpperTail = 0.975;
// RPE: relative motions over these truth distances (m).
constexpr int kRpeDistancesM[] = {1, 5, 10};
// Landmark types in schema order; vanishing points have no position in the world (no map, no
// association), only a detector error.
constexpr LandmarkType kAllTypes[] = {LandmarkType::kDoorPlate, LandmarkType::kCorner,
                                      LandmarkType::kLamp, LandmarkType::kDoor,
                                      LandmarkType::kVanishingPoint};
constexpr LandmarkType kMapTypes[] = {LandmarkType::kDoorPlate, LandmarkType::kCorner,
                                      LandmarkType::kLamp, LandmarkType::kDoor};

// A broken invariant is a bug: say what and abort (STYLE item 10).
void CheckOrDie(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "corridorsim::ComputeMetrics: %s\n", what);
  std::abort();
}

// ---- Rounding: fixed steps per unit so the JSON is byte-stable --------------------------------

// The project's stable JSON rounding (common/io/stable_json.h).
double RoundDiv(double value, double steps_per_unit) { return RoundToStep(value, steps_per_unit); }
Json Metres(double v) { return RoundDiv(v, 1e6); }
Json Rad(double v) { return RoundDiv(v, 1e8); }
Json Px(double v) { return RoundDiv(v, 1e4); }
Json Ratio(double v) { return RoundDiv(v, 1e6); }  // fractions, NEES, NIS, real-time factor
Json Seconds(double v) { return RoundDiv(v, 1e6); }
Json Ms(double v) { return RoundDiv(v, 1e4); }
// A fraction, or null for an empty denominator.
Json Fraction(std::size_t numerator, std::size_t denominator) {
  if (denominator == 0) return nullptr;
  return Ratio(static_cast<double>(numerator) / static_cast<double>(denominator));
}

// Mean, RMSE and maximum of non-negative values (null when there are none).
struct Stats {
  std::size_t count = 0;
  double sum = 0.0;
  double sum_sq = 0.0;
  double max = 0.0;
  void Add(double v) {
    ++count;
    sum += v;
    sum_sq += v * v;
    max = std::max(max, v);
  }
  std::optional<double> mean() const {
    return count == 0 ? std::nullopt : std::optional(sum / static_cast<double>(count));
  }
  std::optional<double> rms() const {
    return count == 0 ? std::nullopt
                      : std::optional(std::sqrt(sum_sq / static_cast<double>(count)));
  }
  std::optional<double> maximum() const { return count == 0 ? std::nullopt : std::optional(max); }
};
Json OrNull(const std::optional<double>& v, Json (*round)(double)) {
  return v ? round(*v) : Json(nullptr);
}

double ChiSquareQuantile(double dof, double p) {
  return boost::math::quantile(boost::math::chi_squared_distribution<double>(dof), p);
}

// ---- Trajectory -------------------------------------------------------------------------------

// The truth at `stamp`: exact on the grid, interpolated between grid points, none outside.
std::optional<SE2> TruthAt(const std::vector<TruthPose>& truth, TimeNs stamp) {
  const auto it = std::lower_bound(truth.begin(), truth.end(), stamp,
                                   [](const TruthPose& p, TimeNs s) { return p.stamp_ns < s; });
  if (it == truth.end()) return std::nullopt;
  if (it->stamp_ns == stamp) return it->world_from_robot;
  if (it == truth.begin()) return std::nullopt;
  const TruthPose& before = *(it - 1);
  const double t = static_cast<double>(stamp - before.stamp_ns) /
                   static_cast<double>(it->stamp_ns - before.stamp_ns);
  return SE2::Interpolate(before.world_from_robot, it->world_from_robot, t);
}

struct MatchedSample {
  TimeNs stamp_ns = 0;
  SE2 estimate;
  SE2 truth;
  Matrix3d covariance;
};

struct MatchedTrajectory {
  std::vector<MatchedSample> samples;
  std::size_t without_truth = 0;  // estimates outside the truth's time span
};

MatchedTrajectory MatchToTruth(const std::vector<TruthPose>& truth,
                               const std::vector<EstimateSample>& estimates) {
  CheckOrDie(std::is_sorted(
                 truth.begin(), truth.end(),
                 [](const TruthPose& a, const TruthPose& b) { return a.stamp_ns < b.stamp_ns; }),
             "truth is not in stamp order");
  MatchedTrajectory out;
  for (const EstimateSample& e : estimates) {
    const std::optional<SE2> t = TruthAt(truth, e.stamp_ns);
    if (!t) {
      ++out.without_truth;
      continue;
    }
    out.samples.push_back({e.stamp_ns, e.world_from_robot, *t, e.covariance});
  }
  return out;
}

// Estimate minus truth in the world frame: (x m, y m, yaw rad wrapped).
Vector3d PoseError(const SE2& estimate, const SE2& truth) {
  return {estimate.x() - truth.x(), estimate.y() - truth.y(),
          NormalizeAngle(estimate.yaw() - truth.yaw())};
}

// NEES e^T P^-1 e over 3 dof, or none when P is not positive definite.
std::optional<double> Nees(const Vector3d& error, const Matrix3d& covariance) {
  if (!covariance.allFinite()) return std::nullopt;
  const Eigen::LLT<Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success) return std::nullopt;
  // LLT accepts some matrices with a zero pivot; require a strictly positive diagonal of L.
  const Matrix3d l = llt.matrixL();
  if ((l.diagonal().array() <= 0.0).any()) return std::nullopt;
  return error.dot(llt.solve(error));
}

// Closed-form least-squares rotation + translation in the plane (Horn / Umeyama without scale)
// that maps the estimated positions onto the true ones: truth ~ aligned_from_estimate * estimate.
SE2 AlignPositions(const std::vector<MatchedSample>& samples) {
  Vector2d mean_estimate = Vector2d::Zero();
  Vector2d mean_truth = Vector2d::Zero();
  for (const MatchedSample& s : samples) {
    mean_estimate += s.estimate.translation();
    mean_truth += s.truth.translation();
  }
  const double n = static_cast<double>(samples.size());
  mean_estimate /= n;
  mean_truth /= n;
  double sum_dot = 0.0;
  double sum_cross = 0.0;
  for (const MatchedSample& s : samples) {
    const Vector2d a = s.estimate.translation() - mean_estimate;
    const Vector2d b = s.truth.translation() - mean_truth;
    sum_dot += a.dot(b);
    sum_cross += a.x() * b.y() - a.y() * b.x();
  }
  // All estimated positions equal: any rotation fits; keep none.
  const double yaw = (sum_dot == 0.0 && sum_cross == 0.0) ? 0.0 : std::atan2(sum_cross, sum_dot);
  const SE2 rotation(0.0, 0.0, yaw);
  return SE2(mean_truth - rotation * mean_estimate, yaw);
}

void AddTrajectoryMetrics(const MatchedTrajectory& matched, Json& out) {
  const std::vector<MatchedSample>& samples = matched.samples;
  out["samples"] = samples.size();
  out["samples_without_truth"] = matched.without_truth;
  if (samples.empty()) return;

  // Distance travelled along the truth, cumulative per sample (RPE pairs are chosen by it).
  std::vector<double> travelled_m(samples.size(), 0.0);
  for (std::size_t i = 1; i < samples.size(); ++i) {
    travelled_m[i] = travelled_m[i - 1] +
                     (samples[i].truth.translation() - samples[i - 1].truth.translation()).norm();
  }
  out["distance_travelled_m"] = Metres(travelled_m.back());

  // ATE, unaligned: the filters share the start pose, so the world frames agree.
  Stats ate;
  Stats ate_yaw;
  for (const MatchedSample& s : samples) {
    const Vector3d e = PoseError(s.estimate, s.truth);
    ate.Add(e.head<2>().norm());
    ate_yaw.Add(std::abs(e.z()));
  }
  out["ate_rmse_m"] = OrNull(ate.rms(), Metres);
  out["ate_mean_m"] = OrNull(ate.mean(), Metres);
  out["ate_max_m"] = OrNull(ate.maximum(), Metres);
  out["ate_yaw_rmse_rad"] = OrNull(ate_yaw.rms(), Rad);

  // ATE after the least-squares SE2 alignment of the positions.
  const SE2 aligned_from_estimate = AlignPositions(samples);
  Stats aligned;
  for (const MatchedSample& s : samples) {
    aligned.Add((aligned_from_estimate * s.estimate.translation() - s.truth.translation()).norm());
  }
  out["ate_aligned_rmse_m"] = OrNull(aligned.rms(), Metres);
  out["ate_aligned_mean_m"] = OrNull(aligned.mean(), Metres);
  out["ate_aligned_max_m"] = OrNull(aligned.maximum(), Metres);
  out["alignment"] = {{"x_m", Metres(aligned_from_estimate.x())},
                      {"y_m", Metres(aligned_from_estimate.y())},
                      {"yaw_rad", Rad(aligned_from_estimate.yaw())}};

  // RPE: for each sample i the first j whose truth distance from i reaches d; the error of the
  // relative motion is (truth_i^-1 truth_j)^-1 (estimate_i^-1 estimate_j).
  for (const int distance_m : kRpeDistancesM) {
    Stats trans;
    Stats yaw;
    std::size_t j = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      j = std::max(j, i + 1);
      while (j < samples.size() && travelled_m[j] - travelled_m[i] < distance_m) ++j;
      if (j >= samples.size()) break;
      const SE2 truth_motion = samples[i].truth.Inverse() * samples[j].truth;
      const SE2 estimate_motion = samples[i].estimate.Inverse() * samples[j].estimate;
      const SE2 error = truth_motion.Inverse() * estimate_motion;
      trans.Add(error.translation().norm());
      yaw.Add(std::abs(error.yaw()));
    }
    const std::string prefix = "rpe_" + std::to_string(distance_m) + "m_";
    out[prefix + "trans_rmse_m"] = OrNull(trans.rms(), Metres);
    out[prefix + "yaw_rmse_rad"] = OrNull(yaw.rms(), Rad);
    out[prefix + "pairs"] = trans.count;
  }

  const Vector3d final_error = PoseError(samples.back().estimate, samples.back().truth);
  out["final_position_error_m"] = Metres(final_error.head<2>().norm());
  out["final_yaw_error_rad"] = Rad(std::abs(final_error.z()));

  // NEES over 3 dof; samples whose covariance is not positive definite (the shared start pose
  // has a zero covariance) are skipped and counted.
  const double sample_low = ChiSquareQuantile(3, kBandLowerTail);
  const double sample_high = ChiSquareQuantile(3, kBandUpperTail);
  std::size_t used = 0;
  std::size_t in_band = 0;
  double sum = 0.0;
  for (const MatchedSample& s : samples) {
    const std::optional<double> nees = Nees(PoseError(s.estimate, s.truth), s.covariance);
    if (!nees) continue;
    ++used;
    sum += *nees;
    if (*nees >= sample_low && *nees <= sample_high) ++in_band;
  }
  out["nees_samples"] = used;
  out["nees_skipped"] = samples.size() - used;
  if (used == 0) {
    out["nees_mean"] = nullptr;
    out["nees_in_band_fraction"] = nullptr;
    out["nees_mean_band_low"] = nullptr;
    out["nees_mean_band_high"] = nullptr;
    return;
  }
  const double n = static_cast<double>(used);
  out["nees_mean"] = Ratio(sum / n);
  out["nees_in_band_fraction"] = Fraction(in_band, used);
  // The average of N independent NEES values times N is chi2(3N).
  out["nees_mean_band_low"] = Ratio(ChiSquareQuantile(3 * n, kBandLowerTail) / n);
  out["nees_mean_band_high"] = Ratio(ChiSquareQuantile(3 * n, kBandUpperTail) / n);
}

// ---- NIS ----------------------------------------------------------------------------------------

void AddNisMetrics(const std::vector<slam::Innovation>& innovations, Json& out) {
  Json nis = Json::object();
  for (const LandmarkType type : kAllTypes) {
    std::size_t count = 0;
    std::size_t gated = 0;
    std::size_t in_band = 0;
    double sum = 0.0;
    double dof_sum = 0.0;
    for (const slam::Innovation& innovation : innovations) {
      if (innovation.type != type) continue;
      CheckOrDie(innovation.dof > 0, "an innovation has no degrees of freedom");
      if (!innovation.accepted) {
        ++gated;
        continue;
      }
      ++count;
      sum += innovation.nis;
      dof_sum += innovation.dof;
      if (innovation.nis >= ChiSquareQuantile(innovation.dof, kBandLowerTail) &&
          innovation.nis <= ChiSquareQuantile(innovation.dof, kBandUpperTail)) {
        ++in_band;
      }
    }
    if (count == 0 && gated == 0) continue;
    Json t;
    t["count"] = count;
    t["gated"] = gated;
    if (count == 0) {
      t["mean"] = nullptr;
      t["in_band_fraction"] = nullptr;
      t["mean_band_low"] = nullptr;
      t["mean_band_high"] = nullptr;
    } else {
      const double n = static_cast<double>(count);
      t["mean"] = Ratio(sum / n);
      t["in_band_fraction"] = Fraction(in_band, count);
      // The sum of independent chi2(d_i) is chi2(sum d_i).
      t["mean_band_low"] = Ratio(ChiSquareQuantile(dof_sum, kBandLowerTail) / n);
      t["mean_band_high"] = Ratio(ChiSquareQuantile(dof_sum, kBandUpperTail) / n);
    }
    nis[slam::LandmarkTypeName(type)] = std::move(t);
  }
  if (!nis.empty()) out["nis"] = std::move(nis);
}

// ---- Matching -----------------------------------------------------------------------------------

// One-to-one greedy matching: candidates in ascending cost (ties by indices), each side used once.
struct Candidate {
  double cost = 0.0;
  std::size_t a = 0;
  std::size_t b = 0;
};
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

// A ground-truth landmark in the world frame.
struct TruthLandmark {
  int id = 0;
  Vector3d position_in_world;
  std::string label;  // door plates: room number
};

// Door: the midpoint of its two columns on the wall face, at the underside of the top bar.
// Lamps: lit or not, plus the apparent (mirrored) lamp of each reflector (P3 treats it as a lamp).
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

// Truth of one frame of `type`: id and the pixel a detection of it is compared with.
struct TruthPixel {
  int id = 0;
  Vector2d pixel;
};
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

// Where a detection is in its image: doors by the centre of their box, the rest by their pixel.
Vector2d DetectionPixel(const slam::Detection& d) {
  if (d.type == LandmarkType::kDoor) return 0.5 * (d.box_px.head<2>() + d.box_px.tail<2>());
  return d.pixel;
}

using FrameKey = std::pair<std::string, TimeNs>;  // camera id, stamp

// What one pipeline is measured against.
struct PipelineContext {
  const worlds::World* world = nullptr;
  const MetricsOptions* options = nullptr;
  std::map<FrameKey, const render::FrameTruth*> frames;  // of the cameras the pipeline used
};

bool HasType(const PipelineRecord& p, LandmarkType type) {
  return std::any_of(p.landmarks.begin(), p.landmarks.end(),
                     [type](const slam::LandmarkEstimate& l) { return l.type == type; }) ||
         std::any_of(p.detections.begin(), p.detections.end(),
                     [type](const slam::Detection& d) { return d.type == type; });
}

// Map matching of one type: estimated landmark id -> ground-truth id.
struct MapMatch {
  std::map<int, int> truth_of_estimate;
};

MapMatch AddMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                       LandmarkType type, Json& out) {
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

  Json m;
  m["estimated"] = estimates.size();
  m["matched"] = matches.size();
  m["spurious"] = estimates.size() - matches.size();
  // Observed: ground truth that appears in a frame the pipeline processed; only these can be
  // missed (the rest of the world was never in view).
  if (context.frames.empty()) {
    m["observed"] = nullptr;
    m["missed"] = nullptr;
  } else {
    std::set<int> observed;
    for (const auto& [key, frame] : context.frames) {
      for (const TruthPixel& t : FrameTruthPixels(*frame, type)) observed.insert(t.id);
    }
    std::size_t missed = 0;
    for (const int id : observed) missed += matched_truth.count(id) == 0 ? 1 : 0;
    m["observed"] = observed.size();
    m["missed"] = missed;
  }
  m["mean_error_m"] = OrNull(error.mean(), Metres);
  m["rmse_m"] = OrNull(error.rms(), Metres);
  m["max_error_m"] = OrNull(error.maximum(), Metres);
  if (type == LandmarkType::kCorner || type == LandmarkType::kLamp) {
    m["z_rmse_m"] = OrNull(z_error.rms(), Metres);
  }
  if (type == LandmarkType::kDoorPlate) {
    m["room_number_accuracy"] = Fraction(labels_agree, matches.size());
  }
  out[slam::LandmarkTypeName(type)] = std::move(m);
  return result;
}

// Data association of one type. A detection's true identity is the nearest truth of its type in
// the frame truth of its camera and stamp (within identity_gate_px). The detection that created
// the landmark its identity matched is the initialisation, not an association decision.
void AddAssociationMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                           LandmarkType type, const MapMatch& map, Json& out) {
  std::map<int, int> estimate_of_truth;
  for (const auto& [estimate, truth] : map.truth_of_estimate) estimate_of_truth[truth] = estimate;
  std::size_t associations = 0;
  std::size_t correct = 0;
  std::size_t possible = 0;
  std::size_t unverifiable = 0;
  for (const slam::Detection& d : pipeline.detections) {
    if (d.type != type) continue;
    const auto frame = context.frames.find({d.camera_id, d.stamp_ns});
    const bool to_unknown_landmark =
        d.landmark_id >= 0 && map.truth_of_estimate.count(d.landmark_id) == 0 &&
        std::none_of(pipeline.landmarks.begin(), pipeline.landmarks.end(),
                     [&d](const slam::LandmarkEstimate& l) { return l.id == d.landmark_id; });
    if (frame == context.frames.end() || to_unknown_landmark) {
      // No truth for its frame, or its landmark is not in the final map (deleted).
      ++unverifiable;
      continue;
    }
    std::optional<int> identity;
    double best_px = context.options->identity_gate_px;
    for (const TruthPixel& t : FrameTruthPixels(*frame->second, type)) {
      const double distance_px = (t.pixel - DetectionPixel(d)).norm();
      if (distance_px <= best_px) {
        best_px = distance_px;
        identity = t.id;
      }
    }
    const auto mapped = map.truth_of_estimate.find(d.landmark_id);
    const bool maps_to_identity =
        identity && mapped != map.truth_of_estimate.end() && mapped->second == *identity;
    if (d.new_landmark && maps_to_identity) continue;  // the initialisation
    const bool associated = d.landmark_id >= 0 && !d.new_landmark;
    if (associated) ++associations;
    if (associated && maps_to_identity) ++correct;
    if (identity && estimate_of_truth.count(*identity) != 0) ++possible;
  }
  Json a;
  a["associations"] = associations;
  a["correct"] = correct;
  a["possible"] = possible;
  a["unverifiable"] = unverifiable;
  a["precision"] = Fraction(correct, associations);
  a["recall"] = Fraction(correct, possible);
  out[slam::LandmarkTypeName(type)] = std::move(a);
}

// ---- Detectors ----------------------------------------------------------------------------------

double BoxIou(const Vector4d& a, const Vector4d& b) {
  const double w = std::min(a[2], b[2]) - std::max(a[0], b[0]);
  const double h = std::min(a[3], b[3]) - std::max(a[1], b[1]);
  if (w <= 0.0 || h <= 0.0) return 0.0;
  const double inter = w * h;
  const double area_a = (a[2] - a[0]) * (a[3] - a[1]);
  const double area_b = (b[2] - b[0]) * (b[3] - b[1]);
  return inter / (area_a + area_b - inter);
}

// Detections of `type` grouped by frame, and the frames of the cameras that produced any.
struct DetectionsByFrame {
  std::map<FrameKey, std::vector<const slam::Detection*>> by_frame;
  std::vector<std::pair<FrameKey, const render::FrameTruth*>> frames;  // truth frames to score
  std::size_t without_truth = 0;  // detections whose frame has no truth
};
DetectionsByFrame GroupDetections(const PipelineRecord& pipeline, const PipelineContext& context,
                                  LandmarkType type) {
  DetectionsByFrame out;
  std::set<std::string> cameras;
  for (const slam::Detection& d : pipeline.detections) {
    if (d.type != type) continue;
    cameras.insert(d.camera_id);
    if (context.frames.count({d.camera_id, d.stamp_ns}) == 0) {
      ++out.without_truth;
      continue;
    }
    out.by_frame[{d.camera_id, d.stamp_ns}].push_back(&d);
  }
  for (const auto& [key, frame] : context.frames) {
    if (cameras.count(key.first) != 0) out.frames.emplace_back(key, frame);
  }
  return out;
}

// Hits, false alarms and misses of one detector; truth that is hard to see (cut by the border,
// mostly hidden) is neither hit nor missed when matched or not.
struct DetectorCounts {
  std::size_t detections = 0;
  std::size_t true_positives = 0;
  std::size_t false_positives = 0;
  std::size_t false_negatives = 0;
  std::size_t ignored = 0;  // detections matched to truth that is not detectable
};
void AddCounts(const DetectorCounts& c, std::size_t without_truth, Json& out) {
  out["detections"] = c.detections;
  out["true_positives"] = c.true_positives;
  out["false_positives"] = c.false_positives;
  out["false_negatives"] = c.false_negatives;
  out["ignored"] = c.ignored;
  out["without_truth"] = without_truth;
  out["precision"] = Fraction(c.true_positives, c.true_positives + c.false_positives);
  out["recall"] = Fraction(c.true_positives, c.true_positives + c.false_negatives);
}

// Scores the frames of one type: `cost(detection, truth index)` gives a match cost or none.
template <class Truth, class CostFn, class DetectableFn, class HitFn>
DetectorCounts ScoreFrames(const DetectionsByFrame& grouped,
                           const std::vector<Truth>& (*truth_of)(const render::FrameTruth&),
                           CostFn cost, DetectableFn detectable, HitFn on_hit) {
  DetectorCounts counts;
  static const std::vector<const slam::Detection*> kNone;
  for (const auto& [key, frame] : grouped.frames) {
    const auto it = grouped.by_frame.find(key);
    const std::vector<const slam::Detection*>& detections =
        it == grouped.by_frame.end() ? kNone : it->second;
    const std::vector<Truth>& truth = truth_of(*frame);
    std::vector<Candidate> candidates;
    for (std::size_t a = 0; a < detections.size(); ++a) {
      for (std::size_t b = 0; b < truth.size(); ++b) {
        if (const std::optional<double> c = cost(*detections[a], truth[b])) {
          candidates.push_back({*c, a, b});
        }
      }
    }
    const auto matches = GreedyMatch(std::move(candidates), detections.size(), truth.size());
    std::vector<bool> truth_matched(truth.size(), false);
    counts.detections += detections.size();
    for (const auto& [a, b] : matches) {
      truth_matched[b] = true;
      if (detectable(truth[b])) {
        ++counts.true_positives;
        on_hit(*detections[a], truth[b]);
      } else {
        ++counts.ignored;
      }
    }
    counts.false_positives += detections.size() - matches.size();
    for (std::size_t b = 0; b < truth.size(); ++b) {
      if (!truth_matched[b] && detectable(truth[b])) ++counts.false_negatives;
    }
  }
  return counts;
}

const std::vector<render::PlateTruth>& PlatesOf(const render::FrameTruth& f) { return f.plates; }
const std::vector<render::LampTruth>& LampsOf(const render::FrameTruth& f) { return f.lamps; }
const std::vector<render::DoorTruth>& DoorsOf(const render::FrameTruth& f) { return f.doors; }

Json PlateDetectorMetrics(const PipelineRecord& pipeline, const PipelineContext& context) {
  const DetectionsByFrame grouped = GroupDetections(pipeline, context, LandmarkType::kDoorPlate);
  const MetricsOptions& options = *context.options;
  Stats iou;
  std::size_t read = 0;
  std::size_t read_correctly = 0;
  const DetectorCounts counts = ScoreFrames<render::PlateTruth>(
      grouped, PlatesOf,
      [&](const slam::Detection& d, const render::PlateTruth& t) -> std::optional<double> {
        const Vector4d box(t.bbox_min_px.x(), t.bbox_min_px.y(), t.bbox_max_px.x(),
                           t.bbox_max_px.y());
        const double value = BoxIou(d.box_px, box);
        if (value < options.min_box_iou) return std::nullopt;
        return -value;
      },
      [&](const render::PlateTruth& t) {
        return t.fully_in_image && t.visible_fraction >= options.min_visible_fraction;
      },
      [&](const slam::Detection& d, const render::PlateTruth& t) {
        const Vector4d box(t.bbox_min_px.x(), t.bbox_min_px.y(), t.bbox_max_px.x(),
                           t.bbox_max_px.y());
        iou.Add(BoxIou(d.box_px, box));
        if (!d.label.empty()) {
          ++read;
          if (d.label == t.room_number) ++read_correctly;
        }
      });
  Json out;
  AddCounts(counts, grouped.without_truth, out);
  out["mean_iou"] = OrNull(iou.mean(), Ratio);
  out["room_number_read_fraction"] = Fraction(read, counts.true_positives);
  out["room_number_accuracy"] = Fraction(read_correctly, read);
  return out;
}

Json LampDetectorMetrics(const PipelineRecord& pipeline, const PipelineContext& context) {
  const DetectionsByFrame grouped = GroupDetections(pipeline, context, LandmarkType::kLamp);
  const MetricsOptions& options = *context.options;
  Stats centre_error;
  const DetectorCounts counts = ScoreFrames<render::LampTruth>(
      grouped, LampsOf,
      [&](const slam::Detection& d, const render::LampTruth& t) -> std::optional<double> {
        const double distance_px = (d.pixel - t.center_px).norm();
        if (distance_px > std::max(t.radius_px, options.min_gate_px)) return std::nullopt;
        return distance_px;
      },
      [&](const render::LampTruth& t) {
        return t.on && !t.cut_by_border && t.visible_fraction >= options.min_visible_fraction;
      },
      [&](const slam::Detection& d, const render::LampTruth& t) {
        centre_error.Add((d.pixel - t.center_px).norm());
      });
  Json out;
  AddCounts(counts, grouped.without_truth, out);
  out["mean_center_error_px"] = OrNull(centre_error.mean(), Px);
  out["rmse_center_error_px"] = OrNull(centre_error.rms(), Px);
  return out;
}

Json DoorDetectorMetrics(const PipelineRecord& pipeline, const PipelineContext& context) {
  const DetectionsByFrame grouped = GroupDetections(pipeline, context, LandmarkType::kDoor);
  const MetricsOptions& options = *context.options;
  std::size_t with_state = 0;
  std::size_t state_correct = 0;
  const DetectorCounts counts = ScoreFrames<render::DoorTruth>(
      grouped, DoorsOf,
      [&](const slam::Detection& d, const render::DoorTruth& t) -> std::optional<double> {
        const Vector2d centre_px = 0.5 * (t.column_a_px + t.column_b_px);
        const double gate_px =
            std::max(0.5 * (t.column_a_px - t.column_b_px).norm(), options.min_gate_px);
        const double distance_px = (DetectionPixel(d) - centre_px).norm();
        if (distance_px > gate_px) return std::nullopt;
        return distance_px;
      },
      [](const render::DoorTruth& t) { return t.visible; },
      [&](const slam::Detection& d, const render::DoorTruth& t) {
        if (!d.open) return;
        ++with_state;
        // An empty doorway (no leaf) is open.
        if (*d.open == (t.state != worlds::DoorState::kClosed)) ++state_correct;
      });
  Json out;
  AddCounts(counts, grouped.without_truth, out);
  out["open_state_accuracy"] = Fraction(state_correct, with_state);
  return out;
}

// Vanishing point: each detection against the nearest in-image truth VP of its frame; frames
// whose camera is inside a corridor whose VP is in the image count as detectable.
Json VanishingPointMetrics(const PipelineRecord& pipeline, const PipelineContext& context) {
  const DetectionsByFrame grouped =
      GroupDetections(pipeline, context, LandmarkType::kVanishingPoint);
  Stats error;
  Stats u_error;
  std::size_t without_vp = 0;
  std::size_t detectable_frames = 0;
  std::size_t detected_frames = 0;
  for (const auto& [key, frame] : grouped.frames) {
    const auto it = grouped.by_frame.find(key);
    const bool detectable = std::any_of(
        frame->vanishing_points.begin(), frame->vanishing_points.end(),
        [](const render::VanishingPointTruth& v) { return v.in_image && v.camera_in_segment; });
    if (detectable) ++detectable_frames;
    if (it == grouped.by_frame.end()) continue;
    if (detectable) ++detected_frames;
    for (const slam::Detection* d : it->second) {
      const render::VanishingPointTruth* nearest = nullptr;
      for (const render::VanishingPointTruth& v : frame->vanishing_points) {
        if (!v.in_image) continue;
        if (nearest == nullptr ||
            (v.pixel - d->pixel).squaredNorm() < (nearest->pixel - d->pixel).squaredNorm()) {
          nearest = &v;
        }
      }
      if (nearest == nullptr) {
        ++without_vp;
        continue;
      }
      error.Add((nearest->pixel - d->pixel).norm());
      u_error.Add(std::abs(nearest->pixel.x() - d->pixel.x()));
    }
  }
  Json out;
  out["count"] = error.count;
  out["without_truth"] = grouped.without_truth + without_vp;
  out["mean_error_px"] = OrNull(error.mean(), Px);
  out["rmse_error_px"] = OrNull(error.rms(), Px);
  out["mean_abs_u_error_px"] = OrNull(u_error.mean(), Px);
  out["detected_frame_fraction"] = Fraction(detected_frames, detectable_frames);
  return out;
}

void AddTimingMetrics(const PipelineRecord& pipeline, const PipelineContext& context, Json& out) {
  // Frames the pipeline processed: distinct (camera, stamp) of the cameras it used.
  const std::size_t frames = context.frames.size();
  const std::size_t steps = pipeline.estimates.size();
  double total_s = 0.0;
  Json stage_seconds = Json::object();
  for (const auto& [stage, seconds] : pipeline.stage_seconds) {
    stage_seconds[stage] = Seconds(seconds);
    total_s += seconds;
  }
  Json t;
  t["frames"] = frames;
  t["steps"] = steps;
  t["stage_seconds"] = std::move(stage_seconds);
  if (frames > 0) {
    Json per_frame = Json::object();
    for (const auto& [stage, seconds] : pipeline.stage_seconds) {
      per_frame[stage] = Ms(seconds * 1e3 / static_cast<double>(frames));
    }
    t["stage_ms_per_frame"] = std::move(per_frame);
    t["total_ms_per_frame"] = Ms(total_s * 1e3 / static_cast<double>(frames));
  } else {
    t["total_ms_per_frame"] = nullptr;
  }
  t["total_ms_per_step"] = steps > 0 ? Ms(total_s * 1e3 / static_cast<double>(steps)) : Json();
  out["timing"] = std::move(t);
}

Json PipelineMetrics(const MetricsInput& input, const PipelineRecord& pipeline) {
  PipelineContext context;
  context.world = input.world;
  context.options = &input.options;
  const std::set<std::string> cameras(pipeline.cameras_used.begin(), pipeline.cameras_used.end());
  for (const FrameTruthSample& f : input.frames) {
    if (cameras.count(f.truth.camera_id) != 0) {
      context.frames[{f.truth.camera_id, f.stamp_ns}] = &f.truth;
    }
  }

  Json out;
  AddTrajectoryMetrics(MatchToTruth(input.truth, pipeline.estimates), out);
  AddNisMetrics(pipeline.innovations, out);

  Json map = Json::object();
  Json association = Json::object();
  for (const LandmarkType type : kMapTypes) {
    if (!HasType(pipeline, type)) continue;
    const MapMatch matched = AddMapMetrics(pipeline, context, type, map);
    if (!context.frames.empty() &&
        std::any_of(pipeline.detections.begin(), pipeline.detections.end(),
                    [type](const slam::Detection& d) { return d.type == type; })) {
      AddAssociationMetrics(pipeline, context, type, matched, association);
    }
  }
  if (!map.empty()) out["map"] = std::move(map);
  if (!association.empty()) out["data_association"] = std::move(association);

  Json detection = Json::object();
  if (!context.frames.empty()) {
    const auto has = [&pipeline](LandmarkType type) {
      return std::any_of(pipeline.detections.begin(), pipeline.detections.end(),
                         [type](const slam::Detection& d) { return d.type == type; });
    };
    if (has(LandmarkType::kVanishingPoint)) {
      detection["vanishing_point"] = VanishingPointMetrics(pipeline, context);
    }
    if (has(LandmarkType::kDoorPlate)) {
      detection["door_plate"] = PlateDetectorMetrics(pipeline, context);
    }
    if (has(LandmarkType::kLamp)) detection["lamp"] = LampDetectorMetrics(pipeline, context);
    if (has(LandmarkType::kDoor)) detection["door"] = DoorDetectorMetrics(pipeline, context);
  }
  if (!detection.empty()) out["detection"] = std::move(detection);

  AddTimingMetrics(pipeline, context, out);
  out["health"] = {{"non_positive_covariance", pipeline.health.non_positive_covariance},
                   {"rejected_updates", pipeline.health.rejected_updates}};
  return out;
}

Json RunMetrics(const MetricsInput& input) {
  Json run;
  double wall_total_s = 0.0;
  Json wall = Json::object();
  for (const auto& [stage, seconds] : input.timing.wall_seconds) {
    wall[stage] = Seconds(seconds);
    wall_total_s += seconds;
  }
  run["sim_seconds"] = Seconds(input.timing.sim_seconds);
  run["wall_seconds"] = std::move(wall);
  run["wall_total_s"] = Seconds(wall_total_s);
  if (wall_total_s > 0.0) {
    run["real_time_factor"] = Ratio(input.timing.sim_seconds / wall_total_s);
    Json fraction = Json::object();
    for (const auto& [stage, seconds] : input.timing.wall_seconds) {
      fraction[stage] = Ratio(seconds / wall_total_s);
    }
    run["wall_fraction"] = std::move(fraction);
  } else {
    run["real_time_factor"] = nullptr;
  }
  return run;
}

// ---- Expectations -------------------------------------------------------------------------------

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t");
  return s.substr(begin, end - begin + 1);
}

}  // namespace

nlohmann::ordered_json ComputeMetrics(const MetricsInput& input) {
  CheckOrDie(input.world != nullptr, "input.world is null");
  Json out;
  out["schema_version"] = 1;
  out["run"] = RunMetrics(input);
  std::map<std::string, std::size_t> frames_per_camera;
  for (const FrameTruthSample& f : input.frames) ++frames_per_camera[f.truth.camera_id];
  out["frames"] = {{"count", input.frames.size()}, {"per_camera", frames_per_camera}};
  Json pipelines = Json::object();
  for (const PipelineRecord& pipeline : input.pipelines) {
    CheckOrDie(!pipelines.contains(pipeline.name), "two pipelines share a name");
    pipelines[pipeline.name] = PipelineMetrics(input, pipeline);
  }
  out["pipelines"] = std::move(pipelines);
  return out;
}

std::string ErrorSeriesCsv(const std::vector<TruthPose>& truth, const PipelineRecord& pipeline) {
  std::string csv = "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n";
  char line[256];
  for (const MatchedSample& s : MatchToTruth(truth, pipeline.estimates).samples) {
    const Vector3d e = PoseError(s.estimate, s.truth);
    const Vector3d sigma = s.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    std::snprintf(line, sizeof(line), "%.9f,%.6f,%.6f,%.8f,%.6f,%.6f,%.8f,", ToSeconds(s.stamp_ns),
                  RoundDiv(e.x(), 1e6), RoundDiv(e.y(), 1e6), RoundDiv(e.z(), 1e8),
                  RoundDiv(sigma.x(), 1e6), RoundDiv(sigma.y(), 1e6), RoundDiv(sigma.z(), 1e8));
    csv += line;
    if (const std::optional<double> nees = Nees(e, s.covariance)) {
      std::snprintf(line, sizeof(line), "%.6f", RoundDiv(*nees, 1e6));
      csv += line;
    }
    csv += '\n';
  }
  return csv;
}

std::vector<std::string> MetricNames() {
  std::vector<std::string> names = {"samples",
                                    "samples_without_truth",
                                    "distance_travelled_m",
                                    "ate_rmse_m",
                                    "ate_mean_m",
                                    "ate_max_m",
                                    "ate_yaw_rmse_rad",
                                    "ate_aligned_rmse_m",
                                    "ate_aligned_mean_m",
                                    "ate_aligned_max_m",
                                    "alignment.x_m",
                                    "alignment.y_m",
                                    "alignment.yaw_rad"};
  for (const int d : kRpeDistancesM) {
    const std::string prefix = "rpe_" + std::to_string(d) + "m_";
    names.push_back(prefix + "trans_rmse_m");
    names.push_back(prefix + "yaw_rmse_rad");
    names.push_back(prefix + "pairs");
  }
  for (const char* n :
       {"final_position_error_m", "final_yaw_error_rad", "nees_samples", "nees_skipped",
        "nees_mean", "nees_in_band_fraction", "nees_mean_band_low", "nees_mean_band_high"}) {
    names.emplace_back(n);
  }
  for (const LandmarkType type : kAllTypes) {
    for (const char* n :
         {"count", "gated", "mean", "in_band_fraction", "mean_band_low", "mean_band_high"}) {
      names.push_back("nis." + slam::LandmarkTypeName(type) + "." + n);
    }
  }
  for (const LandmarkType type : kMapTypes) {
    const std::string prefix = "map." + slam::LandmarkTypeName(type) + ".";
    for (const char* n : {"estimated", "matched", "spurious", "observed", "missed", "mean_error_m",
                          "rmse_m", "max_error_m"}) {
      names.push_back(prefix + n);
    }
    if (type == LandmarkType::kCorner || type == LandmarkType::kLamp) {
      names.push_back(prefix + "z_rmse_m");
    }
    if (type == LandmarkType::kDoorPlate) names.push_back(prefix + "room_number_accuracy");
  }
  for (const LandmarkType type : kMapTypes) {
    for (const char* n :
         {"associations", "correct", "possible", "unverifiable", "precision", "recall"}) {
      names.push_back("data_association." + slam::LandmarkTypeName(type) + "." + n);
    }
  }
  for (const char* n : {"count", "without_truth", "mean_error_px", "rmse_error_px",
                        "mean_abs_u_error_px", "detected_frame_fraction"}) {
    names.push_back(std::string("detection.vanishing_point.") + n);
  }
  for (const char* type : {"door_plate", "lamp", "door"}) {
    for (const char* n : {"detections", "true_positives", "false_positives", "false_negatives",
                          "ignored", "without_truth", "precision", "recall"}) {
      names.push_back(std::string("detection.") + type + "." + n);
    }
  }
  for (const char* n : {"mean_iou", "room_number_read_fraction", "room_number_accuracy"}) {
    names.push_back(std::string("detection.door_plate.") + n);
  }
  names.emplace_back("detection.lamp.mean_center_error_px");
  names.emplace_back("detection.lamp.rmse_center_error_px");
  names.emplace_back("detection.door.open_state_accuracy");
  for (const char* n :
       {"timing.frames", "timing.steps", "timing.total_ms_per_frame", "timing.total_ms_per_step",
        "health.non_positive_covariance", "health.rejected_updates"}) {
    names.emplace_back(n);
  }
  return names;
}

std::optional<std::string> ParseExpectation(const std::string& text, Expectation* out) {
  const std::string where = " in expectation '" + text + "'";
  const auto op_begin = text.find_first_of("<>=!");
  if (op_begin == std::string::npos) {
    return "no comparison (use <, <=, > or >=)" + where;
  }
  const auto op_end = text.find_first_not_of("<>=!", op_begin);
  const std::string op = text.substr(op_begin, op_end - op_begin);
  Expectation e;
  if (op == "<") {
    e.op = Expectation::Op::kLess;
  } else if (op == "<=") {
    e.op = Expectation::Op::kLessEqual;
  } else if (op == ">") {
    e.op = Expectation::Op::kGreater;
  } else if (op == ">=") {
    e.op = Expectation::Op::kGreaterEqual;
  } else {
    return "bad operator '" + op + "' (use <, <=, > or >=)" + where;
  }
  const std::string left = Trim(text.substr(0, op_begin));
  const auto dot = left.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == left.size()) {
    return "expected <pipeline>.<metric> before '" + op + "'" + where;
  }
  e.pipeline = left.substr(0, dot);
  e.metric = left.substr(dot + 1);
  const std::vector<std::string> names = MetricNames();
  if (std::find(names.begin(), names.end(), e.metric) == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    return "unknown metric '" + e.metric + "' (known: " + known + ")" + where;
  }
  const std::string number =
      op_end == std::string::npos ? std::string() : Trim(text.substr(op_end));
  const char* first = number.data();
  const char* last = number.data() + number.size();
  const auto [ptr, ec] = std::from_chars(first, last, e.value);
  if (number.empty() || ec != std::errc() || ptr != last || !std::isfinite(e.value)) {
    return "'" + number + "' is not a number" + where;
  }
  e.text = text;
  *out = e;
  return std::nullopt;
}

std::vector<ExpectationResult> CheckExpectations(const nlohmann::ordered_json& metrics,
                                                 const std::vector<Expectation>& expectations) {
  std::vector<ExpectationResult> results;
  for (const Expectation& e : expectations) {
    ExpectationResult r;
    r.expectation = e;
    const Json* node = nullptr;
    if (metrics.contains("pipelines") && metrics["pipelines"].contains(e.pipeline)) {
      node = &metrics["pipelines"][e.pipeline];
      std::size_t begin = 0;
      while (node != nullptr) {
        const auto dot = e.metric.find('.', begin);
        const std::string key = e.metric.substr(begin, dot - begin);
        node = node->is_object() && node->contains(key) ? &(*node)[key] : nullptr;
        if (dot == std::string::npos) break;
        begin = dot + 1;
      }
    }
    if (node != nullptr && node->is_number()) {
      const double v = node->get<double>();
      r.measured = v;
      switch (e.op) {
        case Expectation::Op::kLess:
          r.passed = v < e.value;
          break;
        case Expectation::Op::kLessEqual:
          r.passed = v <= e.value;
          break;
        case Expectation::Op::kGreater:
          r.passed = v > e.value;
          break;
        case Expectation::Op::kGreaterEqual:
          r.passed = v >= e.value;
          break;
      }
    }
    results.push_back(std::move(r));
  }
  return results;
}

}  // namespace corridorsim
