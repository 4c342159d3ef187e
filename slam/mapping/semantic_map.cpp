#include "slam/mapping/semantic_map.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <set>
#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "common/error.h"

namespace corridorsim::slam {
namespace {

constexpr const char* kFormat = "corridorsim.semantic_map";
constexpr int kVersion = 1;

bool IsDigits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A label fit for a map: 1..kSemanticMapMaxRoomChars printable ASCII characters.
bool IsRoomLabel(const std::string& s) {
  return !s.empty() && s.size() <= kSemanticMapMaxRoomChars &&
         std::all_of(s.begin(), s.end(), [](char c) { return c > 0x20 && c < 0x7f; });
}

[[noreturn]] void Fail(const std::string& key, const std::string& message) {
  throw SemanticMapError(0, 0, key, message);
}

std::string TypeName(const nlohmann::json& value) { return value.type_name(); }

// The 1-based line and column of byte `offset` (1-based, as nlohmann counts) of `text`.
std::pair<int, int> LineColumn(const std::string& text, std::size_t offset) {
  int line = 1, column = 1;
  const std::size_t end = std::min(offset > 0 ? offset - 1 : 0, text.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

// Unknown and missing keys of one object.
void RequireKeys(const nlohmann::json& object, const std::string& key,
                 const std::vector<std::string>& required,
                 const std::vector<std::string>& optional) {
  if (!object.is_object()) Fail(key, "expected an object (got " + TypeName(object) + ")");
  for (const auto& [name, value] : object.items()) {
    (void)value;
    if (std::find(required.begin(), required.end(), name) == required.end() &&
        std::find(optional.begin(), optional.end(), name) == optional.end()) {
      std::string known;
      for (const auto& k : required) known += (known.empty() ? "" : ", ") + k;
      for (const auto& k : optional) known += ", " + k;
      Fail(key.empty() ? name : key + "." + name, "unknown key (known: " + known + ")");
    }
  }
  for (const std::string& name : required) {
    if (!object.contains(name)) Fail(key, "missing key '" + name + "'");
  }
}

double Number(const nlohmann::json& value, const std::string& key, double max_abs) {
  if (!value.is_number()) Fail(key, "expected a number (got " + TypeName(value) + ")");
  const double v = value.get<double>();
  if (!std::isfinite(v) || std::abs(v) > max_abs) {
    Fail(key,
         "must be a finite number within +-" + std::to_string(static_cast<long long>(max_abs)));
  }
  return v;
}

}  // namespace

SemanticMapError::SemanticMapError(int line, int column, std::string key, std::string message)
    : std::runtime_error((key.empty() ? std::string() : key + ": ") + message),
      line_(line),
      column_(column),
      key_(std::move(key)),
      message_(std::move(message)) {}

bool RoomNumberLess(const std::string& a, const std::string& b) {
  const auto rank = [](const std::string& s) {
    const bool digits = IsDigits(s);
    const std::size_t first = digits ? std::min(s.find_first_not_of('0'), s.size()) : 0;
    const std::string value = digits ? s.substr(first) : s;
    return std::make_tuple(!digits, digits ? value.size() : 0, value, s);
  };
  return rank(a) < rank(b);
}

std::vector<SemanticMapEntry> SemanticMapFromLandmarks(
    const std::vector<LandmarkEstimate>& landmarks) {
  std::vector<SemanticMapEntry> entries;
  for (const LandmarkEstimate& l : landmarks) {
    if (l.type != LandmarkType::kDoorPlate || !IsRoomLabel(l.label)) continue;
    SemanticMapEntry e;
    e.room = l.label;
    e.landmark_id = l.id;
    e.position_in_world = l.position_in_world;
    e.covariance = l.covariance;
    const auto same = std::find_if(entries.begin(), entries.end(),
                                   [&](const SemanticMapEntry& o) { return o.room == e.room; });
    if (same == entries.end()) {
      entries.push_back(e);
      continue;
    }
    const double variance = e.covariance(0, 0) + e.covariance(1, 1);
    const double other = same->covariance(0, 0) + same->covariance(1, 1);
    if (variance < other || (variance == other && e.landmark_id < same->landmark_id)) *same = e;
  }
  std::sort(entries.begin(), entries.end(),
            [](const SemanticMapEntry& a, const SemanticMapEntry& b) {
              return RoomNumberLess(a.room, b.room);
            });
  return entries;
}

std::string SemanticMapToJson(std::vector<SemanticMapEntry> entries) {
  std::sort(entries.begin(), entries.end(),
            [](const SemanticMapEntry& a, const SemanticMapEntry& b) {
              return RoomNumberLess(a.room, b.room);
            });
  nlohmann::ordered_json rooms = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const SemanticMapEntry& e = entries[i];
    CheckOrDie(IsRoomLabel(e.room), "slam::SemanticMapToJson", "a room number is not a label");
    CheckOrDie(i == 0 || entries[i - 1].room != e.room, "slam::SemanticMapToJson",
               "a room number appears twice");
    const int n = e.planar ? 2 : 3;
    nlohmann::ordered_json covariance = nlohmann::ordered_json::array();
    for (int r = 0; r < n; ++r) {
      nlohmann::ordered_json row = nlohmann::ordered_json::array();
      for (int c = 0; c < n; ++c) row.push_back(e.covariance(r, c));
      covariance.push_back(row);
    }
    nlohmann::ordered_json room;
    room["room"] = e.room;
    room["landmark_id"] = e.landmark_id;
    room["position_m"] = {e.position_in_world.x(), e.position_in_world.y(),
                          e.position_in_world.z()};
    room["covariance_m2"] = covariance;
    rooms.push_back(room);
  }
  nlohmann::ordered_json map;
  map["format"] = kFormat;
  map["version"] = kVersion;
  map["frame"] = "world";
  map["rooms"] = rooms;
  return map.dump(2) + "\n";
}

std::vector<SemanticMapEntry> ParseSemanticMap(const std::string& text) {
  if (text.size() > kSemanticMapMaxBytes) {
    Fail("", "longer than " + std::to_string(kSemanticMapMaxBytes) + " bytes");
  }
  // nlohmann keeps the last of duplicate keys: refuse them while parsing.
  std::vector<std::set<std::string>> keys_of_open_objects;
  const nlohmann::json::parser_callback_t no_duplicates =
      [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        if (event == Event::object_start) keys_of_open_objects.emplace_back();
        if (event == Event::object_end) keys_of_open_objects.pop_back();
        if (event == Event::key &&
            !keys_of_open_objects.back().insert(parsed.get<std::string>()).second) {
          Fail(parsed.get<std::string>(), "duplicate key");
        }
        return true;
      };
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text, no_duplicates);
  } catch (const nlohmann::json::parse_error& e) {
    const auto [line, column] = LineColumn(text, e.byte);
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..."
    const std::size_t colon = what.find(": ");
    throw SemanticMapError(
        line, column, "",
        "not JSON: " + (colon == std::string::npos ? what : what.substr(colon + 2)));
  } catch (const nlohmann::json::exception& e) {
    // "[json.exception.out_of_range.406] number overflow parsing '1e400'"
    std::string what = e.what();
    const std::size_t bracket = what.find("] ");
    Fail("", "not JSON: " + (bracket == std::string::npos ? what : what.substr(bracket + 2)));
  }
  RequireKeys(root, "", {"format", "version", "frame", "rooms"}, {});
  if (root["format"] != kFormat) Fail("format", std::string("expected \"") + kFormat + "\"");
  if (root["version"] != kVersion) Fail("version", "expected " + std::to_string(kVersion));
  if (root["frame"] != "world") Fail("frame", "expected \"world\"");
  const nlohmann::json& rooms = root["rooms"];
  if (!rooms.is_array()) Fail("rooms", "expected an array (got " + TypeName(rooms) + ")");
  if (rooms.size() > kSemanticMapMaxRooms) {
    Fail("rooms", "more than " + std::to_string(kSemanticMapMaxRooms) + " rooms");
  }
  std::vector<SemanticMapEntry> entries;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < rooms.size(); ++i) {
    const std::string key = "rooms[" + std::to_string(i) + "]";
    const nlohmann::json& room = rooms[i];
    RequireKeys(room, key, {"room", "landmark_id", "position_m", "covariance_m2"}, {});
    SemanticMapEntry e;
    if (!room["room"].is_string() || !IsRoomLabel(room["room"].get<std::string>())) {
      Fail(key + ".room", "expected 1 to " + std::to_string(kSemanticMapMaxRoomChars) +
                              " printable characters without spaces");
    }
    e.room = room["room"].get<std::string>();
    if (!seen.insert(e.room).second) Fail(key + ".room", "room '" + e.room + "' appears twice");
    const nlohmann::json& id = room["landmark_id"];
    if (!id.is_number_integer() || id.get<long long>() < -1 || id.get<long long>() > INT_MAX) {
      Fail(key + ".landmark_id", "expected an integer in [-1, " + std::to_string(INT_MAX) + "]");
    }
    e.landmark_id = static_cast<int>(id.get<long long>());
    const nlohmann::json& position = room["position_m"];
    if (!position.is_array() || position.size() != 3) {
      Fail(key + ".position_m", "expected [x, y, z] in metres");
    }
    for (int k = 0; k < 3; ++k) {
      e.position_in_world[k] =
          Number(position[k], key + ".position_m[" + std::to_string(k) + "]", kSemanticMapMaxAbsM);
    }
    const nlohmann::json& covariance = room["covariance_m2"];
    const std::size_t n = covariance.is_array() ? covariance.size() : 0;
    if (n != 2 && n != 3) {
      Fail(key + ".covariance_m2", "expected a 3x3 matrix (or 2x2 over x, y) as rows");
    }
    e.planar = n == 2;
    for (std::size_t r = 0; r < n; ++r) {
      if (!covariance[r].is_array() || covariance[r].size() != n) {
        Fail(key + ".covariance_m2",
             "expected " + std::to_string(n) + " rows of " + std::to_string(n) + " numbers");
      }
      for (std::size_t c = 0; c < n; ++c) {
        e.covariance(static_cast<int>(r), static_cast<int>(c)) =
            Number(covariance[r][c],
                   key + ".covariance_m2[" + std::to_string(r) + "][" + std::to_string(c) + "]",
                   kSemanticMapMaxAbsM * kSemanticMapMaxAbsM);
      }
    }
    for (int r = 0; r < static_cast<int>(n); ++r) {
      if (e.covariance(r, r) < 0) Fail(key + ".covariance_m2", "a variance is negative");
      for (int c = 0; c < r; ++c) {
        const double scale =
            std::max({1e-300, std::abs(e.covariance(r, c)), std::abs(e.covariance(c, r))});
        if (std::abs(e.covariance(r, c) - e.covariance(c, r)) > 1e-9 * scale) {
          Fail(key + ".covariance_m2", "not symmetric");
        }
      }
    }
    entries.push_back(e);
  }
  return entries;
}

}  // namespace corridorsim::slam
