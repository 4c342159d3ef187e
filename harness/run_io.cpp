#include "harness/run_io.h"

#include <cmath>
#include <cstdio>

#include "common/io/stable_json.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

constexpr double kSlipStepsPerM = 1e9;  // slips are often far below a micrometre

}  // namespace

nlohmann::ordered_json EventJson(const sim::Event& e) {
  nlohmann::ordered_json j;
  j["t"] = ToSeconds(e.stamp_ns);
  j["t_ns"] = e.stamp_ns;
  j["type"] = sim::EventKindName(e.kind);
  switch (e.kind) {
    case sim::EventKind::kCollisionBegin:
    case sim::EventKind::kCollisionEnd: {
      j["object_id"] = e.instance_id;
      j["object_class"] = worlds::SemanticClassName(e.semantic_class);
      j["position"] = RoundedJson(e.position_in_world, json_steps::kMetres);
      if (e.kind == sim::EventKind::kCollisionBegin) {
        j["depth_m"] = RoundToStep(e.depth_m, json_steps::kMetres);
      }
      break;
    }
    case sim::EventKind::kSlip:
      j["wheel"] = e.left_wheel ? "left" : "right";
      j["extra_distance_m"] = RoundToStep(e.distance_m, kSlipStepsPerM);
      break;
    case sim::EventKind::kFrameDropped:
      j["camera"] = e.camera_id;
      break;
    case sim::EventKind::kPathDone:
    case sim::EventKind::kTimeout:
      break;
  }
  return j;
}

std::string OvEvalHeader() {
  return "# timestamp(s) tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 "
         "Pt23 Pt33\n";
}

std::string OvEvalLine(TimeNs stamp_ns, const SE2& pose, const Eigen::Matrix3d& p) {
  const std::string tum = sim::TumLine(stamp_ns, SE3::FromSE2(pose));
  char buf[320];
  std::snprintf(buf, sizeof(buf), " 0 0 0 0 0 %.9e %.9e %.9e 0 %.9e 0 0", p(2, 2), p(0, 0), p(0, 1),
                p(1, 1));
  return tum + buf;
}

}  // namespace corridorsim
