#include "harness/run/sensor_bus.h"

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/run/async_consumer.h"
#include "harness/run/stopwatch.h"
#include "sim/robot_path.h"
#include "sim/simulation.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

sim::CameraMessage Frame(TimeNs stamp, std::size_t camera) {
  sim::CameraMessage m;
  m.stamp_ns = stamp;
  m.camera = camera;
  return m;
}

sim::Event Drop(TimeNs stamp, const std::string& camera_id) {
  sim::Event e;
  e.stamp_ns = stamp;
  e.kind = sim::EventKind::kFrameDropped;
  e.camera_id = camera_id;
  return e;
}

WheelOdometry Odometry(TimeNs stamp) {
  WheelOdometry o;
  o.stamp_ns = stamp;
  return o;
}

// Writes down every delivery as "<what>@<stamp>" (camera sets list their slots).
class Recorder : public BusConsumer {
 public:
  explicit Recorder(std::vector<std::string>* log, std::string name = "")
      : log_(log), name_(std::move(name)) {}
  void OnTruth(const sim::TruthSample& t) override { Add("truth", t.stamp_ns); }
  void OnOdometry(const WheelOdometry& o) override { Add("odometry", o.stamp_ns); }
  void OnCameraSet(const CameraSet& set) override {
    std::string slots;
    for (const CameraSlot& s : set.cameras) slots += s.camera_id + (s.message ? "+" : "-");
    Add("set[" + slots + "]", set.stamp_ns);
  }
  void OnEvent(const sim::Event& e) override { Add("event", e.stamp_ns); }
  void OnImu(const sim::ImuMessage& m) override { Add("imu", m.sample.stamp_ns); }
  void OnScan(const sim::ScanMessage& m) override {
    Add("scan(" + std::to_string(m.scan.stamp_ns) + ")", m.complete_ns);
  }
  void OnStepEnd(const sim::TruthSample& truth, bool last) override {
    Add(last ? "end(last)" : "end", truth.stamp_ns);
  }

 private:
  void Add(const std::string& what, TimeNs stamp) {
    log_->push_back(name_ + what + "@" + std::to_string(stamp));
  }
  std::vector<std::string>* log_;
  std::string name_;
};

const std::vector<std::string> kCameras = {"front", "lateral", "upward"};

// What a Recorder on a bus of kCameras writes down when `step` is published.
std::vector<std::string> Delivered(const sim::StepOutput& step, bool last) {
  std::vector<std::string> log;
  Recorder recorder(&log);
  SensorBus bus(kCameras);
  bus.Subscribe(&recorder);
  bus.Publish(step, last);
  return log;
}

}  // namespace

TEST_CASE("frames due at one stamp arrive as one set in rig order, a dropped frame as a hole",
          "[harness][bus]") {
  sim::StepOutput step;
  step.frames = {Frame(200, 2), Frame(100, 1), Frame(100, 0)};  // camera order, as emitted
  step.events = {Drop(200, "lateral")};
  const std::vector<CameraSet> sets = GroupCameraSets(step, kCameras);
  REQUIRE(sets.size() == 2);
  CHECK(sets[0].stamp_ns == 100);
  REQUIRE(sets[0].cameras.size() == 2);
  CHECK(sets[0].cameras[0].camera_id == "front");
  CHECK(sets[0].cameras[0].message == &step.frames[2]);
  CHECK(sets[0].cameras[1].camera_id == "lateral");
  CHECK(sets[0].cameras[1].message == &step.frames[1]);
  CHECK(sets[1].stamp_ns == 200);
  REQUIRE(sets[1].cameras.size() == 2);
  CHECK(sets[1].cameras[0].camera_id == "lateral");
  CHECK(sets[1].cameras[0].message == nullptr);  // the hole
  CHECK(sets[1].cameras[1].camera_id == "upward");
  CHECK(sets[1].cameras[1].camera == 2);
  REQUIRE(sets[1].Find("lateral") != nullptr);
  CHECK(sets[1].Find("front") == nullptr);  // not due at 200
}

TEST_CASE("a set of dropped frames only still arrives, and drops of unrendered cameras do not",
          "[harness][bus]") {
  sim::StepOutput step;
  step.events = {Drop(300, "front"), Drop(300, "rear")};
  const std::vector<CameraSet> sets = GroupCameraSets(step, kCameras);
  REQUIRE(sets.size() == 1);
  REQUIRE(sets[0].cameras.size() == 1);
  CHECK(sets[0].cameras[0].camera_id == "front");
  CHECK(sets[0].cameras[0].message == nullptr);
}

TEST_CASE(
    "the bus delivers a step in stamp order, odometry before frames before events, then "
    "the step's truth",
    "[harness][bus]") {
  sim::StepOutput step;
  step.truth.stamp_ns = 1000;
  step.odometry = {Odometry(400), Odometry(900)};
  step.frames = {Frame(400, 0), Frame(100, 1)};
  step.events = {Drop(400, "upward"), sim::Event{}};
  step.events[1].stamp_ns = 1000;
  step.events[1].kind = sim::EventKind::kPathDone;
  const std::vector<std::string> log = Delivered(step, /*last=*/true);
  const std::vector<std::string> expected = {
      "set[lateral+]@100", "odometry@400", "set[front+upward-]@400", "event@400",
      "odometry@900",      "event@1000",   "end(last)@1000"};
  CHECK(log == expected);
}

sim::TruthSample Truth(TimeNs stamp) {
  sim::TruthSample t;
  t.stamp_ns = stamp;
  return t;
}

TEST_CASE("the truth of a stamp arrives before the messages of that stamp", "[harness][bus]") {
  sim::StepOutput step;
  step.truth.stamp_ns = 1000;
  step.truth_samples = {Truth(400), Truth(500)};
  step.odometry = {Odometry(400)};
  step.frames = {Frame(400, 0)};
  const std::vector<std::string> log = Delivered(step, /*last=*/false);
  const std::vector<std::string> expected = {"truth@400", "odometry@400", "set[front+]@400",
                                             "truth@500", "end@1000"};
  CHECK(log == expected);
}

TEST_CASE("IMU samples come after odometry and a sweep at its last beam, before the camera set",
          "[harness][bus]") {
  sim::StepOutput step;
  step.truth.stamp_ns = 1000;
  step.odometry = {Odometry(400)};
  step.frames = {Frame(400, 0)};
  step.events = {Drop(400, "upward")};
  sim::ImuMessage imu;
  imu.sample.stamp_ns = 400;
  sim::ImuMessage later = imu;
  later.sample.stamp_ns = 900;
  step.imu = {imu, later};
  sim::ScanMessage scan;
  scan.scan.stamp_ns = 100;  // its first beam, in an earlier step
  scan.complete_ns = 400;
  step.scans = {scan};
  const std::vector<std::string> log = Delivered(step, /*last=*/false);
  const std::vector<std::string> expected = {
      "odometry@400", "imu@400", "scan(100)@400", "set[front+upward-]@400",
      "event@400",    "imu@900", "end@1000"};
  CHECK(log == expected);
}

TEST_CASE("an async consumer passes IMU samples and sweeps on in the inline order",
          "[harness][bus]") {
  std::vector<std::string> inline_log, async_log;
  Recorder inline_recorder(&inline_log), async_recorder(&async_log);
  AsyncConsumer async(async_recorder, 1);
  SensorBus bus(kCameras);
  bus.Subscribe(&inline_recorder);
  bus.Subscribe(&async);
  for (int k = 1; k <= 5; ++k) {
    sim::StepOutput step;
    step.truth.stamp_ns = k * 100;
    sim::ImuMessage imu;
    imu.sample.stamp_ns = k * 100 - 50;
    sim::ScanMessage scan;
    scan.scan.stamp_ns = k * 100 - 90;
    scan.complete_ns = k * 100 - 10;
    step.imu = {imu};
    step.scans = {scan};
    bus.Publish(step, k == 5);
  }
  async.Drain();
  CHECK(async_log == inline_log);
  REQUIRE(async_log.size() == 15);
  CHECK(async_log[0] == "imu@50");
  CHECK(async_log[1] == "scan(10)@90");
}

TEST_CASE("consumers receive each message in the order they subscribed", "[harness][bus]") {
  sim::StepOutput step;
  step.truth.stamp_ns = 20;
  step.odometry = {Odometry(10)};
  std::vector<std::string> log;
  Recorder a(&log, "a:"), b(&log, "b:");
  SensorBus bus(kCameras);
  bus.Subscribe(&a);
  bus.Subscribe(&b);
  bus.Publish(step, false);
  const std::vector<std::string> expected = {"a:odometry@10", "b:odometry@10", "a:end@20",
                                             "b:end@20"};
  CHECK(log == expected);
}

TEST_CASE(
    "a run on the bus sees the start, every odometry message once in stamp order and one "
    "last step",
    "[harness][bus]") {
  worlds::WorldOptions world_options;
  world_options.length_m = 8.0;
  world_options.doors.count = 0;
  world_options.plates.count = 0;
  world_options.distractors = worlds::DistractorOptions{0, 0, 0, 0, 0};
  const worlds::World world = worlds::Generate(world_options, 3);
  sim::SimulationOptions options;
  options.max_duration_ns = FromSeconds(2.0);
  sim::Simulation simulation(world, options, sim::BuildRobotPath(world, options.robot_path));

  class Checker : public BusConsumer {
   public:
    void OnStart(const sim::TruthSample& truth) override { starts.push_back(truth.stamp_ns); }
    void OnTruth(const sim::TruthSample& truth) override { truths.push_back(truth.stamp_ns); }
    void OnOdometry(const WheelOdometry& o) override { stamps.push_back(o.stamp_ns); }
    void OnStepEnd(const sim::TruthSample& truth, bool last) override {
      if (last) lasts.push_back(truth.stamp_ns);
      ++steps;
    }
    std::vector<TimeNs> starts, truths, stamps, lasts;
    int steps = 0;
  } checker;
  SensorBus bus({});
  bus.Subscribe(&checker);
  bus.Run(simulation);
  CHECK(checker.starts == std::vector<TimeNs>{0});
  CHECK(checker.lasts == std::vector<TimeNs>{simulation.now_ns()});
  CHECK(checker.steps == 2000);  // 2 s at the default 1 kHz
  // 50 Hz odometry from stamp 0 to 2 s inclusive.
  REQUIRE(checker.stamps.size() == 101);
  for (std::size_t i = 0; i < checker.stamps.size(); ++i) {
    CHECK(checker.stamps[i] == static_cast<TimeNs>(i) * 20'000'000);
  }
  // The truth on the 100 Hz grid after the start (the odometry stamps lie on it).
  REQUIRE(checker.truths.size() == 200);
  for (std::size_t i = 0; i < checker.truths.size(); ++i) {
    CHECK(checker.truths[i] == static_cast<TimeNs>(i + 1) * 10'000'000);
  }
}

}  // namespace corridorsim

namespace corridorsim {
namespace {

// Records the frames' first pixel too: the copy must carry the image, not a dangling pointer.
class FrameRecorder : public BusConsumer {
 public:
  explicit FrameRecorder(std::vector<std::string>* log) : log_(log) {}
  void OnStart(const sim::TruthSample& t) override { Add("start", t.stamp_ns); }
  void OnTruth(const sim::TruthSample& t) override { Add("truth", t.stamp_ns); }
  void OnOdometry(const WheelOdometry& o) override { Add("odometry", o.stamp_ns); }
  void OnCameraSet(const CameraSet& set) override {
    std::string slots;
    for (const CameraSlot& s : set.cameras) {
      slots += s.camera_id + (s.message ? "=" + std::to_string(s.message->frame.rgb.data.at(0))
                                        : std::string("-"));
    }
    Add("set[" + slots + "]", set.stamp_ns);
    if (throw_at_ == set.stamp_ns) throw std::runtime_error("pipeline failed");
  }
  void OnEvent(const sim::Event& e) override { Add("event", e.stamp_ns); }
  void OnStepEnd(const sim::TruthSample& truth, bool last) override {
    Add(last ? "end(last)" : "end", truth.stamp_ns);
  }
  TimeNs throw_at_ = -1;

 private:
  void Add(const std::string& what, TimeNs stamp) {
    log_->push_back(what + "@" + std::to_string(stamp));
  }
  std::vector<std::string>* log_;
};

sim::StepOutput StepWithFrames(TimeNs end, std::uint8_t pixel) {
  sim::StepOutput step;
  step.truth.stamp_ns = end;
  step.truth_samples = {Truth(end - 50)};
  step.odometry = {Odometry(end - 50)};
  step.frames = {Frame(end - 50, 0), Frame(end - 50, 2)};
  for (sim::CameraMessage& m : step.frames) {
    m.frame.rgb = Image8(2, 2, 3);
    m.frame.rgb.data[0] = static_cast<std::uint8_t>(pixel + m.camera);
  }
  step.events = {Drop(end - 50, "lateral")};
  return step;
}

}  // namespace

TEST_CASE("an async consumer sees the calls of an inline one, in order, with the frames copied",
          "[harness][bus]") {
  std::vector<std::string> inline_log, async_log;
  FrameRecorder inline_recorder(&inline_log), async_recorder(&async_log);
  // after_batch runs on the worker after each batch; it sees every call up to the batch's end.
  std::vector<std::size_t> snapshots;
  AsyncConsumer async(async_recorder, 1, [&] { snapshots.push_back(async_log.size()); });
  SensorBus bus(kCameras);
  bus.Subscribe(&inline_recorder);
  bus.Subscribe(&async);
  for (int k = 1; k <= 20; ++k) {
    // Each step's frames are destroyed when the step goes out of scope: the queue holds copies.
    const sim::StepOutput step = StepWithFrames(k * 100, static_cast<std::uint8_t>(10 * k));
    bus.Publish(step, k == 20);
  }
  async.Drain();
  CHECK(async_log == inline_log);
  CHECK(async_log.size() == 20 * 5);
  CHECK(async_log[2] == "set[front=10lateral-upward=12]@50");
  // Each camera set closes a batch (truth, odometry, set; then the event and step end wait for
  // the next one), and the last step end closes the last.
  std::vector<std::size_t> expected_snapshots;
  for (std::size_t k = 1; k <= 20; ++k) expected_snapshots.push_back(5 * k - 2);
  expected_snapshots.push_back(100);
  CHECK(snapshots == expected_snapshots);
}

TEST_CASE("an async consumer's exception reaches the loop at the next call or at Drain",
          "[harness][bus]") {
  std::vector<std::string> log;
  FrameRecorder recorder(&log);
  recorder.throw_at_ = 250;
  AsyncConsumer async(recorder, 1);
  SensorBus bus(kCameras);
  bus.Subscribe(&async);
  const auto run = [&] {
    for (int k = 1; k <= 10; ++k) bus.Publish(StepWithFrames(k * 100, 1), k == 10);
    async.Drain();
  };
  CHECK_THROWS_WITH(run(), "pipeline failed");
}

TEST_CASE("a thread's CPU clock counts its work, not its sleep (timing.json's cpu_ms_per_frame)",
          "[harness]") {
  using namespace std::chrono_literals;
  const double before_sleep = ThreadCpuSeconds();
  std::this_thread::sleep_for(50ms);
  CHECK(ThreadCpuSeconds() - before_sleep < 0.02);
  // Work until the clock has moved 10 ms (at most 10 s of wall time, however busy the machine).
  const double before_work = ThreadCpuSeconds();
  const WallClock::time_point deadline = WallClock::now() + 10s;
  volatile double sink = 0.0;
  while (ThreadCpuSeconds() - before_work < 0.01 && WallClock::now() < deadline) {
    for (int k = 0; k < 10000; ++k) sink = sink + k;
  }
  CHECK(ThreadCpuSeconds() - before_work >= 0.01);
}

}  // namespace corridorsim
