#include "slam/registry.h"

#include <utility>

#include "slam/odometry_pipeline.h"
#include "slam/p1_harris_pipeline.h"
#include "slam/p1_vp_doorplate_pipeline.h"
#include "slam/p3_upward_pipeline.h"

namespace corridorsim::slam {
namespace {

// The options of a pipeline type `P` whose options struct `Options` has a table and a
// Check(), and which is constructed from (options, calibration, seed).
template <class Options, class P>
class TypedOptions : public PipelineOptions {
 public:
  TypedOptions(const OptionTable<Options>& table, Options defaults)
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

// `defaults` gives the type's defaults when several types share one options struct (p3_upward,
// p3_corners, p2_upward); else the struct's own.
template <class Options, class P>
PipelineType Type(std::string name, const OptionTable<Options>& (*table)(),
                  Options (*defaults)() = nullptr) {
  return {std::move(name), [table, defaults]() -> std::unique_ptr<PipelineOptions> {
            return std::make_unique<TypedOptions<Options, P>>(table(),
                                                              defaults ? defaults() : Options{});
          }};
}

}  // namespace

const std::vector<PipelineType>& PipelineTypes() {
  static const std::vector<PipelineType> types = {
      Type<OdometryPipelineOptions, OdometryPipeline>("odometry", &OdometryPipelineOptionsTable),
      Type<P1HarrisOptions, P1HarrisPipeline>("p1_harris", &P1HarrisOptionsTable),
      Type<P1VpDoorplateOptions, P1VpDoorplatePipeline>("p1_vp_doorplate",
                                                        &P1VpDoorplateOptionsTable),
      Type<P3UpwardOptions, P3UpwardPipeline>("p3_upward", &P3UpwardOptionsTable,
                                              &P3UpwardDefaults),
      Type<P3UpwardOptions, P3UpwardPipeline>("p3_corners", &P3UpwardOptionsTable,
                                              &P3CornersDefaults),
      Type<P3UpwardOptions, P3UpwardPipeline>("p2_upward", &P3UpwardOptionsTable,
                                              &P2UpwardDefaults),
  };
  return types;
}

std::vector<std::string> PipelineNames() {
  std::vector<std::string> names;
  for (const PipelineType& type : PipelineTypes()) names.push_back(type.name);
  return names;
}

std::unique_ptr<PipelineOptions> NewPipelineOptions(const std::string& name) {
  for (const PipelineType& type : PipelineTypes()) {
    if (type.name == name) return type.new_options();
  }
  return nullptr;
}

}  // namespace corridorsim::slam
