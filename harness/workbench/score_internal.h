#pragma once
// What the score's files share (score_input.cpp: the dataset's labels and the detections read and
// checked; score_evaluation.cpp: COCO's matching and the metrics): a circle's box and numbers as
// messages and bin names print them. Internal to harness/workbench/.

#include <array>
#include <cstdio>
#include <string>

namespace corridorsim::score_internal {

/// The box [x, y, w, h] around a circle (cx, cy, r).
inline std::array<double, 4> CircleBox(const std::array<double, 3>& c) {
  return {c[0] - c[2], c[1] - c[2], 2 * c[2], 2 * c[2]};
}

/// A number as printf's %g prints it.
inline std::string FormatNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", v);
  return buffer;
}

}  // namespace corridorsim::score_internal
