#include "sim/simulation.h"

#include "common/enum_names.h"
#include "common/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <numbers>

namespace corridorsim::sim {
namespace {

constexpr TimeNs kSafetyMarginNs = 60 * kNanosecondsPerSecond;

// The time a perfectly followed path takes at cruise speed and turn rate, ramps left out.
double NominalDurationS(const RobotPath& path, const RobotPathOptions& options) {
  double s = path.length_m() / options.speed_mps +
             path.total_turn_rad() / (options.turn_rate_dps * std::numbers::pi / 180.0);
  for (const VelocityCommand& c : path.commands) s += c.duration_s;
  return s;
}

// The truth grid's period: a rate the harness sets, never user input, so a bad one is a bug.
TimeNs TruthGridPeriodNs(double rate_hz) {
  CheckOrDie(rate_hz >= 1e-3 && rate_hz <= 1e6, "sim::Simulation",
             "the truth grid's rate must lie in [1e-3, 1e6] Hz");
  return PeriodFromRateHz(rate_hz);
}

SE2 Planar(const SE3& pose) {
  const Eigen::Vector3d x_axis = pose.rotation().col(0);
  return SE2(pose.translation().x(), pose.translation().y(), std::atan2(x_axis.y(), x_axis.x()));
}

}  // namespace

constexpr EnumName<EventKind> kEventKindNames[] = {{EventKind::kCollisionBegin, "collision_begin"},
                                                   {EventKind::kCollisionEnd, "collision_end"},
                                                   {EventKind::kSlip, "slip"},
                                                   {EventKind::kPathDone, "path_done"},
                                                   {EventKind::kTimeout, "timeout"},
                                                   {EventKind::kFrameDropped, "frame_dropped"}};

std::string EventKindName(EventKind kind) { return NameOf(kEventKindNames, kind); }

std::string TumLine(TimeNs stamp_ns, const SE3& pose) {
  const Eigen::Quaterniond& q = pose.quaternion();
  const Eigen::Vector3d& t = pose.translation();
  // Seconds from the integer nanoseconds: whole seconds, then nine digits of the fraction.
  const TimeNs whole = stamp_ns / kNanosecondsPerSecond;
  const TimeNs frac = stamp_ns % kNanosecondsPerSecond;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%lld.%09lld %.6f %.6f %.6f %.9f %.9f %.9f %.9f",
                static_cast<long long>(whole), static_cast<long long>(frac), t.x(), t.y(), t.z(),
                q.x(), q.y(), q.z(), q.w());
  return buf;
}

Simulation::Simulation(const worlds::World& world, const SimulationOptions& options, RobotPath path,
                       render::Rig* rig, const render::RigOptions* rig_options)
    : world_(world),
      options_(options),
      rig_(rig),
      path_(std::move(path)),
      odometer_(options.robot.odometry, options.robot.wheel_diameter_m, options.seed),
      odometry_clock_(PeriodFromRateHz(options.robot.odometry.rate_hz), 0),
      truth_clock_(TruthGridPeriodNs(options.truth_rate_hz), 0) {
  truth_clock_.Advance();  // the truth at 0 is the start truth
  follower_ = std::make_unique<PathFollower>(path_, options_.robot_path);
  physics_ = std::make_unique<RobotPhysics>(world, options_.robot, path_.world_from_start);
  step_ns_ = options_.robot.physics_step_ns();
  control_clock_ = SensorClock(PeriodFromRateHz(options_.robot.control_rate_hz), 0);
  if (rig_options) {
    for (const render::CameraOptions& c : rig_options->cameras) {
      if (c.enabled) camera_options_.push_back(c);
    }
  }
  CheckOrDie(!rig_ || rig_options, "sim::Simulation", "a rig needs the options it was built from");
  if (rig_) {
    for (const render::CameraOptions& c : camera_options_) {
      camera_clocks_.emplace_back(PeriodFromRateHz(c.rate_hz), FromSeconds(c.phase_s));
      drop_rngs_.emplace_back(options.seed, 0, "sim.clock.drop." + c.id);
    }
  }
  motion_sensors_ = std::make_unique<MotionSensors>(world, options_.imus, options_.lasers,
                                                    options_.seed, step_ns_);
  end_ns_ = options_.max_duration_ns > 0
                ? options_.max_duration_ns
                : 2 * FromSeconds(NominalDurationS(path_, options_.robot_path)) + kSafetyMarginNs;

  output_.truth.stamp_ns = 0;
  output_.truth.state = physics_->state();
  FillTruth(&output_.truth);
  // Messages stamped 0 come out of the first Step(), with those of its interval.
}

Simulation::~Simulation() = default;

double Simulation::progress() const {
  if (options_.max_duration_ns > 0) {
    return std::min(1.0, static_cast<double>(now_ns_) / static_cast<double>(end_ns_));
  }
  return follower_->progress();
}

TruthSample Simulation::Interpolate(const TruthSample& a, const TruthSample& b,
                                    TimeNs stamp) const {
  if (stamp == b.stamp_ns) return b;
  if (stamp == a.stamp_ns) return a;
  const double t =
      static_cast<double>(stamp - a.stamp_ns) / static_cast<double>(b.stamp_ns - a.stamp_ns);
  TruthSample s;
  s.stamp_ns = stamp;
  s.state.world_from_robot =
      SE3::Interpolate(a.state.world_from_robot, b.state.world_from_robot, t);
  s.state.linear_velocity_in_world =
      (1 - t) * a.state.linear_velocity_in_world + t * b.state.linear_velocity_in_world;
  s.state.angular_velocity_in_world =
      (1 - t) * a.state.angular_velocity_in_world + t * b.state.angular_velocity_in_world;
  s.state.left_wheel_angle_rad =
      (1 - t) * a.state.left_wheel_angle_rad + t * b.state.left_wheel_angle_rad;
  s.state.right_wheel_angle_rad =
      (1 - t) * a.state.right_wheel_angle_rad + t * b.state.right_wheel_angle_rad;
  FillTruth(&s);
  return s;
}

void Simulation::FillTruth(TruthSample* sample) const {
  sample->world_from_robot_2d = Planar(sample->state.world_from_robot);
  sample->world_from_camera.resize(camera_options_.size());
  for (std::size_t k = 0; k < camera_options_.size(); ++k) {
    sample->world_from_camera[k] =
        sample->state.world_from_robot * camera_options_[k].mount.RobotFromCamera();
  }
}

void Simulation::EmitDue(const TruthSample& before, const TruthSample& after) {
  const TimeNs now = after.stamp_ns;
  // The truth on its grid and at the odometry stamps, merged in stamp order (each stamp once).
  // Stamps at or before the step's start were reported before (0: the start truth).
  auto add_truth = [&](TruthSample sample) {
    if (sample.stamp_ns <= before.stamp_ns) return;
    std::vector<TruthSample>& out = output_.truth_samples;
    auto it =
        std::lower_bound(out.begin(), out.end(), sample.stamp_ns,
                         [](const TruthSample& s, TimeNs stamp) { return s.stamp_ns < stamp; });
    if (it != out.end() && it->stamp_ns == sample.stamp_ns) return;
    out.insert(it, std::move(sample));
  };
  while (truth_clock_.next_ns() <= now) {
    add_truth(Interpolate(before, after, truth_clock_.next_ns()));
    truth_clock_.Advance();
  }
  // Odometry.
  while (odometry_clock_.next_ns() <= now) {
    const TruthSample at = Interpolate(before, after, odometry_clock_.next_ns());
    add_truth(at);
    std::vector<SlipEvent> slips;
    output_.odometry.push_back(odometer_.Measure(at.stamp_ns, at.state.left_wheel_angle_rad,
                                                 at.state.right_wheel_angle_rad, &slips));
    for (const SlipEvent& slip : slips) {
      Event e;
      e.stamp_ns = slip.stamp_ns;
      e.kind = EventKind::kSlip;
      e.left_wheel = slip.left_wheel;
      e.distance_m = slip.extra_distance_m;
      output_.events.push_back(e);
    }
    odometry_clock_.Advance();
  }
  // Cameras, each at its own rate, rendered at the true pose of its stamp. Every frame due in
  // this step is started before any is finished: a camera's remap and noise run while the next
  // ones draw (render::Rig). The frames are kept in place until the rig is done with them.
  const auto t0 = std::chrono::steady_clock::now();
  std::deque<CameraMessage> started;
  for (std::size_t k = 0; k < camera_clocks_.size(); ++k) {
    SensorClock& clock = camera_clocks_[k];
    while (clock.next_ns() <= now) {
      // A lost frame: one draw per stamp and camera, only when frames can be lost.
      if (camera_options_[k].drop_probability > 0 &&
          drop_rngs_[k].Bernoulli(camera_options_[k].drop_probability)) {
        Event e;
        e.stamp_ns = clock.next_ns();
        e.kind = EventKind::kFrameDropped;
        e.camera_id = camera_options_[k].id;
        output_.events.push_back(e);
        clock.Advance();
        continue;
      }
      const TruthSample at = Interpolate(before, after, clock.next_ns());
      CameraMessage& message = started.emplace_back();
      message.stamp_ns = at.stamp_ns;
      message.frame_index = clock.count();
      message.camera = k;
      message.world_from_robot = at.state.world_from_robot;
      try {
        rig_->StartCamera(k, at.state.world_from_robot, options_.seed, message.frame_index,
                          &message.frame);
      } catch (...) {
        rig_->Abandon();  // the frames already started are written by the rig: let it end first
        throw;
      }
      clock.Advance();
    }
  }
  if (started.empty()) return;
  rig_->Wait();
  for (CameraMessage& message : started) {
    render::FrameTruthInput input;
    input.world = &world_;
    input.camera_id = camera_options_[message.camera].id;
    input.model = camera_options_[message.camera].model;
    input.world_from_camera = message.frame.world_from_camera;
    input.world_from_robot = message.world_from_robot;
    input.instance = &message.frame.instance;
    input.semantic = &message.frame.semantic;
    message.truth = render::ComputeFrameTruth(input);
    output_.frames.push_back(std::move(message));
  }
  render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void Simulation::TrackContacts() {
  const std::vector<Contact>& now = physics_->contacts();
  auto has = [](const std::vector<Contact>& list, int id) {
    return std::any_of(list.begin(), list.end(),
                       [&](const Contact& c) { return c.instance_id == id; });
  };
  // A contact that begins carries its penetration depth; one that ends, none.
  auto emit = [this](EventKind kind, const Contact& c) {
    Event e;
    e.stamp_ns = now_ns_;
    e.kind = kind;
    e.instance_id = c.instance_id;
    e.semantic_class = c.semantic_class;
    e.position_in_world = c.position_in_world;
    if (kind == EventKind::kCollisionBegin) e.depth_m = c.depth_m;
    output_.events.push_back(e);
  };
  for (const Contact& c : now) {
    if (!has(touching_, c.instance_id)) emit(EventKind::kCollisionBegin, c);
  }
  for (const Contact& c : touching_) {
    if (!has(now, c.instance_id)) emit(EventKind::kCollisionEnd, c);
  }
  touching_ = now;
}

const StepOutput& Simulation::Step() {
  const TruthSample before = output_.truth;
  output_.truth_samples.clear();
  output_.odometry.clear();
  output_.frames.clear();
  output_.imu.clear();
  output_.scans.clear();
  output_.events.clear();
  if (finished_) return output_;

  // The driver acts at the control rate, from ground truth.
  if (control_clock_.next_ns() <= now_ns_) {
    while (control_clock_.next_ns() <= now_ns_) control_clock_.Advance();
    ++control_updates_;
    const DriveCommand command = follower_->Update(now_ns_, before.world_from_robot_2d);
    const Eigen::Vector2d wheels =
        WheelSpeedsFor(options_.robot, command.linear_mps, command.angular_rps);
    physics_->SetWheelSpeeds(wheels.x(), wheels.y());
  }
  physics_->Step();
  now_ns_ += step_ns_;

  output_.truth.stamp_ns = now_ns_;
  output_.truth.state = physics_->state();
  FillTruth(&output_.truth);
  TrackContacts();
  motion_sensors_->Emit(before.stamp_ns, before.state, now_ns_, output_.truth.state, &output_.imu,
                        &output_.scans);
  EmitDue(before, output_.truth);

  if (follower_->done() && !path_done_) {
    path_done_ = true;
    Event e;
    e.stamp_ns = now_ns_;
    e.kind = EventKind::kPathDone;
    output_.events.push_back(e);
    if (options_.max_duration_ns == 0) finished_ = true;
  }
  if (!finished_ && now_ns_ >= end_ns_) {
    finished_ = true;
    if (!path_done_) {
      Event e;
      e.stamp_ns = now_ns_;
      e.kind = EventKind::kTimeout;
      output_.events.push_back(e);
    }
  }
  return output_;
}

}  // namespace corridorsim::sim
