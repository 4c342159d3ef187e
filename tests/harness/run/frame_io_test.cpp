// Tests harness/run/frame_io.cpp: the intrinsics JSON writes robot_from_camera in the project's one
// JSON pose convention (common/io/stable_json.h: t to 1e-6 m, q to 1e-9, qw >= 0), and
// corridorsim reads the models back from it.
#include "harness/run/frame_io.h"

#include <catch2/catch.hpp>

#include "common/io/camera_json.h"

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

TEST_CASE("the intrinsics.json corridorsim writes reads back as the same model", "[frame_io]") {
  // Every camera of the default rig (pinhole with depth, pinhole, fisheye), with distortion and
  // numbers that need every digit, as snapshot and drive write them (every camera by id) and as
  // dataset writes one.
  render::RigOptions rig = render::RigOptions::Default();
  PinholeRadTan front = *rig.cameras[0].model.pinhole();
  front.fy *= 1.0 + 1e-7;
  front.k1 = -0.0123456789012345;
  front.p2 = 1e-5 / 3;
  rig.cameras[0].model = front;
  KannalaBrandt upward = *rig.cameras[2].model.kannala_brandt();
  upward.k1 = 0.01 / 3;
  upward.k4 = -1e-4 / 7;
  rig.cameras[2].model = upward;
  REQUIRE_FALSE(rig.Check());
  nlohmann::ordered_json file;
  for (const render::CameraOptions& options : rig.cameras)
    file[options.id] = IntrinsicsJson(options);
  const nlohmann::ordered_json read = nlohmann::ordered_json::parse(file.dump(2));
  for (const render::CameraOptions& options : rig.cameras) {
    INFO(options.id);
    CHECK(CameraModelFromIntrinsicsJson(read, options.id) == options.model);
    const nlohmann::ordered_json entry =
        nlohmann::ordered_json::parse(IntrinsicsJson(options).dump(2));
    CHECK(CameraModelFromJson(entry) == options.model);
    CHECK(CameraModelFromIntrinsicsJson(entry, options.id) == options.model);
  }
}

}  // namespace
}  // namespace corridorsim
