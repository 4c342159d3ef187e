#include "harness/workbench/dataset.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "common/io/sha256.h"
#include "common/io/stable_json.h"
#include "common/random.h"
#include "harness/run/frame_io.h"
#include "harness/run/job_inputs.h"
#include "harness/run/simulation_setup.h"
#include "render/backend.h"
#include "worlds/image_io.h"
#include "worlds/world_io.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Json = nlohmann::ordered_json;

constexpr int kFormatVersion = 1;
const SourceLocation kCommandLine{"command line", 0, 0};

double Px(double v) { return RoundToStep(v, json_steps::kPx); }
double Fraction(double v) { return RoundToStep(v, 1e6); }
double Metres(double v) { return RoundToStep(v, json_steps::kMetres); }
double Deg(double v) { return RoundToStep(v, json_steps::kDeg); }
double Ratio(double v) { return RoundToStep(v, json_steps::kRatio); }

int Digits(int n) { return n < 10 ? 1 : 1 + Digits(n / 10); }

// ---- poses ------------------------------------------------------------------------------------

// M poses at the centres of M equal parts of the path's legs (start -> waypoint 1 -> ...), each
// heading along its leg: evenly spaced, and never two at a round trip's turning point.
std::vector<SE2> PathPoses(const Scenario& scenario, const worlds::World& world,
                           const render::RigOptions& rig, int count) {
  if (scenario.robot_path.kind == sim::PathKind::kScript) {
    throw InputError(kCommandLine, "--poses",
                     "path: the scenario's path is a script of velocity commands, which has no "
                     "legs to space poses along (use --poses random)");
  }
  const sim::RobotPath path = BuildScenarioRobotPath(scenario, world);
  if (auto problem = sim::CheckPathPlacement(world, scenario.robot, path, &rig)) {
    throw LocateProblem(scenario, problem->section, problem->problem);
  }
  struct Leg {
    Vector2d from, to;
    double length_m;
  };
  std::vector<Leg> legs;
  Vector2d at = path.world_from_start.translation();
  double total_m = 0.0;
  for (const sim::Waypoint& w : path.waypoints) {
    const double length = (w.p_in_world - at).norm();
    if (length > 0.0) legs.push_back(Leg{at, w.p_in_world, length});
    total_m += length;
    at = w.p_in_world;
  }
  if (legs.empty()) {
    throw LocateProblem(scenario, "path",
                        OptionsProblem{"kind", "the path has no leg to place dataset poses on"});
  }
  std::vector<SE2> poses;
  std::size_t leg = 0;
  double leg_start_m = 0.0;
  for (int i = 0; i < count; ++i) {
    const double s = total_m * (i + 0.5) / count;
    while (leg + 1 < legs.size() && s > leg_start_m + legs[leg].length_m) {
      leg_start_m += legs[leg].length_m;
      ++leg;
    }
    const Leg& l = legs[leg];
    const Vector2d direction = (l.to - l.from) / l.length_m;
    const Vector2d p = l.from + direction * std::min(s - leg_start_m, l.length_m);
    poses.emplace_back(p.x(), p.y(), std::atan2(direction.y(), direction.x()));
  }
  return poses;
}

// Uniform over the corridor segments' floor rectangles (a segment drawn in proportion to its
// area; where two overlap at a junction the overlap is twice as likely), yaw uniform; a pose whose
// chassis or cameras collide (CheckPosePlacement, as snapshot checks --pose) is drawn again.
std::vector<SE2> RandomPoses(const Scenario& scenario, const worlds::World& world,
                             const render::RigOptions& rig, int count) {
  RandomStream rng(world.seed, 0, "dataset.poses");
  std::vector<double> cumulative_area;
  double area = 0.0;
  for (const worlds::CorridorSegment& s : world.segments) {
    area += (s.end - s.start).norm() * s.width_m;
    cumulative_area.push_back(area);
  }
  CheckOrDie(area > 0.0, "RandomPoses", "a world without corridor floor");
  std::vector<SE2> poses;
  for (int i = 0; i < count; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < kMaxPoseTries && !placed; ++attempt) {
      const double pick = rng.Uniform(0.0, area);
      const std::size_t k = std::min<std::size_t>(
          std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
              cumulative_area.begin(),
          world.segments.size() - 1);
      const worlds::CorridorSegment& s = world.segments[k];
      const Vector2d along = s.direction();
      const Vector2d left(-along.y(), along.x());
      // One draw per statement (a call's arguments are evaluated in the compiler's order), in
      // the order GCC took them: across, then along.
      const double across = rng.Uniform(-0.5 * s.width_m, 0.5 * s.width_m);
      const double distance = rng.Uniform(0.0, (s.end - s.start).norm());
      const Vector2d p = s.start + along * distance + left * across;
      const SE2 pose(p.x(), p.y(), rng.Uniform(-std::numbers::pi, std::numbers::pi));
      if (!CheckPosePlacement(world, scenario, rig, pose)) {
        poses.push_back(pose);
        placed = true;
      }
    }
    if (!placed) {
      throw InputError(kCommandLine, "--poses",
                       "random: no pose of world seed " + std::to_string(world.seed) +
                           " keeps the robot and its cameras clear of the walls in " +
                           std::to_string(kMaxPoseTries) +
                           " draws (a corridor too narrow for the robot?)");
    }
  }
  return poses;
}

// The camera's optical centre must lie inside a corridor segment, 0.15 m from its walls and ends.
bool InsideCorridor(const worlds::World& world, const Vector2d& p) {
  for (const worlds::CorridorSegment& s : world.segments) {
    const Vector2d d = s.direction();
    const Vector2d n(-d.y(), d.x());
    const double along = (p - s.start).dot(d), across = (p - s.start).dot(n);
    if (along >= 0.15 && along <= (s.end - s.start).norm() - 0.15 &&
        std::abs(across) <= s.width_m / 2 - 0.15) {
      return true;
    }
  }
  return false;
}

// Lateral views of door plates (P1's reading task, what `train-detectors` learns from): each
// frame aims the lateral camera at a plate, or with probability kAimDistractorFraction at a
// poster or notice board with printed digits (hard negatives). The camera stands 0.4-3.5 m from
// the target, up to 50 deg off its normal, inside the corridor, and looks at it +-30 deg; the
// robot's pose follows from the camera's mount. A pose whose chassis or cameras collide is drawn
// again, target included.
std::vector<SE2> PlatePoses(const Scenario& scenario, const worlds::World& world,
                            const render::RigOptions& rig, int count) {
  const render::CameraOptions* lateral = nullptr;
  for (const render::CameraOptions& c : rig.cameras) {
    if (c.id == "lateral" && c.enabled) lateral = &c;
  }
  if (!lateral) {
    throw InputError(kCommandLine, "--poses",
                     "plates: aims the lateral camera, which is not among the dataset's cameras "
                     "(sensors.lateral.enabled, --cameras)");
  }
  std::vector<const worlds::Distractor*> printed;
  for (const worlds::Distractor& d : world.distractors) {
    if (!d.text.empty()) printed.push_back(&d);
  }
  if (world.plates.empty()) {
    throw InputError(kCommandLine, "--poses",
                     "plates: world seed " + std::to_string(world.seed) +
                         " has no door plate to aim at (world.plates)");
  }
  RandomStream rng(world.seed, 0, "dataset.poses");
  const Vector2d mount(lateral->mount.x_m, lateral->mount.y_m);
  const auto pick = [&](std::size_t n) {
    return std::size_t(rng.UniformInt(0, static_cast<std::int64_t>(n) - 1));
  };
  std::vector<SE2> poses;
  for (int i = 0; i < count; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < kMaxPoseTries && !placed; ++attempt) {
      Vector3d target, normal;
      if (!printed.empty() && rng.Bernoulli(kAimDistractorFraction)) {
        const worlds::Distractor& d = *printed[pick(printed.size())];
        target = d.center + d.normal * (d.size_m.y() / 2);
        normal = d.normal;
      } else {
        const worlds::DoorPlate& p = world.plates[pick(world.plates.size())];
        target = p.center;
        normal = p.normal;
      }
      const Vector2d n = normal.head<2>().normalized();
      const Vector2d t(-n.y(), n.x());
      const double distance = rng.Uniform(0.4, 3.5);
      const double off = rng.Uniform(-50.0, 50.0) * std::numbers::pi / 180.0;
      const double aim_error = rng.Uniform(-30.0, 30.0) * std::numbers::pi / 180.0;
      const Vector2d camera = target.head<2>() + distance * (std::cos(off) * n + std::sin(off) * t);
      if (!InsideCorridor(world, camera)) continue;
      const Vector2d to_target = target.head<2>() - camera;
      // The camera looks along the robot's heading + its mount's yaw, from (x, y) on the robot.
      const double robot_yaw = std::atan2(to_target.y(), to_target.x()) + aim_error -
                               lateral->mount.yaw_deg * std::numbers::pi / 180.0;
      const Vector2d robot = camera - Eigen::Rotation2Dd(robot_yaw) * mount;
      const SE2 pose(robot.x(), robot.y(), std::atan2(std::sin(robot_yaw), std::cos(robot_yaw)));
      if (!CheckPosePlacement(world, scenario, rig, pose)) {
        poses.push_back(pose);
        placed = true;
      }
    }
    if (!placed) {
      throw InputError(kCommandLine, "--poses",
                       "plates: no view of a plate of world seed " + std::to_string(world.seed) +
                           " keeps the robot and its cameras clear of the walls in " +
                           std::to_string(kMaxPoseTries) + " draws");
    }
  }
  return poses;
}

// ---- annotations ------------------------------------------------------------------------------

// The camera's optical centre and axis in the world: distances and viewing angles of landmarks.
struct Viewer {
  Vector3d centre;
  Vector3d axis;
  double Distance(const Vector3d& p) const { return (p - centre).norm(); }
  double AngleDeg(const Vector3d& p) const {
    const Vector3d ray = (p - centre).normalized();
    return std::acos(std::clamp(axis.dot(ray), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  }
};

// A box between two pixel centres (the project's convention: pixel centres at integers) as COCO
// [x, y, w, h] (pixel edges: +0.5), clipped to the image; none when nothing of it is inside.
std::optional<std::array<double, 4>> CocoBox(const Vector2d& min_px, const Vector2d& max_px,
                                             int width, int height) {
  const double x0 = Px(std::clamp(min_px.x() + 0.5, 0.0, double(width)));
  const double y0 = Px(std::clamp(min_px.y() + 0.5, 0.0, double(height)));
  const double x1 = Px(std::clamp(max_px.x() + 0.5, 0.0, double(width)));
  const double y1 = Px(std::clamp(max_px.y() + 0.5, 0.0, double(height)));
  if (x1 <= x0 || y1 <= y0) return std::nullopt;
  return std::array<double, 4>{x0, y0, Px(x1 - x0), Px(y1 - y0)};
}

Json BoxJson(const std::array<double, 4>& b) { return Json::array({b[0], b[1], b[2], b[3]}); }

// Per door id: the bounding box and pixel count of its pixels in the instance image (frame and
// leaf carry the door's id).
struct PixelBox {
  int min_u = 0, min_v = 0, max_u = -1, max_v = -1;
  int count = 0;
};
std::map<int, PixelBox> DoorPixels(const render::FrameTruth& truth,
                                   const render::CameraFrame& frame, int width) {
  std::map<int, PixelBox> boxes;
  for (const render::DoorTruth& d : truth.doors) {
    if (d.visible) boxes[d.id];
  }
  if (boxes.empty()) return boxes;
  const auto [lowest, highest] = std::pair(boxes.begin()->first, boxes.rbegin()->first);
  for (std::size_t i = 0; i < frame.instance.size(); ++i) {
    const auto id = static_cast<int>(frame.instance[i]);
    if (id < lowest || id > highest) continue;
    const auto it = boxes.find(id);
    if (it == boxes.end()) continue;
    PixelBox& b = it->second;
    const int u = static_cast<int>(i % width), v = static_cast<int>(i / width);
    if (b.count++ == 0) {
      b.min_u = b.max_u = u;
      b.min_v = b.max_v = v;
    } else {
      b.min_u = std::min(b.min_u, u);
      b.max_u = std::max(b.max_u, u);
      b.min_v = std::min(b.min_v, v);
      b.max_v = std::max(b.max_v, v);
    }
  }
  return boxes;
}

}  // namespace

std::string DatasetWorldStem(int world_index, int worlds) {
  const std::string digits = std::to_string(world_index);
  const std::size_t width = static_cast<std::size_t>(std::max(3, Digits(std::max(worlds - 1, 0))));
  return "w" + std::string(width > digits.size() ? width - digits.size() : 0, '0') + digits;
}

std::string DatasetCategoryName(int category_id) {
  switch (category_id) {
    case kCategoryDoorPlate:
      return "door_plate";
    case kCategoryDoor:
      return "door";
    case kCategoryLamp:
      return "lamp";
    case kCategoryCeilingCorner:
      return "ceiling_corner";
    default:
      return "";
  }
}

nlohmann::ordered_json DatasetCategoriesJson() {
  Json categories = Json::array();
  const char* const supercategory[] = {"sign", "structure", "ceiling", "ceiling"};
  for (int id = 1; id <= kDatasetCategoryCount; ++id) {
    categories.push_back(
        {{"id", id}, {"name", DatasetCategoryName(id)}, {"supercategory", supercategory[id - 1]}});
  }
  // Corners are COCO keypoint objects of one keypoint.
  categories.back()["keypoints"] = Json::array({"corner"});
  categories.back()["skeleton"] = Json::array();
  return categories;
}

std::vector<SE2> DatasetPoses(const Scenario& scenario, const worlds::World& world,
                              const render::RigOptions& rig, DatasetPoseMode mode, int count) {
  switch (mode) {
    case DatasetPoseMode::kPath:
      return PathPoses(scenario, world, rig, count);
    case DatasetPoseMode::kPlates:
      return PlatePoses(scenario, world, rig, count);
    case DatasetPoseMode::kRandom:
      break;
  }
  return RandomPoses(scenario, world, rig, count);
}

std::string DatasetFrameStem(int world_index, int frame_index, int worlds, int frames_per_world) {
  const int frame_digits = std::max(4, Digits(std::max(frames_per_world - 1, 0)));
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "_f%0*d", frame_digits, frame_index);
  return DatasetWorldStem(world_index, worlds) + buffer;
}

nlohmann::ordered_json FrameAnnotations(const worlds::World& world, const render::FrameTruth& truth,
                                        const render::CameraFrame& frame, int width, int height) {
  const Viewer viewer{frame.world_from_camera.translation(),
                      frame.world_from_camera.rotation() * Vector3d::UnitZ()};
  Json annotations = Json::array();
  const auto base = [](int category, const std::array<double, 4>& box, double area) {
    return Json{
        {"category_id", category}, {"bbox", BoxJson(box)}, {"area", Px(area)}, {"iscrowd", 0}};
  };

  for (const render::PlateTruth& p : truth.plates) {
    if (p.visible_fraction <= 0.0) continue;
    const auto box = CocoBox(p.bbox_min_px, p.bbox_max_px, width, height);
    if (!box) continue;
    Json a = base(kCategoryDoorPlate, *box, (*box)[2] * (*box)[3]);
    a["landmark_id"] = p.id;
    a["room_number"] = p.room_number;
    a["distance_m"] = Metres(p.distance_m);
    a["viewing_angle_deg"] = Deg(p.viewing_angle_deg);
    a["visible_fraction"] = Ratio(p.visible_fraction);
    annotations.push_back(std::move(a));
  }

  std::map<int, const worlds::Doorway*> doors;
  for (const worlds::Doorway& d : world.doors) doors[d.id] = &d;
  const std::map<int, PixelBox> door_pixels = DoorPixels(truth, frame, width);
  for (const render::DoorTruth& d : truth.doors) {
    if (!d.visible) continue;
    const PixelBox& b = door_pixels.at(d.id);
    if (b.count < kMinDoorPixels) continue;
    // Pixel u covers [u, u + 1) in COCO's convention.
    const std::array<double, 4> box{double(b.min_u), double(b.min_v), double(b.max_u - b.min_u + 1),
                                    double(b.max_v - b.min_v + 1)};
    // The landmark is the opening's centre: midway between the columns, half its height.
    const worlds::Doorway& door = *doors.at(d.id);
    const Vector2d mid = 0.5 * (door.column_a + door.column_b);
    const Vector3d centre(mid.x(), mid.y(), 0.5 * door.top_height_m);
    Json a = base(kCategoryDoor, box, b.count);
    a["landmark_id"] = d.id;
    a["state"] = worlds::DoorStateName(d.state);
    a["distance_m"] = Metres(viewer.Distance(centre));
    a["viewing_angle_deg"] = Deg(viewer.AngleDeg(centre));
    annotations.push_back(std::move(a));
  }

  std::map<int, const worlds::Lamp*> lamps;
  for (const worlds::Lamp& l : world.lamps) lamps[l.id] = &l;
  std::map<int, const worlds::Reflector*> reflectors;
  for (const worlds::Reflector& r : world.reflectors) reflectors[r.id] = &r;
  for (const render::LampTruth& l : truth.lamps) {
    if (l.visible_fraction <= 0.0) continue;
    const Vector2d c = l.center_px + Vector2d(0.5, 0.5);  // COCO convention
    const double r = l.radius_px;
    const auto box =
        CocoBox(l.center_px - Vector2d(r, r), l.center_px + Vector2d(r, r), width, height);
    if (!box) continue;  // the whole circle lies outside the image
    // A reflection is seen where the mirrored lamp appears, behind the reflector.
    const Vector3d centre =
        l.reflection ? reflectors.at(l.id)->apparent_lamp_center : lamps.at(l.id)->center;
    Json a = base(kCategoryLamp, *box, (*box)[2] * (*box)[3]);
    a["landmark_id"] = l.id;
    a["circle"] = Json::array({Px(c.x()), Px(c.y()), Px(r)});
    a["shape"] = worlds::LampShapeName(l.shape);
    a["reflection"] = l.reflection;
    a["on"] = l.on;
    a["visible_fraction"] = Ratio(l.visible_fraction);
    a["distance_m"] = Metres(viewer.Distance(centre));
    a["viewing_angle_deg"] = Deg(viewer.AngleDeg(centre));
    annotations.push_back(std::move(a));
  }

  std::map<int, const worlds::CornerPoint*> corners;
  for (const worlds::CornerPoint& c : world.corner_points) corners[c.id] = &c;
  for (const render::CornerTruth& c : truth.corners) {
    const double x = Px(c.pixel.x() + 0.5), y = Px(c.pixel.y() + 0.5);
    if (!(x >= 0.0 && x < width && y >= 0.0 && y < height)) continue;
    const Vector3d& position = corners.at(c.id)->position;
    // A 1x1 box centred on the point, clipped to the image (the point is inside, so some is).
    const std::array<double, 4> box =
        *CocoBox(c.pixel - Vector2d(0.5, 0.5), c.pixel + Vector2d(0.5, 0.5), width, height);
    Json a = base(kCategoryCeilingCorner, box, box[2] * box[3]);
    a["landmark_id"] = c.id;
    a["keypoints"] = Json::array({x, y, 2});
    a["num_keypoints"] = 1;
    a["kind"] = worlds::CornerKindName(c.kind);
    a["distance_m"] = Metres(viewer.Distance(position));
    a["viewing_angle_deg"] = Deg(viewer.AngleDeg(position));
    annotations.push_back(std::move(a));
  }
  return annotations;
}

void WriteDatasetAnnotations(const fs::path& dir, const std::string& camera, int worlds,
                             int frames_per_world) {
  Json coco;
  coco["info"] = {{"description", "corridorsim dataset, camera " + camera},
                  {"file_names", "relative to the camera's folder"},
                  {"pixels", "COCO: (0, 0) is the top-left corner of the top-left pixel"}};
  coco["images"] = Json::array();
  coco["annotations"] = Json::array();
  std::int64_t annotation_id = 0;
  for (int w = 0; w < worlds; ++w) {
    for (int f = 0; f < frames_per_world; ++f) {
      const fs::path file =
          dir / camera / "truth" / (DatasetFrameStem(w, f, worlds, frames_per_world) + ".json");
      const std::string name = file.string();
      const Json truth = ParseJsonInput(ReadRegularFile(file, kMaxDatasetTruthBytes), name);
      const JsonField top{name, "", truth};
      if (!truth.is_object()) top.Fail("expected an object");
      const std::int64_t image_id = std::int64_t(w) * frames_per_world + f + 1;
      Json image{{"id", image_id}};
      for (const char* key : {"file_name", "width", "height", "world_index", "frame_index",
                              "world_seed", "world_from_camera"}) {
        image[key] = top.At(key).value;
      }
      if (truth.contains("vanishing_point")) image["vanishing_point"] = truth["vanishing_point"];
      if (truth.contains("appearance")) image["appearance"] = truth["appearance"];
      coco["images"].push_back(std::move(image));
      top.At("annotations").ArraySize();
      for (const Json& a : truth["annotations"]) {
        if (!a.is_object()) top.At("annotations").Fail("expected an array of objects");
        Json annotation{{"id", ++annotation_id}, {"image_id", image_id}};
        for (const auto& [key, value] : a.items()) annotation[key] = value;
        coco["annotations"].push_back(std::move(annotation));
      }
    }
  }
  coco["categories"] = DatasetCategoriesJson();
  WriteFileAtomic(dir / camera / "annotations.json", JsonFileText(coco, 1));
}

namespace {

// The manifest says what the folder's bytes depend on; a rerun resumes only into a folder whose
// manifest is the same bytes.
std::string ManifestJson(const Scenario& scenario, std::uint64_t seed,
                         const DatasetRequest& request, const std::vector<std::string>& cameras,
                         const render::Backend& backend) {
  Json j;
  j["format"] = "corridorsim dataset";
  j["format_version"] = kFormatVersion;
  j["scenario"] = {{"name", scenario.name},
                   {"sha256", Sha256Hex(ResolvedScenarioYaml(scenario, seed))},
                   {"sha256_of", "the resolved scenario with the seed (a run's scenario.yaml)"}};
  j["seed"] = seed;
  j["world_seeds"] = "seed + world index (modulo 2^64)";
  j["worlds"] = request.worlds;
  j["frames_per_world"] = request.frames_per_world;
  j["cameras"] = cameras;
  j["poses"] = DatasetPoseModeName(request.poses);
  const render::BackendInfo info = backend.info();
  const char* gallivm_perf = std::getenv("GALLIVM_PERF");
  j["render"] = {{"backend", render::BackendName(backend.kind())},
                 {"device", info.device},
                 {"gl_renderer", info.renderer},
                 {"gl_version", info.version},
                 {"GALLIVM_PERF", gallivm_perf ? Json(gallivm_perf) : Json(nullptr)}};
  j["categories"] = DatasetCategoriesJson();
  return JsonFileText(j);
}

// The first top-level key whose value differs between two manifests, for the refusal message.
std::string FirstDifference(const std::string& existing, const std::string& wanted) {
  try {
    const Json a = Json::parse(existing), b = Json::parse(wanted);
    for (const auto& [key, value] : b.items()) {
      if (!a.contains(key) || a[key] != value) return key;
    }
  } catch (const nlohmann::json::exception&) {
    return "(not JSON)";
  }
  return "(formatting)";
}

// A folder with files is this job's only when it holds StagedDirectory::kOutputFolderMarker
// (a regular file, not a link), which `dataset` writes before anything else: an empty or missing
// folder is filled; one of ours holding this dataset's manifest is resumed; one of ours with
// another manifest (or another corridorsim job's folder) is cleared with --force, else refused;
// one without the marker is never touched, whatever it holds (a dataset.json of the user's).
void WriteManifestAndCheck(const fs::path& dir, const std::string& manifest, bool force) {
  std::error_code error;
  const fs::path manifest_path = dir / "dataset.json";
  const fs::path marker = dir / StagedDirectory::kOutputFolderMarker;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error)) {
    throw InputError(kCommandLine, "--out", dir.string() + " exists and is not a folder");
  }
  const bool has_files = fs::is_directory(dir, error) && !fs::is_empty(dir, error);
  if (has_files) {
    if (!fs::is_regular_file(fs::symlink_status(marker, error))) {
      throw InputError(kCommandLine, "--out",
                       dir.string() + " holds files that corridorsim did not write (it has no " +
                           StagedDirectory::kOutputFolderMarker +
                           "): dataset resumes or replaces only its own folders; choose another "
                           "--out");
    }
    const bool has_manifest = fs::exists(fs::symlink_status(manifest_path, error));
    const std::optional<std::string> existing =
        has_manifest
            ? std::optional<std::string>(ReadRegularFile(manifest_path, kMaxDatasetManifestBytes))
            : std::nullopt;
    if (existing == manifest) return;  // resume
    if (!force) {
      throw InputError(
          kCommandLine, "--out",
          existing
              ? manifest_path.string() + " was written with other arguments (first difference: `" +
                    FirstDifference(*existing, manifest) +
                    "`); use --force to replace the dataset, or another --out"
              : dir.string() +
                    " holds another corridorsim job's output (no dataset.json); use --force "
                    "to replace it, or another --out");
    }
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      fs::remove_all(entry.path());
    }
  }
  EnsureWritableDirectory(dir);
  WriteFileAtomic(marker,
                  "This folder was written by corridorsim dataset: it resumes into it, and "
                  "`--force` may replace it whole.\n");
  WriteFileAtomic(manifest_path, manifest);
}

// The selected cameras in the rig's order: --cameras must name enabled cameras.
std::vector<std::string> SelectCameras(const Scenario& scenario,
                                       const std::vector<std::string>& requested) {
  std::vector<std::string> enabled;
  for (const render::CameraOptions& c : scenario.rig.cameras) {
    if (c.enabled) enabled.push_back(c.id);
  }
  std::string enabled_list;
  for (const std::string& id : enabled) enabled_list += (enabled_list.empty() ? "" : ", ") + id;
  if (requested.empty()) {
    if (enabled.empty()) {
      throw InputError(kCommandLine, "--cameras",
                       "the scenario enables no camera (sensors.<camera>.enabled)");
    }
    return enabled;
  }
  std::set<std::string> wanted;
  for (const std::string& id : requested) {
    if (std::find(enabled.begin(), enabled.end(), id) == enabled.end()) {
      throw InputError(kCommandLine, "--cameras",
                       "'" + id + "' is not a camera the scenario enables (enabled: " +
                           (enabled_list.empty() ? "none" : enabled_list) + ")");
    }
    if (!wanted.insert(id).second) {
      throw InputError(kCommandLine, "--cameras", "'" + id + "' is named twice");
    }
  }
  std::vector<std::string> selected;
  for (const std::string& id : enabled) {
    if (wanted.count(id)) selected.push_back(id);
  }
  return selected;
}

// `dataset: world 2/5 frame 10/20`: in place on a terminal, else a line per tenth of the job and
// at the end of each world (no clock: the same lines every time).
class DatasetProgress {
 public:
  DatasetProgress(int worlds, int frames) : worlds_(worlds), frames_(frames) {
    tty_ = ::isatty(STDERR_FILENO) != 0;
  }
  void Update(int world, int frame) {
    const std::int64_t done = std::int64_t(world) * frames_ + frame + 1;
    const std::int64_t total = std::int64_t(worlds_) * frames_;
    const int decile = static_cast<int>(10 * done / total);
    char line[128];
    std::snprintf(line, sizeof(line), "dataset: world %d/%d frame %d/%d", world + 1, worlds_,
                  frame + 1, frames_);
    if (tty_) {
      std::fprintf(stderr, "\r%s", line);
      if (done == total) std::fputc('\n', stderr);
    } else if (decile != last_decile_ || frame + 1 == frames_) {
      std::fprintf(stderr, "%s\n", line);
    }
    last_decile_ = decile;
  }

 private:
  int worlds_, frames_;
  bool tty_ = false;
  int last_decile_ = 0;
};

}  // namespace

DatasetWorld::DatasetWorld(const Scenario& scenario, const render::RigOptions& rig,
                           render::BackendKind backend, std::uint64_t world_seed, int world_index,
                           int worlds, DatasetPoseMode mode, int frames)
    : scenario_(scenario),
      rig_(rig),
      backend_(backend),
      world_index_(world_index),
      worlds_(worlds),
      frames_(frames),
      world_(GenerateWorld(scenario, world_seed)),
      poses_(DatasetPoses(scenario, world_, rig, mode, frames)) {}

DatasetWorld::~DatasetWorld() = default;

std::vector<DatasetFrame> DatasetWorld::Render(int f) {
  CheckOrDie(f >= 0 && f < frames_, "DatasetWorld::Render", "frame index out of range");
  if (!renderer_) renderer_ = std::make_unique<Renderer>(world_, rig_, backend_);
  const std::string stem = DatasetFrameStem(world_index_, f, worlds_, frames_);
  const SE3 world_from_robot = SE3::FromSE2(poses_[std::size_t(f)]);
  std::vector<render::CameraFrame> frames;
  renderer_->rig->Render(world_from_robot, world_.seed, static_cast<std::uint64_t>(f), &frames);
  std::vector<DatasetFrame> out;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const render::CameraOptions& options = renderer_->rig->cameras()[k].options();
    DatasetFrame d{std::move(frames[k]), options.depth, Json()};
    const render::CameraFrame& frame = d.frame;
    const int width = frame.rgb.width, height = frame.rgb.height;
    const render::FrameTruth truth = FrameTruthOf(world_, options, frame, world_from_robot);
    Json& j = d.truth;
    j["world_index"] = world_index_;
    j["frame_index"] = f;
    j["world_seed"] = world_.seed;
    j["file_name"] = "images/" + stem + ".png";
    j["width"] = width;
    j["height"] = height;
    if (scenario_.world.appearance.Any()) {
      // What the world's appearance randomisation drew, as numbers `score` bins recall by.
      const worlds::AppearanceDraw& a = world_.appearance;
      const auto mean = [](const Eigen::Vector3f& c) { return double(c.mean()); };
      j["appearance"] = {{"wall_brightness", Fraction(mean(a.wall))},
                         {"floor_brightness", Fraction(mean(a.floor))},
                         {"ceiling_brightness", Fraction(mean(a.ceiling))},
                         {"door_brightness", Fraction(mean(a.door))},
                         {"lamp_brightness", Fraction(a.lamp_brightness)},
                         {"lamp_temperature_k", Fraction(a.lamp_temperature_k)},
                         {"distractor_density", Fraction(a.distractor_density)},
                         {"camera_exposure", Fraction(a.camera_exposure)},
                         {"camera_noise", Fraction(a.camera_noise)},
                         {"camera_blur_px", Fraction(a.camera_blur_px)}};
    }
    const Json truth_json = render::FrameTruthJson(truth);
    for (const auto& [key, value] : truth_json.items()) j[key] = value;
    if (frame.camera_id == "front") {
      // The vanishing point of the corridor the camera stands in, COCO pixel convention.
      j["vanishing_point"] = nullptr;
      for (const render::VanishingPointTruth& vp : truth.vanishing_points) {
        if (!vp.camera_in_segment) continue;
        j["vanishing_point"] = Json::array({Px(vp.pixel.x() + 0.5), Px(vp.pixel.y() + 0.5)});
        break;
      }
    }
    j["annotations"] = FrameAnnotations(world_, truth, frame, width, height);
    out.push_back(std::move(d));
  }
  return out;
}

DatasetManifest ReadDatasetManifest(const fs::path& dir) {
  DatasetManifest m;
  m.file = (dir / "dataset.json").string();
  m.json = ParseJsonInput(ReadRegularFile(dir / "dataset.json", kMaxDatasetManifestBytes), m.file);
  const JsonField top{m.file, "", m.json};
  if (!m.json.is_object()) top.Fail("expected an object");
  if (top.At("format").String() != "corridorsim dataset") {
    top.At("format").Fail("expected \"corridorsim dataset\"");
  }
  const JsonField cameras = top.At("cameras");
  for (std::size_t i = 0; i < cameras.ArraySize(); ++i) {
    // A camera names a folder of DIR: a plain name, never a path out of it.
    const std::string id = cameras.At(i).String();
    if (id.empty() || id.size() > 64 || !std::all_of(id.begin(), id.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
        })) {
      cameras.At(i).Fail("expected a camera name: 1 to 64 letters, digits, '_' or '-'");
    }
    m.cameras.push_back(id);
  }
  return m;
}

int RunDataset(const DatasetRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file, request.settings);
  const std::vector<std::string> cameras = SelectCameras(scenario, request.cameras);
  const render::BackendKind backend_kind = ChooseBackend(scenario.rig.backend);
  const std::uint64_t seed = request.seed.value_or(scenario.seed);
  const int n_worlds = request.worlds, n_frames = request.frames_per_world;
  CheckOrDie(n_worlds >= 1 && n_worlds <= kMaxDatasetWorlds && n_frames >= 1 &&
                 n_frames <= kMaxDatasetFramesPerWorld,
             "RunDataset", "counts out of bounds (ParseCommandLine checks them)");
  render::RigOptions rig_options = scenario.rig;
  for (render::CameraOptions& c : rig_options.cameras) {
    c.enabled = std::find(cameras.begin(), cameras.end(), c.id) != cameras.end();
  }
  const fs::path dir = request.out_dir;
  RefuseOutputOverInputs(dir, "--out", ScenarioInputs(scenario));

  // World 0 and its poses before anything is written: a scenario whose worlds cannot be built,
  // or poses that cannot be placed, are mostly found here.
  std::optional<DatasetWorld> world(std::in_place, scenario, rig_options, backend_kind, seed, 0,
                                    n_worlds, request.poses, n_frames);

  // The manifest names the renderer, so a GL context comes first.
  const std::string manifest = [&] {
    const std::unique_ptr<render::Backend> backend = render::CreateBackend(backend_kind);
    return ManifestJson(scenario, seed, request, cameras, *backend);
  }();
  WriteManifestAndCheck(dir, manifest, request.force);
  for (const render::CameraOptions& c : rig_options.cameras) {
    if (!c.enabled) continue;
    for (const char* sub : {"images", "labels", "truth"}) fs::create_directories(dir / c.id / sub);
    if (c.depth) fs::create_directories(dir / c.id / "depth");
    WriteFileAtomic(dir / c.id / "intrinsics.json", JsonFileText(IntrinsicsJson(c)));
  }

  DatasetProgress progress(n_worlds, n_frames);
  std::int64_t rendered = 0;
  for (int w = 0; w < n_worlds; ++w) {
    // Every pose is drawn even when its frame is done: a resumed world gets the same poses.
    if (w > 0) {
      world.emplace(scenario, rig_options, backend_kind, seed + static_cast<std::uint64_t>(w), w,
                    n_worlds, request.poses, n_frames);
    }
    const fs::path world_dir = dir / "worlds" / DatasetWorldStem(w, n_worlds);
    if (!fs::exists(world_dir / "ground_truth.json")) {
      fs::create_directories(world_dir);
      WriteFileAtomic(world_dir / "ground_truth.json",
                      JsonFileText(worlds::GroundTruthJson(world->world())));
    }
    for (int f = 0; f < n_frames; ++f) {
      const std::string stem = DatasetFrameStem(w, f, n_worlds, n_frames);
      const bool done = std::all_of(cameras.begin(), cameras.end(), [&](const std::string& id) {
        return fs::exists(dir / id / "truth" / (stem + ".json"));
      });
      if (!done) {
        for (const DatasetFrame& frame : world->Render(f)) {
          const render::CameraFrame& image = frame.frame;
          const fs::path camera_dir = dir / image.camera_id;
          const int width = image.rgb.width, height = image.rgb.height;
          WriteFileAtomic(camera_dir / "images" / (stem + ".png"),
                          EncodePng(image.rgb, image.camera_id + " " + stem));
          WriteFileAtomic(camera_dir / "labels" / (stem + ".png"),
                          EncodeLabels(image, width, height));
          if (frame.depth) {
            WriteFileAtomic(camera_dir / "depth" / (stem + ".png"),
                            EncodeDepth(image.noisy_depth_m, image.camera_id + " depth " + stem));
          }
          // Written last: its presence marks the frame done.
          WriteFileAtomic(camera_dir / "truth" / (stem + ".json"), JsonFileText(frame.truth, 1));
        }
        ++rendered;
      }
      progress.Update(w, f);
    }
  }
  for (const std::string& id : cameras) WriteDatasetAnnotations(dir, id, n_worlds, n_frames);
  std::string camera_list;
  for (const std::string& id : cameras) camera_list += (camera_list.empty() ? "" : ",") + id;
  std::printf("dataset: %d worlds x %d frames, cameras %s: rendered %lld frames, wrote %s\n",
              n_worlds, n_frames, camera_list.c_str(), static_cast<long long>(rendered),
              dir.string().c_str());
  return 0;
}

}  // namespace corridorsim
