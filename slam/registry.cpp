#include "slam/registry.h"

#include "slam/odometry_pipeline.h"

namespace corridorsim::slam {
namespace {

class OdometryConfig : public PipelineConfig {
 public:
  void Parse(YamlMap& options) override { ParseOdometryPipelineOptions(options, options_); }
  std::optional<OptionsProblem> Check() const override { return options_.Check(); }
  std::unique_ptr<Pipeline> Create(const Calibration& calibration) const override {
    return std::make_unique<OdometryPipeline>(options_, calibration);
  }

 private:
  OdometryPipelineOptions options_;
};

}  // namespace

std::vector<std::string> PipelineNames() { return {"odometry"}; }

std::unique_ptr<PipelineConfig> NewPipelineConfig(const std::string& name) {
  if (name == "odometry") return std::make_unique<OdometryConfig>();
  return nullptr;
}

}  // namespace corridorsim::slam
