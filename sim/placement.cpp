#include "sim/placement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/options_checker.h"
#include "render/camera_placement.h"

namespace corridorsim::sim {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTouchM = 1e-9;          // touching a solid is not intersecting it
constexpr double kMaxTurnStepRad = kDeg;  // turns and arcs: at most this per step
constexpr double kFloorStepM = 0.02;      // cameras: corridor/room clearance along a chord (under
                                          // render::kCameraClearanceM - kNearPlaneM)
constexpr double kStraightEpsM = 1e-9;

std::string Num(double v) { return FormatNumber(v); }

// The world's collision boxes on a uniform grid in x-y, so that a query costs what is near it.
class BoxGrid {
 public:
  explicit BoxGrid(const worlds::World& world) : boxes_(world.collision_boxes) {
    for (const worlds::CollisionBox& b : boxes_) bounds_.extend(Extent(b));
    if (bounds_.isEmpty()) return;
    // Cells of at least 1 m, at most 65536 of them and 4096 a side, whatever the world's size.
    const Vector2d size = bounds_.sizes();
    cell_m_ = std::max(
        {1.0, std::sqrt(size.x() * size.y() / 65536.0), size.x() / 4096.0, size.y() / 4096.0});
    nx_ = std::max(1, static_cast<int>(std::ceil(size.x() / cell_m_)));
    ny_ = std::max(1, static_cast<int>(std::ceil(size.y() / cell_m_)));
    cells_.resize(static_cast<std::size_t>(nx_) * ny_);
    seen_.assign(boxes_.size(), 0);
    for (std::size_t i = 0; i < boxes_.size(); ++i) {
      const Range r = Cells(Extent(boxes_[i]));
      for (int y = r.y0; y <= r.y1; ++y) {
        for (int x = r.x0; x <= r.x1; ++x) cells_[Index(x, y)].push_back(i);
      }
    }
  }

  static AlignedBox2d Extent(const worlds::CollisionBox& b) {
    return AlignedBox2d(Vector2d(b.center.head<2>() - b.half_extents.head<2>()),
                        Vector2d(b.center.head<2>() + b.half_extents.head<2>()));
  }

  // Calls f(box) once for every box in a cell that `query` touches; f returns true to stop.
  template <class F>
  void ForEachNear(const AlignedBox2d& query, F&& f) const {
    if (cells_.empty() || query.intersection(bounds_).isEmpty()) return;
    ++stamp_;
    const Range r = Cells(query.intersection(bounds_));
    for (int y = r.y0; y <= r.y1; ++y) {
      for (int x = r.x0; x <= r.x1; ++x) {
        for (std::size_t i : cells_[Index(x, y)]) {
          if (seen_[i] == stamp_) continue;
          seen_[i] = stamp_;
          if (f(boxes_[i])) return;
        }
      }
    }
  }

 private:
  struct Range {
    int x0, x1, y0, y1;
  };
  Range Cells(const AlignedBox2d& box) const {
    const auto cell = [&](double v, double lo, int n) {
      return std::clamp(static_cast<int>(std::floor((v - lo) / cell_m_)), 0, n - 1);
    };
    return {
        cell(box.min().x(), bounds_.min().x(), nx_), cell(box.max().x(), bounds_.min().x(), nx_),
        cell(box.min().y(), bounds_.min().y(), ny_), cell(box.max().y(), bounds_.min().y(), ny_)};
  }
  std::size_t Index(int x, int y) const { return static_cast<std::size_t>(y) * nx_ + x; }

  const std::vector<worlds::CollisionBox>& boxes_;
  AlignedBox2d bounds_;
  double cell_m_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::size_t>> cells_;
  mutable std::vector<std::uint64_t> seen_;
  mutable std::uint64_t stamp_ = 0;
};

// Convex hull of points in the plane (Andrew's monotone chain), counter-clockwise.
std::vector<Vector2d> ConvexHull(std::vector<Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Vector2d& a, const Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  const auto cross = [](const Vector2d& o, const Vector2d& a, const Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Vector2d> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Whether a convex polygon and an axis-aligned rectangle overlap by more than kTouchM
// (separating axes: the rectangle's two and the polygon's edge normals).
bool Overlaps(const std::vector<Vector2d>& polygon, const AlignedBox2d& box) {
  const auto separated = [&](const Vector2d& axis, double box_lo, double box_hi) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Vector2d& v : polygon) {
      const double d = axis.dot(v);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return hi <= box_lo + kTouchM || lo >= box_hi - kTouchM;
  };
  if (separated(Vector2d::UnitX(), box.min().x(), box.max().x())) return false;
  if (separated(Vector2d::UnitY(), box.min().y(), box.max().y())) return false;
  const Vector2d corners[4] = {
      box.corner(AlignedBox2d::BottomLeft), box.corner(AlignedBox2d::BottomRight),
      box.corner(AlignedBox2d::TopLeft), box.corner(AlignedBox2d::TopRight)};
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vector2d edge = polygon[(i + 1) % polygon.size()] - polygon[i];
    if (edge.norm() < 1e-12) continue;
    const Vector2d axis = Vector2d(-edge.y(), edge.x()).normalized();
    double lo = INFINITY, hi = -INFINITY;
    for (const Vector2d& c : corners) {
      lo = std::min(lo, axis.dot(c));
      hi = std::max(hi, axis.dot(c));
    }
    if (separated(axis, lo, hi)) return false;
  }
  return true;
}

// Whether the segment a-b passes through the open interior of `box` (slab test).
bool SegmentEntersBox(const Vector3d& a, const Vector3d& b, const worlds::CollisionBox& box) {
  const Vector3d d = b - a;
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = box.center[k] - box.half_extents[k] + kTouchM;
    const double hi = box.center[k] + box.half_extents[k] - kTouchM;
    if (!(lo < hi)) return false;
    if (std::abs(d[k]) < 1e-15) {
      if (a[k] <= lo || a[k] >= hi) return false;
      continue;
    }
    double ta = (lo - a[k]) / d[k], tb = (hi - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t0 < t1)) return false;
  }
  return true;
}

std::string Where(const SE2& pose, double along_m) {
  return "at (" + Num(pose.x()) + ", " + Num(pose.y()) + ") m heading " +
         Num(std::round(pose.yaw() / kDeg * 10) / 10) + " deg, " +
         Num(std::round(along_m * 100) / 100) + " m along the path";
}

std::string SolidName(const worlds::CollisionBox& box) {
  return worlds::SemanticClassName(box.semantic_class) + " (instance " +
         std::to_string(box.instance_id) + ")";
}

// A point sensor that must stay in the open: a camera's optical centre or a scanner's origin.
struct Camera {
  std::string id;
  Vector3d p_in_robot;
  const char* kind = "camera";
};

// The first problem of one sweep: what hit, where.
struct Hit {
  enum Kind { kBody, kCamera, kLeftWorld } kind = kBody;
  std::string camera_id;  // kCamera
  std::string message;
};

// Sweeps the robot (its chassis boxes) and the cameras along the path; stops at the first hit.
class Sweep {
 public:
  Sweep(const worlds::World& world, const BoxGrid& grid, const RobotOptions& robot,
        std::vector<Camera> cameras)
      : world_(world), grid_(grid), boxes_(ChassisBoxes(robot)), cameras_(std::move(cameras)) {
    char size[96];
    std::snprintf(size, sizeof(size), "%s x %s x %s m", Num(robot.body_length_m).c_str(),
                  Num(robot.body_width_m).c_str(), Num(robot.body_height_m).c_str());
    body_size_ = size;
    // The farthest swept point from the robot's origin sets the step of turns and arcs.
    for (const ChassisBox& b : boxes_) {
      reach_m_ = std::max(
          reach_m_, (b.center_in_robot.head<2>().cwiseAbs() + b.half_extents.head<2>()).norm());
    }
    for (const Camera& c : cameras_) reach_m_ = std::max(reach_m_, c.p_in_robot.head<2>().norm());
    world_xy_ = AlignedBox2d(world.bounds.min().head<2>(), world.bounds.max().head<2>());
  }

  std::optional<Hit> Run(const RobotPath& path) {
    pose_ = path.world_from_start;
    along_m_ = 0.0;
    if (Move(pose_)) return hit_;
    if (path.kind == PathKind::kScript) {
      for (const VelocityCommand& c : path.commands) {
        if (Command(c)) return hit_;
      }
      return std::nullopt;
    }
    for (const Waypoint& w : path.waypoints) {
      const Vector2d step = w.p_in_world - pose_.translation();
      if (step.norm() > kStraightEpsM) {
        const double heading = std::atan2(step.y(), step.x());
        if (Turn(NormalizeAngle(heading - pose_.yaw()))) return hit_;
        if (Move(SE2(w.p_in_world, heading))) return hit_;
      }
      if (Turn(w.turn_rad)) return hit_;
    }
    return std::nullopt;
  }

 private:
  // One move from pose_ to `next`: translation exactly, a small rotation to kMaxSagittaM.
  bool Move(const SE2& next) {
    const SE2 from = pose_;
    along_m_ += (next.translation() - from.translation()).norm();
    pose_ = next;
    for (const ChassisBox& b : boxes_) {
      std::vector<Vector2d> corners;
      corners.reserve(8);
      for (const SE2* pose : {&from, &next}) {
        for (const double sx : {-1.0, 1.0}) {
          for (const double sy : {-1.0, 1.0}) {
            corners.push_back(*pose * Vector2d(b.center_in_robot.x() + sx * b.half_extents.x(),
                                               b.center_in_robot.y() + sy * b.half_extents.y()));
          }
        }
      }
      const std::vector<Vector2d> hull = ConvexHull(corners);
      AlignedBox2d extent;
      for (const Vector2d& c : hull) extent.extend(c);
      const double z_lo = b.center_in_robot.z() - b.half_extents.z();
      const double z_hi = b.center_in_robot.z() + b.half_extents.z();
      const worlds::CollisionBox* first = nullptr;
      grid_.ForEachNear(extent, [&](const worlds::CollisionBox& solid) {
        if (z_hi <= solid.center.z() - solid.half_extents.z() + kTouchM ||
            z_lo >= solid.center.z() + solid.half_extents.z() - kTouchM) {
          return false;
        }
        if (Overlaps(hull, BoxGrid::Extent(solid))) first = &solid;
        return first != nullptr;
      });
      if (first) {
        hit_ = Hit{Hit::kBody, "",
                   "the robot body (" + body_size_ + ") " + Where(next, along_m_) +
                       ", intersects a " + SolidName(*first)};
        return true;
      }
    }
    for (const Camera& c : cameras_) {
      const Vector3d a = Lift(from, c.p_in_robot), b = Lift(next, c.p_in_robot);
      const auto camera_hit = [&](const Vector3d& p, const std::string& what) {
        hit_ = Hit{Hit::kCamera, c.id,
                   std::string("the ") + c.kind + " at (" + Num(p.x()) + ", " + Num(p.y()) + ", " +
                       Num(p.z()) + ") m, the robot " + Where(next, along_m_) + ", is " + what};
        return true;
      };
      // Solids within the clearance of the chord (the boxes grown by it), then the corridor's
      // boundary at steps along it (render::CameraSpaceProblem: walls, floor, ceilings).
      const double r = render::kCameraClearanceM;
      const AlignedBox2d extent(Vector2d(a.head<2>().cwiseMin(b.head<2>()).array() - r),
                                Vector2d(a.head<2>().cwiseMax(b.head<2>()).array() + r));
      const worlds::CollisionBox* first = nullptr;
      grid_.ForEachNear(extent, [&](const worlds::CollisionBox& solid) {
        worlds::CollisionBox grown = solid;
        grown.half_extents.array() += r;
        if (SegmentEntersBox(a, b, grown)) first = &solid;
        return first != nullptr;
      });
      if (first) {
        return camera_hit(b, "inside a " + SolidName(*first) + " or within " + Num(r) +
                                 " m of it (the near plane, " + Num(render::kNearPlaneM) +
                                 " m, and 1 cm): it would see through it");
      }
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kFloorStepM)));
      for (int k = 0; k <= n; ++k) {
        const Vector3d p = a + (b - a) * (static_cast<double>(k) / n);
        if (auto problem = render::CameraSpaceProblem(world_, p)) return camera_hit(p, *problem);
      }
    }
    // Only a script can get here, through no solid: the world's bounds end every sweep.
    if (!world_xy_.contains(next.translation())) {
      hit_ = Hit{Hit::kLeftWorld, "", "drives the robot out of the world " + Where(next, along_m_)};
      return true;
    }
    return false;
  }

  static Vector3d Lift(const SE2& pose, const Vector3d& p_in_robot) {
    const Vector2d xy = pose * Vector2d(p_in_robot.head<2>());
    return Vector3d(xy.x(), xy.y(), p_in_robot.z());
  }

  // The angle step for a rotation about a centre `radius_m` from the robot's origin.
  double RotationStep(double radius_m) const {
    const double rho = std::abs(radius_m) + reach_m_;
    return rho > 0 ? std::min(kMaxTurnStepRad, std::sqrt(8 * kMaxSagittaM / rho)) : kMaxTurnStepRad;
  }

  // An in-place turn by `angle_rad` (a rotation repeats after a full turn: at most one is swept).
  bool Turn(double angle_rad) {
    if (angle_rad == 0.0) return false;
    const SE2 start = pose_;
    const double swept =
        std::copysign(std::min(std::abs(angle_rad), 2 * std::numbers::pi), angle_rad);
    const int n = static_cast<int>(std::ceil(std::abs(swept) / RotationStep(0.0)));
    for (int k = 1; k <= n; ++k) {
      if (Move(SE2(start.translation(), start.yaw() + swept * k / n))) return true;
    }
    pose_ = SE2(start.translation(), start.yaw() + angle_rad);
    return false;
  }

  // A script command: a straight line, an in-place turn or an arc of constant curvature, swept
  // until it is done, it has gone round once, or the robot leaves the world.
  bool Command(const VelocityCommand& c) {
    const double v = c.linear_mps, w = c.angular_dps * kDeg, t = c.duration_s;
    if (w == 0.0) return v == 0.0 ? false : Move(pose_ * SE2(v * t, 0.0, 0.0));
    if (v == 0.0) return Turn(w * t);
    const SE2 start = pose_;
    const double radius_m = v / w, angle_rad = w * t;
    const double swept =
        std::copysign(std::min(std::abs(angle_rad), 2 * std::numbers::pi), angle_rad);
    const auto arc = [&](double phi) {
      return start * SE2(radius_m * std::sin(phi), radius_m * (1 - std::cos(phi)), phi);
    };
    const double step = RotationStep(radius_m);
    const double n = std::ceil(std::abs(swept) / step);
    for (double k = 1; k <= n; ++k) {
      if (Move(arc(swept * k / n))) return true;
    }
    pose_ = arc(angle_rad);
    return false;
  }

  const worlds::World& world_;
  const BoxGrid& grid_;
  std::vector<ChassisBox> boxes_;
  std::vector<Camera> cameras_;
  std::string body_size_;
  double reach_m_ = 0.0;
  AlignedBox2d world_xy_;
  SE2 pose_;
  double along_m_ = 0.0;
  Hit hit_;
};

}  // namespace

std::optional<PlacementProblem> CheckPathPlacement(const worlds::World& world,
                                                   const RobotOptions& robot, const RobotPath& path,
                                                   const render::RigOptions* rig,
                                                   const std::vector<LaserOptions>& lasers) {
  const BoxGrid grid(world);
  std::vector<Camera> cameras;
  if (rig) {
    for (const render::CameraOptions& c : rig->cameras) {
      if (c.enabled) cameras.push_back({c.id, c.mount.RobotFromCamera().translation()});
    }
  }
  // A scanner's origin: outside the chassis (the robot is not in what its beams meet, so from
  // inside it would see through its own body), then in the open along the path like a camera.
  for (const LaserOptions& l : lasers) {
    if (!l.enabled) continue;
    const Vector3d p = l.mount.RobotFromBody().translation();
    for (const ChassisBox& box : ChassisBoxes(robot)) {
      if (((p - box.center_in_robot).cwiseAbs() - box.half_extents).maxCoeff() < 0.0) {
        return PlacementProblem{
            "sensors",
            {l.id + ".mount", "the scanner at (" + Num(p.x()) + ", " + Num(p.y()) + ", " +
                                  Num(p.z()) +
                                  ") m in the robot frame is inside the chassis: its beams would "
                                  "start inside the robot (mount it above the top plate, "
                                  "body_height_m " +
                                  Num(robot.body_height_m) +
                                  " m, or outside "
                                  "the body)"}};
      }
    }
    cameras.push_back({l.id, p, "scanner"});
  }
  const std::optional<Hit> hit = Sweep(world, grid, robot, cameras).Run(path);
  if (!hit) return std::nullopt;
  const std::string path_key = path.kind == PathKind::kScript ? "commands" : "kind";
  if (hit->kind == Hit::kCamera) {
    return PlacementProblem{"sensors", {hit->camera_id + ".mount", hit->message}};
  }
  if (hit->kind == Hit::kLeftWorld) return PlacementProblem{"path", {path_key, hit->message}};

  // The body: the first dimension whose default would let the robot drive the path.
  const auto body_fits = [&](const RobotOptions& r) {
    return !Sweep(world, grid, r, {}).Run(path).has_value();
  };
  const RobotOptions defaults;
  struct Dimension {
    const char* key;
    double RobotOptions::*member;
  };
  const Dimension dimensions[] = {{"body_width_m", &RobotOptions::body_width_m},
                                  {"body_length_m", &RobotOptions::body_length_m},
                                  {"body_height_m", &RobotOptions::body_height_m},
                                  {"wheelbase_m", &RobotOptions::wheelbase_m}};
  const auto blame = [&](const Dimension& d) {
    return PlacementProblem{"robot", {d.key, hit->message + " (got " + Num(robot.*d.member) + ")"}};
  };
  RobotOptions all_default = robot;
  const Dimension* first_larger = nullptr;
  for (const Dimension& d : dimensions) {
    if (!(robot.*d.member > defaults.*d.member)) continue;
    RobotOptions one = robot;
    one.*d.member = defaults.*d.member;
    if (body_fits(one)) return blame(d);
    all_default.*d.member = defaults.*d.member;
    if (!first_larger) first_larger = &d;
  }
  if (first_larger && body_fits(all_default)) return blame(*first_larger);
  return PlacementProblem{"path", {path_key, hit->message}};
}

}  // namespace corridorsim::sim
