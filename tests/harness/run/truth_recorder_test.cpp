// Tests harness/run/truth_recorder.cpp: the truth a run keeps and writes (ground_truth.tum), at 0,
// on the 100 Hz grid and at every odometry stamp whatever the physics rate, planar in
// ground_truth.tum and full 3D in ground_truth_3d.tum.
#include "harness/run/truth_recorder.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/run/run_io.h"
#include "harness/run/sensor_bus.h"
#include "sim/robot_path.h"
#include "sim/simulation.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

worlds::World Corridor() {
  worlds::WorldOptions world_options;
  world_options.length_m = 8.0;
  world_options.doors.count = 0;
  world_options.plates.count = 0;
  world_options.distractors = worlds::DistractorOptions{0, 0, 0, 0, 0};
  return worlds::Generate(world_options, 3);
}

// Records odometry stamps next to the truth.
class OdometryStamps : public BusConsumer {
 public:
  void OnOdometry(const WheelOdometry& o) override { stamps.push_back(o.stamp_ns); }
  std::vector<TimeNs> stamps;
};

struct Recorded {
  std::vector<TimeNs> truth_stamps;
  std::vector<TimeNs> odometry_stamps;
  std::string planar_tum, full_tum;
};

Recorded Record(const worlds::World& world, double physics_hz, double odometry_hz) {
  sim::SimulationOptions options;
  options.robot.physics_rate_hz = physics_hz;
  options.robot.odometry.rate_hz = odometry_hz;
  options.truth_rate_hz = kTruthFileRateHz;
  options.max_duration_ns = FromSeconds(2.0);
  sim::Simulation simulation(world, options, sim::BuildRobotPath(world, options.robot_path));
  TruthRecorder truth;
  OdometryStamps odometry;
  SensorBus bus({});
  bus.Subscribe(&truth);
  bus.Subscribe(&odometry);
  bus.Run(simulation);
  Recorded r;
  for (const TruthPose& p : truth.poses()) r.truth_stamps.push_back(p.stamp_ns);
  r.odometry_stamps = odometry.stamps;
  r.planar_tum = truth.PlanarTum();
  r.full_tum = truth.FullPoseTum();
  return r;
}

std::vector<std::string> DataLines(const std::string& tum) {
  std::vector<std::string> lines;
  std::istringstream in(tum);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  return lines;
}

TEST_CASE(
    "the truth is kept at 0, on the 100 Hz grid and at every odometry stamp at any physics rate",
    "[harness][truth]") {
  const worlds::World world = Corridor();
  const TimeNs grid = PeriodFromRateHz(kTruthFileRateHz);
  for (const double odometry_hz : {50.0, 30.0}) {
    std::size_t rows_at_1000 = 0;
    for (const double physics_hz : {1000.0, 1001.0, 333.3}) {
      CAPTURE(odometry_hz, physics_hz);
      const Recorded r = Record(world, physics_hz, odometry_hz);
      std::vector<TimeNs> expected = r.odometry_stamps;
      for (TimeNs t = 0; t <= FromSeconds(2.0); t += grid) expected.push_back(t);
      std::sort(expected.begin(), expected.end());
      expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
      CHECK(r.truth_stamps == expected);
      // The file has a row per kept stamp; the same rows whatever the physics rate.
      CHECK(DataLines(r.planar_tum).size() == r.truth_stamps.size());
      if (physics_hz == 1000.0) rows_at_1000 = r.truth_stamps.size();
      CHECK(r.truth_stamps.size() == rows_at_1000);
    }
    CHECK(rows_at_1000 == (odometry_hz == 50.0 ? 201u : 201u + 60u));  // 30 Hz: 60 off the grid
  }
}

TEST_CASE("ground_truth.tum holds the planar pose, ground_truth_3d.tum the 3D pose at its stamps",
          "[harness][truth]") {
  const worlds::World world = Corridor();
  const Recorded r = Record(world, 1000.0, 50.0);
  const std::vector<std::string> planar = DataLines(r.planar_tum);
  const std::vector<std::string> full = DataLines(r.full_tum);
  REQUIRE(planar.size() == full.size());
  CHECK(r.planar_tum.rfind("# ground truth: planar world_from_robot", 0) == 0);
  CHECK(r.full_tum.rfind("# ground truth: world_from_robot in 3D", 0) == 0);
  bool any_height = false;
  for (std::size_t i = 0; i < planar.size(); ++i) {
    std::istringstream p(planar[i]), f(full[i]);
    std::string tp, tf;
    double pv[7], fv[7];
    p >> tp;
    f >> tf;
    REQUIRE(tp == tf);
    for (int k = 0; k < 7; ++k) p >> pv[k], f >> fv[k];
    CHECK(pv[2] == 0.0);  // z
    CHECK(pv[3] == 0.0);  // qx: no roll
    CHECK(pv[4] == 0.0);  // qy: no pitch
    CHECK(pv[0] == Approx(fv[0]).margin(1e-3));
    CHECK(pv[1] == Approx(fv[1]).margin(1e-3));
    any_height |= fv[2] != 0.0 || fv[3] != 0.0 || fv[4] != 0.0;
  }
  CHECK(any_height);  // the physics' chassis is not exactly planar
}

}  // namespace
}  // namespace corridorsim
