#pragma once
// Data association metrics of one landmark type: each detection's true identity (the nearest truth
// of its type in its frame, within identity_gate_px) against the landmark it was associated with,
// under the map matching (docs/metrics.md, `data_association.<type>`).

#include "harness/metrics/map.h"
#include "harness/metrics/matching.h"
#include "harness/metrics/registry.h"

namespace corridorsim::metrics {

/// Writes data_association.<type> under `out` (the pipeline's object). The detection that created
/// the landmark its identity matched is the initialisation, not an association decision.
void AddAssociationMetrics(const PipelineRecord& pipeline, const PipelineContext& context,
                           slam::LandmarkType type, const MapMatch& map, const MetricWriter& out);

}  // namespace corridorsim::metrics
