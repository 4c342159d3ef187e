#include "slam/registry.h"

#include <algorithm>
#include <mutex>
#include <utility>

#include "slam/imu_odometry_pipeline.h"
#include "slam/laser_slam_pipeline.h"
#include "slam/odometry_pipeline.h"
#include "slam/p1_harris_pipeline.h"
#include "slam/p1_vp_doorplate_pipeline.h"
#include "slam/p3_upward_pipeline.h"

namespace corridorsim::slam {
namespace {

std::mutex& PluginTypesMutex() {
  static std::mutex mutex;
  return mutex;
}

std::vector<PipelineType>& PluginTypes() {
  static std::vector<PipelineType> types;
  return types;
}

}  // namespace

bool IsPipelineName(const std::string& name) {
  if (name.empty() || name.size() > kMaxPipelineNameLength) return false;
  if (name[0] < 'a' || name[0] > 'z') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

const std::vector<PipelineType>& ShippedPipelineTypes() {
  static const std::vector<PipelineType> types = {
      MakePipelineType<OdometryPipelineOptions, OdometryPipeline>("odometry",
                                                                  &OdometryPipelineOptionsTable),
      MakePipelineType<P1HarrisOptions, P1HarrisPipeline>("p1_harris", &P1HarrisOptionsTable),
      MakePipelineType<P1VpDoorplateOptions, P1VpDoorplatePipeline>("p1_vp_doorplate",
                                                                    &P1VpDoorplateOptionsTable),
      MakePipelineType<P3UpwardOptions, P3UpwardPipeline>("p3_upward", &P3UpwardOptionsTable,
                                                          &P3UpwardDefaults),
      MakePipelineType<P3UpwardOptions, P3UpwardPipeline>("p3_corners", &P3UpwardOptionsTable,
                                                          &P3CornersDefaults),
      MakePipelineType<P3UpwardOptions, P3UpwardPipeline>("p2_upward", &P3UpwardOptionsTable,
                                                          &P2UpwardDefaults),
      MakePipelineType<ImuOdometryOptions, ImuOdometryPipeline>("imu_odometry",
                                                                &ImuOdometryOptionsTable),
      MakePipelineType<LaserSlamOptions, LaserSlamPipeline>("laser_slam", &LaserSlamOptionsTable),
  };
  return types;
}

std::vector<PipelineType> PipelineTypes() {
  std::vector<PipelineType> types = ShippedPipelineTypes();
  const std::lock_guard<std::mutex> lock(PluginTypesMutex());
  types.insert(types.end(), PluginTypes().begin(), PluginTypes().end());
  return types;
}

std::optional<PipelineType> FindPipelineType(const std::string& name) {
  for (const PipelineType& type : ShippedPipelineTypes()) {
    if (type.name == name) return type;
  }
  const std::lock_guard<std::mutex> lock(PluginTypesMutex());
  for (const PipelineType& type : PluginTypes()) {
    if (type.name == name) return type;
  }
  return std::nullopt;
}

void AddPipelineType(PipelineType type) {
  const auto taken = [&](const std::vector<PipelineType>& types) {
    return std::any_of(types.begin(), types.end(),
                       [&](const PipelineType& t) { return t.name == type.name; });
  };
  const std::lock_guard<std::mutex> lock(PluginTypesMutex());
  if (taken(ShippedPipelineTypes()) || taken(PluginTypes())) {
    throw std::logic_error("the pipeline type '" + type.name + "' is already registered");
  }
  PluginTypes().push_back(std::move(type));
}

std::vector<std::string> PipelineNames() {
  std::vector<std::string> names;
  for (const PipelineType& type : PipelineTypes()) names.push_back(type.name);
  return names;
}

std::unique_ptr<PipelineOptions> NewPipelineOptions(const std::string& name) {
  const std::optional<PipelineType> type = FindPipelineType(name);
  return type ? type->new_options() : nullptr;
}

}  // namespace corridorsim::slam
