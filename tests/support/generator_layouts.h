// The worlds of the generator tests (tests/worlds/generator*_test.cpp): the options of the four
// layouts at the sizes of the shipped scenarios, and whether a box lies inside one of a floor
// plan's rectangles or cells.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "tests/support/tolerances.h"
#include "worlds/world.h"

namespace corridorsim::test {

/// The options of the four layouts, with the sizes of the shipped scenarios.
inline std::vector<worlds::WorldOptions> LayoutOptions() {
  using worlds::Layout;
  std::vector<worlds::WorldOptions> all_options(4);
  all_options[0].layout = Layout::kStraight;  // the defaults: 55 m, 16 doors, 14 plates
  all_options[1].layout = Layout::kLTurn;
  all_options[1].length_m = 30;
  all_options[1].second_length_m = 20;
  all_options[1].doors.count = 14;
  all_options[1].plates.count = 12;
  all_options[2].layout = Layout::kTJunction;
  all_options[2].length_m = 40;
  all_options[2].second_length_m = 15;
  all_options[2].doors.count = 14;
  all_options[2].plates.count = 12;
  all_options[3].layout = Layout::kLoop;
  all_options[3].length_m = 30;
  all_options[3].second_length_m = 16;
  all_options[3].doors.count = 20;
  all_options[3].plates.count = 18;
  return all_options;
}

/// Whether `box` lies inside one of `boxes`, within kGeomTolM.
inline bool InsideAny(const std::vector<Eigen::AlignedBox2d>& boxes,
                      const Eigen::AlignedBox2d& box) {
  for (const Eigen::AlignedBox2d& b : boxes) {
    if ((box.min().array() >= b.min().array() - kGeomTolM).all() &&
        (box.max().array() <= b.max().array() + kGeomTolM).all()) {
      return true;
    }
  }
  return false;
}

inline bool InsideAny(const std::vector<Eigen::AlignedBox2d>& boxes, const Eigen::Vector2d& p) {
  return InsideAny(boxes, Eigen::AlignedBox2d(p, p));
}

}  // namespace corridorsim::test
