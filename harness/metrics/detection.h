#pragma once
// Detector metrics against the per-frame truth of the cameras that produced detections: door
// plates (box IoU), lamps (centre gate), doors (column midpoint gate, open state) and vanishing
// points (pixel error); docs/metrics.md, `detection.<type>`.

#include "harness/metrics/matching.h"
#include "harness/metrics/registry.h"

namespace corridorsim::metrics {

/// Whether a plate was legible in its frame (MetricsOptions: whole outline in the image, mostly
/// visible, at least min_plate_height_px high, viewed within max_plate_viewing_angle_deg of its
/// normal): only legible plates count as detectable or as observed by a pipeline.
bool PlateLegible(const render::PlateTruth& truth, const MetricsOptions& options);

/// Box IoU of two [x0, y0, x1, y1] boxes (px).
double BoxIou(const Eigen::Vector4d& a, const Eigen::Vector4d& b);

/// Writes detection.<type> under `out` (the pipeline's object) for every type the pipeline
/// detected; nothing without frames.
void AddDetectionMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                         const MetricWriter& out);

}  // namespace corridorsim::metrics
