#include "render/camera_placement.h"

#include "common/options_checker.h"

#include <algorithm>
#include <cmath>

namespace corridorsim::render {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

const auto& Num = FormatNumber;

// Where a point is: inside the corridor or a room, or why not.
enum class Space { kInside, kBelowFloor, kAboveCeiling, kOutside };

// A corridor segment's floor rectangle runs half a width past an end that meets another
// segment's (the corner square of an L or a loop), else to the end wall (worlds/layout.cpp).
bool SharesEnd(const worlds::World& world, const worlds::CorridorSegment& seg,
               const Eigen::Vector2d& p) {
  return std::any_of(world.segments.begin(), world.segments.end(),
                     [&](const worlds::CorridorSegment& other) {
                       return other.id != seg.id &&
                              ((other.start - p).norm() < 1e-6 || (other.end - p).norm() < 1e-6);
                     });
}

Space Locate(const worlds::World& world, const Vector3d& p, double* ceiling_m) {
  Space space = Space::kOutside;
  const auto consider = [&](double height_m) {
    if (p.z() > 0 && p.z() < height_m) {
      space = Space::kInside;
    } else if (space != Space::kInside) {
      space = p.z() <= 0 ? Space::kBelowFloor : Space::kAboveCeiling;
      *ceiling_m = height_m;
    }
  };
  for (const worlds::CorridorSegment& seg : world.segments) {
    const Vector2d d = seg.direction(), q = p.head<2>() - seg.start;
    const double along = q.dot(d), across = q.dot(Vector2d(-d.y(), d.x()));
    const double len = (seg.end - seg.start).norm();
    const double before = SharesEnd(world, seg, seg.start) ? seg.width_m / 2 : 0.0;
    const double after = SharesEnd(world, seg, seg.end) ? seg.width_m / 2 : 0.0;
    if (along >= -before && along <= len + after && std::abs(across) <= seg.width_m / 2) {
      consider(seg.height_m);
    }
  }
  for (const worlds::Doorway& door : world.doors) {
    // The opening through the wall (a closed door's leaf is a solid of its own), and the room.
    const Vector2d u = (door.column_b - door.column_a).normalized();
    const Vector2d q = p.head<2>() - door.column_a;
    const double along = q.dot(u), depth = -q.dot(door.inward_normal);
    const double span = (door.column_b - door.column_a).norm();
    if (along >= door.column_width_m / 2 && along <= span - door.column_width_m / 2 && depth >= 0 &&
        depth <= world.options.wall_thickness_m) {
      consider(door.top_height_m);
    }
    if (door.room && door.room->footprint.contains(p.head<2>())) {
      consider(door.room->ceiling_height_m);
    }
  }
  return space;
}

std::string At(const Vector3d& p) {
  return "at (" + Num(p.x()) + ", " + Num(p.y()) + ", " + Num(p.z()) + ") m";
}

}  // namespace

std::optional<std::string> CameraSpaceProblem(const worlds::World& world,
                                              const Vector3d& p_in_world) {
  double ceiling_m = 0.0;
  switch (Locate(world, p_in_world, &ceiling_m)) {
    case Space::kInside:
      break;
    case Space::kAboveCeiling:
      return "above the ceiling (" + Num(ceiling_m) + " m high)";
    case Space::kBelowFloor:
      return std::string("below the floor");
    case Space::kOutside:
      return std::string("outside the corridor (in or behind a wall)");
  }
  // The corridor's walls, floor and ceilings are axis-aligned planes: the ball of the clearance
  // about the centre stays inside when its six extreme points do.
  const std::string near = "within " + Num(kCameraClearanceM) + " m (the near plane, " +
                           Num(kNearPlaneM) + " m, and 1 cm) of ";
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {-1.0, 1.0}) {
      Vector3d q = p_in_world;
      q[axis] += sign * kCameraClearanceM;
      if (Locate(world, q, &ceiling_m) == Space::kInside) continue;
      if (axis < 2) return near + "a wall: it would see through it";
      return near + (sign > 0 ? "the ceiling" : "the floor") + ": it would see through it";
    }
  }
  return std::nullopt;
}

std::optional<OptionsProblem> CheckCameraPlacement(const worlds::World& world,
                                                   const RigOptions& rig,
                                                   const SE3& world_from_robot) {
  for (const CameraOptions& c : rig.cameras) {
    if (!c.enabled) continue;
    const Vector3d p = (world_from_robot * c.mount.RobotFromCamera()).translation();
    for (const worlds::CollisionBox& box : world.collision_boxes) {
      const double gap = ((p - box.center).cwiseAbs() - box.half_extents).maxCoeff();
      if (gap < kCameraClearanceM) {
        return OptionsProblem{c.id + ".mount",
                              "the camera " + At(p) + " is " +
                                  (gap < 0 ? "inside a "
                                           : "within " + Num(kCameraClearanceM) +
                                                 " m (the near plane and 1 cm) of a ") +
                                  worlds::SemanticClassName(box.semantic_class) + " (instance " +
                                  std::to_string(box.instance_id) + ")"};
      }
    }
    if (auto problem = CameraSpaceProblem(world, p)) {
      return OptionsProblem{c.id + ".mount", "the camera " + At(p) + " is " + *problem};
    }
  }
  return std::nullopt;
}

}  // namespace corridorsim::render
