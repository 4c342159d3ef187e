#include "harness/workbench/score.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "harness/workbench/dataset.h"
#include "harness/workbench/score_internal.h"

// `score`'s input (score.h): a dataset camera's annotations.json as images and labels, and a COCO
// results file as detections, each field checked against the dataset (bounds, categories, the
// image it names), every problem an InputError at `file: field`.

namespace corridorsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Field = JsonField;
using score_internal::CircleBox;
using score_internal::FormatNumber;

// A COCO box [x, y, w, h] intersects the image [0, width] x [0, height] (edges included).
bool Intersects(const std::array<double, 4>& b, const ScoreImage& image) {
  return b[0] <= image.width && b[0] + b[2] >= 0.0 && b[1] <= image.height && b[1] + b[3] >= 0.0;
}

// N numbers of pixel geometry, each within +-kMaxScoreCoordinatePx.
template <std::size_t N>
std::array<double, N> Pixels(const Field& f) {
  const std::array<double, N> v = f.Numbers<N>();
  for (const double x : v) {
    if (std::abs(x) > kMaxScoreCoordinatePx) {
      f.Fail("a coordinate beyond +-" + FormatNumber(kMaxScoreCoordinatePx) + " px");
    }
  }
  return v;
}

// Each element of the array `key` of `top` (an object each, `key[i]` in messages).
template <class Each>
void ForEachObject(const Field& top, const char* key, Each each) {
  const Field array = top.At(key);
  if (!array.value.is_array()) array.Fail("expected an array");
  for (std::size_t i = 0; i < array.value.size(); ++i) {
    const Field f{top.file, std::string(key) + "[" + std::to_string(i) + "]", array.value[i]};
    if (!f.value.is_object()) f.Fail("expected an object");
    each(f);
  }
}

}  // namespace

ScoreDataset ParseScoreDataset(std::string_view text, const std::string& file) {
  const Json root = ParseJsonInput(text, file);
  if (!root.is_object()) FailInFile(file, "", "expected a COCO object");
  const Field top{file, "", root};
  ScoreDataset dataset;
  std::set<std::string> appearance_keys;
  ForEachObject(top, "images", [&](const Field& f) {
    ScoreImage image;
    image.id = f.At("id").Integer();
    for (const char* key : {"width", "height"}) {
      const std::int64_t side = f.At(key).Integer();
      if (side < 1 || side > kMaxScoreImageSide) {
        f.At(key).Fail("outside [1, " + std::to_string(kMaxScoreImageSide) + "] px");
      }
      (std::string(key) == "width" ? image.width : image.height) = static_cast<int>(side);
    }
    if (f.Has("appearance")) {
      const Field a = f.At("appearance");
      if (!a.value.is_object()) a.Fail("expected an object");
      for (const auto& [key, value] : a.value.items()) {
        if (value.is_number() && std::isfinite(value.get<double>())) {
          image.appearance[key] = value.get<double>();
          appearance_keys.insert(key);
          if (appearance_keys.size() > kMaxAppearanceKeys) {
            a.Fail("more than " + std::to_string(kMaxAppearanceKeys) +
                   " distinct appearance keys in the file");
          }
        }
      }
    }
    if (!dataset.images.emplace(image.id, image).second) f.At("id").Fail("a repeated image id");
  });
  ForEachObject(top, "annotations", [&](const Field& f) {
    ScoreLabel label;
    label.image_id = f.At("image_id").Integer();
    if (!dataset.images.count(label.image_id)) f.At("image_id").Fail("no image has this id");
    const std::int64_t category = f.At("category_id").Integer();
    if (category < 1 || category > kDatasetCategoryCount) {
      f.At("category_id").Fail("unknown category");
    }
    label.category_id = static_cast<int>(category);
    label.bbox = Pixels<4>(f.At("bbox"));
    if (label.bbox[2] < 0.0 || label.bbox[3] < 0.0) {
      f.At("bbox").Fail("a box with negative width or height");
    }
    if (f.Has("circle")) {
      label.circle = Pixels<3>(f.At("circle"));
      if ((*label.circle)[2] < 0.0) f.At("circle").Fail("a negative radius");
    }
    if (f.Has("keypoints")) {
      const auto k = Pixels<3>(f.At("keypoints"));
      label.point = std::array<double, 2>{k[0], k[1]};
    }
    if (label.category_id == kCategoryCeilingCorner && !label.point) {
      f.At("keypoints").Fail("missing");
    }
    if (f.Has("room_number")) label.room_number = f.At("room_number").String();
    if (f.Has("distance_m")) label.distance_m = f.At("distance_m").Number();
    if (f.Has("viewing_angle_deg")) label.viewing_angle_deg = f.At("viewing_angle_deg").Number();
    dataset.labels.push_back(std::move(label));
  });
  return dataset;
}

ScoreDataset ReadScoreDataset(const fs::path& dir, const std::optional<std::string>& camera) {
  const std::vector<std::string> ids = ReadDatasetManifest(dir).cameras;
  std::string list;
  for (const std::string& id : ids) list += (list.empty() ? "" : ", ") + id;
  std::string chosen;
  if (camera) {
    if (std::find(ids.begin(), ids.end(), *camera) == ids.end()) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--camera",
                       "'" + *camera + "' is not a camera of the dataset (" + list + ")");
    }
    chosen = *camera;
  } else if (ids.size() == 1) {
    chosen = ids[0];
  } else {
    throw InputError(SourceLocation{"command line", 0, 0}, "--camera",
                     "the dataset has cameras " + list + ": name the one the detections are for");
  }
  const fs::path annotations = dir / chosen / "annotations.json";
  ScoreDataset dataset = ParseScoreDataset(ReadRegularFile(annotations, kMaxAnnotationsFileBytes),
                                           annotations.string());
  dataset.camera = chosen;
  return dataset;
}

std::vector<ScoreDetection> ParseDetections(std::string_view text, const std::string& file,
                                            const ScoreDataset& dataset) {
  std::vector<ScoreDetection> detections;
  // Entry by entry: memory holds the detections, not the whole document.
  const auto each = [&](std::size_t i, const Json& entry) {
    if (i >= kMaxDetections) {
      FailInFile(file, "", "more than " + std::to_string(kMaxDetections) + " detections");
    }
    const Field f{file, "[" + std::to_string(i) + "]", entry};
    if (!f.value.is_object()) f.Fail("expected an object");
    ScoreDetection d;
    d.image_id = f.At("image_id").Integer();
    const auto image = dataset.images.find(d.image_id);
    if (image == dataset.images.end()) {
      f.At("image_id")
          .Fail("no image of the dataset's " + dataset.camera + " camera has id " +
                std::to_string(d.image_id));
    }
    const std::int64_t category = f.At("category_id").Integer();
    if (category < 1 || category > kDatasetCategoryCount) {
      f.At("category_id")
          .Fail("unknown category " + std::to_string(category) +
                " (1 door_plate, 2 door, 3 lamp, 4 ceiling_corner)");
    }
    d.category_id = static_cast<int>(category);
    d.score = f.At("score").Number();
    if (f.Has("bbox")) {
      const Field b = f.At("bbox");
      d.bbox = Pixels<4>(b);
      if ((*d.bbox)[2] < 0.0 || (*d.bbox)[3] < 0.0) b.Fail("a box with negative width or height");
      if (!Intersects(*d.bbox, image->second)) b.Fail("the box lies outside the image");
    }
    if (f.Has("circle")) {
      const Field c = f.At("circle");
      if (d.category_id != kCategoryLamp) c.Fail("only lamps (category 3) may give a circle");
      d.circle = Pixels<3>(c);
      if ((*d.circle)[2] < 0.0) c.Fail("a negative radius");
      if (!Intersects(CircleBox(*d.circle), image->second)) {
        c.Fail("the circle lies outside the image");
      }
    }
    for (const char* key : {"point", "keypoints"}) {
      if (!f.Has(key)) continue;
      const Field p = f.At(key);
      if (d.category_id != kCategoryCeilingCorner) {
        p.Fail("only ceiling corners (category 4) may give a point");
      }
      if (d.point) p.Fail("a second point (give `point` or `keypoints`, not both)");
      if (std::string(key) == "point") {
        d.point = Pixels<2>(p);
      } else {
        const auto k = Pixels<3>(p);
        d.point = std::array<double, 2>{k[0], k[1]};
      }
      if (!Intersects({(*d.point)[0], (*d.point)[1], 0.0, 0.0}, image->second)) {
        p.Fail("the point lies outside the image");
      }
    }
    if (!d.bbox && !d.circle && !d.point) {
      FailInFile(file, f.path + ".bbox",
                 d.category_id == kCategoryLamp ? "missing (a lamp gives `bbox` or `circle`)"
                 : d.category_id == kCategoryCeilingCorner
                     ? "missing (a corner gives `bbox`, `point` or `keypoints`)"
                     : "missing");
    }
    if (f.Has("room_number")) d.room_number = f.At("room_number").String();
    detections.push_back(std::move(d));
  };
  ParseJsonArrayInput(text, file, "expected a JSON array of detections (COCO results format)",
                      each);
  return detections;
}

}  // namespace corridorsim
