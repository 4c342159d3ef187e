#include "common/io/camera_json.h"

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"

namespace corridorsim {
namespace {

constexpr std::array<const char*, 8> kKeys = {"model", "width", "height", "fx",
                                              "fy",    "cx",    "cy",     "distortion"};
// Keys of an intrinsics.json entry beside the model's (harness/run/frame_io.h): not the model's.
constexpr const char* kMountKey = "robot_from_camera";
constexpr const char* kDepthScaleKey = "depth_scale";

[[noreturn]] void Fail(const std::string& key, const std::string& message) {
  throw OptionsError(OptionsProblem{key, message});
}

template <class Json>
const Json& Member(const Json& json, const char* key) {
  const auto it = json.find(key);
  if (it == json.end()) Fail(key, "missing");
  return *it;
}

template <class Json>
int ReadPixels(const Json& json, const char* key) {
  const Json& value = Member(json, key);
  if (!value.is_number_integer()) Fail(key, "must be an integer number of pixels");
  const auto pixels = value.template get<std::int64_t>();
  if (pixels < 0 || pixels > std::numeric_limits<int>::max()) {
    Fail(key, "must lie in [0, " + std::to_string(std::numeric_limits<int>::max()) + "]");
  }
  return static_cast<int>(pixels);
}

template <class Json>
double ReadNumber(const Json& json, const char* key) {
  const Json& value = Member(json, key);
  if (!value.is_number()) Fail(key, "must be a number");
  return value.template get<double>();
}

template <class Json>
std::vector<double> ReadDistortion(const Json& json, std::size_t size, const char* form) {
  const Json& value = Member(json, "distortion");
  if (!value.is_array() || value.size() != size) {
    Fail("distortion",
         std::string("must be an array of ") + std::to_string(size) + " numbers " + form);
  }
  std::vector<double> coefficients;
  for (const Json& c : value) {
    if (!c.is_number()) Fail("distortion", "must hold numbers only");
    coefficients.push_back(c.template get<double>());
  }
  return coefficients;
}

template <class Json>
CameraModel FromJson(const Json& json) {
  if (!json.is_object()) Fail("camera", "a camera model must be a JSON object");
  for (auto it = json.begin(); it != json.end(); ++it) {
    bool known = it.key() == kMountKey || it.key() == kDepthScaleKey;
    for (const char* key : kKeys) known = known || it.key() == key;
    if (!known) {
      Fail(it.key(),
           "unknown key (expected model, width, height, fx, fy, cx, cy, distortion, and in an "
           "intrinsics.json entry robot_from_camera, depth_scale)");
    }
  }
  if (const auto mount = json.find(kMountKey); mount != json.end() && !mount->is_object()) {
    Fail(kMountKey, "must be a pose object {t, q}");
  }
  if (const auto scale = json.find(kDepthScaleKey); scale != json.end()) {
    if (!scale->is_number() || !(scale->template get<double>() > 0.0)) {
      Fail(kDepthScaleKey, "must be a positive number (depth image values per metre)");
    }
  }
  const Json& name = Member(json, "model");
  const std::string pinhole_name(CameraModelKindName(CameraModelKind::kPinholeRadTan));
  const std::string fisheye_name(CameraModelKindName(CameraModelKind::kKannalaBrandt));
  if (!name.is_string() || (name != pinhole_name && name != fisheye_name)) {
    Fail("model", "must be \"" + pinhole_name + "\" or \"" + fisheye_name + "\"");
  }
  const auto fill = [&](auto& m) {
    m.width = ReadPixels(json, "width");
    m.height = ReadPixels(json, "height");
    m.fx = ReadNumber(json, "fx");
    m.fy = ReadNumber(json, "fy");
    m.cx = ReadNumber(json, "cx");
    m.cy = ReadNumber(json, "cy");
  };
  CameraModel model;
  if (name == pinhole_name) {
    PinholeRadTan m;
    fill(m);
    const std::vector<double> d = ReadDistortion(json, 5, "[k1, k2, p1, p2, k3]");
    m.k1 = d[0], m.k2 = d[1], m.p1 = d[2], m.p2 = d[3], m.k3 = d[4];
    model = m;
  } else {
    KannalaBrandt m;
    fill(m);
    const std::vector<double> d = ReadDistortion(json, 4, "[k1, k2, k3, k4]");
    m.k1 = d[0], m.k2 = d[1], m.k3 = d[2], m.k4 = d[3];
    model = m;
  }
  if (const std::optional<std::string> problem = model.Check()) Fail("model", *problem);
  return model;
}

}  // namespace

nlohmann::ordered_json CameraModelToJson(const CameraModel& model) {
  const CameraIntrinsics in = model.intrinsics();
  nlohmann::ordered_json j;
  j["model"] = in.model;
  j["width"] = in.width;
  j["height"] = in.height;
  j["fx"] = in.fx;
  j["fy"] = in.fy;
  j["cx"] = in.cx;
  j["cy"] = in.cy;
  j["distortion"] = in.distortion;
  return j;
}

CameraModel CameraModelFromJson(const nlohmann::ordered_json& json) { return FromJson(json); }

CameraModel CameraModelFromJson(const nlohmann::json& json) { return FromJson(json); }

CameraModel CameraModelFromIntrinsicsJson(const nlohmann::ordered_json& json,
                                          const std::string& camera) {
  if (!json.is_object()) Fail("camera", "a camera model must be a JSON object");
  if (json.contains("model")) return FromJson(json);  // one camera's entry
  const auto entry = json.find(camera);
  if (entry == json.end()) {
    Fail(camera, "missing: the file holds neither a camera model (`model`) nor this camera's");
  }
  if (!entry->is_object()) Fail(camera, "expected a JSON object (a camera model)");
  try {
    return FromJson(*entry);
  } catch (const OptionsError& e) {
    Fail(camera + "." + e.problem().key, e.problem().message);
  }
}

}  // namespace corridorsim
