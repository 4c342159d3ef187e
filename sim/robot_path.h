#pragma once
// Ready-made robot paths over a World and the follower that drives them (the motion side of the
// simulation). The follower is the robot's driver, not an estimator: it reads the TRUE pose
// (world_from_robot) at every control step and returns a (linear m/s, angular rad/s) command for
// a Pioneer 3-DX-like differential-drive robot. It is a pure function of its inputs (no
// randomness, no clock of its own).
//
// Paths are polylines of straight legs joined by in-place turns (P1 drove its 55 m corridor out
// and back at 0.34 m/s, Fig. 14; P3 at 0.30 m/s), UMBmark squares (Borenstein & Feng 1996) for
// odometry calibration, or open-loop velocity scripts.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/enum_names.h"
#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "common/time.h"
#include "worlds/world.h"

namespace corridorsim::sim {

/// Pioneer 3-DX footprint (m): 0.455 m long, about 0.4 m wide with its wheels, turning about the
/// midpoint of its wheel axle.
inline constexpr double kRobotLengthM = 0.455;
inline constexpr double kRobotHalfWidthM = 0.2;
/// Least distance (m) a planned path keeps from every wall face: the radius the footprint sweeps
/// when the robot turns in place (half diagonal: 0.30 m) plus 5 cm for tracking.
inline constexpr double kPathWallClearanceM = 0.35;

enum class PathKind { kRoundTrip, kLoop, kUmbmarkCw, kUmbmarkCcw, kScript };
inline constexpr EnumName<PathKind> kPathKindNames[] = {{PathKind::kRoundTrip, "round_trip"},
                                                        {PathKind::kLoop, "loop"},
                                                        {PathKind::kUmbmarkCw, "umbmark_cw"},
                                                        {PathKind::kUmbmarkCcw, "umbmark_ccw"},
                                                        {PathKind::kScript, "script"}};
std::string PathKindName(PathKind kind);

// Pioneer 3-DX limits (MobileRobots datasheet): 1.2 m/s, 300 deg/s; a path's speed and turn rate
// (and a script's rows) stay within them.
inline constexpr double kMaxPathSpeedMps = 1.2;
inline constexpr double kMaxPathTurnRateDps = 300.0;

/// One open-loop command of a `script` path, held for its duration.
struct VelocityCommand {
  double duration_s = 0.0;
  double linear_mps = 0.0;   // forward speed (m/s), negative backwards
  double angular_dps = 0.0;  // yaw rate (deg/s), positive counter-clockwise
};

/// Scenario section `path:` (docs/scenarios.md).
struct RobotPathOptions {
  PathKind kind = PathKind::kRoundTrip;
  double speed_mps = 0.34;               // cruise speed (P1: 0.34 m/s; P3 drove at 0.30 m/s)
  double acceleration_mps2 = 0.3;        // trapezoidal speed ramps, up and down (m/s^2)
  double turn_rate_dps = 30.0;           // in-place turns: cruise yaw rate (deg/s)
  double turn_acceleration_dps2 = 90.0;  // in-place turns: yaw-rate ramps (deg/s^2)
  double lateral_offset_m = 0.0;         // legs run this far to the left of the corridor axis (m)
  double end_margin_m = 1.0;    // distance kept from corridor ends where the robot starts/turns
  int laps = 1;                 // loop: laps; round_trip: repetitions; umbmark: squares
  double umbmark_side_m = 4.0;  // UMBmark square side (Borenstein: 4 m)
  std::vector<VelocityCommand> commands;  // kind script: driven in order, then stop

  /// The first problem with these options on their own (the world is checked by BuildRobotPath).
  std::optional<OptionsProblem> Check() const;
};

/// The keys of `path:` (parsing, bounds, echo, docs).
const OptionTable<RobotPathOptions>& RobotPathOptionsTable();

/// Reads the keys present in a `path:` map onto `options`; unknown keys and wrong types are
/// InputErrors. `commands` is a list of [duration_s, linear_mps, angular_dps] rows.
void ParseRobotPathOptions(YamlMap& map, RobotPathOptions& options);

/// The end of one straight leg, and the in-place turn made there.
struct Waypoint {
  Eigen::Vector2d p_in_world = Eigen::Vector2d::Zero();  // end of the leg (m)
  double turn_rad = 0.0;  // in-place turn on arrival, positive counter-clockwise (rad)
};

/// A path: from `world_from_start`, drive straight to each waypoint in turn and make its turn.
/// Each turn leaves the robot heading along the next leg; the last one restores the heading the
/// path needs at its end (the start heading for every closed path). A script path has no
/// waypoints, only commands.
struct RobotPath {
  PathKind kind = PathKind::kRoundTrip;
  SE2 world_from_start;
  std::vector<Waypoint> waypoints;
  std::vector<VelocityCommand> commands;  // kind script only

  /// Sum of the straight legs (m).
  double length_m() const;
  /// Sum of the in-place turns' magnitudes (rad).
  double total_turn_rad() const;
  /// Where a perfectly followed path ends.
  SE2 world_from_goal() const;
};

/// The path of `options` in `world` (options.Check() must pass). Throws OptionsError {key relative
/// to `path`, message} when it does not fit: a loop on a non-loop layout ("kind"), a leg closer
/// than kPathWallClearanceM to a wall ("lateral_offset_m", "end_margin_m", "umbmark_side_m"), or
/// an end margin that leaves no corridor to drive.
RobotPath BuildRobotPath(const worlds::World& world, const RobotPathOptions& options);

/// What the robot is asked to do now.
struct DriveCommand {
  double linear_mps = 0.0;   // forward (m/s)
  double angular_rps = 0.0;  // yaw rate (rad/s), positive counter-clockwise
};

/// Drives a RobotPath from the true pose. Call Update at a fixed control rate (the period is taken
/// from consecutive `now_ns`); the first call only starts the clock and returns a stop command.
/// Straight legs: trapezoidal speed profile (ramps at acceleration_mps2, exact braking for the
/// control period so the robot stops on the waypoint), heading + cross-track law to the leg's
/// line. Turns: the same profile on the yaw angle at turn_rate_dps / turn_acceleration_dps2,
/// done within kTurnToleranceRad. Script paths replay their commands open loop.
class PathFollower {
 public:
  static constexpr double kArriveToleranceM = 0.002;  // a leg is done this close to its end
  static constexpr double kTurnToleranceRad = 0.002;  // a turn is done this close to its target
  static constexpr double kCrossTrackGainPerM = 2.0;  // approach angle atan(gain * cross-track)
  static constexpr double kHeadingGainPerS = 2.0;     // yaw rate per rad of heading error

  PathFollower(RobotPath path, const RobotPathOptions& options);

  DriveCommand Update(TimeNs now_ns, const SE2& world_from_robot);
  bool done() const { return done_; }
  /// Fraction of the path done, in [0, 1], by the nominal time of legs and turns; never falls.
  double progress() const;
  const RobotPath& path() const { return path_; }

 private:
  // The path as a flat list of actions: drive a leg or turn in place.
  struct Action {
    bool is_turn = false;
    Eigen::Vector2d from_in_world = Eigen::Vector2d::Zero();  // drive: the leg's line
    Eigen::Vector2d to_in_world = Eigen::Vector2d::Zero();
    double turn_rad = 0.0;       // turn: signed angle
    double heading_after = 0.0;  // nominal heading after the action (rad)
    double nominal_s = 0.0;      // nominal duration (s), for progress
  };

  DriveCommand Drive(const Action& action, double dt_s, const SE2& world_from_robot);
  DriveCommand Turn(const Action& action, double dt_s, const SE2& world_from_robot);
  DriveCommand Script(TimeNs now_ns);
  void NextAction();

  RobotPath path_;
  double speed_mps_;
  double acceleration_mps2_;
  double turn_rate_rps_;
  double turn_acceleration_rps2_;
  std::vector<Action> actions_;
  std::vector<TimeNs> script_ends_ns_;  // script: end of each command after the first call
  double total_nominal_s_ = 0.0;

  bool started_ = false;
  bool done_ = false;
  TimeNs start_ns_ = 0;
  TimeNs last_ns_ = 0;
  std::size_t action_ = 0;
  double action_fraction_ = 0.0;  // of the current action, for progress
  DriveCommand last_command_;
  // Turn state: yaw unwrapped across calls, and the angle the current turn still has to go.
  double last_yaw_rad_ = 0.0;
  double turned_rad_ = 0.0;     // since the current turn started
  double turn_goal_rad_ = 0.0;  // angle to turn, measured from the actual start yaw
  bool turn_started_ = false;
};

}  // namespace corridorsim::sim
