// Named tolerances of the feature-detector tests (tests/slam/features/, the detect command's
// tests): what a detector on pixels is expected to reach, as opposed to the closed-form
// tolerances of tests/support/tolerances.h.
#pragma once

namespace corridorsim::test {

// Vanishing point on a synthetic corridor drawn with anti-aliased edges (px).
inline constexpr double kSyntheticVanishingPointPx = 1.5;
// Vanishing point on a frame rendered by the project against FrameTruth (px): the rendered edges
// carry sensor noise, texture and mesh seams.
inline constexpr double kRenderedVanishingPointPx = 4.0;
// Harris corners on a synthetic checkerboard: the integer pixel of the response's maximum lies
// within a pixel of the true corner; sub-pixel refinement brings it within a quarter pixel.
inline constexpr double kHarrisIntegerPx = 1.0;
inline constexpr double kHarrisSubpixelPx = 0.25;
// Least squares over exact lines: only rounding separates the point from the truth (px).
inline constexpr double kLineIntersectionPx = 1e-9;

}  // namespace corridorsim::test
