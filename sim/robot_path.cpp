#include "sim/robot_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <utility>

#include "common/enum_names.h"
#include "common/io/options_yaml.h"
#include "common/options_checker.h"

namespace corridorsim::sim {
namespace {

using Eigen::Vector2d;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kEpsM = 1e-9;
// Script rows: each command holds for at least a millisecond (a physics step at 1 kHz; a
// shorter one would round towards 0 ns and is never driven), and the rows together fit the
// longest run.
constexpr double kMinCommandS = 1e-3;
constexpr std::size_t kMaxCommands = 10000;

std::string Metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g m", v);
  return buf;
}

std::string Point(const Vector2d& p) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%.2f, %.2f)", p.x(), p.y());
  return buf;
}

Vector2d LeftOf(const Vector2d& direction) { return {-direction.y(), direction.x()}; }

double Cross(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Signed angle (rad) that turns unit direction `a` onto unit direction `b`, in (-pi, pi].
double AngleBetween(const Vector2d& a, const Vector2d& b) {
  return NormalizeAngle(std::atan2(Cross(a, b), a.dot(b)));
}

double PointSegmentDistance(const Vector2d& p, const Vector2d& a, const Vector2d& b) {
  const Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Least distance between two segments in the plane (0 when they cross).
double SegmentDistance(const Vector2d& a, const Vector2d& b, const Vector2d& c, const Vector2d& d) {
  const double d1 = Cross(b - a, c - a), d2 = Cross(b - a, d - a);
  const double d3 = Cross(d - c, a - c), d4 = Cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return 0.0;
  }
  return std::min({PointSegmentDistance(a, c, d), PointSegmentDistance(b, c, d),
                   PointSegmentDistance(c, a, b), PointSegmentDistance(d, a, b)});
}

// A straight piece of the route on the corridor centre line (or the UMBmark square), in travel
// order.
struct CentreLeg {
  Vector2d from;
  Vector2d to;
  Vector2d direction() const { return (to - from).normalized(); }
};

// How one leg's offset line joins the next one's.
enum class Join { kCollinear, kReverse, kCorner };

Join JoinOf(const CentreLeg& a, const CentreLeg& b) {
  const double c = a.direction().dot(b.direction());
  if (c > 1 - 1e-9) return Join::kCollinear;
  if (c < -1 + 1e-9) return Join::kReverse;
  return Join::kCorner;
}

// Intersection of the lines p + s u and q + t v (not parallel).
Vector2d Intersect(const Vector2d& p, const Vector2d& u, const Vector2d& q, const Vector2d& v) {
  const double t = Cross(q - p, u) / Cross(u, v);
  return q + t * v;
}

// The legs of a closed route (the last leg's end is the first leg's start), each shifted
// `offset_m` to the left of its travel direction and joined in place: corners at the
// intersection of the shifted lines, reversals through a short crossing leg (two 90 deg turns;
// one 180 deg turn counter-clockwise when the offset is zero). Driven `laps` times; collinear
// joins between laps pass straight through.
RobotPath OffsetRoute(const std::vector<CentreLeg>& legs, double offset_m, int laps) {
  const std::size_t n = legs.size();
  auto offset_point = [&](std::size_t i, const Vector2d& p) {
    return Vector2d(p + offset_m * LeftOf(legs[i].direction()));
  };
  RobotPath path;
  const CentreLeg& last = legs[n - 1];
  Vector2d start = offset_point(0, legs[0].from);
  if (JoinOf(last, legs[0]) == Join::kCorner) {
    start = Intersect(offset_point(n - 1, last.from), last.direction(), start, legs[0].direction());
  }
  const Vector2d d0 = legs[0].direction();
  path.world_from_start = SE2(start, std::atan2(d0.y(), d0.x()));
  for (int lap = 0; lap < laps; ++lap) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      const bool final_join = lap == laps - 1 && i == n - 1;
      const Vector2d di = legs[i].direction(), dj = legs[j].direction();
      switch (JoinOf(legs[i], legs[j])) {
        case Join::kCollinear:
          if (final_join) path.waypoints.push_back({offset_point(i, legs[i].to), 0.0});
          break;
        case Join::kCorner:
          path.waypoints.push_back(
              {Intersect(offset_point(i, legs[i].from), di, offset_point(j, legs[j].from), dj),
               AngleBetween(di, dj)});
          break;
        case Join::kReverse: {
          const Vector2d end_i = offset_point(i, legs[i].to);
          const Vector2d start_j = offset_point(j, legs[j].from);
          if ((start_j - end_i).norm() < kEpsM) {
            path.waypoints.push_back({end_i, std::numbers::pi});
          } else {
            const Vector2d across = (start_j - end_i).normalized();
            path.waypoints.push_back({end_i, AngleBetween(di, across)});
            path.waypoints.push_back({start_j, AngleBetween(across, dj)});
          }
          break;
        }
      }
    }
  }
  return path;
}

// Corridor legs a round trip drives out along: the first segment and the segments that continue
// from its end (the L's second leg); the loop's first side only.
std::vector<CentreLeg> OutboundLegs(const worlds::World& world, double end_margin_m) {
  std::vector<CentreLeg> legs;
  for (const worlds::CorridorSegment& seg : world.segments) {
    if (!legs.empty() && ((seg.start - legs.back().to).norm() > 1e-6 ||
                          world.options.layout == worlds::Layout::kLoop)) {
      break;
    }
    legs.push_back({seg.start, seg.end});
  }
  double corridor_length_m = 0.0;
  for (const CentreLeg& leg : legs) corridor_length_m += (leg.to - leg.from).norm();
  const Vector2d first_direction = legs.front().direction();
  const Vector2d last_direction = legs.back().direction();
  legs.front().from += end_margin_m * first_direction;
  legs.back().to -= end_margin_m * last_direction;
  if ((legs.front().to - legs.front().from).dot(first_direction) <= kEpsM ||
      (legs.back().to - legs.back().from).dot(last_direction) <= kEpsM) {
    throw OptionsError({"end_margin_m", "leaves no straight leg to drive: " + Metres(end_margin_m) +
                                            " from both ends of a corridor " +
                                            Metres(corridor_length_m) + " long"});
  }
  return legs;
}

double CorridorWidth(const worlds::World& world) {
  double width = world.segments.front().width_m;
  for (const worlds::CorridorSegment& seg : world.segments) width = std::min(width, seg.width_m);
  return width;
}

// The first straight leg that does not run forward (an end margin or offset that eats it).
std::optional<std::string> BackwardLeg(const RobotPath& path) {
  Vector2d from = path.world_from_start.translation();
  double heading = path.world_from_start.yaw();
  for (const Waypoint& w : path.waypoints) {
    const Vector2d step = w.p_in_world - from;
    if (step.norm() > kEpsM) {
      const Vector2d direction(std::cos(heading), std::sin(heading));
      if (step.dot(direction) < step.norm() * (1 - 1e-9)) {
        return "leaves no straight leg between " + Point(from) + " and " + Point(w.p_in_world);
      }
    }
    heading = NormalizeAngle(heading + w.turn_rad);
    from = w.p_in_world;
  }
  return std::nullopt;
}

// The closest wall to the path's legs, if it is nearer than kPathWallClearanceM.
std::optional<std::string> WallTooClose(const worlds::World& world, const RobotPath& path) {
  Vector2d from = path.world_from_start.translation();
  for (const Waypoint& w : path.waypoints) {
    for (const worlds::Wall& wall : world.walls) {
      const double d = SegmentDistance(from, w.p_in_world, wall.start, wall.end);
      if (d < kPathWallClearanceM - kEpsM) {
        return "the leg from " + Point(from) + " to " + Point(w.p_in_world) + " passes " +
               Metres(d) + " from wall " + std::to_string(wall.id) + " (the robot needs " +
               Metres(kPathWallClearanceM) + ")";
      }
    }
    from = w.p_in_world;
  }
  return std::nullopt;
}

// Nominal time (s) of a trapezoidal profile over `distance` at cruise `rate` and ramp `accel`.
double TrapezoidTime(double distance, double rate, double accel) {
  if (distance <= 0) return 0.0;
  if (distance >= rate * rate / accel) return distance / rate + rate / accel;
  return 2.0 * std::sqrt(distance / accel);
}

// Highest rate from which braking at `accel` in steps of `dt_s` stops within `remaining`: the
// distance covered is v^2 / (2 a) + v dt / 2 when each step holds its command for dt.
double StoppingRate(double remaining, double accel, double dt_s) {
  if (remaining <= 0) return 0.0;
  const double h = accel * dt_s / 2;
  return -h + std::sqrt(h * h + 2 * accel * remaining);
}

}  // namespace

std::string PathKindName(PathKind kind) { return NameOf(kPathKindNames, kind); }

std::optional<OptionsProblem> RobotPathOptions::Check() const {
  if (auto problem = CheckOptionBounds(RobotPathOptionsTable(), *this)) return problem;
  OptionsChecker c;
  if (kind == PathKind::kScript) {
    c.Require(!commands.empty(), "commands", "kind script needs at least one command");
  } else {
    c.Require(commands.empty(), "commands",
              "only kind script drives commands (kind is " + PathKindName(kind) + ")");
  }
  c.Require(commands.size() <= kMaxCommands, "commands",
            "at most " + std::to_string(kMaxCommands) + " rows (got " +
                std::to_string(commands.size()) + ")");
  double total_s = 0.0;
  for (std::size_t k = 0; k < commands.size() && !c.problem(); ++k) {
    const VelocityCommand& cmd = commands[k];
    const std::string row = "row " + std::to_string(k + 1) + ": ";
    c.Require(
        cmd.duration_s >= kMinCommandS && cmd.duration_s <= kMaxRunSeconds, "commands",
        row + "duration_s must lie in [0.001, 1e+06] s (got " + FormatNumber(cmd.duration_s) + ")");
    total_s += cmd.duration_s;
    c.Require(total_s <= kMaxRunSeconds, "commands",
              row + "the commands up to here last " + FormatNumber(total_s) +
                  " s, more than the longest run (1e+06 s)");
    c.Require(
        std::abs(cmd.linear_mps) <= kMaxPathSpeedMps, "commands",
        row + "linear_mps must lie in [-1.2, 1.2] (got " + FormatNumber(cmd.linear_mps) + ")");
    c.Require(
        std::abs(cmd.angular_dps) <= kMaxPathTurnRateDps, "commands",
        row + "angular_dps must lie in [-300, 300] (got " + FormatNumber(cmd.angular_dps) + ")");
  }
  return c.problem();
}

void ParseRobotPathOptions(YamlMap& map, RobotPathOptions& options) {
  ReadOptions(map, RobotPathOptionsTable(), options);
}

double RobotPath::length_m() const {
  double length = 0.0;
  Vector2d from = world_from_start.translation();
  for (const Waypoint& w : waypoints) {
    length += (w.p_in_world - from).norm();
    from = w.p_in_world;
  }
  return length;
}

double RobotPath::total_turn_rad() const {
  double turn = 0.0;
  for (const Waypoint& w : waypoints) turn += std::abs(w.turn_rad);
  return turn;
}

SE2 RobotPath::world_from_goal() const {
  if (waypoints.empty()) return world_from_start;
  double heading = world_from_start.yaw();
  Vector2d from = world_from_start.translation();
  for (const Waypoint& w : waypoints) {
    const Vector2d step = w.p_in_world - from;
    if (step.norm() > kEpsM) heading = std::atan2(step.y(), step.x());
    heading += w.turn_rad;
    from = w.p_in_world;
  }
  return SE2(from, heading);
}

RobotPath BuildRobotPath(const worlds::World& world, const RobotPathOptions& options) {
  CheckOrDie(!world.segments.empty(), "sim::PathFollower",
             "BuildRobotPath: the world has no corridor segments");
  const double width_m = CorridorWidth(world);
  const double free_half_width_m = width_m / 2 - kPathWallClearanceM;
  const double offset_m = options.lateral_offset_m;
  const double margin_m = options.end_margin_m;
  const bool umbmark =
      options.kind == PathKind::kUmbmarkCw || options.kind == PathKind::kUmbmarkCcw;
  const bool loop_layout = world.options.layout == worlds::Layout::kLoop;

  if (options.kind == PathKind::kLoop && !loop_layout) {
    throw OptionsError({"kind", "a loop path needs world layout loop (the layout is " +
                                    worlds::LayoutName(world.options.layout) + ")"});
  }
  if (umbmark && options.umbmark_side_m > 2 * free_half_width_m + kEpsM) {
    throw OptionsError({"umbmark_side_m",
                        "a square of " + Metres(options.umbmark_side_m) + " needs a corridor " +
                            Metres(options.umbmark_side_m + 2 * kPathWallClearanceM) +
                            " wide to keep the robot " + Metres(kPathWallClearanceM) +
                            " from the walls; this one is " + Metres(width_m) + " wide (at most " +
                            Metres(std::max(0.0, 2 * free_half_width_m)) + " fits)"});
  }
  const double lateral_reach_m = std::abs(offset_m) + (umbmark ? options.umbmark_side_m / 2 : 0.0);
  if (lateral_reach_m > free_half_width_m + kEpsM) {
    throw OptionsError(
        {"lateral_offset_m",
         (lateral_reach_m < width_m / 2
              ? "puts the robot " + Metres(width_m / 2 - lateral_reach_m) + " from a wall"
              : std::string("puts the robot outside the corridor")) +
             "; it needs " + Metres(kPathWallClearanceM) + ", so at most " +
             Metres(std::max(0.0, free_half_width_m - (lateral_reach_m - std::abs(offset_m)))) +
             " to either side fits this " + Metres(width_m) + " wide corridor"});
  }
  if (!loop_layout && margin_m < kPathWallClearanceM - kEpsM) {
    throw OptionsError({"end_margin_m", "puts the robot " + Metres(margin_m) +
                                            " from the corridor's end wall; it needs " +
                                            Metres(kPathWallClearanceM)});
  }

  if (options.kind == PathKind::kScript) {
    // Open loop from end_margin_m along the first corridor, offset to the left, facing along it.
    const worlds::CorridorSegment& seg = world.segments.front();
    const Vector2d d = seg.direction();
    RobotPath path;
    path.kind = options.kind;
    path.world_from_start =
        SE2(seg.start + margin_m * d + offset_m * LeftOf(d), std::atan2(d.y(), d.x()));
    path.commands = options.commands;
    return path;
  }

  std::vector<CentreLeg> legs;
  double route_offset_m = offset_m;
  switch (options.kind) {
    case PathKind::kRoundTrip: {
      legs = OutboundLegs(world, margin_m);
      const std::size_t out = legs.size();
      for (std::size_t k = out; k-- > 0;) legs.push_back({legs[k].to, legs[k].from});
      break;
    }
    case PathKind::kLoop: {
      // Around the rectangle from end_margin_m along its first side, back to that point.
      for (const worlds::CorridorSegment& seg : world.segments)
        legs.push_back({seg.start, seg.end});
      const Vector2d start = legs.front().from + margin_m * legs.front().direction();
      if (margin_m >= (legs.front().to - legs.front().from).norm() - kEpsM) {
        throw OptionsError(
            {"end_margin_m", "the loop starts " + Metres(margin_m) +
                                 " along its first side, which is only " +
                                 Metres((legs.front().to - legs.front().from).norm()) + " long"});
      }
      legs.front().from = start;
      if (margin_m > kEpsM) legs.push_back({world.segments.front().start, start});
      break;
    }
    case PathKind::kUmbmarkCw:
    case PathKind::kUmbmarkCcw: {
      // The square, centred on the corridor axis and shifted left by the offset (its size is
      // what UMBmark measures, so the offset moves it instead of shrinking it).
      const worlds::CorridorSegment& seg = world.segments.front();
      const Vector2d d = seg.direction(), left = LeftOf(d);
      const double side = options.umbmark_side_m;
      const double sign = options.kind == PathKind::kUmbmarkCw ? -1.0 : 1.0;  // turn direction
      const Vector2d c0 = seg.start + margin_m * d + (offset_m - sign * side / 2) * left;
      const Vector2d c1 = c0 + side * d, c2 = c1 + sign * side * left, c3 = c0 + sign * side * left;
      legs = {{c0, c1}, {c1, c2}, {c2, c3}, {c3, c0}};
      route_offset_m = 0.0;
      break;
    }
    case PathKind::kScript:
      break;
  }

  RobotPath path = OffsetRoute(legs, route_offset_m, options.laps);
  path.kind = options.kind;
  // A run that ends with the path (duration_s 0) lasts about twice its nominal time: it must fit
  // the longest run, as duration_s does.
  const double nominal_s = path.length_m() / options.speed_mps +
                           path.total_turn_rad() / (options.turn_rate_dps * kDegToRad);
  if (!(nominal_s <= kMaxRunSeconds)) {
    throw OptionsError(
        {options.laps > 1 ? "laps" : "speed_mps",
         "the path (" + Metres(path.length_m()) + " in " + std::to_string(options.laps) +
             " laps) takes " + FormatNumber(nominal_s) + " s at speed_mps " +
             FormatNumber(options.speed_mps) + ", more than the longest run (1e+06 s)"});
  }
  if (const auto backward = BackwardLeg(path)) {
    throw OptionsError({umbmark ? "umbmark_side_m" : "end_margin_m", *backward});
  }
  if (const auto too_close = WallTooClose(world, path)) {
    throw OptionsError({umbmark ? "umbmark_side_m" : "end_margin_m", *too_close});
  }
  return path;
}

// ---- PathFollower
// ------------------------------------------------------------------------------

PathFollower::PathFollower(RobotPath path, const RobotPathOptions& options)
    : path_(std::move(path)),
      speed_mps_(options.speed_mps),
      acceleration_mps2_(options.acceleration_mps2),
      turn_rate_rps_(options.turn_rate_dps * kDegToRad),
      turn_acceleration_rps2_(options.turn_acceleration_dps2 * kDegToRad) {
  CheckOrDie(
      speed_mps_ > 0 && acceleration_mps2_ > 0 && turn_rate_rps_ > 0 && turn_acceleration_rps2_ > 0,
      "sim::PathFollower", "speeds and accelerations must be positive (RobotPathOptions::Check)");
  if (path_.kind == PathKind::kScript) {
    for (const VelocityCommand& c : path_.commands) total_nominal_s_ += c.duration_s;
    done_ = path_.commands.empty();
    return;
  }
  Vector2d from = path_.world_from_start.translation();
  double heading = path_.world_from_start.yaw();
  for (const Waypoint& w : path_.waypoints) {
    const Vector2d step = w.p_in_world - from;
    if (step.norm() > kEpsM) {
      Action drive;
      drive.from_in_world = from;
      drive.to_in_world = w.p_in_world;
      drive.heading_after = std::atan2(step.y(), step.x());
      CheckOrDie(std::abs(NormalizeAngle(drive.heading_after - heading)) < 1e-6,
                 "sim::PathFollower",
                 "a leg does not start along the heading the previous turn left");
      drive.nominal_s = TrapezoidTime(step.norm(), speed_mps_, acceleration_mps2_);
      actions_.push_back(drive);
      heading = drive.heading_after;
    }
    if (std::abs(w.turn_rad) > 0) {
      Action turn;
      turn.is_turn = true;
      turn.from_in_world = turn.to_in_world = w.p_in_world;
      turn.turn_rad = w.turn_rad;
      turn.heading_after = NormalizeAngle(heading + w.turn_rad);
      turn.nominal_s = TrapezoidTime(std::abs(w.turn_rad), turn_rate_rps_, turn_acceleration_rps2_);
      actions_.push_back(turn);
      heading = turn.heading_after;
    }
    from = w.p_in_world;
  }
  for (const Action& a : actions_) total_nominal_s_ += a.nominal_s;
  done_ = actions_.empty();
}

double PathFollower::progress() const {
  if (done_) return 1.0;
  if (!started_ || total_nominal_s_ <= 0) return 0.0;
  if (path_.kind == PathKind::kScript) {
    return std::clamp(ToSeconds(last_ns_ - start_ns_) / total_nominal_s_, 0.0, 1.0);
  }
  double done_s = 0.0;
  for (std::size_t k = 0; k < action_; ++k) done_s += actions_[k].nominal_s;
  done_s += action_fraction_ * actions_[action_].nominal_s;
  return std::clamp(done_s / total_nominal_s_, 0.0, 1.0);
}

DriveCommand PathFollower::Update(TimeNs now_ns, const SE2& world_from_robot) {
  if (!started_) {
    started_ = true;
    start_ns_ = last_ns_ = now_ns;
    if (path_.kind == PathKind::kScript) {
      TimeNs end_ns = now_ns;
      for (const VelocityCommand& c : path_.commands) {
        end_ns += FromSeconds(c.duration_s);
        script_ends_ns_.push_back(end_ns);
      }
      return last_command_ = Script(now_ns);
    }
    return last_command_ = DriveCommand{};
  }
  if (done_) return last_command_ = DriveCommand{};
  if (path_.kind == PathKind::kScript) {
    last_ns_ = now_ns;
    return last_command_ = Script(now_ns);
  }
  const double dt_s = ToSeconds(now_ns - last_ns_);
  if (dt_s <= 0) return last_command_;  // called twice at one time: same answer
  last_ns_ = now_ns;
  const Action& action = actions_[action_];
  last_command_ =
      action.is_turn ? Turn(action, dt_s, world_from_robot) : Drive(action, dt_s, world_from_robot);
  return last_command_;
}

void PathFollower::NextAction() {
  ++action_;
  action_fraction_ = 0.0;
  turn_started_ = false;
  if (action_ >= actions_.size()) done_ = true;
}

DriveCommand PathFollower::Drive(const Action& action, double dt_s, const SE2& world_from_robot) {
  const Vector2d leg = action.to_in_world - action.from_in_world;
  const double length_m = leg.norm();
  const Vector2d direction = leg / length_m;
  const Vector2d p_in_world = world_from_robot.translation();
  const double remaining_m = (action.to_in_world - p_in_world).dot(direction);
  const double cross_track_m = (p_in_world - action.from_in_world).dot(LeftOf(direction));
  action_fraction_ = std::max(action_fraction_, std::clamp(1.0 - remaining_m / length_m, 0.0, 1.0));

  const double last_v = last_command_.linear_mps;
  const double step_mps = acceleration_mps2_ * dt_s;
  DriveCommand command;
  if (remaining_m <= kArriveToleranceM) {
    if (last_v <= step_mps) {  // arrived and slow enough to stop now
      NextAction();
      return command;
    }
    command.linear_mps = last_v - step_mps;  // overshot while braking: keep to the ramp
  } else {
    const double wanted = std::min(
        {speed_mps_, last_v + step_mps, StoppingRate(remaining_m, acceleration_mps2_, dt_s)});
    command.linear_mps = std::max({wanted, last_v - step_mps, 0.0});
  }
  // Heading + cross-track law: aim back at the line at atan(k e), turn towards that heading.
  const double leg_heading = std::atan2(direction.y(), direction.x());
  const double wanted_heading = leg_heading - std::atan(kCrossTrackGainPerM * cross_track_m);
  const double heading_error = NormalizeAngle(wanted_heading - world_from_robot.yaw());
  command.angular_rps =
      std::clamp(kHeadingGainPerS * heading_error, -turn_rate_rps_, turn_rate_rps_);
  return command;
}

DriveCommand PathFollower::Turn(const Action& action, double dt_s, const SE2& world_from_robot) {
  const double yaw = world_from_robot.yaw();
  if (!turn_started_) {
    // Aim at the nominal heading (not the start yaw plus the turn) so errors do not add up.
    const double heading_before = NormalizeAngle(action.heading_after - action.turn_rad);
    turn_goal_rad_ = action.turn_rad + NormalizeAngle(heading_before - yaw);
    turned_rad_ = 0.0;
    last_yaw_rad_ = yaw;
    turn_started_ = true;
  }
  turned_rad_ += NormalizeAngle(yaw - last_yaw_rad_);
  last_yaw_rad_ = yaw;
  const double remaining_rad = turn_goal_rad_ - turned_rad_;
  const double turned_fraction =
      turn_goal_rad_ != 0 ? std::clamp(turned_rad_ / turn_goal_rad_, 0.0, 1.0) : 1.0;
  action_fraction_ = std::max(action_fraction_, turned_fraction);

  const double last_w = last_command_.angular_rps;
  const double step_rps = turn_acceleration_rps2_ * dt_s;
  DriveCommand command;
  if (std::abs(remaining_rad) <= kTurnToleranceRad && std::abs(last_w) <= step_rps) {
    NextAction();
    return command;
  }
  const double rate = std::min(
      turn_rate_rps_, StoppingRate(std::abs(remaining_rad), turn_acceleration_rps2_, dt_s));
  const double wanted = std::copysign(rate, remaining_rad);
  command.angular_rps = std::clamp(wanted, last_w - step_rps, last_w + step_rps);
  return command;
}

DriveCommand PathFollower::Script(TimeNs now_ns) {
  for (std::size_t k = 0; k < script_ends_ns_.size(); ++k) {
    if (now_ns < script_ends_ns_[k]) {
      const VelocityCommand& c = path_.commands[k];
      return DriveCommand{c.linear_mps, c.angular_dps * kDegToRad};
    }
  }
  done_ = true;
  return DriveCommand{};
}

}  // namespace corridorsim::sim
