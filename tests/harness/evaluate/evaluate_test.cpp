// Tests harness/evaluate/: the trajectory and landmark files `corridorsim evaluate` reads, the
// alignments, association by stamp, and the metrics on constructed trajectories whose errors are
// known by hand (a scaled, rotated and moved copy of the truth that Sim(3) brings to zero), and
// the world's ground truth read back from its JSON.
#include "harness/evaluate/evaluate.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "harness/evaluate/alignment.h"
#include "harness/evaluate/landmark_file.h"
#include "harness/evaluate/trajectory_file.h"
#include "harness/metrics/expectations.h"
#include "harness/metrics/matching.h"
#include "harness/metrics/registry.h"
#include "harness/run/run_io.h"
#include "tests/harness/metrics/support.h"
#include "tests/support/scratch_dir.h"
#include "tests/support/tolerances.h"
#include "worlds/ground_truth_reader.h"
#include "worlds/world_io.h"

namespace corridorsim::evaluate {
namespace {

using test::ArcTruth;
using test::Json;
using test::Num;

// The truth as a trajectory file would hold it, every pose moved by `g` (position and
// orientation), every `step`-th truth sample, stamps shifted by `shift_ns`.
Trajectory Moved(const std::vector<TruthPose>& truth, const Similarity& g, std::size_t step = 2,
                 TimeNs shift_ns = 0) {
  Trajectory out;
  for (std::size_t k = 0; k < truth.size(); k += step) {
    const SE3 t = SE3::FromSE2(truth[k].world_from_robot);
    TrajectoryPose p;
    p.stamp_ns = truth[k].stamp_ns + shift_ns;
    p.position = g(t.translation());
    p.orientation = Eigen::Quaterniond(g.rotation * t.rotation());
    out.poses.push_back(p);
  }
  return out;
}

Similarity Transform(double scale, double yaw, double roll, const Eigen::Vector3d& t) {
  Similarity g;
  g.scale = scale;
  g.rotation = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  g.translation = t;
  return g;
}

Json Evaluate(const std::vector<TruthPose>& truth, const Trajectory& estimate, Alignment a,
              double max_dt_s = 0.01) {
  return EvaluateTrajectory(truth, estimate, a, max_dt_s, "test").metrics;
}

int LineOf(const std::string& text) {
  try {
    ParseTrajectory(text, "t.tum");
  } catch (const InputError& e) {
    return e.location().line;
  }
  return -1;
}

TEST_CASE("trajectory files: TUM and ov_eval, exact stamps, comments", "[evaluate]") {
  const Trajectory tum = ParseTrajectory(
      "# a comment\n\n  # indented comment\n"
      "12.345678901 1 2 3 0 0 0 1\n"
      "12.3456789015\t1 2 3 0 0 0.7071067811865476 0.7071067811865476\r\n"
      "1.3e1 1 2 3 0 0 0 -1\n",
      "t.tum");
  REQUIRE(tum.poses.size() == 3);
  CHECK(tum.format == Trajectory::Format::kTum);
  CHECK(tum.poses[0].stamp_ns == 12'345'678'901);
  CHECK(tum.poses[1].stamp_ns == 12'345'678'902);  // the tenth decimal rounds half up
  CHECK(tum.poses[2].stamp_ns == 13'000'000'000);
  CHECK(tum.poses[1].orientation.z() == Approx(std::sqrt(0.5)));
  CHECK(tum.poses[2].orientation.w() == 1.0);  // -q is q: qw >= 0
  CHECK(tum.covariances.empty());              // TUM: none

  const Trajectory ov = ParseTrajectory(
      "0.5 1 2 3 0 0 0 1  0.1 0.01 0.02 0.2 0.03 0.3  1 0.5 0.25 2 0.125 3\n", "t.txt");
  REQUIRE(ov.format == Trajectory::Format::kOvEval);
  CHECK(ov.covariances[0].orientation(0, 1) == 0.01);
  CHECK(ov.covariances[0].orientation(1, 0) == 0.01);
  CHECK(ov.covariances[0].orientation(2, 2) == 0.3);
  CHECK(ov.covariances[0].position(1, 2) == 0.125);
  CHECK(ov.covariances[0].position(2, 1) == 0.125);
  CHECK(ov.covariances[0].position(2, 2) == 3.0);
}

TEST_CASE("trajectory files: every malformed line is refused at its line", "[evaluate]") {
  const std::string ok = "# t x y z qx qy qz qw\n1 0 0 0 0 0 0 1\n";
  CHECK(LineOf(ok + "2 0 0 0 0 0 1\n") == 3);                            // 7 columns
  CHECK(LineOf("1 0 0 0 0 0 0 1 0 0\n") == 1);                           // 10: neither format
  CHECK(LineOf(ok + "2 0 0 0 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0\n") == 3);  // 20 after 8
  CHECK(LineOf(ok + "1 0 0 0 0 0 0 1\n") == 3);                          // the stamp repeats
  CHECK(LineOf(ok + "0.5 0 0 0 0 0 0 1\n") == 3);                        // the stamp goes back
  CHECK(LineOf(ok + "2 nan 0 0 0 0 0 1\n") == 3);                        // not finite
  CHECK(LineOf(ok + "2 1e999 0 0 0 0 0 1\n") == 3);                      // overflows
  CHECK(LineOf(ok + "2 0 0 0 0 0 0 2\n") == 3);                          // not a unit quaternion
  CHECK(LineOf(ok + "2 0 0 0 0 0 0 0\n") == 3);                          // the zero quaternion
  CHECK(LineOf(ok + "5e9 0 0 0 0 0 0 1\n") == 3);                        // stamp past the bound
  CHECK(LineOf(ok + "2 0 0\x01 0 0 0 0 1\n") == 3);                      // a control character
  CHECK(LineOf(ok + "2x 0 0 0 0 0 0 1\n") == 3);                         // not a stamp
  CHECK(LineOf(ok + std::string(30, '1') + " 0 0 0 0 0 0 1\n") == 3);
  CHECK(LineOf("# only a comment\n\n") == 0);  // no poses at all
  try {
    ParseTrajectory(ok + "2 0 0 0 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0 0\n", "t.tum");
    FAIL("21 columns accepted");
  } catch (const InputError& e) {
    CHECK(e.location().line == 3);
    CHECK(std::string(e.what()).find("more than 20 columns") != std::string::npos);
  }
}

TEST_CASE("trajectory files: what an attacker writes is refused at its line", "[evaluate]") {
  const std::string ok = "1 0 0 0 0 0 0 1\n";
  for (const char* stamp : {"nan", "-nan", "inf", "-inf", "1e400", "4.1e9", "-4.1e9", "99999999999",
                            "0x10", "1e", ".", "-", "+-1", "1..2"}) {
    INFO(stamp);
    CHECK(LineOf(ok + stamp + " 0 0 0 0 0 0 1\n") == 2);
  }
  CHECK(LineOf(ok + "1.0000000001 0 0 0 0 0 0 1\n") == 2);  // rounds to the same nanosecond
  CHECK(LineOf(ok + "2 0 0 0 nan 0 0 1\n") == 2);           // non-finite quaternion
  CHECK(LineOf(ok + "2 0 0 0 inf 0 0 1\n") == 2);
  CHECK(LineOf(ok + "2 0 0 0 1e200 1e200 0 0\n") == 2);                   // its norm overflows
  CHECK(LineOf(ok + "2 0 0 0 0 0 0 -0\n") == 2);                          // zero, signed
  CHECK(LineOf(ok + "2 0 0 0 0 0 0 1e-300\n") == 2);                      // nearly zero
  CHECK(LineOf(ok + std::string(5000, ' ') + "2 0 0 0 0 0 0 1\n") == 2);  // an overlong line
  CHECK(LineOf(ok + std::string("\x89PNG\r\n\x1a\n", 8)) == 2);           // binary junk
  CHECK(LineOf(ok + std::string("2 0 0 0 0 0 0 1\0", 16)) == 2);          // a NUL
  CHECK(LineOf("") == 0);                                                 // empty
  CHECK(LineOf("\r\n\r\n") == 0);                                         // only CRLF
  // CRLF line ends are line ends; a lone CR elsewhere is a control character.
  CHECK(ParseTrajectory("# c\r\n1 0 0 0 0 0 0 1\r\n2 0 0 0 0 0 0 1\r\n", "t").poses.size() == 2);
  CHECK(LineOf(ok + "2 0 0 0\r0 0 0 1\n") == 2);
}

TEST_CASE("trajectory files are read line by line with the same checks", "[evaluate]") {
  const test::ScratchDir scratch("evaluate_read");
  const std::filesystem::path dir = scratch.path();
  const auto write = [&](const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  };
  // Lines across the reader's 1 MiB chunks, CRLF ends and no final line end: every pose read.
  std::string text;
  for (int k = 1; k <= 60000; ++k) text += std::to_string(k) + ".5 1 2 3 0 0 0 1\r\n";
  text += "60001 1 2 3 0 0 0 1";
  const Trajectory read = ReadTrajectory(write("big.tum", text));
  REQUIRE(read.poses.size() == 60001);
  CHECK(read.poses.back().stamp_ns == 60'001'000'000'000);
  CHECK(read.poses[40000].position.z() == 3.0);
  const auto line_of = [&](const std::string& name, const std::string& body) {
    try {
      ReadTrajectory(write(name, body));
    } catch (const InputError& e) {
      CHECK(e.location().file.find(name) != std::string::npos);
      return e.location().line;
    }
    return -1;
  };
  CHECK(line_of("long.tum", "1 0 0 0 0 0 0 1\n" + std::string(3u << 20, '7') + "\n") == 2);
  CHECK(line_of("empty.tum", "") == 0);
  CHECK(line_of("junk.tum", std::string("\x7f"
                                        "ELF\x02\x01\x01\0\0\0",
                                        10)) == 1);
  CHECK(line_of("late.tum", text + "\n5 0 0 0 0 0 0 1\n") == 60002);
  CHECK_THROWS_AS(ReadTrajectory((dir / "missing.tum").string()), InputError);
  CHECK_THROWS_AS(ReadTrajectory(dir.string()), InputError);  // a folder
}

TEST_CASE("an exact copy scores zero with every alignment", "[evaluate]") {
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Trajectory copy = Moved(truth, Similarity{});
  for (const Alignment a : kAllAlignments) {
    INFO(AlignmentName(a));
    const Json m = Evaluate(truth, copy, a);
    CHECK(m["samples"] == 1001);
    CHECK(m["poses"] == 1001);
    CHECK(Num(m["ate_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
    CHECK(Num(m["ate_3d_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
    CHECK(Num(m["rotation_rmse_rad"]) == Approx(0.0).margin(1e-7));
    CHECK(Num(m["align"]["scale"]) == Approx(1.0).margin(1e-6));
    CHECK_FALSE(m.contains("nees_mean"));  // TUM: no covariances, no NEES
  }
}

TEST_CASE("a scaled, rotated and moved copy: Sim(3) brings it to zero, SE(3) cannot",
          "[evaluate]") {
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  // The estimate is the truth in another frame at 2.5 times its size, as a monocular system
  // gives it: rotated 30 deg about z and 10 deg about x, moved by (3, -2, 1) m.
  const Similarity g = Transform(2.5, 30.0 * M_PI / 180.0, 10.0 * M_PI / 180.0, {3, -2, 1});
  const Trajectory estimate = Moved(truth, g);

  const Json sim3 = Evaluate(truth, estimate, Alignment::kSim3);
  CHECK(Num(sim3["ate_rmse_m"]) == Approx(0.0).margin(2e-6));
  CHECK(Num(sim3["ate_3d_rmse_m"]) == Approx(0.0).margin(2e-6));
  CHECK(Num(sim3["rotation_rmse_rad"]) == Approx(0.0).margin(1e-6));
  CHECK(Num(sim3["ate_yaw_rmse_rad"]) == Approx(0.0).margin(1e-6));
  CHECK(Num(sim3["rpe_5m_trans_rmse_m"]) == Approx(0.0).margin(2e-6));
  CHECK(Num(sim3["final_position_error_m"]) == Approx(0.0).margin(2e-6));
  CHECK(Num(sim3["align"]["scale"]) == Approx(0.4).margin(1e-6));  // 1 / 2.5
  // The alignment's rotation undoes g's: its angle is g's (30 deg about z then 10 about x).
  const double angle = Eigen::AngleAxisd(g.rotation).angle();
  CHECK(Num(sim3["align"]["angle_rad"]) == Approx(angle).margin(1e-6));

  // Without the scale the best rigid fit leaves a large error; unaligned it is larger still.
  const Json se3 = Evaluate(truth, estimate, Alignment::kSE3);
  CHECK(Num(se3["ate_3d_rmse_m"]) > 1.0);
  CHECK(Num(se3["align"]["scale"]) == 1.0);
  const Json none = Evaluate(truth, estimate, Alignment::kNone);
  CHECK(Num(none["ate_3d_rmse_m"]) > Num(se3["ate_3d_rmse_m"]));
}

TEST_CASE("a rigidly moved copy: SE(3) brings it to zero, SE(2) only its planar part",
          "[evaluate]") {
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Trajectory planar = Moved(truth, Transform(1.0, 0.7, 0.0, {5, 1, 0}));
  CHECK(Num(Evaluate(truth, planar, Alignment::kSE2)["ate_rmse_m"]) == Approx(0.0).margin(2e-6));
  CHECK(Num(Evaluate(truth, planar, Alignment::kSE3)["ate_3d_rmse_m"]) == Approx(0.0).margin(2e-6));
  // A z offset: SE(2) leaves it (the planar ATE is zero, the 3D one the offset), SE(3) removes it.
  const Trajectory lifted = Moved(truth, Transform(1.0, 0.7, 0.0, {5, 1, 0.25}));
  const Json se2 = Evaluate(truth, lifted, Alignment::kSE2);
  CHECK(Num(se2["ate_rmse_m"]) == Approx(0.0).margin(2e-6));
  CHECK(Num(se2["ate_3d_rmse_m"]) == Approx(0.25).margin(2e-6));
  CHECK(Num(Evaluate(truth, lifted, Alignment::kSE3)["ate_3d_rmse_m"]) == Approx(0.0).margin(2e-6));
}

TEST_CASE("a constant offset: its size unaligned, and the metrics are metrics.json's",
          "[evaluate]") {
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Trajectory offset = Moved(truth, Transform(1.0, 0.0, 0.0, {0.3, -0.4, 0}));
  const Json m = Evaluate(truth, offset, Alignment::kNone);
  CHECK(Num(m["ate_rmse_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_max_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["final_position_error_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_aligned_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["rpe_1m_trans_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  // The same estimates through the runner's ComputeMetrics give the same shared numbers.
  const Json runner =
      test::RunOne(worlds::World{}, truth, test::Record("offset", truth, [](const SE2& p) {
                     return SE2(p.x() + 0.3, p.y() - 0.4, p.yaw());
                   }));
  for (const char* key :
       {"samples", "distance_travelled_m", "ate_rmse_m", "ate_aligned_rmse_m",
        "rpe_1m_trans_rmse_m", "rpe_10m_pairs", "final_position_error_m", "final_yaw_error_rad"}) {
    INFO(key);
    CHECK(m[key] == runner[key]);
  }
}

TEST_CASE("association: within --max-dt of a truth stamp, truth interpolated there", "[evaluate]") {
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  // Poses 3 ms after the truth grid, each the truth interpolated at its own stamp: exact.
  Trajectory late;
  for (std::size_t k = 0; k + 1 < truth.size(); k += 2) {
    const TimeNs t = truth[k].stamp_ns + 3'000'000;
    const SE2 at = *metrics::TruthAt(truth, t);
    TrajectoryPose p;
    p.stamp_ns = t;
    p.position = Eigen::Vector3d(at.x(), at.y(), 0.0);
    p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(at.yaw(), Eigen::Vector3d::UnitZ()));
    late.poses.push_back(p);
  }
  const Json within = Evaluate(truth, late, Alignment::kNone, 0.01);
  CHECK(within["samples"] == 1000);
  CHECK(within["samples_without_truth"] == 0);
  CHECK(Num(within["ate_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  // With 2 ms allowed no truth stamp is near enough: nothing is scored.
  const Json tight = Evaluate(truth, late, Alignment::kNone, 0.002);
  CHECK(tight["samples"] == 0);
  CHECK(tight["samples_without_truth"] == 1000);
  CHECK_FALSE(tight.contains("ate_rmse_m"));
  // Poses past the truth's end are counted, never scored.
  const Trajectory beyond = Moved(truth, Similarity{}, 2, 15 * test::kGridNs);
  const Json b = Evaluate(truth, beyond, Alignment::kNone);
  CHECK(b["samples_without_truth"].get<int>() == 8);  // stamps 20.01 ... 20.15 s, every 20 ms
  // An alignment needs truth to fit on.
  CHECK_THROWS_AS(Evaluate(truth, late, Alignment::kSE3, 0.002), InputError);
}

TEST_CASE("degenerate alignments are refused with the reason", "[evaluate]") {
  std::vector<TruthPose> line;
  for (int k = 0; k <= 100; ++k) line.push_back({k * test::kGridNs, SE2(0.01 * k, 0.0, 0.0)});
  const Trajectory copy = Moved(line, Similarity{});
  // On a straight line a rotation about it is free: se3 and sim3 refuse, se2 fits.
  CHECK_THROWS_WITH(Evaluate(line, copy, Alignment::kSE3),
                    Catch::Contains("do not all lie on one line"));
  CHECK_THROWS_AS(Evaluate(line, copy, Alignment::kSim3), InputError);
  CHECK(Num(Evaluate(line, copy, Alignment::kSE2)["ate_rmse_m"]) ==
        Approx(0.0).margin(test::kMetricsJsonM));
  Trajectory two;
  two.poses = {copy.poses[0], copy.poses[1]};
  CHECK_THROWS_WITH(Evaluate(line, two, Alignment::kSim3), Catch::Contains("at least 3"));
}

TEST_CASE("NEES of an ov_eval estimate over (x, y, yaw) from its blocks", "[evaluate]") {
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  // 0.1 m off in world x with sigma_x 0.1 m: NEES 1 at every sample.
  Trajectory estimate = Moved(truth, Transform(1.0, 0.0, 0.0, {0.1, 0, 0}));
  estimate.format = Trajectory::Format::kOvEval;
  PoseCovariance c;
  c.position = Eigen::Vector3d(0.01, 0.04, 0.0).asDiagonal();
  c.orientation = Eigen::Vector3d(0.0, 0.0, 1e-4).asDiagonal();
  estimate.covariances.assign(estimate.poses.size(), c);
  const Json m = Evaluate(truth, estimate, Alignment::kNone);
  CHECK(m["nees_samples"] == 1001);
  CHECK(Num(m["nees_mean"]) == Approx(1.0).margin(1e-6));
  CHECK(Num(m["nees_final"]) == Approx(1.0).margin(1e-6));
  // Aligned, the fit has taken out the error the covariance described (here all of it): NEES is
  // left out, and the estimate's object says why.
  for (const Alignment a : {Alignment::kSE2, Alignment::kSE3, Alignment::kSim3}) {
    INFO(AlignmentName(a));
    const Json aligned = Evaluate(truth, estimate, a);
    CHECK(Num(aligned["ate_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
    CHECK_FALSE(aligned.contains("nees_mean"));
    CHECK_FALSE(aligned.contains("nees_samples"));
    CHECK(aligned["nees"].get<std::string>().find("left out") != std::string::npos);
  }
  CHECK_FALSE(m.contains("nees"));  // unaligned: the NEES itself
}

TEST_CASE("landmark maps: the run's format read back, aligned and scored by type", "[evaluate]") {
  const worlds::World world = test::PlateWorld();
  std::vector<slam::LandmarkEstimate> map = {
      test::Landmark(0, slam::LandmarkType::kDoorPlate, {1.1, 1, 1.5}, "101"),
      test::Landmark(1, slam::LandmarkType::kDoorPlate, {4, 1.2, 1.5}, "999"),
      test::Landmark(2, slam::LandmarkType::kLamp, {2, 0, 2.4})};
  map[2].covariance = Eigen::Vector3d(0.01, 0.02, 0.03).asDiagonal();
  // LandmarksJson (the run folder's writer) and ParseLandmarkMap agree.
  const std::string text = LandmarksJson(map).dump(2);
  const std::vector<slam::LandmarkEstimate> read = ParseLandmarkMap(text, "m.json");
  REQUIRE(read.size() == 3);
  CHECK(read[0].label == "101");
  CHECK(read[2].covariance(2, 2) == 0.03);

  Json object;
  AddLandmarkMapMetrics(world, read, object);
  const Json& plates = object["map"]["door_plate"];
  CHECK(plates["matched"] == 2);
  CHECK(Num(plates["rmse_m"]) == Approx(std::sqrt((0.01 + 0.04) / 2.0)).margin(1e-6));
  CHECK(Num(plates["room_number_accuracy"]) == 0.5);
  CHECK(plates["observed"].is_null());  // no frames offline
  CHECK(Num(object["map"]["lamp"]["z_rmse_m"]) == Approx(0.1).margin(1e-6));

  // A map in a frame moved by g is brought back by the alignment that undoes g.
  Similarity g = Transform(1.0, 0.5, 0.0, {1, 2, 0});
  std::vector<slam::LandmarkEstimate> moved = read;
  for (auto& l : moved) l.position_in_world = g(l.position_in_world);
  Similarity back;
  back.rotation = g.rotation.transpose();
  back.translation = -(back.rotation * g.translation);
  const auto aligned = AlignLandmarks(moved, back);
  CHECK((aligned[1].position_in_world - read[1].position_in_world).norm() < 1e-12);
  CHECK(aligned[2].covariance.isApprox(back.rotation * read[2].covariance *
                                       back.rotation.transpose()));

  CHECK_THROWS_WITH(ParseLandmarkMap(R"([{"id": 1, "type": "lamp"}])", "m.json"),
                    Catch::Contains("position_in_world"));
  CHECK_THROWS_WITH(
      ParseLandmarkMap(R"([{"id": 1, "type": "tree", "position_in_world": [0, 0, 0]}])", "m.json"),
      Catch::Contains("unknown type"));
  CHECK_THROWS_WITH(ParseLandmarkMap(R"([{"id": 1, "type": "lamp", "position_in_world": [0, 0, 0],
                                         "colour": "red"}])",
                                     "m.json"),
                    Catch::Contains("unknown key 'colour'"));
  CHECK_THROWS_WITH(ParseLandmarkMap(R"([{"id": 1, "type": "lamp", "position_in_world": [0, 0, 0]},
                                         {"id": 1, "type": "lamp", "position_in_world": [1, 0, 0]}])",
                                     "m.json"),
                    Catch::Contains("a second landmark with this id"));
  CHECK_THROWS_AS(ParseLandmarkMap(R"({"id": 1})", "m.json"), InputError);
}

TEST_CASE("a world's ground truth read back from its JSON gives the same landmarks", "[evaluate]") {
  worlds::World world = test::PlateWorld();
  world.plates[0].door_id = 7;
  worlds::Doorway door;
  door.id = 7;
  door.state = worlds::DoorState::kOpen;
  door.column_a = {3.0, -1.2};
  door.column_b = {4.0, -1.2};
  door.top_height_m = 2.1;
  world.doors.push_back(door);
  world.corner_points.push_back({9, worlds::CornerKind::kVent, {1, 2, 2.7}});
  worlds::Reflector r;
  r.id = 11;
  r.apparent_lamp_center = {5, 2.4, 2.6};
  world.reflectors.push_back(r);
  const worlds::World read =
      worlds::ParseGroundTruthJson(worlds::GroundTruthJson(world).dump(2), "world.json");
  for (const slam::LandmarkType type : metrics::kMapTypes) {
    const auto a = metrics::TruthLandmarks(world, type);
    const auto b = metrics::TruthLandmarks(read, type);
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      CHECK(a[i].id == b[i].id);
      CHECK(a[i].label == b[i].label);
      CHECK((a[i].position_in_world - b[i].position_in_world).norm() < 1e-6);
    }
  }
  CHECK(read.doors[0].state == worlds::DoorState::kOpen);
  CHECK_THROWS_WITH(worlds::ParseGroundTruthJson(R"({"seed": 1, "door_plates": []})", "w.json"),
                    Catch::Contains("lamps"));
}

TEST_CASE("evaluate's expectations name the shared and its own metrics", "[evaluate]") {
  const std::vector<std::string> names = EvaluationMetricNames();
  const auto has = [&](const char* n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  CHECK(has("ate_rmse_m"));
  CHECK(has("rpe_5m_trans_rmse_m"));
  CHECK(has("nees_mean"));
  CHECK(has("map.lamp.rmse_m"));
  CHECK(has("align.scale"));
  CHECK(has("ate_3d_rmse_m"));
  CHECK_FALSE(has("timing.steps"));
  CHECK_FALSE(has("map.occupancy.precision"));
  CHECK_FALSE(has("detection.lamp.recall"));
  Expectation e;
  REQUIRE_FALSE(ParseExpectation("mine.align.scale > 0.3", &e, names));
  CHECK(ParseExpectation("mine.align.scale > 0.3", &e).has_value());  // not a pipeline metric
  Json document;
  document["estimates"]["mine"]["align"]["scale"] = 0.4;
  const auto results = CheckExpectations(document, {e}, "estimates");
  REQUIRE(results.size() == 1);
  CHECK(results[0].passed);
}

}  // namespace
}  // namespace corridorsim::evaluate
