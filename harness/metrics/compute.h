#pragma once
// ComputeMetrics: metrics.json of a closed-loop run, composed of the concerns in this folder
// (trajectory, consistency, map, data association, detection) plus the run's and each pipeline's
// timing and health, every value written through the registry (docs/metrics.md).

#include <nlohmann/json.hpp>

#include "harness/metrics/input.h"

namespace corridorsim {

/// metrics.json (docs/metrics.md). Aborts (a bug of the runner) when input.world is null, truth
/// is not in stamp order or two pipelines share a name; a pipeline's malformed output (an
/// innovation without degrees of freedom, a non-finite covariance or pose) is counted in its
/// `health`, never fatal.
nlohmann::ordered_json ComputeMetrics(const MetricsInput& input);

}  // namespace corridorsim
