#include "scenarios/snapshot.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "render/scene.h"
#include "scenarios/scenario.h"
#include "worlds/image_io.h"
#include "worlds/world_io.h"

namespace corridorsim {
namespace {

constexpr double kDepthScale = 5000.0;  // TUM RGB-D convention: 16-bit depth, 5000 per metre

// Backend named by CORRIDORSIM_RENDER_BACKEND, else the scenario's `render.backend`.
render::BackendKind ChooseBackend(render::BackendKind from_scenario) {
  const char* env = std::getenv("CORRIDORSIM_RENDER_BACKEND");
  if (!env || !*env) return from_scenario;
  const std::string name(env);
  if (name == "osmesa") return render::BackendKind::kOsMesa;
  if (name == "egl") return render::BackendKind::kEgl;
  throw InputError(SourceLocation{"environment", 0, 0}, "CORRIDORSIM_RENDER_BACKEND",
                   "unknown backend '" + name + "' (expected osmesa or egl)");
}

// Labels as a 16-bit RGB PNG: R = semantic class, G = instance id >> 16, B = instance id & 0xffff.
std::string EncodeLabels(const render::CameraFrame& f, int w, int h) {
  std::vector<std::uint16_t> data(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < f.instance.size(); ++i) {
    data[3 * i] = f.semantic[i];
    data[3 * i + 1] = static_cast<std::uint16_t>(f.instance[i] >> 16);
    data[3 * i + 2] = static_cast<std::uint16_t>(f.instance[i] & 0xffffu);
  }
  return EncodePng16(w, h, 3, data, f.camera_id + "_labels.png");
}

std::string EncodeDepth(const ImageF& depth, const std::string& what) {
  std::vector<std::uint16_t> data(depth.data.size());
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double v = std::round(static_cast<double>(depth.data[i]) * kDepthScale);
    data[i] = depth.data[i] > 0 && v < 65535.0 ? static_cast<std::uint16_t>(v) : 0;
  }
  return EncodePng16(depth.width, depth.height, 1, data, what);
}

// The ground truth drawn on the image, for a person to check at a glance.
Image8 DrawOverlay(const Image8& rgb, const render::FrameTruth& truth) {
  cv::Mat img(rgb.height, rgb.width, CV_8UC3);
  std::memcpy(img.data, rgb.data.data(), rgb.data.size());
  const int shift = 4;  // sub-pixel drawing
  auto P = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround(p.x() * 16)),
                     static_cast<int>(std::lround(p.y() * 16)));
  };
  for (const auto& plate : truth.plates) {
    std::vector<cv::Point> poly;
    for (const auto& c : plate.corners_px) poly.push_back(P(c));
    cv::polylines(img, poly, true, cv::Scalar(0, 255, 0), 2, cv::LINE_AA, shift);
    cv::putText(img, plate.room_number,
                cv::Point(static_cast<int>(plate.bbox_min_px.x()),
                          static_cast<int>(plate.bbox_min_px.y()) - 4),
                cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 255, 0), 2, cv::LINE_AA);
  }
  for (const auto& lamp : truth.lamps) {
    const cv::Scalar colour = lamp.reflection ? cv::Scalar(0, 255, 255) : cv::Scalar(255, 200, 0);
    cv::circle(img, P(lamp.center_px), static_cast<int>(std::lround(lamp.radius_px * 16)), colour,
               2, cv::LINE_AA, shift);
    cv::drawMarker(
        img, cv::Point(static_cast<int>(lamp.center_px.x()), static_cast<int>(lamp.center_px.y())),
        colour, cv::MARKER_CROSS, 8, 1);
  }
  for (const auto& door : truth.doors) {
    const cv::Scalar colour = cv::Scalar(255, 60, 60);
    for (const auto& c : {door.column_a_px, door.column_b_px}) {
      cv::circle(img, P(c), 5 * 16, colour, 2, cv::LINE_AA, shift);
    }
    cv::line(img, P(door.column_a_px), P(door.column_b_px), colour, 1, cv::LINE_AA, shift);
  }
  for (const auto& vp : truth.vanishing_points) {
    if (!vp.in_image) continue;
    cv::drawMarker(img, cv::Point(static_cast<int>(vp.pixel.x()), static_cast<int>(vp.pixel.y())),
                   cv::Scalar(255, 0, 255), cv::MARKER_TILTED_CROSS, 18, 2);
  }
  for (const auto& corner : truth.corners) {
    cv::circle(img, P(corner.pixel), 2 * 16, cv::Scalar(0, 128, 255), cv::FILLED, cv::LINE_AA,
               shift);
  }
  Image8 out(rgb.width, rgb.height, 3);
  std::memcpy(out.data.data(), img.data, out.data.size());
  return out;
}

nlohmann::ordered_json PoseJson(const SE3& pose) {
  const Eigen::Quaterniond q = pose.quaternion();
  return {{"t", {pose.translation().x(), pose.translation().y(), pose.translation().z()}},
          {"q", {q.x(), q.y(), q.z(), q.w()}}};
}

nlohmann::ordered_json IntrinsicsJson(const render::CameraSpec& spec) {
  nlohmann::ordered_json j;
  std::visit(
      [&](const auto& m) {
        using M = std::decay_t<decltype(m)>;
        const bool pinhole = std::is_same_v<M, PinholeRadTan>;
        j["model"] = pinhole ? "pinhole_radtan" : "kannala_brandt";
        j["width"] = m.width;
        j["height"] = m.height;
        j["fx"] = m.fx;
        j["fy"] = m.fy;
        j["cx"] = m.cx;
        j["cy"] = m.cy;
        if constexpr (std::is_same_v<M, PinholeRadTan>) {
          j["distortion"] = {m.k1, m.k2, m.p1, m.p2, m.k3};
        } else {
          j["distortion"] = {m.k1, m.k2, m.k3, m.k4};
        }
      },
      spec.model);
  const SE3 robot_from_camera = spec.mount.RobotFromCamera();
  j["robot_from_camera"] = PoseJson(robot_from_camera);
  if (spec.depth) j["depth_scale"] = kDepthScale;
  return j;
}

}  // namespace

SE2 ParsePose(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v)) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--pose",
                       "expected x,y,yaw (metres, metres, degrees), got '" + text + "'");
    }
    values.push_back(v);
  }
  if (values.size() != 3) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--pose",
                     "expected x,y,yaw (metres, metres, degrees), got '" + text + "'");
  }
  return SE2(values[0], values[1], values[2] * std::numbers::pi / 180.0);
}

void RunSnapshot(const SnapshotRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_path);
  const SE2 pose = ParsePose(request.pose_text);
  const render::BackendKind backend_kind = ChooseBackend(scenario.rig.backend);
  try {
    EnsureWritableDirectory(request.out_dir);
  } catch (const std::exception& e) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--out", e.what());
  }
  const std::uint64_t seed = request.seed.value_or(scenario.seed);
  const worlds::World world = GenerateWorld(scenario, seed);
  const SE3 world_from_robot = SE3::FromSE2(pose);
  if (auto problem = render::CheckCameraPlacement(world, scenario.rig, world_from_robot)) {
    throw LocateProblem(scenario, "sensors", *problem);
  }

  const auto t0 = std::chrono::steady_clock::now();
  const render::Scene scene = render::BuildScene(world, scenario.rig.scene);
  std::unique_ptr<render::Backend> backend = render::CreateBackend(backend_kind);
  backend->Upload(scene);
  render::Rig rig(scenario.rig, scene, *backend);
  std::vector<render::CameraFrame> frames;
  rig.Render(world_from_robot, seed, 0, &frames);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  nlohmann::ordered_json truth_json;
  truth_json["seed"] = seed;
  truth_json["world_from_robot"] = PoseJson(world_from_robot);
  truth_json["cameras"] = nlohmann::ordered_json::object();
  nlohmann::ordered_json intrinsics = nlohmann::ordered_json::object();
  std::printf("snapshot: %s backend, robot at (%.2f, %.2f) yaw %.1f deg, %zu cameras in %.0f ms\n",
              render::BackendName(backend_kind).c_str(), pose.x(), pose.y(),
              pose.yaw() * 180.0 / std::numbers::pi, frames.size(), ms);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const render::CameraFrame& frame = frames[k];
    const render::CameraSpec& spec = rig.cameras()[k].spec();
    const std::string& id = frame.camera_id;
    render::FrameTruthInput input;
    input.world = &world;
    input.camera_id = id;
    input.model = spec.model;
    input.world_from_camera = frame.world_from_camera;
    input.world_from_robot = world_from_robot;
    input.instance = &frame.instance;
    input.semantic = &frame.semantic;
    const render::FrameTruth truth = render::ComputeFrameTruth(input);
    truth_json["cameras"][id] = render::FrameTruthJson(truth);
    intrinsics[id] = IntrinsicsJson(spec);

    const std::filesystem::path dir = request.out_dir;
    WriteFileAtomic(dir / (id + "_rgb.png"), EncodePng(frame.rgb, id + "_rgb.png"));
    WriteFileAtomic(dir / (id + "_labels.png"),
                    EncodeLabels(frame, frame.rgb.width, frame.rgb.height));
    WriteFileAtomic(dir / (id + "_overlay.png"),
                    EncodePng(DrawOverlay(frame.rgb, truth), id + "_overlay.png"));
    if (spec.depth) {
      WriteFileAtomic(dir / (id + "_depth.png"),
                      EncodeDepth(frame.noisy_depth_m, id + "_depth.png"));
    }
    std::printf("  %-8s %dx%d  plates %zu, lamps %zu, doors %zu, corners %zu%s\n", id.c_str(),
                frame.rgb.width, frame.rgb.height, truth.plates.size(), truth.lamps.size(),
                truth.doors.size(), truth.corners.size(), spec.depth ? ", depth" : "");
  }
  WriteFileAtomic(request.out_dir / "frame_ground_truth.json", truth_json.dump(2) + "\n");
  WriteFileAtomic(request.out_dir / "intrinsics.json", intrinsics.dump(2) + "\n");
  std::printf("wrote %s\n", request.out_dir.string().c_str());
}

}  // namespace corridorsim
