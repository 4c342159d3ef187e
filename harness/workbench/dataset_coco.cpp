#include "harness/workbench/dataset.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <numbers>
#include <optional>

#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "common/io/stable_json.h"
#include "harness/workbench/dataset_internal.h"
#include "harness/workbench/score_request.h"

// `dataset`'s COCO annotations (dataset.h): the fixed categories, a frame's annotations from its
// truth (FrameAnnotations: plates, doors from the instance image, lamps, ceiling corners) and a
// camera's annotations.json rebuilt from its truth files (WriteDatasetAnnotations).

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using dataset_internal::Deg;
using dataset_internal::Metres;
using dataset_internal::Px;
using dataset_internal::Ratio;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Json = nlohmann::ordered_json;

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

std::string DatasetCategoryName(int category_id) {
  // One list of the names: the classes `score --expect` names are these categories.
  static_assert(std::size(kScoreClassNames) == kDatasetCategoryCount);
  if (category_id < 1 || category_id > kDatasetCategoryCount) return "";
  return kScoreClassNames[category_id - 1];
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

}  // namespace corridorsim
