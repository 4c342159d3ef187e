#pragma once
// Map metrics: the pipeline's final landmarks of one type matched one-to-one to the world's ground
// truth (greedy by horizontal distance within landmark_gate_m), their errors, and what was observed
// but never mapped (docs/metrics.md, `map.<type>`).

#include <map>

#include "harness/metrics/matching.h"
#include "harness/metrics/registry.h"

namespace corridorsim::metrics {

/// Map matching of one type: estimated landmark id -> ground-truth id.
struct MapMatch {
  std::map<int, int> truth_of_estimate;
};

/// Writes map.<type> under `out` (the pipeline's object) and returns the matching.
MapMatch AddMapMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                       slam::LandmarkType type, const MetricWriter& out);

/// Writes map.area under `out` for a pipeline that divided its map at the doors
/// (PipelineRecord::areas non-empty): each scored point landmark's area against the area its true
/// position lies in. `matches`: map.<type>'s matching per type (doors and lamps are used).
void AddAreaMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                    const std::map<slam::LandmarkType, MapMatch>& matches, const MetricWriter& out);

}  // namespace corridorsim::metrics
