#pragma once
// P2 section 5 (Fig. 12): "the grid map can be partitioned into several parts using the doors
// detected". The upward-camera pipelines have no grid map; they divide their landmark map. Each
// registered door opens a room: the rectangle behind the door's wall line, from the line to
// `room_depth_m` deep, and along it from `room_reach_m` beyond either column, cut half-way to the
// next door in the same wall so that rooms never overlap. The room side is the side away from
// where the robot stood when it registered the door (it sees doors from the corridor). Everything
// outside the rooms is the corridor (area 0). A point landmark belongs to the room whose
// rectangle holds it at least `min_depth_m` behind the wall line (points on the line are the
// doorway's own: the corridor's); where rectangles of doors in different walls overlap (a
// corridor's corner), the nearer door's. With `manhattan`, the door lines are first squared to
// the directions the doors agree on. Pure function: `DivideAtDoors`.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/options_table.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

struct DoorAreaOptions {
  double room_depth_m = 6.0;  // how far behind the wall line a room reaches
  double room_reach_m = 2.0;  // how far beyond the door's columns along the wall
  double min_depth_m = 0.15;  // nearer the wall line than this is the doorway (the corridor)
  // Walls meet at right angles (corridorsim's corridors, most buildings): each door's wall line
  // is turned about its midpoint onto the nearer of the two directions the doors agree on (the
  // width-weighted mean of their lines' directions modulo 90 deg) when within max_turn_deg. Two
  // bearing-only column estimates tilt a single door's line by several degrees.
  bool manhattan = true;
  double max_turn_deg = 30.0;
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<DoorAreaOptions>& DoorAreaOptionsTable();

/// A registered door: its two columns and where the robot stood when it registered it.
struct AreaDoor {
  int landmark_id = -1;
  Eigen::Vector2d column_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d column_b = Eigen::Vector2d::Zero();
  Eigen::Vector2d robot_xy = Eigen::Vector2d::Zero();  // at registration: the corridor side
};

struct AreaPoint {
  int landmark_id = -1;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
};

/// The corridor (id 0) and one room per door (ids 1.. in the order of `doors`); a door whose
/// columns coincide, or whose robot position lies on its wall line, opens no room. Landmark ids
/// ascending in each area. Non-finite points are left out of every area.
std::vector<MapArea> DivideAtDoors(const std::vector<AreaDoor>& doors,
                                   const std::vector<AreaPoint>& points,
                                   const DoorAreaOptions& options = {});

}  // namespace corridorsim::slam
