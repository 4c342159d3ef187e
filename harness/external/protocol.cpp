#include "harness/external/protocol.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "common/io/camera_json.h"
#include "common/io/json_input.h"
#include "common/io/stable_json.h"
#include "common/io/yaml_reader.h"
#include "harness/external/reply_keys.h"

namespace corridorsim::external {
namespace {

[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw ProtocolError(where + ": " + what);
}

// A JSON value's text for a message: short and printable.
std::string Excerpt(const nlohmann::json& value) { return InputExcerpt(JsonText(value), 80); }

const nlohmann::json* Find(const nlohmann::json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() || it->is_null() ? nullptr : &*it;
}

double Number(const nlohmann::json& value, const std::string& where) {
  if (!value.is_number()) Fail(where, "expected a number, got " + Excerpt(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) Fail(where, "a non-finite number (" + Excerpt(value) + ")");
  return v;
}

std::int64_t Integer(const nlohmann::json& value, const std::string& where, std::int64_t lo,
                     std::int64_t hi) {
  if (!value.is_number_integer()) Fail(where, "expected an integer, got " + Excerpt(value));
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() >
          static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    Fail(where, "out of range (" + Excerpt(value) + ")");
  }
  const std::int64_t v = value.get<std::int64_t>();
  if (v < lo || v > hi) {
    Fail(where, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                    std::to_string(v) + ")");
  }
  return v;
}

bool Boolean(const nlohmann::json& value, const std::string& where) {
  if (!value.is_boolean()) Fail(where, "expected true or false, got " + Excerpt(value));
  return value.get<bool>();
}

std::string String(const nlohmann::json& value, const std::string& where, std::size_t max_bytes) {
  if (!value.is_string()) Fail(where, "expected a string, got " + Excerpt(value));
  const std::string& s = value.get_ref<const std::string&>();
  if (s.size() > max_bytes) Fail(where, "longer than " + std::to_string(max_bytes) + " bytes");
  return s;
}

// One of two names (a string of at most 32 bytes) as its value: "expected <a> or <b>" else.
template <class E>
E OneOf(const nlohmann::json& value, const std::string& where, std::pair<const char*, E> a,
        std::pair<const char*, E> b) {
  const std::string name = String(value, where, 32);
  if (name == a.first) return a.second;
  if (name == b.first) return b.second;
  Fail(where, std::string("expected ") + a.first + " or " + b.first);
}

const nlohmann::json& Array(const nlohmann::json& value, const std::string& where,
                            std::size_t max_items) {
  if (!value.is_array()) Fail(where, "expected an array, got " + Excerpt(value));
  if (value.size() > max_items) {
    Fail(where, "more than " + std::to_string(max_items) + " items (" +
                    std::to_string(value.size()) + ")");
  }
  return value;
}

// The items of the array `object[key]`, when it is there (at most `max_items`): calls
// `parse(item, "<where>[i]")` for each.
template <class F>
void ForEachItem(const nlohmann::json& object, const char* key, const std::string& where,
                 std::size_t max_items, F parse) {
  if (const nlohmann::json* list = Find(object, key)) {
    Array(*list, where, max_items);
    for (std::size_t i = 0; i < list->size(); ++i) {
      parse((*list)[i], where + "[" + std::to_string(i) + "]");
    }
  }
}

template <int N>
Eigen::Matrix<double, N, 1> Vector(const nlohmann::json& value, const std::string& where) {
  if (!value.is_array() || value.size() != N) {
    Fail(where, "expected " + std::to_string(N) + " numbers, got " + Excerpt(value));
  }
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = Number(value[i], where + "[" + std::to_string(i) + "]");
  return v;
}

Eigen::Matrix3d Matrix3(const nlohmann::json& value, const std::string& where) {
  const Eigen::Matrix<double, 9, 1> v = Vector<9>(value, where);
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = v[3 * r + c];
  }
  return m;
}

nlohmann::ordered_json MatrixJson(const Eigen::Matrix3d& m) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.push_back(m(r, c));
  }
  return out;
}

// Checks that `object` has only keys of `known` (a typo in a reply is a bug to report, not a
// field to drop silently): the message names the key and every valid key.
void OnlyKeys(const nlohmann::json& object, const std::string& where,
              std::initializer_list<const char*> known) {
  if (!object.is_object()) Fail(where, "expected an object, got " + Excerpt(object));
  const std::vector<std::string> keys(known.begin(), known.end());
  for (const auto& [key, value] : object.items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw ProtocolError(UnknownKeyText(where, key, keys));
    }
  }
}

// Parses a reply with `parse` and checks its top-level keys against `keys`. Without `problems`
// any unknown key throws. With it, what `parse` read is kept and the unknown keys go into
// `problems` (reply_keys.h); a ProtocolError of `parse` still throws, naming the unknown keys
// too (a misspelt required key is then why it is missing).
template <class F>
void ParseReplyKeys(const nlohmann::json& reply, const std::string& where, const ReplyKeys& keys,
                    ReplyProblems* problems, F&& parse) {
  ReplyProblems unknown = UnknownKeys(reply, where, keys);
  std::vector<std::string> all = unknown.errors;
  all.insert(all.end(), unknown.warnings.begin(), unknown.warnings.end());
  try {
    parse();
  } catch (const ProtocolError& e) {
    if (all.empty()) throw;
    throw ProtocolError(std::string(e.what()) + "; " + JoinProblems(all));
  }
  if (!problems) {
    if (!all.empty()) throw ProtocolError(JoinProblems(all));
    return;
  }
  problems->errors.insert(problems->errors.end(), unknown.errors.begin(), unknown.errors.end());
  problems->warnings.insert(problems->warnings.end(), unknown.warnings.begin(),
                            unknown.warnings.end());
}

slam::LandmarkType LandmarkTypeFrom(const nlohmann::json& value, const std::string& where) {
  const std::string name = String(value, where, 64);
  for (const slam::LandmarkType t :
       {slam::LandmarkType::kDoorPlate, slam::LandmarkType::kCorner, slam::LandmarkType::kLamp,
        slam::LandmarkType::kDoor, slam::LandmarkType::kVanishingPoint}) {
    if (slam::LandmarkTypeName(t) == name) return t;
  }
  Fail(where, "unknown landmark type '" + InputExcerpt(name, 64) +
                  "' (door_plate, corner, lamp, door, vanishing_point)");
}

slam::Detection ParseDetection(const nlohmann::json& d, const std::string& where, TimeNs stamp_ns,
                               const std::vector<std::string>& cameras) {
  OnlyKeys(d, where,
           {"camera", "type", "pixel", "radius_px", "box_px", "plate_box", "label", "open",
            "column_bearings_rad", "score", "recognition_score", "landmark_id", "new_landmark"});
  slam::Detection out;
  out.stamp_ns = stamp_ns;
  const nlohmann::json* camera = Find(d, "camera");
  if (!camera) Fail(where, "has no camera");
  out.camera_id = String(*camera, where + ".camera", 64);
  bool known = false;
  for (const std::string& c : cameras) known = known || c == out.camera_id;
  if (!known) {
    Fail(where + ".camera",
         "'" + InputExcerpt(out.camera_id, 64) + "' is not a camera of this message");
  }
  const nlohmann::json* type = Find(d, "type");
  if (!type) Fail(where, "has no type");
  out.type = LandmarkTypeFrom(*type, where + ".type");
  if (const nlohmann::json* v = Find(d, "pixel")) out.pixel = Vector<2>(*v, where + ".pixel");
  if (const nlohmann::json* v = Find(d, "radius_px"))
    out.radius_px = Number(*v, where + ".radius_px");
  if (const nlohmann::json* v = Find(d, "box_px")) out.box_px = Vector<4>(*v, where + ".box_px");
  if (const nlohmann::json* v = Find(d, "plate_box")) {
    out.plate_box = OneOf<slam::PlateBox>(*v, where + ".plate_box",
                                          {"number_region", slam::PlateBox::kNumberRegion},
                                          {"outline", slam::PlateBox::kOutline});
  }
  if (const nlohmann::json* v = Find(d, "label")) out.label = String(*v, where + ".label", 256);
  if (const nlohmann::json* v = Find(d, "open")) out.open = Boolean(*v, where + ".open");
  if (const nlohmann::json* v = Find(d, "column_bearings_rad")) {
    out.column_bearings_rad = Vector<2>(*v, where + ".column_bearings_rad");
  }
  if (const nlohmann::json* v = Find(d, "score")) out.score = Number(*v, where + ".score");
  if (const nlohmann::json* v = Find(d, "recognition_score")) {
    out.recognition_score = Number(*v, where + ".recognition_score");
  }
  if (const nlohmann::json* v = Find(d, "landmark_id")) {
    out.landmark_id =
        static_cast<int>(Integer(*v, where + ".landmark_id", -1, std::numeric_limits<int>::max()));
  }
  if (const nlohmann::json* v = Find(d, "new_landmark")) {
    out.new_landmark = Boolean(*v, where + ".new_landmark");
  }
  // The same boundary as a C++ pipeline's detections (slam::DetectionProblem).
  if (const std::optional<std::string> problem = slam::DetectionProblem(out)) {
    Fail(where, "a " + slam::LandmarkTypeName(out.type) + " detection that " + *problem);
  }
  return out;
}

void ParseDetectionList(const nlohmann::json& reply, const std::string& what, TimeNs stamp_ns,
                        const std::vector<std::string>& cameras, ReplyExtras* extras) {
  if (const nlohmann::json* list = Find(reply, "detections")) {
    const std::string where = what + ".detections";
    Array(*list, where, kMaxReplyItems);
    if (cameras.empty() && !list->empty()) {
      Fail(where, "detections come with camera sets (or finish), not with this message");
    }
    for (std::size_t i = 0; i < list->size(); ++i) {
      extras->detections.push_back(
          ParseDetection((*list)[i], where + "[" + std::to_string(i) + "]", stamp_ns, cameras));
    }
  }
}

void ParseInnovationList(const nlohmann::json& reply, const std::string& what, TimeNs stamp_ns,
                         ReplyExtras* extras) {
  ForEachItem(reply, "innovations", what + ".innovations", kMaxReplyItems,
              [&](const nlohmann::json& n, const std::string& w) {
                OnlyKeys(n, w, {"type", "nis", "dof", "accepted"});
                slam::Innovation innovation;
                innovation.stamp_ns = stamp_ns;
                if (!Find(n, "type") || !Find(n, "nis") || !Find(n, "dof")) {
                  Fail(w, "needs type, nis and dof");
                }
                innovation.type = LandmarkTypeFrom(n["type"], w + ".type");
                innovation.nis = Number(n["nis"], w + ".nis");
                if (innovation.nis < 0) Fail(w + ".nis", "must not be negative");
                innovation.dof = static_cast<int>(Integer(n["dof"], w + ".dof", 1, 64));
                if (const nlohmann::json* v = Find(n, "accepted")) {
                  innovation.accepted = Boolean(*v, w + ".accepted");
                }
                extras->innovations.push_back(innovation);
              });
}

void ParseExtras(const nlohmann::json& reply, const std::string& what, TimeNs stamp_ns,
                 const std::vector<std::string>& cameras, ReplyExtras* extras) {
  ParseDetectionList(reply, what, stamp_ns, cameras, extras);
  ParseInnovationList(reply, what, stamp_ns, extras);
}

void CheckReply(const nlohmann::json& reply, const std::string& type) {
  const std::string got = MessageType(reply);
  if (got != type) {
    throw ProtocolError("out of order: expected a '" + type + "' reply, got '" +
                        InputExcerpt(got, 40) + "'");
  }
}

void CheckStamp(const nlohmann::json& reply, const std::string& what, TimeNs expected) {
  const nlohmann::json* stamp = Find(reply, "stamp_ns");
  if (!stamp) Fail(what, "has no stamp_ns");
  const std::int64_t got =
      Integer(*stamp, what + ".stamp_ns", std::numeric_limits<std::int64_t>::min(),
              std::numeric_limits<std::int64_t>::max());
  if (got != expected) {
    throw ProtocolError("out of order: the " + what + " is for stamp_ns " + std::to_string(got) +
                        ", the message answered had " + std::to_string(expected));
  }
}

const ReplyKeys& ReadyKeys() {
  static const ReplyKeys keys{{"type", "name", "version"}, {"name", "version"}};
  return keys;
}

const ReplyKeys& EstimateKeys() {
  static const ReplyKeys keys{
      {"type", "stamp_ns", "pose", "covariance", "detections", "innovations"}, {}};
  return keys;
}

const ReplyKeys& ProcessedKeys() {
  static const ReplyKeys keys{{"type", "stamp_ns", "detections", "innovations"}, {}};
  return keys;
}

const ReplyKeys& FinishedKeys() {
  static const ReplyKeys keys{
      {"type", "landmarks", "detections", "innovations", "maps", "health", "stage_seconds"},
      {"stage_seconds"}};
  return keys;
}

void ParseLandmarks(const nlohmann::json& reply, Finished* finished) {
  Finished& out = *finished;
  ForEachItem(
      reply, "landmarks", "finished.landmarks", kMaxReplyItems,
      [&](const nlohmann::json& l, const std::string& w) {
        OnlyKeys(l, w, {"id", "type", "status", "position", "covariance", "points", "label"});
        if (!Find(l, "id") || !Find(l, "type") || !Find(l, "position")) {
          Fail(w, "needs id, type and position");
        }
        slam::LandmarkEstimate landmark;
        landmark.id =
            static_cast<int>(Integer(l["id"], w + ".id", 0, std::numeric_limits<int>::max()));
        landmark.type = LandmarkTypeFrom(l["type"], w + ".type");
        if (const nlohmann::json* v = Find(l, "status")) {
          landmark.status = OneOf<slam::LandmarkStatus>(
              *v, w + ".status", {"converged", slam::LandmarkStatus::kConverged},
              {"initializing", slam::LandmarkStatus::kInitializing});
        }
        landmark.position_in_world = Vector<3>(l["position"], w + ".position");
        if (const nlohmann::json* v = Find(l, "covariance")) {
          landmark.covariance = Matrix3(*v, w + ".covariance");
        }
        if (const nlohmann::json* v = Find(l, "label"))
          landmark.label = String(*v, w + ".label", 256);
        ForEachItem(l, "points", w + ".points", kMaxLandmarkPoints,
                    [&](const nlohmann::json& p, const std::string& pw) {
                      OnlyKeys(p, pw, {"role", "position", "covariance"});
                      if (!Find(p, "role") || !Find(p, "position"))
                        Fail(pw, "needs role and position");
                      slam::LandmarkPoint point;
                      point.role = String(p["role"], pw + ".role", 64);
                      point.position_in_world = Vector<3>(p["position"], pw + ".position");
                      if (const nlohmann::json* v = Find(p, "covariance")) {
                        point.covariance = Matrix3(*v, pw + ".covariance");
                      }
                      landmark.points.push_back(std::move(point));
                    });
        out.landmarks.push_back(std::move(landmark));
      });
}

void ParseMaps(const nlohmann::json& reply, std::string_view blob, Finished* finished) {
  Finished& out = *finished;
  ForEachItem(reply, "maps", "finished.maps", kMaxMapFiles,
              [&](const nlohmann::json& m, const std::string& w) {
                OnlyKeys(m, w, {"suffix", "offset", "bytes"});
                if (!Find(m, "suffix") || !Find(m, "offset") || !Find(m, "bytes")) {
                  Fail(w, "needs suffix, offset and bytes");
                }
                slam::MapFile map;
                map.suffix = String(m["suffix"], w + ".suffix", 64);
                // A suffix names a file beside the pipeline's own: no folder, nothing hidden.
                if (map.suffix.empty() || map.suffix.find('/') != std::string::npos ||
                    map.suffix.find('\0') != std::string::npos || map.suffix == "." ||
                    map.suffix == ".." || map.suffix.find("..") != std::string::npos) {
                  Fail(w + ".suffix", "must be a file name suffix without '/' or '..' (got '" +
                                          InputExcerpt(map.suffix, 64) + "')");
                }
                for (const char c : map.suffix) {
                  if (static_cast<unsigned char>(c) < 0x20)
                    Fail(w + ".suffix", "has a control character");
                }
                const auto offset = static_cast<std::size_t>(
                    Integer(m["offset"], w + ".offset", 0, static_cast<std::int64_t>(blob.size())));
                const auto bytes = static_cast<std::size_t>(Integer(
                    m["bytes"], w + ".bytes", 0, static_cast<std::int64_t>(blob.size() - offset)));
                map.bytes.assign(blob.substr(offset, bytes));
                for (const slam::MapFile& other : out.maps) {
                  if (other.suffix == map.suffix) Fail(w + ".suffix", "'" + map.suffix + "' twice");
                }
                out.maps.push_back(std::move(map));
              });
}

void ParseHealth(const nlohmann::json& reply, Finished* finished) {
  Finished& out = *finished;
  if (const nlohmann::json* h = Find(reply, "health")) {
    OnlyKeys(
        *h, "finished.health",
        {"non_positive_covariance", "rejected_updates", "rejected_odometry", "rejected_frames"});
    const auto count = [&](const char* key, int* field) {
      if (const nlohmann::json* v = Find(*h, key)) {
        *field = static_cast<int>(
            Integer(*v, std::string("finished.health.") + key, 0, std::numeric_limits<int>::max()));
      }
    };
    count("non_positive_covariance", &out.health.non_positive_covariance);
    count("rejected_updates", &out.health.rejected_updates);
    count("rejected_odometry", &out.health.rejected_odometry);
    count("rejected_frames", &out.health.rejected_frames);
  }
}

void ParseStageSeconds(const nlohmann::json& reply, Finished* finished) {
  Finished& out = *finished;
  if (const nlohmann::json* stages = Find(reply, "stage_seconds")) {
    if (!stages->is_object()) Fail("finished.stage_seconds", "expected an object");
    if (stages->size() > kMaxStages) {
      Fail("finished.stage_seconds", "more than " + std::to_string(kMaxStages) + " stages");
    }
    for (const auto& [name, seconds] : stages->items()) {
      const std::string w = "finished.stage_seconds." + InputExcerpt(name, 64);
      if (name.empty() || name.size() > 64) Fail(w, "a stage name is 1 to 64 bytes");
      const double s = Number(seconds, w);
      if (s < 0) Fail(w, "must not be negative");
      out.stage_seconds[name] = s;
    }
  }
}

}  // namespace

std::string EncodeHeader(std::size_t json_bytes, std::size_t blob_bytes) {
  std::string header(kHeaderBytes, '\0');
  std::memcpy(header.data(), kMagic, 4);
  const auto put = [&header](std::size_t at, std::size_t v) {
    for (int i = 0; i < 4; ++i) header[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
  };
  put(4, json_bytes);
  put(8, blob_bytes);
  return header;
}

Header DecodeHeader(const char (&bytes)[kHeaderBytes]) {
  if (std::memcmp(bytes, kMagic, 4) != 0) {
    throw ProtocolError("malformed message: it does not start with \"CSIM\" (got " +
                        InputExcerpt(std::string(bytes, 4), 20) + ")");
  }
  const auto get = [&bytes](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    }
    return v;
  };
  Header h{get(4), get(8)};
  if (h.json_bytes == 0 || h.json_bytes > kMaxJsonBytes) {
    throw ProtocolError("oversized message: its JSON length " + std::to_string(h.json_bytes) +
                        " is not in [1, " + std::to_string(kMaxJsonBytes) + "]");
  }
  if (h.blob_bytes > kMaxBlobBytes) {
    throw ProtocolError("oversized message: its blob length " + std::to_string(h.blob_bytes) +
                        " is over " + std::to_string(kMaxBlobBytes));
  }
  return h;
}

nlohmann::json ParseMessage(std::string_view json) {
  // Nesting and the count of values are bounded before the (recursive) parser sees the text,
  // as for every JSON a user hands in (common/io/json_input.h).
  try {
    CheckJsonInputBounds(json, "message", kMaxJsonValues);
  } catch (const InputError& e) {
    throw ProtocolError(std::string("malformed message: ") + e.what());
  }
  nlohmann::json message;
  try {
    message = nlohmann::json::parse(json.begin(), json.end());
  } catch (const nlohmann::json::exception& e) {
    std::string why = e.what();
    if (why.find("number overflow") != std::string::npos) {
      why += " (a non-finite number)";
    } else if (json.find("NaN") != std::string_view::npos ||
               json.find("Infinity") != std::string_view::npos) {
      why += " (NaN and Infinity are not JSON: a non-finite number?)";
    }
    throw ProtocolError("malformed message: " + InputExcerpt(why, 300));
  }
  if (!message.is_object()) throw ProtocolError("malformed message: not a JSON object");
  const nlohmann::json* type = Find(message, "type");
  if (!type || !type->is_string()) {
    throw ProtocolError("malformed message: no \"type\" string");
  }
  return message;
}

std::string MessageType(const nlohmann::json& message) {
  return message.at("type").get<std::string>();
}

std::string MessageType(const nlohmann::ordered_json& message) {
  return message.at("type").get<std::string>();
}

nlohmann::ordered_json CalibrationJson(const slam::Calibration& calibration) {
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (const slam::CameraCalibration& c : calibration.cameras) {
    nlohmann::ordered_json camera;
    camera["id"] = c.id;
    camera["model"] = CameraModelToJson(c.model);
    const Eigen::Vector3d t = c.robot_from_camera.translation();
    camera["robot_from_camera"] = {{"translation", {t.x(), t.y(), t.z()}},
                                   {"rotation", MatrixJson(c.robot_from_camera.rotation())}};
    if (c.depth) {
      camera["depth"] = {
          {"min_m", c.depth->min_m}, {"max_m", c.depth->max_m}, {"encoding", "depth_f32"}};
    } else {
      camera["depth"] = nullptr;
    }
    cameras.push_back(std::move(camera));
  }
  return {{"wheelbase_m", calibration.wheelbase_m},
          {"wheel_diameter_m", calibration.wheel_diameter_m},
          {"ticks_per_revolution", calibration.ticks_per_revolution},
          {"cameras", std::move(cameras)}};
}

nlohmann::ordered_json StartMessage(const std::string& pipeline,
                                    const slam::Calibration& calibration,
                                    const std::vector<std::string>& cameras, TimeNs stamp_ns,
                                    const SE2& world_from_robot,
                                    const nlohmann::ordered_json& options, std::uint64_t seed,
                                    std::size_t shared_memory_bytes) {
  return {{"type", "start"},
          {"protocol", kProtocolVersion},
          {"pipeline", pipeline},
          {"seed", seed},
          {"stamp_ns", stamp_ns},
          {"pose", {world_from_robot.x(), world_from_robot.y(), world_from_robot.yaw()}},
          {"calibration", CalibrationJson(calibration)},
          {"cameras", cameras},
          {"options", options},
          {"shared_memory_bytes", shared_memory_bytes}};
}

nlohmann::ordered_json OdometryMessage(const WheelOdometry& o) {
  return {{"type", "odometry"},
          {"stamp_ns", o.stamp_ns},
          {"interval_ns", o.interval_ns},
          {"left_m", o.left_distance_m},
          {"right_m", o.right_distance_m},
          {"left_ticks", o.left_ticks},
          {"right_ticks", o.right_ticks}};
}

nlohmann::ordered_json CamerasMessage(TimeNs stamp_ns, const std::vector<CameraSlice>& cameras,
                                      const std::string& transport) {
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  const auto image = [](const ImageSlice& s) {
    return nlohmann::ordered_json{{"encoding", s.encoding},
                                  {"width", s.width},
                                  {"height", s.height},
                                  {"offset", s.offset},
                                  {"bytes", s.bytes}};
  };
  for (const CameraSlice& c : cameras) {
    nlohmann::ordered_json f = {{"camera", c.camera}, {"dropped", c.dropped}};
    if (!c.dropped) {
      f["stamp_ns"] = c.stamp_ns;
      f["rgb"] = c.rgb ? image(*c.rgb) : nlohmann::ordered_json(nullptr);
      f["depth"] = c.depth ? image(*c.depth) : nlohmann::ordered_json(nullptr);
    }
    frames.push_back(std::move(f));
  }
  return {{"type", "cameras"},
          {"stamp_ns", stamp_ns},
          {"transport", transport},
          {"frames", std::move(frames)}};
}

nlohmann::ordered_json FinishMessage(TimeNs stamp_ns) {
  return {{"type", "finish"}, {"stamp_ns", stamp_ns}};
}

Ready ParseReady(const nlohmann::json& reply, ReplyProblems* problems) {
  CheckReply(reply, "ready");
  Ready ready;
  ParseReplyKeys(reply, "ready reply", ReadyKeys(), problems, [&] {
    if (const nlohmann::json* v = Find(reply, "name")) ready.name = String(*v, "ready.name", 200);
    if (const nlohmann::json* v = Find(reply, "version")) {
      ready.version = String(*v, "ready.version", 200);
    }
  });
  return ready;
}

slam::PoseEstimate ParseEstimate(const nlohmann::json& reply, TimeNs expected_stamp_ns,
                                 ReplyExtras* extras, ReplyProblems* problems) {
  CheckReply(reply, "estimate");
  slam::PoseEstimate estimate;
  ParseReplyKeys(reply, "estimate reply", EstimateKeys(), problems, [&] {
    CheckStamp(reply, "estimate", expected_stamp_ns);
    const nlohmann::json* pose = Find(reply, "pose");
    const nlohmann::json* covariance = Find(reply, "covariance");
    if (!pose || !covariance) Fail("estimate reply", "needs pose and covariance");
    const Eigen::Vector3d x = Vector<3>(*pose, "estimate.pose");
    estimate.stamp_ns = expected_stamp_ns;
    estimate.world_from_robot = SE2(x.x(), x.y(), x.z());
    estimate.covariance = Matrix3(*covariance, "estimate.covariance");
    ParseExtras(reply, "estimate", expected_stamp_ns, {}, extras);
  });
  return estimate;
}

void ParseProcessed(const nlohmann::json& reply, TimeNs expected_stamp_ns,
                    const std::vector<std::string>& cameras, ReplyExtras* extras,
                    ReplyProblems* problems) {
  CheckReply(reply, "processed");
  ParseReplyKeys(reply, "processed reply", ProcessedKeys(), problems, [&] {
    CheckStamp(reply, "processed reply", expected_stamp_ns);
    ParseExtras(reply, "processed", expected_stamp_ns, cameras, extras);
  });
}

Finished ParseFinished(const nlohmann::json& reply, std::string_view blob, TimeNs stamp_ns,
                       const std::vector<std::string>& cameras, ReplyProblems* problems) {
  CheckReply(reply, "finished");
  Finished out;
  // Each part on its own: with `problems`, a bad part costs only itself (what the other parts
  // and the items before the bad one hold is kept) and is reported as an error.
  const auto part = [&](auto&& parse) {
    try {
      parse();
    } catch (const ProtocolError& e) {
      if (!problems) throw;
      problems->errors.push_back(e.what());
    }
  };
  ParseReplyKeys(reply, "finished reply", FinishedKeys(), problems, [] {});
  part([&] { ParseDetectionList(reply, "finished", stamp_ns, cameras, &out.extras); });
  part([&] { ParseInnovationList(reply, "finished", stamp_ns, &out.extras); });
  part([&] { ParseLandmarks(reply, &out); });
  part([&] { ParseMaps(reply, blob, &out); });
  part([&] { ParseHealth(reply, &out); });
  part([&] { ParseStageSeconds(reply, &out); });
  return out;
}

}  // namespace corridorsim::external
