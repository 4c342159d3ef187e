#include "harness/run/frame_io.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/io/camera_json.h"
#include "worlds/image_io.h"

namespace corridorsim {

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

render::FrameTruth FrameTruthOf(const worlds::World& world, const render::CameraOptions& options,
                                const render::CameraFrame& frame, const SE3& world_from_robot) {
  render::FrameTruthInput input;
  input.world = &world;
  input.camera_id = frame.camera_id;
  input.model = options.model;
  input.world_from_camera = frame.world_from_camera;
  input.world_from_robot = world_from_robot;
  input.instance = &frame.instance;
  input.semantic = &frame.semantic;
  return render::ComputeFrameTruth(input);
}

nlohmann::ordered_json IntrinsicsJson(const render::CameraOptions& options) {
  nlohmann::ordered_json j = CameraModelToJson(options.model);
  const SE3 robot_from_camera = options.mount.RobotFromCamera();
  j["robot_from_camera"] = PoseJson(robot_from_camera);
  if (options.depth) j["depth_scale"] = kDepthScale;
  return j;
}

}  // namespace corridorsim
