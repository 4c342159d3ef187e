// Named tolerances for the test suite; every test takes its tolerances from here.
#pragma once

namespace corridorsim::test {

// Jacobians: central-difference step (relative to max(1, |x_i|)) and the allowed mismatch, relative
// to max(1, largest numerical entry).
inline constexpr double kNumericalJacobianStep = 1e-6;
inline constexpr double kJacobianRelTol = 1e-6;

// Poses: composed and inverted transforms (m, rad, matrix entries).
inline constexpr double kPoseTol = 1e-12;

// Motion model: the P1 eq. 13 step's overshoot along an arc against its closed form
// (delta / 2) / sin(delta / 2) - 1, relative; only rounding over the summed steps separates them.
inline constexpr double kMotionModelBiasRel = 1e-4;

// Odometry: distances summed in double over thousands of messages agree to rounding (m).
inline constexpr double kOdometryRoundingM = 1e-9;

// Statistical tests of noise models over many seeds: two-sided bounds at this confidence
// (each tail holds (1 - confidence) / 2 of the reference distribution).
inline constexpr double kStatConfidence = 0.99;

// Cameras: Project(Unproject(pixel)) (px) and Unproject(Project(p)) (unit-bearing components).
inline constexpr double kRoundTripPx = 1e-9;
inline constexpr double kRoundTripBearing = 1e-12;
// Field of view computed from the model against the one it was built from (rad).
inline constexpr double kFovRad = 1e-12;

// Worlds: positions the generator and the floor plan compute in double from options lengths agree
// to rounding (m, m^2); mesh data is float, so unit normals and positions agree to float rounding.
inline constexpr double kGeomTolM = 1e-9;
inline constexpr double kFloatTol = 1e-5;

// Frame truth: projected landmarks against values a test computes independently by closed form
// (px, rad). Both sides are exact formulas, so only rounding separates them.
inline constexpr double kFrameTruthPx = 1e-6;
inline constexpr double kFrameTruthRad = 1e-9;

// Metrics: metrics.json rounds metres to 1e-6, rad to 1e-8, px to 1e-4 and ratios (fractions,
// NEES, NIS) to 1e-6; a value a test computes by closed form agrees to one rounding step.
inline constexpr double kMetricsJsonM = 1e-6;
inline constexpr double kMetricsJsonRad = 1e-8;
inline constexpr double kMetricsJsonPx = 1e-4;
inline constexpr double kMetricsJsonRatio = 1e-6;

// Exported text files: poses as written with fixed decimals (TUM: 6 decimals of metres and 9 of
// quaternions; EuRoC ground truth: 9 of both), read back and compared (m, rotation-matrix entries).
inline constexpr double kTumTranslationTolM = 0.6e-6;
inline constexpr double kTumRotationTol = 1e-8;
inline constexpr double kEurocPoseTol = 1e-8;

}  // namespace corridorsim::test
