// Tests scenarios/metrics.cpp: trajectory errors (ATE unaligned and aligned, RPE), NEES and NIS
// consistency, map matching, data association, detector scores, expectations and the error CSV,
// each on a constructed case whose answer is known in closed form.
#include "harness/metrics.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <catch2/catch.hpp>

#include "common/random.h"
#include "tests/support/tolerances.h"

namespace corridorsim {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector4d;
using Json = nlohmann::ordered_json;
using slam::LandmarkType;

constexpr TimeNs kGridNs = 10'000'000;  // the 100 Hz truth grid

// A left-turning arc at 1 m/s: radius 20 m, sampled on the truth grid for `seconds`.
std::vector<TruthPose> ArcTruth(double seconds) {
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
PipelineRecord Record(const std::string& name, const std::vector<TruthPose>& truth,
                      const std::function<SE2(const SE2&)>& f,
                      const Matrix3d& covariance = Matrix3d::Identity() * 1e-2) {
  PipelineRecord record;
  record.name = name;
  for (std::size_t k = 0; k < truth.size(); k += 2) {
    record.estimates.push_back({truth[k].stamp_ns, f(truth[k].world_from_robot), covariance});
  }
  return record;
}

Json RunOne(const worlds::World& world, const std::vector<TruthPose>& truth,
            const PipelineRecord& record, std::vector<FrameTruthSample> frames = {}) {
  MetricsInput input;
  input.world = &world;
  input.truth = truth;
  input.frames = std::move(frames);
  input.pipelines = {record};
  return ComputeMetrics(input)["pipelines"][record.name];
}

double Num(const Json& j) { return j.get<double>(); }

TEST_CASE("identical trajectories give zero errors", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Json m = RunOne(world, truth, Record("same", truth, [](const SE2& p) { return p; }));
  CHECK(m["samples"] == 1001);
  CHECK(m["samples_without_truth"] == 0);
  CHECK(Num(m["distance_travelled_m"]) == Approx(20.0).margin(test::kMetricsJsonM));
  for (const char* key :
       {"ate_rmse_m", "ate_mean_m", "ate_max_m", "ate_aligned_rmse_m", "ate_aligned_max_m",
        "rpe_1m_trans_rmse_m", "rpe_10m_trans_rmse_m", "final_position_error_m"}) {
    INFO(key);
    CHECK(Num(m[key]) == 0.0);
  }
  CHECK(Num(m["ate_yaw_rmse_rad"]) == 0.0);
  CHECK(Num(m["rpe_5m_yaw_rmse_rad"]) == 0.0);
  CHECK(m["rpe_10m_pairs"].get<int>() > 0);
  CHECK(Num(m["nees_mean"]) == 0.0);
  // Nothing to map, no innovations, no frames: those metrics are absent, never invented.
  CHECK_FALSE(m.contains("map"));
  CHECK_FALSE(m.contains("nis"));
  CHECK_FALSE(m.contains("data_association"));
  CHECK_FALSE(m.contains("detection"));
  CHECK(m["timing"]["total_ms_per_frame"].is_null());
}

TEST_CASE("a constant offset gives that ATE unaligned and none aligned", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Json m = RunOne(world, truth, Record("offset", truth, [](const SE2& p) {
                          return SE2(p.x() + 0.3, p.y() - 0.4, p.yaw());
                        }));
  CHECK(Num(m["ate_rmse_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_mean_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_max_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["final_position_error_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_aligned_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["x_m"]) == Approx(-0.3).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["y_m"]) == Approx(0.4).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["yaw_rad"]) == Approx(0.0).margin(test::kMetricsJsonRad));
  // A translation does not change any relative motion.
  CHECK(Num(m["rpe_1m_trans_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
}

TEST_CASE("a rotated and translated copy aligns to zero error", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const SE2 copy_from_truth(2.0, -1.0, 0.7);
  const Json m = RunOne(world, truth,
                        Record("moved", truth, [&](const SE2& p) { return copy_from_truth * p; }));
  CHECK(Num(m["ate_rmse_m"]) > 1.0);
  CHECK(Num(m["ate_aligned_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_aligned_max_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  const SE2 truth_from_copy = copy_from_truth.Inverse();
  CHECK(Num(m["alignment"]["yaw_rad"]) ==
        Approx(truth_from_copy.yaw()).margin(test::kMetricsJsonRad));
  CHECK(Num(m["alignment"]["x_m"]) == Approx(truth_from_copy.x()).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["y_m"]) == Approx(truth_from_copy.y()).margin(test::kMetricsJsonM));
  // A rigid motion of the whole trajectory leaves relative motions unchanged.
  CHECK(Num(m["rpe_5m_trans_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["rpe_5m_yaw_rmse_rad"]) == Approx(0.0).margin(test::kMetricsJsonRad));
}

TEST_CASE("RPE of a heading drift grows with the distance as the drift's arc", "[metrics]") {
  // Truth drives straight along x; the estimate turns at drift_rad_per_m (a constant-curvature
  // arc), so over any d metres its relative motion is the arc's chord and turn.
  const worlds::World world;
  const double drift_rad_per_m = 0.01;
  const double step_m = 0.25;  // exact in binary: truth distances sum exactly
  std::vector<TruthPose> truth;
  PipelineRecord record;
  record.name = "drift";
  for (int k = 0; k <= 100; ++k) {
    const double s_m = step_m * k;
    truth.push_back({k * kGridNs, SE2(s_m, 0.0, 0.0)});
    const double yaw = drift_rad_per_m * s_m;
    record.estimates.push_back(
        {k * kGridNs,
         SE2(std::sin(yaw) / drift_rad_per_m, (1.0 - std::cos(yaw)) / drift_rad_per_m, yaw),
         Matrix3d::Identity()});
  }
  const Json m = RunOne(world, truth, record);
  for (const int d : {1, 5, 10}) {
    INFO("d = " << d);
    const double turn = drift_rad_per_m * d;
    const double along = std::sin(turn) / drift_rad_per_m - d;
    const double across = (1.0 - std::cos(turn)) / drift_rad_per_m;
    const std::string prefix = "rpe_" + std::to_string(d) + "m_";
    CHECK(Num(m[prefix + "yaw_rmse_rad"]) == Approx(turn).margin(test::kMetricsJsonRad));
    CHECK(Num(m[prefix + "trans_rmse_m"]) ==
          Approx(std::hypot(along, across)).margin(test::kMetricsJsonM));
    // Every start sample with d metres of truth after it.
    CHECK(m[prefix + "pairs"] == 101 - static_cast<int>(d / step_m));
  }
}

// Estimates whose errors are drawn from `covariance_k` (x, y, yaw), reported with
// covariance_k * reported_scale.
PipelineRecord DrawnEstimates(const std::vector<TruthPose>& truth, double reported_scale) {
  RandomStream random(7, 0, "tests.metrics.nees");
  PipelineRecord record;
  record.name = "drawn";
  for (std::size_t k = 0; k < truth.size(); k += 2) {
    // A covariance that changes along the run: its x-y axes turn with the robot.
    const double yaw = truth[k].world_from_robot.yaw();
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    rotation.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(yaw).toRotationMatrix();
    const double grow = 1.0 + 0.001 * static_cast<double>(k);
    const Vector3d sigma(0.2 * grow, 0.05 * grow, 0.03);
    const Matrix3d covariance = rotation * sigma.cwiseAbs2().asDiagonal() * rotation.transpose();
    const Matrix3d l = covariance.llt().matrixL();
    const Vector3d z(random.Normal(), random.Normal(), random.Normal());
    const Vector3d e = l * z;
    const SE2& t = truth[k].world_from_robot;
    record.estimates.push_back({truth[k].stamp_ns,
                                SE2(t.x() + e.x(), t.y() + e.y(), t.yaw() + e.z()),
                                covariance * reported_scale});
  }
  return record;
}

TEST_CASE("NEES of errors drawn from the covariance lands in band; an overconfident one does not",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(40.0);
  const Json good = RunOne(world, truth, DrawnEstimates(truth, 1.0));
  const double n = good["nees_samples"].get<double>();
  REQUIRE(n == 2001);
  CHECK(good["nees_skipped"] == 0);
  // The band of the mean: chi2(3N) / N, two-sided 95 %.
  const boost::math::chi_squared_distribution<double> mean_dist(3 * n);
  CHECK(Num(good["nees_mean_band_low"]) ==
        Approx(boost::math::quantile(mean_dist, 0.025) / n).margin(test::kMetricsJsonRatio));
  CHECK(Num(good["nees_mean_band_high"]) ==
        Approx(boost::math::quantile(mean_dist, 0.975) / n).margin(test::kMetricsJsonRatio));
  CHECK(Num(good["nees_mean"]) >= Num(good["nees_mean_band_low"]));
  CHECK(Num(good["nees_mean"]) <= Num(good["nees_mean_band_high"]));
  // About 95 % of the samples inside the per-sample interval (binomial bound).
  const double z = boost::math::quantile(boost::math::normal(), 0.5 + test::kStatConfidence / 2);
  const double bound = z * std::sqrt(0.95 * 0.05 / n);
  CHECK(Num(good["nees_in_band_fraction"]) == Approx(0.95).margin(bound));

  const Json overconfident = RunOne(world, truth, DrawnEstimates(truth, 0.25));
  CHECK(Num(overconfident["nees_mean"]) > Num(overconfident["nees_mean_band_high"]));
  CHECK(Num(overconfident["nees_in_band_fraction"]) < 0.95 - bound);
}

TEST_CASE("NIS is reported per landmark type over the accepted updates", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("nis", truth, [](const SE2& p) { return p; });
  // Lamps, 2 dof: 1, 2, 3 accepted (inside [0.0506, 7.38]), 0.01 accepted (below), 50 gated.
  for (const double nis : {1.0, 2.0, 3.0, 0.01}) {
    record.innovations.push_back({0, LandmarkType::kLamp, nis, 2, true});
  }
  record.innovations.push_back({0, LandmarkType::kLamp, 50.0, 2, false});
  // Doors, 1 dof: one above the interval (5.02).
  record.innovations.push_back({0, LandmarkType::kDoor, 6.0, 1, true});
  const Json m = RunOne(world, truth, record);
  REQUIRE(m.contains("nis"));
  const Json& lamp = m["nis"]["lamp"];
  CHECK(lamp["count"] == 4);
  CHECK(lamp["gated"] == 1);
  CHECK(Num(lamp["mean"]) == Approx(6.01 / 4).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamp["in_band_fraction"]) == Approx(0.75).margin(test::kMetricsJsonRatio));
  const boost::math::chi_squared_distribution<double> lamp_mean(8);  // 4 updates x 2 dof
  CHECK(Num(lamp["mean_band_low"]) ==
        Approx(boost::math::quantile(lamp_mean, 0.025) / 4).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamp["mean_band_high"]) ==
        Approx(boost::math::quantile(lamp_mean, 0.975) / 4).margin(test::kMetricsJsonRatio));
  const Json& door = m["nis"]["door"];
  CHECK(door["count"] == 1);
  CHECK(Num(door["in_band_fraction"]) == 0.0);
  CHECK_FALSE(m["nis"].contains("corner"));
}

worlds::World PlateWorld() {
  worlds::World world;
  world.plates.resize(3);
  const std::vector<Vector3d> centres = {{1, 1, 1.5}, {4, 1, 1.5}, {8, -1, 1.5}};
  for (int i = 0; i < 3; ++i) {
    world.plates[i].id = i + 1;
    world.plates[i].center = centres[i];
    world.plates[i].room_number = std::to_string(101 + i);
  }
  worlds::Lamp lamp;
  lamp.id = 4;
  lamp.center = Vector3d(2, 0, 2.5);
  world.lamps.push_back(lamp);
  return world;
}

slam::LandmarkEstimate Landmark(int id, LandmarkType type, const Vector3d& p,
                                const std::string& label = "") {
  slam::LandmarkEstimate l;
  l.id = id;
  l.type = type;
  l.position_in_world = p;
  l.label = label;
  return l;
}

render::PlateTruth PlateSeen(int id, const Vector2d& center_px) {
  render::PlateTruth p;
  p.id = id;
  p.center_px = center_px;
  return p;
}

FrameTruthSample Frame(const std::string& camera, TimeNs stamp) {
  FrameTruthSample f;
  f.stamp_ns = stamp;
  f.truth.camera_id = camera;
  return f;
}

TEST_CASE("landmark matching counts a spurious and a missed landmark and wrong room numbers",
          "[metrics]") {
  const worlds::World world = PlateWorld();
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("map", truth, [](const SE2& p) { return p; });
  record.cameras_used = {"lateral"};
  record.landmarks = {
      Landmark(10, LandmarkType::kDoorPlate, {1.1, 1.0, 1.4}, "101"),   // plate 1, 0.1 m off
      Landmark(11, LandmarkType::kDoorPlate, {4.0, 1.2, 1.5}, "999"),   // plate 2, wrong number
      Landmark(12, LandmarkType::kDoorPlate, {20.0, 0.0, 1.5}, "120"),  // nothing near: spurious
      // Two lamps near the one lamp: one-to-one leaves the farther one spurious.
      Landmark(20, LandmarkType::kLamp, {2.05, 0.0, 2.5}),
      Landmark(21, LandmarkType::kLamp, {2.3, 0.0, 2.4}),
  };
  FrameTruthSample frame = Frame("lateral", 0);
  for (int id = 1; id <= 3; ++id) frame.truth.plates.push_back(PlateSeen(id, {100.0 * id, 50}));
  const Json m = RunOne(world, truth, record, {frame});
  REQUIRE(m.contains("map"));
  const Json& plates = m["map"]["door_plate"];
  CHECK(plates["estimated"] == 3);
  CHECK(plates["matched"] == 2);
  CHECK(plates["spurious"] == 1);
  CHECK(plates["observed"] == 3);
  CHECK(plates["missed"] == 1);  // plate 3 was seen but never mapped
  CHECK(Num(plates["mean_error_m"]) == Approx(0.15).margin(test::kMetricsJsonM));
  CHECK(Num(plates["rmse_m"]) == Approx(std::sqrt(0.025)).margin(test::kMetricsJsonM));
  CHECK(Num(plates["max_error_m"]) == Approx(0.2).margin(test::kMetricsJsonM));
  CHECK(Num(plates["room_number_accuracy"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  const Json& lamps = m["map"]["lamp"];
  CHECK(lamps["matched"] == 1);
  CHECK(lamps["spurious"] == 1);
  CHECK(lamps["observed"] == 0);  // no frame saw the lamp: it cannot be missed
  CHECK(lamps["missed"] == 0);
  CHECK(Num(lamps["mean_error_m"]) == Approx(0.05).margin(test::kMetricsJsonM));
  CHECK(Num(lamps["z_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
}

slam::Detection PlateDetection(TimeNs stamp, const Vector2d& px, int landmark, bool created) {
  slam::Detection d;
  d.stamp_ns = stamp;
  d.camera_id = "lateral";
  d.type = LandmarkType::kDoorPlate;
  d.pixel = px;
  d.landmark_id = landmark;
  d.new_landmark = created;
  return d;
}

TEST_CASE("data association precision and recall count one wrong association", "[metrics]") {
  const worlds::World world = PlateWorld();
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("da", truth, [](const SE2& p) { return p; });
  record.cameras_used = {"lateral"};
  record.landmarks = {Landmark(10, LandmarkType::kDoorPlate, {1, 1, 1.5}, "101"),
                      Landmark(20, LandmarkType::kDoorPlate, {4, 1, 1.5}, "102")};
  std::vector<FrameTruthSample> frames;
  for (const TimeNs t : {1, 2, 3}) {
    FrameTruthSample f = Frame("lateral", t);
    f.truth.plates = {PlateSeen(1, {100, 200}), PlateSeen(2, {400, 200})};
    frames.push_back(f);
  }
  record.detections = {
      PlateDetection(1, {101, 200}, 10, true),   // creates the landmark of plate 1
      PlateDetection(1, {399, 201}, 20, true),   // creates the landmark of plate 2
      PlateDetection(2, {102, 199}, 10, false),  // correct
      PlateDetection(2, {401, 200}, 10, false),  // wrong: plate 2 associated with plate 1's
      PlateDetection(3, {400, 202}, 20, false),  // correct
      PlateDetection(3, {99, 200}, -1, false),   // plate 1 not associated: a miss
      PlateDetection(3, {100, 201}, 99, false),  // a landmark not in the final map
  };
  const Json m = RunOne(world, truth, record, frames);
  REQUIRE(m.contains("data_association"));
  const Json& da = m["data_association"]["door_plate"];
  CHECK(da["associations"] == 3);
  CHECK(da["correct"] == 2);
  CHECK(da["possible"] == 4);
  CHECK(da["unverifiable"] == 1);
  CHECK(Num(da["precision"]) == Approx(2.0 / 3.0).margin(test::kMetricsJsonRatio));
  CHECK(Num(da["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
}

TEST_CASE("detector precision, recall, IoU, centre error and door state against frame truth",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("detectors", truth, [](const SE2& p) { return p; });
  record.cameras_used = {"front", "lateral", "upward"};

  FrameTruthSample lateral = Frame("lateral", 5);
  const auto plate = [](int id, double x0, double x1, bool full) {
    render::PlateTruth p;
    p.id = id;
    p.room_number = std::to_string(100 + id);
    p.bbox_min_px = Vector2d(x0, 100);
    p.bbox_max_px = Vector2d(x1, 150);
    p.center_px = Vector2d((x0 + x1) / 2, 125);
    p.fully_in_image = full;
    p.visible_fraction = 1.0;
    return p;
  };
  lateral.truth.plates = {plate(1, 100, 200, true), plate(2, 300, 400, true),
                          plate(3, 600, 640, false)};  // cut by the border: not scored
  const auto plate_detection = [](const Vector4d& box, const std::string& label) {
    slam::Detection d;
    d.stamp_ns = 5;
    d.camera_id = "lateral";
    d.type = LandmarkType::kDoorPlate;
    d.box_px = box;
    d.pixel = 0.5 * (box.head<2>() + box.tail<2>());
    d.label = label;
    return d;
  };
  record.detections.push_back(plate_detection({105, 100, 205, 150}, "101"));  // IoU 4750/5250
  record.detections.push_back(plate_detection({500, 300, 520, 310}, ""));     // nothing there
  record.detections.push_back(plate_detection({600, 100, 640, 150}, "103"));  // the cut plate

  FrameTruthSample upward = Frame("upward", 5);
  const auto lamp = [](int id, const Vector2d& c, double r) {
    render::LampTruth l;
    l.id = id;
    l.center_px = c;
    l.radius_px = r;
    l.visible_fraction = 1.0;
    return l;
  };
  upward.truth.lamps = {lamp(1, {320, 240}, 20), lamp(2, {100, 100}, 15)};
  render::DoorTruth door;
  door.id = 3;
  door.state = worlds::DoorState::kOpen;
  door.column_a_px = Vector2d(200, 300);
  door.column_b_px = Vector2d(260, 300);
  door.visible = true;
  upward.truth.doors = {door};
  const auto upward_detection = [](LandmarkType type, const Vector2d& px) {
    slam::Detection d;
    d.stamp_ns = 5;
    d.camera_id = "upward";
    d.type = type;
    d.pixel = px;
    return d;
  };
  record.detections.push_back(upward_detection(LandmarkType::kLamp, {323, 244}));  // 5 px off
  record.detections.push_back(upward_detection(LandmarkType::kLamp, {500, 400}));  // nothing
  slam::Detection door_detection = upward_detection(LandmarkType::kDoor, {230, 300});
  door_detection.box_px = Vector4d(198, 290, 262, 310);
  door_detection.open = true;
  record.detections.push_back(door_detection);

  FrameTruthSample front = Frame("front", 5);
  render::VanishingPointTruth vp;
  vp.direction_in_world = Vector2d(1, 0);
  vp.pixel = Vector2d(320, 240);
  vp.in_image = true;
  vp.camera_in_segment = true;
  front.truth.vanishing_points = {vp};
  slam::Detection vp_detection;
  vp_detection.stamp_ns = 5;
  vp_detection.camera_id = "front";
  vp_detection.type = LandmarkType::kVanishingPoint;
  vp_detection.pixel = Vector2d(323, 244);
  record.detections.push_back(vp_detection);

  const Json m = RunOne(world, truth, record, {front, lateral, upward});
  REQUIRE(m.contains("detection"));
  const Json& plates = m["detection"]["door_plate"];
  CHECK(plates["detections"] == 3);
  CHECK(plates["true_positives"] == 1);
  CHECK(plates["false_positives"] == 1);
  CHECK(plates["false_negatives"] == 1);
  CHECK(plates["ignored"] == 1);
  CHECK(Num(plates["precision"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(plates["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(plates["mean_iou"]) == Approx(4750.0 / 5250.0).margin(test::kMetricsJsonRatio));
  CHECK(Num(plates["room_number_accuracy"]) == 1.0);
  const Json& lamps = m["detection"]["lamp"];
  CHECK(Num(lamps["precision"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamps["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamps["mean_center_error_px"]) == Approx(5.0).margin(test::kMetricsJsonPx));
  const Json& doors = m["detection"]["door"];
  CHECK(Num(doors["precision"]) == 1.0);
  CHECK(Num(doors["recall"]) == 1.0);
  CHECK(Num(doors["open_state_accuracy"]) == 1.0);
  const Json& vps = m["detection"]["vanishing_point"];
  CHECK(vps["count"] == 1);
  CHECK(Num(vps["mean_error_px"]) == Approx(5.0).margin(test::kMetricsJsonPx));
  CHECK(Num(vps["mean_abs_u_error_px"]) == Approx(3.0).margin(test::kMetricsJsonPx));
  CHECK(Num(vps["detected_frame_fraction"]) == 1.0);
  CHECK(m["timing"]["frames"] == 3);

  SECTION("every scalar in the pipeline's object is a known metric name") {
    const std::vector<std::string> names_list = MetricNames();
    const std::set<std::string> names(names_list.begin(), names_list.end());
    std::vector<std::string> unknown;
    std::function<void(const Json&, const std::string&)> walk = [&](const Json& j,
                                                                    const std::string& path) {
      if (j.is_object()) {
        for (const auto& [key, value] : j.items()) {
          walk(value, path.empty() ? key : path + "." + key);
        }
      } else if (path.rfind("timing.stage_", 0) != 0 && names.count(path) == 0) {
        unknown.push_back(path);
      }
    };
    walk(m, "");
    CHECK(unknown.empty());
  }
}

TEST_CASE("expectations parse '<pipeline>.<metric> <op> <number>' and reject the rest",
          "[metrics]") {
  Expectation e;
  REQUIRE_FALSE(ParseExpectation("p1_vp_doorplate.ate_rmse_m < 0.15", &e));
  CHECK(e.pipeline == "p1_vp_doorplate");
  CHECK(e.metric == "ate_rmse_m");
  CHECK(e.op == Expectation::Op::kLess);
  CHECK(e.value == 0.15);
  CHECK(e.text == "p1_vp_doorplate.ate_rmse_m < 0.15");
  REQUIRE_FALSE(ParseExpectation("p3.nis.lamp.mean>=0.5", &e));
  CHECK(e.metric == "nis.lamp.mean");
  CHECK(e.op == Expectation::Op::kGreaterEqual);
  CHECK(e.value == 0.5);

  const auto bad_op = ParseExpectation("p1.ate_rmse_m == 0.1", &e);
  REQUIRE(bad_op);
  CHECK_THAT(*bad_op, Catch::Contains("bad operator '=='"));
  REQUIRE(ParseExpectation("p1.ate_rmse_m =< 0.1", &e));
  const auto unknown = ParseExpectation("p1.ate_rmse < 0.1", &e);
  REQUIRE(unknown);
  CHECK_THAT(*unknown, Catch::Contains("unknown metric 'ate_rmse' (known: ") &&
                           Catch::Contains("ate_rmse_m"));
  const auto not_number = ParseExpectation("p1.ate_rmse_m < 0.1x", &e);
  REQUIRE(not_number);
  CHECK_THAT(*not_number, Catch::Contains("'0.1x' is not a number"));
  REQUIRE(ParseExpectation("p1.ate_rmse_m < nan", &e));
  REQUIRE(ParseExpectation("p1.ate_rmse_m <", &e));
  REQUIRE(ParseExpectation("ate_rmse_m < 1", &e));  // no pipeline
}

TEST_CASE("expectations pass, fail, and fail on a missing or null metric", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  MetricsInput input;
  input.world = &world;
  input.truth = truth;
  input.pipelines = {
      Record("offset", truth, [](const SE2& p) { return SE2(p.x() + 0.3, p.y() - 0.4, p.yaw()); }),
      // A zero covariance gives no NEES: nees_mean is null.
      Record(
          "no_cov", truth, [](const SE2& p) { return p; }, Matrix3d::Zero())};
  const Json metrics = ComputeMetrics(input);
  std::vector<Expectation> expectations;
  for (const char* text :
       {"offset.ate_rmse_m < 0.6", "offset.ate_rmse_m >= 0.6", "offset.nis.lamp.mean < 3",
        "absent.ate_rmse_m < 1", "no_cov.nees_mean < 10"}) {
    Expectation e;
    REQUIRE_FALSE(ParseExpectation(text, &e));
    expectations.push_back(e);
  }
  const std::vector<ExpectationResult> results = CheckExpectations(metrics, expectations);
  REQUIRE(results.size() == 5);
  CHECK(results[0].passed);
  CHECK(*results[0].measured == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK_FALSE(results[1].passed);
  CHECK(results[1].measured.has_value());
  for (std::size_t i = 2; i < 5; ++i) {
    INFO(results[i].expectation.text);
    CHECK_FALSE(results[i].passed);
    CHECK_FALSE(results[i].measured.has_value());
  }
}

TEST_CASE("the error series CSV has one row per estimate with errors, sigmas and NEES",
          "[metrics]") {
  const std::vector<TruthPose> truth = {
      {0, SE2(0.0, 0.0, 0.0)}, {kGridNs, SE2(1.0, 0.0, 0.2)}, {2 * kGridNs, SE2(2.0, 0.0, 0.4)}};
  PipelineRecord record;
  record.name = "csv";
  // At the start with a zero covariance (no NEES), then between grid points (truth interpolated:
  // x 1.5, yaw 0.3), then after the truth ends (no row).
  record.estimates.push_back({0, SE2(0.0, 0.0, 0.0), Matrix3d::Zero()});
  const Matrix3d covariance = Vector3d(0.04, 0.09, 0.01).asDiagonal();
  record.estimates.push_back({kGridNs + kGridNs / 2, SE2(1.6, -0.2, 0.35), covariance});
  record.estimates.push_back({3 * kGridNs, SE2(3.0, 0.0, 0.6), covariance});
  const std::string csv = ErrorSeriesCsv(truth, record);
  CHECK(csv ==
        "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n"
        "0.000000000,0.000000,0.000000,0.00000000,0.000000,0.000000,0.00000000,\n"
        // NEES = 0.1^2/0.04 + 0.2^2/0.09 + 0.05^2/0.01
        "0.015000000,0.100000,-0.200000,0.05000000,0.200000,0.300000,0.10000000,0.944444\n");
}

}  // namespace
}  // namespace corridorsim
