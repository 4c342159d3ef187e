#pragma once
// Metrics of a closed-loop run (issue 5): trajectory errors (ATE unaligned and SE2-aligned, RPE
// over travelled distance, final error), consistency (NEES of the pose, NIS per landmark type),
// map errors after matching to ground truth, data association, detector quality against the
// per-frame truth, timing and health; and the scenario `expectations` that assert on them. The
// runner collects the inputs and calls ComputeMetrics once; the JSON schema is docs/metrics.md.
//
// The code lives in harness/metrics/, one file per concern; every metric is declared once in
// harness/metrics/registry.h. This header is what the rest of the harness includes.

#include "harness/metrics/compute.h"       // ComputeMetrics
#include "harness/metrics/consistency.h"   // ErrorSeriesCsv
#include "harness/metrics/expectations.h"  // Expectation, ParseExpectation, CheckExpectations
#include "harness/metrics/input.h"         // MetricsInput, PipelineRecord, TruthPose, ...
#include "harness/metrics/registry.h"      // MetricNames
