#include "harness/evaluate/landmark_file.h"

#include <climits>
#include <cmath>
#include <initializer_list>
#include <set>

#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "common/io/yaml_reader.h"             // InputExcerpt
#include "harness/evaluate/trajectory_file.h"  // the bounds of numbers

namespace corridorsim::evaluate {
namespace {

using Json = nlohmann::ordered_json;

void OnlyKeys(const JsonField& f, std::initializer_list<const char*> known) {
  if (!f.value.is_object()) f.Fail("expected an object");
  for (const auto& [key, value] : f.value.items()) {
    bool ok = false;
    std::string list;
    for (const char* k : known) {
      ok = ok || key == k;
      list += (list.empty() ? "" : ", ") + std::string(k);
    }
    if (!ok) f.Fail("unknown key '" + InputExcerpt(key, 60) + "' (known: " + list + ")");
  }
}

Eigen::Vector3d Position(const JsonField& f) {
  const auto v = f.Numbers<3>();
  for (const double x : v) {
    if (std::abs(x) > kMaxCoordinateMetres) f.Fail("a coordinate beyond +-1e9 m");
  }
  return {v[0], v[1], v[2]};
}

Eigen::Matrix3d Covariance(const JsonField& f) {
  if (f.ArraySize() != 3) f.Fail("expected 3 rows of 3 numbers");
  Eigen::Matrix3d m;
  for (std::size_t r = 0; r < 3; ++r) {
    const auto row = f.At(r).Numbers<3>();
    for (std::size_t c = 0; c < 3; ++c) {
      if (std::abs(row[c]) > kMaxCovarianceEntry) f.At(r).Fail("an entry beyond +-1e12");
      m(r, c) = row[c];
    }
  }
  return m;
}

std::string ShortText(const JsonField& f, std::size_t max_bytes) {
  std::string s = f.String();
  if (s.size() > max_bytes) f.Fail("longer than " + std::to_string(max_bytes) + " bytes");
  return s;
}

}  // namespace

std::vector<slam::LandmarkEstimate> ParseLandmarkMap(std::string_view text,
                                                     const std::string& file) {
  const Json document = ParseJsonInput(text, file);
  const JsonField top{file, "", document};
  if (!document.is_array()) top.Fail("expected an array of landmarks");
  const std::size_t n = top.ArraySize();
  if (n > kMaxLandmarks) top.Fail("more than " + std::to_string(kMaxLandmarks) + " landmarks");
  std::vector<slam::LandmarkEstimate> out;
  std::set<int> ids;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonField l = top.At(i);
    OnlyKeys(l, {"id", "type", "status", "label", "position_in_world", "covariance", "points"});
    slam::LandmarkEstimate landmark;
    const JsonField id = l.At("id");
    const std::int64_t id_value = id.Integer();
    if (id_value < 0 || id_value > INT_MAX) id.Fail("must lie in [0, 2147483647]");
    landmark.id = static_cast<int>(id_value);
    if (!ids.insert(landmark.id).second) id.Fail("a second landmark with this id");
    const JsonField type = l.At("type");
    const std::string type_name = type.String();
    bool known = false;
    std::string types;
    for (const slam::LandmarkType t :
         {slam::LandmarkType::kDoorPlate, slam::LandmarkType::kCorner, slam::LandmarkType::kLamp,
          slam::LandmarkType::kDoor, slam::LandmarkType::kVanishingPoint}) {
      types += (types.empty() ? "" : ", ") + slam::LandmarkTypeName(t);
      if (slam::LandmarkTypeName(t) == type_name) {
        landmark.type = t;
        known = true;
      }
    }
    if (!known) type.Fail("unknown type (expected one of " + types + ")");
    if (l.Has("status")) {
      const JsonField status = l.At("status");
      const std::string s = status.String();
      if (s == "converged") {
        landmark.status = slam::LandmarkStatus::kConverged;
      } else if (s == "initializing") {
        landmark.status = slam::LandmarkStatus::kInitializing;
      } else {
        status.Fail("expected converged or initializing");
      }
    }
    if (l.Has("label")) landmark.label = ShortText(l.At("label"), 256);
    landmark.position_in_world = Position(l.At("position_in_world"));
    if (l.Has("covariance")) landmark.covariance = Covariance(l.At("covariance"));
    if (l.Has("points")) {
      const JsonField points = l.At("points");
      const std::size_t count = points.ArraySize();
      if (count > kMaxLandmarkPoints) {
        points.Fail("more than " + std::to_string(kMaxLandmarkPoints) + " points");
      }
      for (std::size_t k = 0; k < count; ++k) {
        const JsonField p = points.At(k);
        OnlyKeys(p, {"role", "position_in_world", "covariance"});
        slam::LandmarkPoint point;
        point.role = ShortText(p.At("role"), 64);
        point.position_in_world = Position(p.At("position_in_world"));
        if (p.Has("covariance")) point.covariance = Covariance(p.At("covariance"));
        landmark.points.push_back(std::move(point));
      }
    }
    out.push_back(std::move(landmark));
  }
  return out;
}

std::vector<slam::LandmarkEstimate> ReadLandmarkMap(const std::string& file) {
  return ParseLandmarkMap(ReadRegularFile(file, kMaxLandmarkFileBytes), file);
}

}  // namespace corridorsim::evaluate
