// Tests scenarios/export.cpp: frames rendered from the tiny world at known poses go through the
// DatasetExporter, and every layout is read back as its consumers read it (index files, PNGs
// with OpenCV, the ORB-SLAM settings with cv::FileStorage, EuRoC sensor.yaml with yaml-cpp, the
// COCO JSON with nlohmann-json).
#include "harness/run/export.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "harness/run/frame_io.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "render/scene.h"
#include "tests/support/exported_dataset.h"
#include "tests/support/scratch_dir.h"
#include "tests/support/tiny_world.h"

namespace corridorsim::export_tests {
namespace {

constexpr double kWheelbaseM = 0.331;

// Small cameras with the default mounts: a 64x48 RGB-D front, a distorted 64x48 lateral
// pinhole and a 64x48 Kannala-Brandt upward fisheye (noise on, as in a run).
render::RigOptions SmallRig() {
  render::RigOptions rig = render::RigOptions::Default();
  for (render::CameraOptions& camera : rig.cameras) {
    if (camera.id == "front") {
      camera.model = PinholeRadTan::FromFov(64, 48, 58.0 * kDeg);
    } else if (camera.id == "lateral") {
      PinholeRadTan model = PinholeRadTan::FromFov(64, 48, 60.0 * kDeg);
      model.k1 = -0.1;
      model.k2 = 0.01;
      model.p1 = 0.001;
      camera.model = model;
    } else {
      KannalaBrandt model = KannalaBrandt::FromFov(64, 48, 110.0 * kDeg);
      model.k1 = 0.01;
      camera.model = model;
    }
  }
  REQUIRE_FALSE(rig.Check());
  return rig;
}

// The robot's true pose: frame k's pose from k * period until the next frame. Frame 0 shows the
// plate to the front camera, frames 1-3 to the lateral camera (the robot faces -x there).
SE3 RobotPoseAt(TimeNs t) {
  const std::int64_t k = std::min<std::int64_t>(t / kFramePeriodNs, 3);
  if (k == 0) return SE3::FromSE2(SE2(-1.0, 0.3, -20.0 * kDeg));
  return SE3::FromSE2(SE2(3.0 - 0.2 * static_cast<double>(k), 0.3, std::numbers::pi));
}

struct Input {
  sim::CameraMessage message;
  std::string camera_id;
};

// Four frames of every camera of SmallRig(), rendered once for all tests.
struct Rendered {
  worlds::World world = test::TinyWorld();
  render::RigOptions rig = SmallRig();
  std::vector<Input> inputs;  // in stamp order, cameras in rig order

  Rendered() {
    const render::Scene scene = render::BuildScene(world);
    std::unique_ptr<render::Backend> backend = render::CreateBackend(render::BackendKind::kOsMesa);
    backend->Upload(scene);
    render::Rig renderer(rig, scene, *backend);
    for (std::uint64_t k = 0; k < 4; ++k) {
      const TimeNs t = static_cast<TimeNs>(k) * kFramePeriodNs;
      for (std::size_t c = 0; c < renderer.cameras().size(); ++c) {
        const render::CameraOptions& options = renderer.cameras()[c].options();
        Input in;
        in.camera_id = options.id;
        in.message.stamp_ns = t;
        in.message.frame_index = k;
        in.message.camera = c;
        in.message.world_from_robot = RobotPoseAt(t);
        renderer.RenderCamera(c, in.message.world_from_robot, 5, k, &in.message.frame);
        render::FrameTruthInput truth;
        truth.world = &world;
        truth.camera_id = options.id;
        truth.model = options.model;
        truth.world_from_camera = in.message.frame.world_from_camera;
        truth.world_from_robot = in.message.world_from_robot;
        truth.instance = &in.message.frame.instance;
        truth.semantic = &in.message.frame.semantic;
        in.message.truth = render::ComputeFrameTruth(truth);
        inputs.push_back(std::move(in));
      }
    }
  }
};

const Rendered& Frames() {
  static const Rendered rendered;
  return rendered;
}

WheelOdometry Odometry(TimeNs t) {
  WheelOdometry o;
  o.stamp_ns = t;
  o.interval_ns = 20'000'000;
  o.left_distance_m = 0.004 + 1e-6 * static_cast<double>(t / o.interval_ns);
  o.right_distance_m = 0.005;
  o.left_ticks = 100;
  o.right_ticks = 125;
  return o;
}

// Everything a run hands the exporter, with the robot's truth at 100 Hz.
void ExportAll(const fs::path& dir, const render::RigOptions& rig) {
  DatasetExporter exporter(dir, rig, kWheelbaseM);
  const TimeNs end = 3 * kFramePeriodNs;
  std::size_t next = 0;
  for (TimeNs t = 0; t <= end; t += kTruthPeriodNs) {
    exporter.AddTruth(t, RobotPoseAt(t));
    if (t % (2 * kTruthPeriodNs) == 0) exporter.AddOdometry(Odometry(t));
    for (; next < Frames().inputs.size() && Frames().inputs[next].message.stamp_ns <= t; ++next) {
      const Input& in = Frames().inputs[next];
      if (rig.Find(in.camera_id)->enabled) exporter.AddFrame(in.message, in.camera_id);
    }
  }
  exporter.Finish();
}

std::vector<const Input*> InputsOf(const std::string& camera_id) {
  std::vector<const Input*> out;
  for (const Input& in : Frames().inputs) {
    if (in.camera_id == camera_id) out.push_back(&in);
  }
  return out;
}

// TUM seconds as the exact integer nanoseconds they were written from.
TimeNs TumStamp(const std::string& text) {
  const std::size_t dot = text.find('.');
  REQUIRE(dot != std::string::npos);
  REQUIRE(text.size() - dot - 1 == 9);
  return std::stoll(text.substr(0, dot)) * kNanosecondsPerSecond + std::stoll(text.substr(dot + 1));
}

// Rotation distance that ignores the quaternion's sign.
double RotationError(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return (a.toRotationMatrix() - b.toRotationMatrix()).cwiseAbs().maxCoeff();
}

std::vector<double> Doubles(const YAML::Node& node) { return node.as<std::vector<double>>(); }

TEST_CASE("the front camera is exported in TUM RGB-D layout with its noisy depth", "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  ExportAll(dir.path(), Frames().rig);
  const fs::path tum = dir.path() / "tum_rgbd";
  const std::vector<const Input*> front = InputsOf("front");

  const auto rgb = Rows(tum / "rgb.txt", ' ');
  const auto depth = Rows(tum / "depth.txt", ' ');
  const auto associations = Rows(tum / "associations.txt", ' ');
  REQUIRE(rgb.size() == front.size());
  REQUIRE(depth.size() == front.size());
  REQUIRE(associations.size() == front.size());
  for (std::size_t k = 0; k < front.size(); ++k) {
    const sim::CameraMessage& m = front[k]->message;
    const std::string name = std::to_string(m.stamp_ns) + ".png";
    // Every index line names an existing file, stamped with its frame's time.
    REQUIRE(rgb[k].size() == 2);
    CHECK(TumStamp(rgb[k][0]) == m.stamp_ns);
    CHECK(rgb[k][1] == "rgb/" + name);
    CHECK(fs::is_regular_file(tum / rgb[k][1]));
    REQUIRE(depth[k].size() == 2);
    CHECK(TumStamp(depth[k][0]) == m.stamp_ns);
    CHECK(depth[k][1] == "depth/" + name);
    CHECK(fs::is_regular_file(tum / depth[k][1]));
    // associations: t_rgb rgb/x.png t_depth depth/x.png of the same frame.
    REQUIRE(associations[k].size() == 4);
    CHECK(associations[k][0] == rgb[k][0]);
    CHECK(associations[k][1] == rgb[k][1]);
    CHECK(associations[k][2] == depth[k][0]);
    CHECK(associations[k][3] == depth[k][1]);

    // RGB as rendered (OpenCV reads BGR).
    const cv::Mat image = cv::imread((tum / rgb[k][1]).string(), cv::IMREAD_UNCHANGED);
    REQUIRE(image.type() == CV_8UC3);
    REQUIRE(image.cols == 64);
    REQUIRE(image.rows == 48);
    const Image8& expected_rgb = m.frame.rgb;
    int rgb_mismatches = 0;
    for (int v = 0; v < 48; ++v) {
      for (int u = 0; u < 64; ++u) {
        const cv::Vec3b bgr = image.at<cv::Vec3b>(v, u);
        const std::uint8_t* p = expected_rgb.Pixel(u, v);
        rgb_mismatches += bgr[2] != p[0] || bgr[1] != p[1] || bgr[0] != p[2];
      }
    }
    CHECK(rgb_mismatches == 0);

    // Depth: 16-bit, 5000 per metre, from the noisy depth (which differs from the exact one).
    const cv::Mat d = cv::imread((tum / depth[k][1]).string(), cv::IMREAD_UNCHANGED);
    REQUIRE(d.type() == CV_16UC1);
    REQUIRE(d.cols == 64);
    REQUIRE(d.rows == 48);
    int valid = 0, mismatches = 0, differs_from_exact = 0;
    for (int v = 0; v < 48; ++v) {
      for (int u = 0; u < 64; ++u) {
        const float noisy = m.frame.noisy_depth_m.at(u, v);
        const long expected = noisy > 0 ? std::lround(noisy * 5000.0) : 0;
        const int stored = d.at<std::uint16_t>(v, u);
        mismatches += stored != expected;
        valid += stored > 0;
        differs_from_exact += stored != std::lround(m.frame.depth_m.at(u, v) * 5000.0);
      }
    }
    CHECK(mismatches == 0);
    CHECK(valid > 100);  // the floor
    CHECK(differs_from_exact > 0);
  }

  // groundtruth.txt: world_from_camera of the front camera at 100 Hz and at every frame.
  const render::CameraOptions& options = *Frames().rig.Find("front");
  const SE3 robot_from_camera = options.mount.RobotFromCamera();
  const auto groundtruth = Rows(tum / "groundtruth.txt", ' ');
  REQUIRE(groundtruth.size() == static_cast<std::size_t>(3 * kFramePeriodNs / kTruthPeriodNs + 1));
  std::map<TimeNs, SE3> written;
  for (const auto& row : groundtruth) {
    REQUIRE(row.size() == 8);
    const TimeNs t = TumStamp(row[0]);
    const Eigen::Vector3d p(std::stod(row[1]), std::stod(row[2]), std::stod(row[3]));
    const Eigen::Quaterniond q(std::stod(row[7]), std::stod(row[4]), std::stod(row[5]),
                               std::stod(row[6]));
    CHECK(std::abs(q.norm() - 1.0) < kTumRotationTol);
    written[t] = SE3(q, p);
    const SE3 expected = RobotPoseAt(t) * robot_from_camera;
    CHECK((p - expected.translation()).cwiseAbs().maxCoeff() < kTumTranslationTolM);
    CHECK(RotationError(q, expected.quaternion()) < kTumRotationTol);
  }
  for (const Input* in : front) {
    const auto it = written.find(in->message.stamp_ns);
    REQUIRE(it != written.end());
    const SE3& world_from_camera = in->message.frame.world_from_camera;
    CHECK((it->second.translation() - world_from_camera.translation()).cwiseAbs().maxCoeff() <
          kTumTranslationTolM);
    CHECK(RotationError(it->second.quaternion(), world_from_camera.quaternion()) < kTumRotationTol);
  }
}

TEST_CASE("the ORB-SLAM settings file reads back with cv::FileStorage", "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  ExportAll(dir.path(), Frames().rig);
  const fs::path path = dir.path() / "tum_rgbd" / "orb_slam.yaml";
  CHECK(ReadText(path).rfind("%YAML:1.0\n", 0) == 0);
  cv::FileStorage settings(path.string(), cv::FileStorage::READ);
  REQUIRE(settings.isOpened());
  const PinholeRadTan& k = *Frames().rig.Find("front")->model.pinhole();
  CHECK(settings["Camera.type"].string() == "PinHole");
  // ORB-SLAM3 reads these with isReal() / isInt().
  for (const char* key :
       {"Camera.fx", "Camera.fy", "Camera.cx", "Camera.cy", "Camera.k1", "Camera.k2", "Camera.p1",
        "Camera.p2", "Camera.k3", "Camera.fps", "Camera.bf", "ThDepth", "DepthMapFactor"}) {
    INFO(key);
    CHECK(settings[key].isReal());
  }
  CHECK(settings["Camera.width"].isInt());
  CHECK(settings["Camera.height"].isInt());
  CHECK(settings["Camera.RGB"].isInt());
  CHECK(settings["ORBextractor.nFeatures"].isInt());
  CHECK(settings["Viewer.ViewpointF"].isReal());
  CHECK(settings["Camera.fx"].real() == k.fx);
  CHECK(settings["Camera.fy"].real() == k.fy);
  CHECK(settings["Camera.cx"].real() == k.cx);
  CHECK(settings["Camera.cy"].real() == k.cy);
  CHECK(settings["Camera.k1"].real() == k.k1);
  CHECK(static_cast<int>(settings["Camera.width"]) == 64);
  CHECK(static_cast<int>(settings["Camera.height"]) == 48);
  CHECK(settings["Camera.fps"].real() == Frames().rig.Find("front")->rate_hz);
  CHECK(settings["DepthMapFactor"].real() == 5000.0);
  CHECK(static_cast<int>(settings["Camera.RGB"]) == 1);
  CHECK(settings["Camera.bf"].real() ==
        Approx(Frames().rig.Find("front")->depth_noise.baseline_m * k.fx));
  CHECK(settings["ThDepth"].real() == 40.0);
}

TEST_CASE("a fisheye front camera's ORB-SLAM settings read back with cv::FileStorage as its model",
          "[export]") {
  // docs/export.md: "KannalaBrandt8" with k1..k4 for a fisheye front camera, every value the
  // model's (coefficients that need every digit of a double).
  render::RigOptions rig = render::RigOptions::Default();
  KannalaBrandt fisheye = KannalaBrandt::FromFov(64, 48, 110.0 * kDeg);
  fisheye.fy *= 1.0 + 1e-7;
  fisheye.k1 = 0.01 / 3;
  fisheye.k2 = -1e-3 / 7;
  fisheye.k3 = 1e-4 / 3;
  fisheye.k4 = -1e-5 / 3;
  for (render::CameraOptions& camera : rig.cameras) camera.enabled = camera.id == "front";
  render::CameraOptions& front = rig.cameras[0];
  front.model = fisheye;
  front.depth = false;
  REQUIRE_FALSE(rig.Check());
  const test::ScratchDir dir("corridorsim_export_test");
  DatasetExporter exporter(dir.path(), rig, kWheelbaseM);
  sim::CameraMessage message;
  message.frame.camera_id = "front";
  message.frame.rgb = Image8(64, 48, 3);
  message.frame.instance.assign(64 * 48, 0);
  message.frame.semantic.assign(64 * 48, 0);
  exporter.AddFrame(message, "front");
  exporter.Finish();
  cv::FileStorage settings((dir.path() / "tum_rgbd" / "orb_slam.yaml").string(),
                           cv::FileStorage::READ);
  REQUIRE(settings.isOpened());
  CHECK(settings["Camera.type"].string() == "KannalaBrandt8");
  CHECK(settings["Camera.fx"].real() == fisheye.fx);
  CHECK(settings["Camera.fy"].real() == fisheye.fy);
  CHECK(settings["Camera.cx"].real() == fisheye.cx);
  CHECK(settings["Camera.cy"].real() == fisheye.cy);
  CHECK(settings["Camera.k1"].real() == fisheye.k1);
  CHECK(settings["Camera.k2"].real() == fisheye.k2);
  CHECK(settings["Camera.k3"].real() == fisheye.k3);
  CHECK(settings["Camera.k4"].real() == fisheye.k4);
  CHECK(settings["Camera.p1"].empty());
  CHECK(static_cast<int>(settings["Camera.width"]) == 64);
  CHECK(static_cast<int>(settings["Camera.height"]) == 48);
  CHECK(settings["Camera.bf"].empty());  // no depth
}

TEST_CASE("the upward and lateral cameras are exported in EuRoC layout", "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  ExportAll(dir.path(), Frames().rig);
  const fs::path mav0 = dir.path() / "euroc" / "mav0";
  for (const auto& [cam, camera_id] : {std::pair{"cam0", "upward"}, std::pair{"cam1", "lateral"}}) {
    INFO(cam);
    const render::CameraOptions& options = *Frames().rig.Find(camera_id);
    const std::vector<const Input*> frames = InputsOf(camera_id);
    const fs::path folder = mav0 / cam;
    CHECK(ReadText(folder / "data.csv").rfind("#timestamp [ns],filename\n", 0) == 0);
    const auto rows = Rows(folder / "data.csv", ',');
    REQUIRE(rows.size() == frames.size());
    for (std::size_t k = 0; k < rows.size(); ++k) {
      REQUIRE(rows[k].size() == 2);
      CHECK(std::stoll(rows[k][0]) == frames[k]->message.stamp_ns);
      CHECK(rows[k][1] == rows[k][0] + ".png");
      const cv::Mat image = cv::imread((folder / "data" / rows[k][1]).string(), cv::IMREAD_COLOR);
      REQUIRE(image.cols == 64);
      REQUIRE(image.rows == 48);
    }
    CHECK(std::distance(fs::directory_iterator(folder / "data"), fs::directory_iterator()) ==
          static_cast<std::ptrdiff_t>(frames.size()));

    const YAML::Node sensor = YAML::LoadFile((folder / "sensor.yaml").string());
    CHECK(sensor["sensor_type"].as<std::string>() == "camera");
    CHECK(sensor["T_BS"]["rows"].as<int>() == 4);
    CHECK(sensor["T_BS"]["cols"].as<int>() == 4);
    const std::vector<double> t_bs = Doubles(sensor["T_BS"]["data"]);
    REQUIRE(t_bs.size() == 16);
    const SE3 robot_from_camera = options.mount.RobotFromCamera();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) CHECK(t_bs[4 * r + c] == robot_from_camera.rotation()(r, c));
      CHECK(t_bs[4 * r + 3] == robot_from_camera.translation()(r));
    }
    CHECK(t_bs[12] == 0.0);
    CHECK(t_bs[15] == 1.0);
    CHECK(sensor["rate_hz"].as<double>() == options.rate_hz);
    CHECK(sensor["resolution"].as<std::vector<int>>() == std::vector<int>{64, 48});
    CHECK(sensor["camera_model"].as<std::string>() == "pinhole");
    const std::vector<double> intrinsics = Doubles(sensor["intrinsics"]);
    const std::vector<double> distortion = Doubles(sensor["distortion_coefficients"]);
    if (camera_id == std::string("upward")) {
      const KannalaBrandt& m = *options.model.kannala_brandt();
      CHECK(sensor["distortion_model"].as<std::string>() == "equidistant");
      CHECK(intrinsics == std::vector<double>{m.fx, m.fy, m.cx, m.cy});
      CHECK(distortion == std::vector<double>{m.k1, m.k2, m.k3, m.k4});
    } else {
      const PinholeRadTan& m = *options.model.pinhole();
      CHECK(sensor["distortion_model"].as<std::string>() == "radial-tangential");
      CHECK(intrinsics == std::vector<double>{m.fx, m.fy, m.cx, m.cy});
      CHECK(distortion == std::vector<double>{m.k1, m.k2, m.p1, m.p2});
    }
  }
}

TEST_CASE("labels and the frame truth are exported per camera and frame", "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  ExportAll(dir.path(), Frames().rig);
  for (const Input& in : Frames().inputs) {
    const sim::CameraMessage& m = in.message;
    const fs::path stem = dir.path() / "labels" / in.camera_id / std::to_string(m.stamp_ns);
    INFO(stem.string());
    const cv::Mat labels = cv::imread(stem.string() + ".png", cv::IMREAD_UNCHANGED);
    REQUIRE(labels.type() == CV_16UC3);
    REQUIRE(labels.cols == 64);
    REQUIRE(labels.rows == 48);
    int mismatches = 0;
    for (int v = 0; v < 48; ++v) {
      for (int u = 0; u < 64; ++u) {
        const cv::Vec3w bgr = labels.at<cv::Vec3w>(v, u);
        const std::size_t i = static_cast<std::size_t>(v) * 64 + u;
        const std::uint32_t id = (std::uint32_t(bgr[1]) << 16) | bgr[0];
        mismatches += bgr[2] != m.frame.semantic[i] || id != m.frame.instance[i];
      }
    }
    CHECK(mismatches == 0);
    const auto truth = nlohmann::json::parse(ReadText(stem.string() + ".json"));
    CHECK(truth["stamp_ns"] == m.stamp_ns);
    CHECK(truth["frame_index"] == m.frame_index);
    CHECK(truth["camera_id"] == in.camera_id);
    CHECK(truth["plates"].size() == m.truth.plates.size());
    const auto expected = nlohmann::json::parse(render::FrameTruthJson(m.truth).dump());
    REQUIRE(truth.size() == expected.size() + 2);
    for (const auto& [key, value] : expected.items()) {
      INFO(key);
      CHECK(truth[key] == value);
    }
  }
}

TEST_CASE("COCO JSON has one annotation per visible plate of the front and lateral images",
          "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  ExportAll(dir.path(), Frames().rig);
  const auto coco = nlohmann::json::parse(ReadText(dir.path() / "coco" / "plates.json"));
  REQUIRE(coco["categories"].size() == 1);
  CHECK(coco["categories"][0]["name"] == "door_plate");
  const int category = coco["categories"][0]["id"];

  // The expected images: front and lateral frames, by file name.
  std::map<std::string, const Input*> expected;
  for (const Input& in : Frames().inputs) {
    const std::string name = std::to_string(in.message.stamp_ns) + ".png";
    if (in.camera_id == "front") expected["tum_rgbd/rgb/" + name] = &in;
    if (in.camera_id == "lateral") expected["euroc/mav0/cam1/data/" + name] = &in;
  }
  REQUIRE(coco["images"].size() == expected.size());
  std::map<int, const Input*> by_id;
  for (const auto& image : coco["images"]) {
    const std::string file_name = image["file_name"];
    REQUIRE(expected.count(file_name) == 1);
    CHECK(fs::is_regular_file(dir.path() / file_name));
    CHECK(image["width"] == 64);
    CHECK(image["height"] == 48);
    by_id[image["id"].get<int>()] = expected[file_name];
  }
  REQUIRE(by_id.size() == expected.size());

  std::size_t plates = 0;
  std::set<std::string> cameras_with_plates;
  for (const auto& [name, in] : expected) {
    plates += in->message.truth.plates.size();
    if (!in->message.truth.plates.empty()) cameras_with_plates.insert(in->camera_id);
  }
  // The poses put the plate in view of both cameras.
  CHECK(cameras_with_plates == std::set<std::string>{"front", "lateral"});
  REQUIRE(coco["annotations"].size() == plates);
  std::set<int> annotation_ids;
  for (const auto& a : coco["annotations"]) {
    annotation_ids.insert(a["id"].get<int>());
    const Input* in = by_id.at(a["image_id"].get<int>());
    CHECK(a["category_id"] == category);
    CHECK(a["iscrowd"] == 0);
    CHECK(a["attributes"]["room_number"] == "101");
    CHECK(a["attributes"]["plate_id"] == test::TinyWorldIds::kPlate);
    const std::vector<double> bbox = a["bbox"];
    REQUIRE(bbox.size() == 4);
    CHECK(bbox[0] >= 0.0);
    CHECK(bbox[1] >= 0.0);
    CHECK(bbox[2] > 0.0);
    CHECK(bbox[3] > 0.0);
    CHECK(bbox[0] + bbox[2] <= 64.0);
    CHECK(bbox[1] + bbox[3] <= 48.0);
    CHECK(a["area"].get<double>() == Approx(bbox[2] * bbox[3]).margin(1e-3));
    // The box holds the plate's centre (pixel centres are at +0.5 in COCO's edge coordinates).
    REQUIRE(in->message.truth.plates.size() == 1);
    const Eigen::Vector2d centre = in->message.truth.plates[0].center_px;
    CHECK(centre.x() + 0.5 >= bbox[0]);
    CHECK(centre.x() + 0.5 <= bbox[0] + bbox[2]);
    CHECK(centre.y() + 0.5 >= bbox[1]);
    CHECK(centre.y() + 0.5 <= bbox[1] + bbox[3]);
  }
  CHECK(annotation_ids.size() == plates);
}

TEST_CASE("odometry and the robot's ground truth are exported as CSV", "[export]") {
  const test::ScratchDir dir("corridorsim_export_test");
  render::RigOptions rig = SmallRig();
  // The robot drives at 0.5 m/s along y; frames without images (nothing rendered) export nothing.
  const auto pose = [](TimeNs t) { return SE3::FromSE2(SE2(1.0, 0.5 * ToSeconds(t), 0.3)); };
  {
    DatasetExporter exporter(dir.path(), rig, kWheelbaseM);
    for (TimeNs t = 0; t <= 100'000'000; t += kTruthPeriodNs) {
      exporter.AddTruth(t, pose(t));
      exporter.AddOdometry(Odometry(t));
      sim::CameraMessage unrendered;
      unrendered.stamp_ns = t;
      exporter.AddFrame(unrendered, "front");
    }
    exporter.Finish();
  }
  CHECK_FALSE(fs::exists(dir.path() / "tum_rgbd"));
  CHECK_FALSE(fs::exists(dir.path() / "labels"));
  CHECK_FALSE(fs::exists(dir.path() / "coco"));
  CHECK_FALSE(fs::exists(dir.path() / "euroc" / "mav0" / "cam0"));

  const std::string odometry_text = ReadText(dir.path() / "odometry.csv");
  CHECK(odometry_text.find("wheelbase_m: 0.331\n") != std::string::npos);
  CHECK(odometry_text.find("\ntimestamp_ns,left_distance_m,right_distance_m,left_ticks,"
                           "right_ticks\n") != std::string::npos);
  const auto odometry = Rows(dir.path() / "odometry.csv", ',');
  REQUIRE(odometry.size() == 12);  // the header row and 11 messages
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    const WheelOdometry o = Odometry(static_cast<TimeNs>(k - 1) * kTruthPeriodNs);
    REQUIRE(odometry[k].size() == 5);
    CHECK(std::stoll(odometry[k][0]) == o.stamp_ns);
    CHECK(std::stod(odometry[k][1]) == Approx(o.left_distance_m).margin(1e-9));
    CHECK(std::stod(odometry[k][2]) == Approx(o.right_distance_m).margin(1e-9));
    CHECK(std::stoll(odometry[k][3]) == o.left_ticks);
    CHECK(std::stoll(odometry[k][4]) == o.right_ticks);
  }

  const auto truth =
      Rows(dir.path() / "euroc" / "mav0" / "state_groundtruth_estimate0" / "data.csv", ',');
  REQUIRE(truth.size() == 11);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    REQUIRE(truth[k].size() == 17);
    const TimeNs t = std::stoll(truth[k][0]);
    CHECK(t == static_cast<TimeNs>(k) * kTruthPeriodNs);
    std::vector<double> v;
    for (std::size_t i = 1; i < 17; ++i) v.push_back(std::stod(truth[k][i]));
    const SE3 expected = pose(t);
    CHECK((Eigen::Vector3d(v[0], v[1], v[2]) - expected.translation()).norm() < kEurocPoseTol);
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);  // w, x, y, z
    CHECK(RotationError(q, expected.quaternion()) < kEurocPoseTol);
    CHECK(Eigen::Vector3d(v[7], v[8], v[9]).isApprox(Eigen::Vector3d(0, 0.5, 0), 1e-6));
    for (std::size_t i = 10; i < 16; ++i) CHECK(v[i] == 0.0);
  }
}

TEST_CASE("a disabled camera writes nothing", "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  render::RigOptions rig = SmallRig();
  for (render::CameraOptions& camera : rig.cameras) camera.enabled = camera.id != "upward";
  ExportAll(dir.path(), rig);
  CHECK(fs::exists(dir.path() / "euroc" / "mav0" / "cam1" / "data.csv"));
  CHECK_FALSE(fs::exists(dir.path() / "euroc" / "mav0" / "cam0"));
  CHECK_FALSE(fs::exists(dir.path() / "labels" / "upward"));
  CHECK(fs::exists(dir.path() / "labels" / "lateral"));
  DatasetExporter exporter(dir.path() / "again", rig, kWheelbaseM);
  CHECK_THROWS_AS(exporter.AddFrame(InputsOf("upward")[0]->message, "upward"),
                  std::invalid_argument);
}

TEST_CASE("an export folder that cannot be made throws naming it", "[export]") {
  const test::ScratchDir dir("corridorsim_export_test");
  const fs::path file = dir.path() / "a_file";
  std::ofstream(file) << "not a folder";
  const fs::path target = file / "export";
  try {
    DatasetExporter exporter(target, SmallRig(), kWheelbaseM);
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Catch::Contains(target.string()));
  }
  // A folder that already holds an export is refused too, naming it.
  fs::create_directories(dir.path() / "old" / "labels");
  try {
    DatasetExporter exporter(dir.path() / "old", SmallRig(), kWheelbaseM);
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Catch::Contains((dir.path() / "old").string()));
    CHECK_THAT(e.what(), Catch::Contains("labels"));
  }
}

TEST_CASE("out-of-order stamps, wrong image sizes and use after Finish are refused",
          "[export][gl]") {
  const test::ScratchDir dir("corridorsim_export_test");
  DatasetExporter exporter(dir.path(), Frames().rig, kWheelbaseM);
  const Input& first = *InputsOf("front")[0];
  const Input& second = *InputsOf("front")[1];
  exporter.AddFrame(second.message, "front");
  CHECK_THROWS_AS(exporter.AddFrame(second.message, "front"), std::invalid_argument);
  CHECK_THROWS_AS(exporter.AddFrame(first.message, "front"), std::invalid_argument);
  CHECK_THROWS_AS(exporter.AddFrame(second.message, "lateral"), std::invalid_argument);
  sim::CameraMessage small = InputsOf("lateral")[0]->message;
  small.frame.rgb = Image8(32, 24, 3);
  CHECK_THROWS_AS(exporter.AddFrame(small, "lateral"), std::invalid_argument);
  exporter.AddTruth(0, SE3());
  CHECK_THROWS_AS(exporter.AddTruth(0, SE3()), std::invalid_argument);
  exporter.AddOdometry(Odometry(20));
  CHECK_THROWS_AS(exporter.AddOdometry(Odometry(10)), std::invalid_argument);
  exporter.Finish();
  CHECK(Rows(dir.path() / "tum_rgbd" / "rgb.txt", ' ').size() == 1);
  CHECK_THROWS_AS(exporter.Finish(), std::logic_error);
  CHECK_THROWS_AS(exporter.AddTruth(1, SE3()), std::logic_error);
}

TEST_CASE("two exports of the same input are byte-identical", "[export][gl]") {
  const test::ScratchDir a("corridorsim_export_test_a"), b("corridorsim_export_test_b");
  ExportAll(a.path(), Frames().rig);
  ExportAll(b.path(), Frames().rig);
  std::map<std::string, std::string> files_a, files_b;
  for (const auto& [root, files] : {std::pair{&a, &files_a}, std::pair{&b, &files_b}}) {
    for (const auto& entry : fs::recursive_directory_iterator(root->path())) {
      if (entry.is_regular_file()) {
        (*files)[fs::relative(entry.path(), root->path()).generic_string()] =
            ReadText(entry.path());
      }
    }
  }
  CHECK(files_a.size() > 40);
  CHECK(files_a.count("coco/plates.json") == 1);
  CHECK(files_a == files_b);
}

}  // namespace
}  // namespace corridorsim::export_tests
