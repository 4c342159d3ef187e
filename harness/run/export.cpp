#include "harness/run/export.h"
#include "harness/run/run_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <variant>

#include <nlohmann/json.hpp>

#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "harness/run/export_yaml.h"
#include "harness/run/frame_io.h"
#include "render/frame_truth.h"
#include "worlds/image_io.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

// What the export writes at its root; an existing one means an earlier export is there.
constexpr const char* kRootEntries[] = {"tum_rgbd", "euroc", "labels", "coco", "odometry.csv"};

std::string Quoted(const fs::path& path) { return "'" + path.string() + "'"; }

std::string StampName(TimeNs stamp_ns) { return std::to_string(stamp_ns); }

std::string EurocFolder(int number) { return "cam" + std::to_string(number); }

// Nine decimals; a value that rounds to zero is written without a sign.
std::string Fixed9(double value) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.9f", value);
  const std::string text = buf;
  return text == "-0.000000000" ? text.substr(1) : text;
}

// COCO boxes and areas in pixels (common/io/stable_json.h).
double Round4(double v) { return RoundToStep(v, json_steps::kPx); }

void CheckFrame(const render::CameraOptions& options, const render::CameraFrame& f) {
  const CameraIntrinsics in = options.model.intrinsics();
  const std::size_t n = static_cast<std::size_t>(in.width) * in.height;
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument("DatasetExporter: " + options.id + " frame: " + what);
  };
  if (f.rgb.width != in.width || f.rgb.height != in.height || f.rgb.channels != 3 ||
      f.rgb.data.size() != 3 * n) {
    fail("the RGB image is not " + std::to_string(in.width) + "x" + std::to_string(in.height) +
         " RGB");
  }
  if (f.instance.size() != n || f.semantic.size() != n)
    fail("the label images have the wrong size");
  if (options.depth && (f.noisy_depth_m.width != in.width || f.noisy_depth_m.height != in.height ||
                        f.noisy_depth_m.data.size() != n)) {
    fail("the noisy depth image has the wrong size");
  }
}

}  // namespace

DatasetExporter::DatasetExporter(const fs::path& dir, const render::RigOptions& rig,
                                 double wheelbase_m)
    : dir_(dir), wheelbase_m_(wheelbase_m) {
  EnsureWritableDirectory(dir_);
  for (const char* entry : kRootEntries) {
    std::error_code ec;
    if (fs::exists(dir_ / entry, ec) || ec) {
      throw std::runtime_error("cannot export into " + Quoted(dir_) + ": it already holds " +
                               entry + " (export into a new or empty folder)");
    }
  }
  for (std::size_t k = 0; k < rig.cameras.size(); ++k) {
    const render::CameraOptions& options = rig.cameras[k];
    if (!options.enabled) continue;
    CameraOutput camera;
    camera.options = options;
    camera.order = k;
    camera.euroc_number = EurocCameraNumber(rig, options.id);
    if (options.id == "front") {
      camera.layout = Layout::kTumRgbd;
      camera.image_dir = fs::path("tum_rgbd") / "rgb";
      camera.depth_dir = fs::path("tum_rgbd") / "depth";
    } else {  // every other camera of the rig has a number
      camera.layout = Layout::kEuroc;
      const fs::path folder = fs::path("euroc") / "mav0" / EurocFolder(camera.euroc_number);
      camera.image_dir = folder / "data";
      camera.depth_dir = folder / "depth";
    }
    cameras_.push_back(std::move(camera));
  }
}

int DatasetExporter::EurocCameraNumber(const render::RigOptions& rig,
                                       const std::string& camera_id) {
  if (camera_id == "upward") return 0;
  if (camera_id == "lateral") return 1;
  int next = 2;  // the rig's cameras beyond the three, in its order
  for (const render::CameraOptions& c : rig.cameras) {
    if (c.id == "front" || c.id == "lateral" || c.id == "upward") continue;
    if (c.id == camera_id) return next;
    ++next;
  }
  return -1;
}

bool DatasetExporter::has_tum() const {
  return std::any_of(cameras_.begin(), cameras_.end(), [](const CameraOutput& c) {
    return c.layout == Layout::kTumRgbd && !c.stamps.empty();
  });
}

void DatasetExporter::CheckOpen(const char* what) const {
  if (finished_) throw std::logic_error(std::string("DatasetExporter::") + what + " after Finish");
}

DatasetExporter::CameraOutput& DatasetExporter::Camera(const std::string& camera_id) {
  for (CameraOutput& camera : cameras_) {
    if (camera.options.id == camera_id) return camera;
  }
  throw std::invalid_argument("DatasetExporter: the rig has no enabled camera '" + camera_id + "'");
}

// Creates a folder under the export root, naming it when that fails.
void DatasetExporter::MakeDir(const fs::path& relative) const {
  const fs::path path = dir_ / relative;
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw std::runtime_error("cannot create folder " + Quoted(path) + ": " + ec.message());
}

void DatasetExporter::AddFrame(const sim::CameraMessage& message, const std::string& camera_id) {
  CheckOpen("AddFrame");
  CameraOutput& camera = Camera(camera_id);
  const render::CameraFrame& f = message.frame;
  if (f.rgb.empty()) return;  // not rendered: nothing to export
  if (!f.camera_id.empty() && f.camera_id != camera_id) {
    throw std::invalid_argument("DatasetExporter: a frame of camera '" + f.camera_id +
                                "' given as '" + camera_id + "'");
  }
  const TimeNs t = message.stamp_ns;
  if (t < 0 || (!camera.stamps.empty() && t <= camera.stamps.back())) {
    throw std::invalid_argument("DatasetExporter: " + camera_id + " frame at " + std::to_string(t) +
                                " ns: stamps must be non-negative and increase per camera");
  }
  CheckFrame(camera.options, f);
  const int width = f.rgb.width, height = f.rgb.height;
  const fs::path labels_dir = fs::path("labels") / camera_id;
  if (camera.stamps.empty()) {
    camera.first_world_from_robot = {t, message.world_from_robot};
    MakeDir(camera.image_dir);
    if (camera.options.depth) MakeDir(camera.depth_dir);
    MakeDir(labels_dir);
  }

  const std::string name = StampName(t) + ".png";
  WriteFileAtomic(dir_ / camera.image_dir / name, EncodePng(f.rgb, camera_id + " " + name));
  if (camera.options.depth) {
    WriteFileAtomic(dir_ / camera.depth_dir / name,
                    EncodeDepth(f.noisy_depth_m, camera_id + " depth " + name));
  }
  if (camera.layout == Layout::kTumRgbd)
    camera.world_from_camera.emplace_back(t, f.world_from_camera);
  WriteFileAtomic(dir_ / labels_dir / name, EncodeLabels(f, width, height));
  nlohmann::ordered_json truth;
  truth["stamp_ns"] = t;
  truth["frame_index"] = message.frame_index;
  const nlohmann::ordered_json frame_truth = render::FrameTruthJson(message.truth);
  for (const auto& [key, value] : frame_truth.items()) truth[key] = value;
  WriteFileAtomic(dir_ / labels_dir / (StampName(t) + ".json"), JsonFileText(truth, 1));

  // Door plates: the cameras that read them (front, lateral).
  if (camera_id == "front" || camera_id == "lateral") {
    CocoImage image;
    image.stamp_ns = t;
    image.camera_order = camera.order;
    image.file_name = (camera.image_dir / name).generic_string();
    image.width = width;
    image.height = height;
    for (const render::PlateTruth& p : message.truth.plates) {
      // Pixel centres to pixel edges (+0.5), clipped to the image; the corners are rounded
      // before the size so that the box stays inside the image.
      const double x0 = Round4(std::clamp(p.bbox_min_px.x() + 0.5, 0.0, double(width)));
      const double y0 = Round4(std::clamp(p.bbox_min_px.y() + 0.5, 0.0, double(height)));
      const double x1 = Round4(std::clamp(p.bbox_max_px.x() + 0.5, 0.0, double(width)));
      const double y1 = Round4(std::clamp(p.bbox_max_px.y() + 0.5, 0.0, double(height)));
      PlateBox box;
      box.plate_id = p.id;
      box.room_number = p.room_number;
      box.x = x0;
      box.y = y0;
      box.w = Round4(x1 - x0);
      box.h = Round4(y1 - y0);
      box.visible_fraction = RoundToStep(p.visible_fraction, json_steps::kRatio);
      box.fully_in_image = p.fully_in_image;
      image.plates.push_back(std::move(box));
    }
    coco_images_.push_back(std::move(image));
  }
  camera.stamps.push_back(t);
}

void DatasetExporter::AddOdometry(const WheelOdometry& odometry) {
  CheckOpen("AddOdometry");
  if (!odometry_.empty() && odometry.stamp_ns <= odometry_.back().stamp_ns) {
    throw std::invalid_argument("DatasetExporter: odometry at " +
                                std::to_string(odometry.stamp_ns) + " ns: stamps must increase");
  }
  odometry_.push_back(odometry);
}

void DatasetExporter::AddTruth(TimeNs stamp_ns, const SE3& world_from_robot,
                               const Eigen::Matrix<double, 6, 1>& biases) {
  CheckOpen("AddTruth");
  if (stamp_ns < 0 || (!truth_.empty() && stamp_ns <= truth_.back().first)) {
    throw std::invalid_argument("DatasetExporter: truth at " + std::to_string(stamp_ns) +
                                " ns: stamps must be non-negative and increase");
  }
  truth_.emplace_back(stamp_ns, world_from_robot);
  truth_biases_.push_back(biases);
}

void DatasetExporter::Finish() {
  CheckOpen("Finish");
  finished_ = true;
  for (const CameraOutput& camera : cameras_) {
    if (camera.stamps.empty()) continue;
    if (camera.layout == Layout::kTumRgbd) FinishTum(camera);
    if (camera.layout == Layout::kEuroc) FinishEuroc(camera);
  }
  FinishEurocCameraList();
  FinishGroundTruth();
  FinishOdometry();
  FinishCoco();
}

// The first pose of the ground truth: the first AddTruth pose, or the robot's pose at the
// camera's first frame when that is earlier (or there is no truth).
BodyStart DatasetExporter::StartOf(const CameraOutput& camera) const {
  if (!truth_.empty() && truth_.front().first <= camera.first_world_from_robot.first) {
    return {truth_.front().first, truth_.front().second};
  }
  return {camera.first_world_from_robot.first, camera.first_world_from_robot.second};
}

void DatasetExporter::FinishTum(const CameraOutput& camera) const {
  const fs::path tum = dir_ / "tum_rgbd";
  std::ostringstream rgb, depth, associations, groundtruth;
  rgb << "# color images\n# corridorsim " << camera.options.id
      << " camera, seconds from the start of the run\n# timestamp filename\n";
  depth << "# depth maps\n# corridorsim " << camera.options.id
        << " camera, 16-bit, 5000 per metre, 0 = invalid\n# timestamp filename\n";
  for (const TimeNs t : camera.stamps) {
    const std::string s = StampSeconds(t), name = StampName(t) + ".png";
    rgb << s << " rgb/" << name << "\n";
    if (camera.options.depth) {
      depth << s << " depth/" << name << "\n";
      associations << s << " rgb/" << name << " " << s << " depth/" << name << "\n";
    }
  }
  WriteFileAtomic(tum / "rgb.txt", rgb.str());
  if (camera.options.depth) {
    WriteFileAtomic(tum / "depth.txt", depth.str());
    WriteFileAtomic(tum / "associations.txt", associations.str());
  }

  // The optical centre: every truth sample through the mount, and each frame's own pose (the
  // frame's wins where both exist, so every image has its exact pose).
  std::vector<std::pair<TimeNs, SE3>> poses;
  const SE3 robot_from_camera = camera.options.mount.RobotFromCamera();
  std::size_t i = 0, j = 0;
  const auto& frames = camera.world_from_camera;
  while (i < truth_.size() || j < frames.size()) {
    if (j < frames.size() && (i == truth_.size() || frames[j].first <= truth_[i].first)) {
      if (i < truth_.size() && truth_[i].first == frames[j].first) ++i;
      poses.push_back(frames[j++]);
    } else {
      poses.emplace_back(truth_[i].first, truth_[i].second * robot_from_camera);
      ++i;
    }
  }
  groundtruth << "# ground truth trajectory\n# corridorsim " << camera.options.id
              << " camera: world_from_camera (optical centre, OpenCV optical axes) in frame W\n"
              << "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& [t, pose] : poses) groundtruth << sim::TumLine(t, pose) << "\n";
  WriteFileAtomic(tum / "groundtruth.txt", groundtruth.str());
  WriteFileAtomic(tum / "orb_slam.yaml", OrbSlamYaml(camera.options));
  WriteFileAtomic(
      tum / "sensor.yaml",
      CameraSensorYaml(camera.options, "corridorsim " + camera.options.id + " camera as tum_rgbd",
                       StartOf(camera)));
}

void DatasetExporter::FinishEuroc(const CameraOutput& camera) const {
  const std::string cam = EurocFolder(camera.euroc_number);
  const fs::path folder = dir_ / "euroc" / "mav0" / cam;
  std::ostringstream csv;
  csv << "#timestamp [ns],filename\n";
  for (const TimeNs t : camera.stamps) csv << t << "," << t << ".png\n";
  WriteFileAtomic(folder / "data.csv", csv.str());
  // A depth camera's depth/ holds an image per RGB image, of the same name: the same index.
  if (camera.options.depth) WriteFileAtomic(folder / "depth.csv", csv.str());
  WriteFileAtomic(
      folder / "sensor.yaml",
      CameraSensorYaml(camera.options, "corridorsim " + camera.options.id + " camera as " + cam,
                       StartOf(camera)));
}

// euroc/mav0/cameras.yaml: which camera each cam<N>/ holds. Only with a camera beyond the fixed
// cam0 (upward) and cam1 (lateral), so that an export of the three default cameras is what it
// always was.
void DatasetExporter::FinishEurocCameraList() const {
  std::vector<const CameraOutput*> exported;
  for (const CameraOutput& camera : cameras_) {
    if (camera.layout == Layout::kEuroc && !camera.stamps.empty()) exported.push_back(&camera);
  }
  if (std::none_of(exported.begin(), exported.end(),
                   [](const CameraOutput* c) { return c->euroc_number >= 2; })) {
    return;
  }
  std::stable_sort(exported.begin(), exported.end(),
                   [](const CameraOutput* a, const CameraOutput* b) {
                     return a->euroc_number < b->euroc_number;
                   });
  std::ostringstream y;
  y << "# corridorsim: the scenario's camera in each euroc/mav0/cam<N>/ (docs/export.md). cam0 is\n"
    << "# always the upward camera and cam1 the lateral one; the scenario's other cameras follow\n"
    << "# from cam2 in the order the scenario names them (a disabled one keeps its number). The\n"
    << "# front camera is tum_rgbd/. Only the cameras exported are listed.\n";
  for (const CameraOutput* camera : exported) {
    y << EurocFolder(camera->euroc_number) << ": " << camera->options.id << "\n";
  }
  WriteFileAtomic(dir_ / "euroc" / "mav0" / "cameras.yaml", y.str());
}

// EuRoC's state_groundtruth_estimate0: the robot's pose, its velocity in W by central
// differences of the poses (one-sided at the ends), and the first IMU's true biases (zero
// without an IMU).
void DatasetExporter::FinishGroundTruth() const {
  if (truth_.empty()) return;
  const fs::path folder = fs::path("euroc") / "mav0" / "state_groundtruth_estimate0";
  MakeDir(folder);
  std::ostringstream csv;
  csv << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
         "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad "
         "s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m "
         "s^-2], b_a_RS_S_z [m s^-2]\n";
  const std::size_t n = truth_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const auto& [t, pose] = truth_[k];
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    if (n > 1) {
      const std::size_t a = k == 0 ? 0 : k - 1, b = k + 1 == n ? k : k + 1;
      v = (truth_[b].second.translation() - truth_[a].second.translation()) /
          ToSeconds(truth_[b].first - truth_[a].first);
    }
    const Eigen::Vector3d& p = pose.translation();
    const Eigen::Quaterniond& q = pose.quaternion();
    csv << t;
    for (const double value :
         {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z()})
      csv << "," << Fixed9(value);
    for (int i = 0; i < 6; ++i) {
      const double b = truth_biases_[k][i];
      csv << "," << (b == 0.0 ? std::string("0") : Fixed9(b));  // no IMU: as before, 0
    }
    csv << "\n";
  }
  WriteFileAtomic(dir_ / folder / "data.csv", csv.str());
}

void DatasetExporter::FinishOdometry() const {
  std::ostringstream csv;
  csv << "# corridorsim wheel odometry: signed distance each wheel travelled since the previous "
         "message; wheelbase_m: "
      << YamlReal(wheelbase_m_) << "\n"
      << "timestamp_ns,left_distance_m,right_distance_m,left_ticks,right_ticks\n";
  for (const WheelOdometry& o : odometry_) {
    csv << o.stamp_ns << "," << Fixed9(o.left_distance_m) << "," << Fixed9(o.right_distance_m)
        << "," << o.left_ticks << "," << o.right_ticks << "\n";
  }
  WriteFileAtomic(dir_ / "odometry.csv", csv.str());
}

void DatasetExporter::FinishCoco() const {
  if (coco_images_.empty()) return;
  std::vector<const CocoImage*> images;
  for (const CocoImage& image : coco_images_) images.push_back(&image);
  std::stable_sort(images.begin(), images.end(), [](const CocoImage* a, const CocoImage* b) {
    return std::pair(a->stamp_ns, a->camera_order) < std::pair(b->stamp_ns, b->camera_order);
  });
  nlohmann::ordered_json coco;
  coco["info"] = {{"description", "corridorsim door plates"},
                  {"file_names", "relative to the export root"}};
  coco["images"] = nlohmann::ordered_json::array();
  coco["annotations"] = nlohmann::ordered_json::array();
  constexpr int kDoorPlateCategory = 1;
  int image_id = 0, annotation_id = 0;
  for (const CocoImage* image : images) {
    ++image_id;
    coco["images"].push_back({{"id", image_id},
                              {"file_name", image->file_name},
                              {"width", image->width},
                              {"height", image->height},
                              {"stamp_ns", image->stamp_ns}});
    for (const PlateBox& box : image->plates) {
      coco["annotations"].push_back({{"id", ++annotation_id},
                                     {"image_id", image_id},
                                     {"category_id", kDoorPlateCategory},
                                     {"bbox", {box.x, box.y, box.w, box.h}},
                                     {"area", Round4(box.w * box.h)},
                                     {"iscrowd", 0},
                                     {"attributes",
                                      {{"room_number", box.room_number},
                                       {"plate_id", box.plate_id},
                                       {"visible_fraction", box.visible_fraction},
                                       {"fully_in_image", box.fully_in_image}}}});
    }
  }
  coco["categories"] = nlohmann::ordered_json::array(
      {{{"id", kDoorPlateCategory}, {"name", "door_plate"}, {"supercategory", "sign"}}});
  MakeDir("coco");
  WriteFileAtomic(dir_ / "coco" / "plates.json", JsonFileText(coco, 1));
}

}  // namespace corridorsim
