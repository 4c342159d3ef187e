#pragma once
// The pipelines this build ships, by the names scenarios use under `pipelines:`. Each name has a
// configuration object that reads its options (include chains apply base first, so a child
// file's keys override the base's), checks them and creates the pipeline for a calibration.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

class PipelineConfig {
 public:
  virtual ~PipelineConfig() = default;
  /// Reads the keys present in `options` (the map under `pipelines.<name>`) onto this config;
  /// unknown keys are errors.
  virtual void Parse(YamlMap& options) = 0;
  /// The first problem (key relative to the pipeline's map), or nothing.
  virtual std::optional<OptionsProblem> Check() const = 0;
  virtual std::unique_ptr<Pipeline> Create(const Calibration& calibration) const = 0;
};

/// Names of the shipped pipelines, in a fixed order.
std::vector<std::string> PipelineNames();

/// A configuration with default options for pipeline `name`, or nullptr for an unknown name.
std::unique_ptr<PipelineConfig> NewPipelineConfig(const std::string& name);

}  // namespace corridorsim::slam
