#pragma once
// The pipelines this build ships, by the names scenarios use under `pipelines:`. Each pipeline
// type has an options struct with its table (common/options_table.h) and a factory: the harness
// reads `pipelines.<name>` through the table (include chains apply base first, so a child file's
// keys override the base's), checks the options and creates the pipeline for a calibration. slam/
// never sees YAML.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/options_table.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// One pipeline's options as a scenario sets them: its type's options struct behind its table.
class PipelineOptions {
 public:
  virtual ~PipelineOptions() = default;
  /// The options' table and the options it describes (for parsing, the echo and the docs).
  virtual const OptionTableBase& table() const = 0;
  virtual void* options() = 0;
  virtual const void* options() const = 0;
  /// The first problem (key relative to the pipeline's map), or nothing.
  virtual std::optional<OptionsProblem> Check() const = 0;
  /// A pipeline for `calibration` whose random choices (training, RANSAC, sampling) all draw
  /// from streams of `seed` (the harness derives it from the run's seed and the pipeline's name).
  virtual std::unique_ptr<Pipeline> Create(const Calibration& calibration,
                                           std::uint64_t seed) const = 0;
};

/// A shipped pipeline type: its name and a factory of its default options.
struct PipelineType {
  std::string name;
  std::function<std::unique_ptr<PipelineOptions>()> new_options;
};

/// The shipped pipeline types, in a fixed order.
const std::vector<PipelineType>& PipelineTypes();

/// Names of the shipped pipelines, in a fixed order.
std::vector<std::string> PipelineNames();

/// The default options of pipeline `name`, or nullptr for an unknown name.
std::unique_ptr<PipelineOptions> NewPipelineOptions(const std::string& name);

}  // namespace corridorsim::slam
