#include "slam/registry.h"

#include "slam/odometry_pipeline.h"
#include "slam/p1_harris_pipeline.h"
#include "slam/p1_vp_doorplate_pipeline.h"

namespace corridorsim::slam {
namespace {

// The options of a pipeline type `P` whose options struct `Options` has a table and a
// Check(), and which is constructed from (options, calibration, seed).
template <class Options, class P>
class TypedOptions : public PipelineOptions {
 public:
  explicit TypedOptions(const OptionTable<Options>& table) : table_(table) {}
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

template <class Options, class P>
PipelineType Type(std::string name, const OptionTable<Options>& (*table)()) {
  return {std::move(name), [table]() -> std::unique_ptr<PipelineOptions> {
            return std::make_unique<TypedOptions<Options, P>>(table());
          }};
}

}  // namespace

const std::vector<PipelineType>& PipelineTypes() {
  static const std::vector<PipelineType> types = {
      Type<OdometryPipelineOptions, OdometryPipeline>("odometry", &OdometryPipelineOptionsTable),
      Type<P1HarrisOptions, P1HarrisPipeline>("p1_harris", &P1HarrisOptionsTable),
      Type<P1VpDoorplateOptions, P1VpDoorplatePipeline>("p1_vp_doorplate",
                                                        &P1VpDoorplateOptionsTable),
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
