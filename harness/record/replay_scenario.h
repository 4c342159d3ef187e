#pragma once
// The scenario a replay runs (docs/recordings.md): the recording's own, or one the user gives
// whose world, robot, path, sensors, rendering and duration are the recording's (its pipelines
// and expectations may differ: that is the point of a replay).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/record/recorder.h"
#include "harness/scenario/scenario.h"

namespace corridorsim::record {

/// `scenario_file` with `settings`, or (empty file) the recording's scenario with them. Throws
/// InputError naming the first key (dotted, e.g. "world.length_m") where it differs from the
/// recording's, or `--seed` when `seed` is not the recording's.
Scenario ReplayScenario(const RecordingInfo& recording, const std::string& recording_file,
                        const std::string& scenario_file, const std::vector<std::string>& settings,
                        const std::optional<std::uint64_t>& seed);

/// The first difference between two resolved scenario YAML texts outside the keys a replay may
/// change (name, description, seed, plugins, pipelines, expectations): "key: what", or "".
std::string FirstStreamDifference(const std::string& recorded_yaml, const std::string& yaml);

}  // namespace corridorsim::record
