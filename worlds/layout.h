#pragma once
// The deterministic floor plan of a WorldOptions: corridor segments, the walls that bound their
// union, and how many doorways each side wall carries. No randomness: WorldOptions::Check() uses it
// to reject all_options whose doors cannot fit, and the generator places the doors it allocates.

#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "worlds/world.h"

namespace corridorsim::worlds {

struct LayoutPlan {
  std::vector<CorridorSegment> segments;
  std::vector<Eigen::AlignedBox2d> segment_rects;  // walkable rectangle of each segment
  std::vector<Wall> walls;                         // boundary of the union of the rectangles
  std::vector<Eigen::AlignedBox2d> floor_cells;    // disjoint rectangles covering the union
  std::vector<int> doors_per_wall;                 // parallel to walls
  double door_footprint_m = 0.0;                   // opening plus both frame columns
};

/// Builds the plan of `options`, assigning ids from `first_id` upwards (segments, then walls).
/// Returns a problem when the doorways cannot be placed.
std::optional<OptionsProblem> PlanLayout(const WorldOptions& options, int first_id,
                                         LayoutPlan* plan);

/// Usable interval of a wall for doorways and wall objects: [margin, length - margin].
double UsableWallLength(const Wall& wall, const WorldOptions& options);

}  // namespace corridorsim::worlds
