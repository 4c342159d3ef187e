#pragma once
// The pipeline types, by the names scenarios use under `pipelines:`: the ones this build ships
// and those plugins register (slam/plugin.h). Each pipeline
// type has an options struct with its table (common/options_table.h) and a factory: the harness
// reads `pipelines.<name>` through the table (include chains apply base first, so a child file's
// keys override the base's), checks the options and creates the pipeline for a calibration. slam/
// never sees YAML.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
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

/// A pipeline type: its name and a factory of its default options. `library` is empty for the
/// types this build ships; a plugin's types carry the path of the library that registered them
/// (harness/scenario/plugins.h).
struct PipelineType {
  std::string name;
  std::function<std::unique_ptr<PipelineOptions>()> new_options;
  std::string library;
};

/// The options of a pipeline type `P` whose options struct `Options` has a table and a
/// `std::optional<OptionsProblem> Check() const`, and which is constructed from
/// `(const Options&, const Calibration&, std::uint64_t seed)`: what every shipped type and every
/// plugin's type is made of.
template <class Options, class P>
class TypedPipelineOptions : public PipelineOptions {
 public:
  TypedPipelineOptions(const OptionTable<Options>& table, Options defaults)
      : table_(table), options_(std::move(defaults)) {}
  const OptionTableBase& table() const override { return table_; }
  void* options() override { return &options_; }
  const void* options() const override { return &options_; }
  std::optional<OptionsProblem> Check() const override { return options_.Check(); }
  std::unique_ptr<Pipeline> Create(const Calibration& calibration,
                                   std::uint64_t seed) const override {
    return std::make_unique<P>(options_, calibration, seed);
  }

 private:
  const OptionTable<Options>& table_;
  Options options_;
};

/// The pipeline type `name` of pipeline class `P` with options `Options` described by `table()`.
/// `defaults` gives the type's defaults when several types share one options struct (p3_upward,
/// p3_corners, p2_upward); else the struct's own.
template <class Options, class P>
PipelineType MakePipelineType(std::string name, const OptionTable<Options>& (*table)(),
                              Options (*defaults)() = nullptr) {
  return {std::move(name),
          [table, defaults]() -> std::unique_ptr<PipelineOptions> {
            return std::make_unique<TypedPipelineOptions<Options, P>>(
                table(), defaults ? defaults() : Options{});
          },
          ""};
}

/// A pipeline's name names its files in the run folder (`<name>.tum`, `maps/<name>.bt`) and its
/// object in metrics.json; a type's name is one too (the default name of its entry): 1 to
/// kMaxPipelineNameLength lower-case letters, digits and '_', starting with a letter.
inline constexpr std::size_t kMaxPipelineNameLength = 64;
bool IsPipelineName(const std::string& name);

/// The pipeline types this build ships, in a fixed order (the generated docs list these).
const std::vector<PipelineType>& ShippedPipelineTypes();

/// Every pipeline type a scenario may name now: the shipped ones, then the plugins' in the order
/// they were loaded.
std::vector<PipelineType> PipelineTypes();

/// Names of PipelineTypes(), in that order.
std::vector<std::string> PipelineNames();

/// The default options of pipeline type `name`, or nullptr for an unknown name.
std::unique_ptr<PipelineOptions> NewPipelineOptions(const std::string& name);

/// The type named `name`, or nothing.
std::optional<PipelineType> FindPipelineType(const std::string& name);

/// Adds a plugin's type (its `library` set). The caller (harness/scenario/plugins.cpp) has checked
/// that the name is a valid pipeline name and not taken; a taken name throws std::logic_error.
/// Thread-safe; types are never removed (a plugin's code stays loaded).
void AddPipelineType(PipelineType type);

}  // namespace corridorsim::slam
