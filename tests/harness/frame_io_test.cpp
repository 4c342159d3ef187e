// Tests harness/frame_io.cpp: the intrinsics JSON writes robot_from_camera in the project's one
// JSON pose convention (common/io/stable_json.h: t to 1e-6 m, q to 1e-9, qw >= 0).
#include "harness/frame_io.h"

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

TEST_CASE("intrinsics write robot_from_camera as a stable pose with qw >= 0", "[frame_io]") {
  render::CameraOptions options;
  options.id = "lateral";
  // The lateral camera's mount (docs/frames.md).
  options.mount.x_m = 0.0;
  options.mount.y_m = 0.12;
  options.mount.z_m = 0.55;
  options.mount.yaw_deg = 90.0;
  options.mount.pitch_deg = 25.0;
  const nlohmann::ordered_json j = IntrinsicsJson(options);
  const nlohmann::ordered_json& pose = j["robot_from_camera"];
  CHECK(pose == PoseJson(options.mount.RobotFromCamera()));
  CHECK(pose["t"].dump() == "[0.0,0.12,0.55]");
  REQUIRE(pose["q"].size() == 4);
  CHECK(pose["q"][3].get<double>() >= 0.0);
  for (const auto& c : pose["q"]) {
    CHECK(RoundToStep(c.get<double>(), json_steps::kUnitVector) == c.get<double>());
  }
  // The same rotation as the mount's.
  const Eigen::Quaterniond q(pose["q"][3].get<double>(), pose["q"][0].get<double>(),
                             pose["q"][1].get<double>(), pose["q"][2].get<double>());
  CHECK(q.angularDistance(options.mount.RobotFromCamera().quaternion()) < 1e-8);
}

}  // namespace
}  // namespace corridorsim
