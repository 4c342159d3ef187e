// The reply readers of the lockstep protocol (protocol.h, "What corridorsim reads back";
// docs/protocol.md): each checks a program's reply and names what is wrong with it.
#include <algorithm>
#include <limits>
#include <utility>

#include "common/io/yaml_reader.h"
#include "harness/external/protocol.h"
#include "harness/external/reply_keys.h"
#include "harness/external/reply_values.h"

namespace corridorsim::external {
namespace {

using namespace reply_values;

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

using Declared = std::vector<slam::MeasurementType>;

// "scan_match (3 dof), wall_line (2 dof)", or "none".
std::string DeclaredNames(const Declared& declared) {
  std::string names;
  for (const slam::MeasurementType& t : declared) {
    names += (names.empty() ? "" : ", ") + t.name + " (" + std::to_string(t.dof) + " dof)";
  }
  return names.empty() ? "none" : names;
}

// The type of an innovation or a detection: a shipped landmark type, or one of `declared` (then
// its declaration; `*type` is left as it is).
const slam::MeasurementType* MeasurementTypeFrom(const nlohmann::json& value,
                                                 const std::string& where, const Declared& declared,
                                                 slam::LandmarkType* type) {
  const std::string name = String(value, where, 64);
  for (const slam::MeasurementType& t : declared) {
    if (t.name == name) return &t;
  }
  for (const slam::LandmarkType t :
       {slam::LandmarkType::kDoorPlate, slam::LandmarkType::kCorner, slam::LandmarkType::kLamp,
        slam::LandmarkType::kDoor, slam::LandmarkType::kVanishingPoint}) {
    if (slam::LandmarkTypeName(t) == name) {
      *type = t;
      return nullptr;
    }
  }
  Fail(where, "unknown type '" + InputExcerpt(name, 64) +
                  "': neither a shipped landmark type (door_plate, corner, lamp, door, "
                  "vanishing_point) nor one the program declared in its ready reply (" +
                  DeclaredNames(declared) + ")");
}

slam::Detection ParseDetection(const nlohmann::json& d, const std::string& where, TimeNs stamp_ns,
                               const std::vector<std::string>& cameras, const Declared& declared) {
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
  if (const slam::MeasurementType* own =
          MeasurementTypeFrom(*type, where + ".type", declared, &out.type)) {
    out.measurement = own->name;
  }
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
    Fail(where, "a " + slam::MeasurementName(out) + " detection that " + *problem);
  }
  return out;
}

void ParseDetectionList(const nlohmann::json& reply, const std::string& what, TimeNs stamp_ns,
                        const std::vector<std::string>& cameras, const Declared& declared,
                        ReplyExtras* extras) {
  if (const nlohmann::json* list = Find(reply, "detections")) {
    const std::string where = what + ".detections";
    Array(*list, where, kMaxReplyItems);
    if (cameras.empty() && !list->empty()) {
      Fail(where, "detections come with camera sets (or finish), not with this message");
    }
    for (std::size_t i = 0; i < list->size(); ++i) {
      extras->detections.push_back(ParseDetection((*list)[i], where + "[" + std::to_string(i) + "]",
                                                  stamp_ns, cameras, declared));
    }
  }
}

void ParseInnovationList(const nlohmann::json& reply, const std::string& what, TimeNs stamp_ns,
                         const Declared& declared, ReplyExtras* extras) {
  ForEachItem(reply, "innovations", what + ".innovations", kMaxReplyItems,
              [&](const nlohmann::json& n, const std::string& w) {
                OnlyKeys(n, w, {"type", "nis", "dof", "accepted"});
                slam::Innovation innovation;
                innovation.stamp_ns = stamp_ns;
                if (!Find(n, "type") || !Find(n, "nis") || !Find(n, "dof")) {
                  Fail(w, "needs type, nis and dof");
                }
                const slam::MeasurementType* own =
                    MeasurementTypeFrom(n["type"], w + ".type", declared, &innovation.type);
                innovation.nis = Number(n["nis"], w + ".nis");
                if (innovation.nis < 0) Fail(w + ".nis", "must not be negative");
                innovation.dof = static_cast<int>(Integer(n["dof"], w + ".dof", 1, 64));
                if (own) {
                  innovation.measurement = own->name;
                  if (innovation.dof != own->dof) {
                    Fail(w + ".dof", std::to_string(innovation.dof) + " for the type '" +
                                         own->name + "', declared with " +
                                         std::to_string(own->dof));
                  }
                }
                if (const nlohmann::json* v = Find(n, "accepted")) {
                  innovation.accepted = Boolean(*v, w + ".accepted");
                }
                extras->innovations.push_back(innovation);
              });
}

void ParseExtras(const nlohmann::json& reply, const std::string& what, TimeNs stamp_ns,
                 const std::vector<std::string>& cameras, const Declared& declared,
                 ReplyExtras* extras) {
  ParseDetectionList(reply, what, stamp_ns, cameras, declared, extras);
  ParseInnovationList(reply, what, stamp_ns, declared, extras);
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

// The keys of a version-1 ready reply, and those version 2 adds.
const ReplyKeys& ReadyKeys(int protocol) {
  static const ReplyKeys v1{{"type", "protocol", "name", "version"}, {"name", "version"}};
  static const ReplyKeys v2{
      {"type", "protocol", "name", "version", "imus", "lasers", "measurement_types"},
      {"name", "version"}};
  return protocol >= 2 ? v2 : v1;
}

// The sensors of one kind a version-2 ready reply asks for: ids of `offered`, each once.
std::vector<std::string> ParseSensorList(const nlohmann::json& reply, const char* key,
                                         const std::vector<std::string>& offered) {
  std::vector<std::string> ids;
  ForEachItem(reply, key, std::string("ready.") + key, 64,
              [&](const nlohmann::json& item, const std::string& w) {
                std::string id = String(item, w, 64);
                if (std::find(offered.begin(), offered.end(), id) == offered.end()) {
                  std::string list;
                  for (const std::string& o : offered) list += (list.empty() ? "" : ", ") + o;
                  Fail(w, "'" + InputExcerpt(id, 64) + "' is not one of the robot's (" +
                              (list.empty() ? std::string("none") : list) + ")");
                }
                if (std::find(ids.begin(), ids.end(), id) != ids.end()) {
                  Fail(w, "'" + id + "' twice");
                }
                ids.push_back(std::move(id));
              });
  return ids;
}

// A version-2 ready reply's measurement types of the program's own.
std::vector<slam::MeasurementType> ParseMeasurementTypes(const nlohmann::json& reply) {
  std::vector<slam::MeasurementType> types;
  ForEachItem(
      reply, "measurement_types", "ready.measurement_types",
      static_cast<std::size_t>(slam::kMaxMeasurementTypes),
      [&](const nlohmann::json& item, const std::string& w) {
        OnlyKeys(item, w, {"name", "dof"});
        if (!Find(item, "name") || !Find(item, "dof")) Fail(w, "needs name and dof");
        slam::MeasurementType t;
        t.name = String(item["name"], w + ".name", 64);
        t.dof = static_cast<int>(Integer(item["dof"], w + ".dof", std::numeric_limits<int>::min(),
                                         std::numeric_limits<int>::max()));
        types.push_back(std::move(t));
      });
  // The same boundary as a C++ pipeline's declaration (harness/run/pipeline_runner.cpp).
  if (const std::optional<std::string> problem = slam::MeasurementTypesProblem(types)) {
    Fail("ready.measurement_types", "the program " + *problem);
  }
  return types;
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

Ready ParseReady(const nlohmann::json& reply, ReplyProblems* problems,
                 const OfferedSensors& offered) {
  CheckReply(reply, "ready");
  Ready ready;
  // The version it speaks first: it decides the valid keys.
  if (const nlohmann::json* v = Find(reply, "protocol")) {
    ready.protocol =
        static_cast<int>(Integer(*v, "ready.protocol", kProtocolVersion, kProtocolMaxVersion));
  }
  if (ready.protocol < 2) {
    for (const char* key : {"imus", "lasers", "measurement_types"}) {
      if (reply.contains(key)) {
        Fail("ready reply", std::string("'") + key +
                                "' is a key of protocol version 2: the reply needs "
                                "\"protocol\": 2 (the start message's protocol_max)");
      }
    }
  }
  ParseReplyKeys(reply, "ready reply", ReadyKeys(ready.protocol), problems, [&] {
    if (const nlohmann::json* v = Find(reply, "name")) ready.name = String(*v, "ready.name", 200);
    if (const nlohmann::json* v = Find(reply, "version")) {
      ready.version = String(*v, "ready.version", 200);
    }
    if (ready.protocol >= 2) {
      ready.imus = ParseSensorList(reply, "imus", offered.imus);
      ready.lasers = ParseSensorList(reply, "lasers", offered.lasers);
      ready.measurement_types = ParseMeasurementTypes(reply);
    }
  });
  return ready;
}

slam::PoseEstimate ParseEstimate(const nlohmann::json& reply, TimeNs expected_stamp_ns,
                                 ReplyExtras* extras, ReplyProblems* problems,
                                 const Declared& declared) {
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
    ParseExtras(reply, "estimate", expected_stamp_ns, {}, declared, extras);
  });
  return estimate;
}

void ParseProcessed(const nlohmann::json& reply, TimeNs expected_stamp_ns,
                    const std::vector<std::string>& cameras, ReplyExtras* extras,
                    ReplyProblems* problems, const Declared& declared) {
  CheckReply(reply, "processed");
  ParseReplyKeys(reply, "processed reply", ProcessedKeys(), problems, [&] {
    CheckStamp(reply, "processed reply", expected_stamp_ns);
    ParseExtras(reply, "processed", expected_stamp_ns, cameras, declared, extras);
  });
}

Finished ParseFinished(const nlohmann::json& reply, std::string_view blob, TimeNs stamp_ns,
                       const std::vector<std::string>& cameras, ReplyProblems* problems,
                       const Declared& declared) {
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
  part([&] { ParseDetectionList(reply, "finished", stamp_ns, cameras, declared, &out.extras); });
  part([&] { ParseInnovationList(reply, "finished", stamp_ns, declared, &out.extras); });
  part([&] { ParseLandmarks(reply, &out); });
  part([&] { ParseMaps(reply, blob, &out); });
  part([&] { ParseHealth(reply, &out); });
  part([&] { ParseStageSeconds(reply, &out); });
  return out;
}

}  // namespace corridorsim::external
