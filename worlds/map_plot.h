#pragma once
// map.png: a top-down plan of a world that a person reads at a glance (walkable area, rooms,
// walls, doorways by state, door plates with their room numbers, lamps, reflectors, distractors),
// with a title line, a scale bar and a legend.

#include <Eigen/Core>

#include "common/image.h"
#include "worlds/world.h"

namespace corridorsim::worlds {

/// Where the plan lies in the image: world x-y (frame W, metres) to pixels, x to the right and
/// +y (left in W) up. The one metre-to-pixel transform of the plan.
struct MapView {
  double px_per_m = 0.0;
  Eigen::Vector2d min_in_world{0, 0};  // world x-y drawn at `min_px` (bottom-left of the plan)
  Eigen::Vector2d min_px{0, 0};        // pixel (x right, y down) of `min_in_world`
  int width_px = 0;                    // whole image, title and legend included
  int height_px = 0;

  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p_in_world) const {
    return {min_px.x() + (p_in_world.x() - min_in_world.x()) * px_per_m,
            min_px.y() - (p_in_world.y() - min_in_world.y()) * px_per_m};
  }
  /// A direction of W (x-y) as a pixel direction (the y flip alone).
  static Eigen::Vector2d DirectionToPixel(const Eigen::Vector2d& d_in_world) {
    return {d_in_world.x(), -d_in_world.y()};
  }
};

/// The view RenderMap uses. `px_per_m` <= 0 chooses it so that the plan's longest side is about
/// 2400 px, clamped to [20, 80] px/m. Throws std::invalid_argument for a non-finite scale or one
/// that makes the image larger than 20000 px on a side.
MapView ComputeMapView(const World& world, double px_per_m = 0.0);

/// The plan as an RGB image (row 0 on top). Deterministic: the same world gives the same pixels.
Image8 RenderMap(const World& world, double px_per_m = 0.0);

}  // namespace corridorsim::worlds
