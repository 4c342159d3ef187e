#include "harness/run/where.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <vector>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/json_input.h"
#include "slam/mapping/semantic_map.h"

namespace corridorsim {
namespace {

constexpr const char* kSuffix = "_semantic.json";
constexpr std::size_t kMaxMaps = 1000;       // semantic maps read from one run folder
constexpr std::size_t kMaxListedRooms = 40;  // rooms named in the "unknown room" message

[[noreturn]] void FailAt(const std::filesystem::path& path, const std::string& message) {
  throw InputError(SourceLocation{path.string(), 0, 0}, "", message);
}

std::vector<slam::SemanticMapEntry> ReadMap(const std::filesystem::path& path) {
  const std::string text = ReadRegularFile(path, slam::kSemanticMapMaxBytes);
  // Nesting and values bounded before the map's parser builds the document.
  CheckJsonInputBounds(text, path.string(), kMaxJsonValues);
  try {
    return slam::ParseSemanticMap(text);
  } catch (const slam::SemanticMapError& e) {
    throw InputError(SourceLocation{path.string(), e.line(), e.column()}, e.key(), e.message());
  }
}

// The pipelines with a semantic map in `maps`, by name.
std::vector<std::string> MappedPipelines(const std::filesystem::path& maps) {
  std::vector<std::string> names;
  std::error_code error;
  for (std::filesystem::directory_iterator it(maps, error), end; !error && it != end;
       it.increment(error)) {
    const std::string file = it->path().filename().string();
    const std::size_t n = std::strlen(kSuffix);
    if (file.size() > n && file.compare(file.size() - n, n, kSuffix) == 0) {
      names.push_back(file.substr(0, file.size() - n));
      if (names.size() > kMaxMaps) FailAt(maps, "more than " + std::to_string(kMaxMaps) + " maps");
    }
  }
  if (error) FailAt(maps, "cannot be listed: " + error.message());
  std::sort(names.begin(), names.end());
  return names;
}

std::string Format(const char* format, double a, double b, double c, double d) {
  char line[256];
  std::snprintf(line, sizeof(line), format, a, b, c, d);
  return line;
}

}  // namespace

std::string LocateRoom(const WhereRequest& request) {
  std::error_code error;
  if (!std::filesystem::is_directory(request.run_dir, error)) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--run",
                     "no such folder '" + request.run_dir.string() + "'");
  }
  const std::filesystem::path maps = request.run_dir / "maps";
  if (!std::filesystem::is_directory(maps, error)) {
    FailAt(maps,
           "no such folder: the run wrote no maps (a run writes maps/ for pipelines that "
           "build them)");
  }
  std::vector<std::string> pipelines;
  if (!request.pipeline.empty()) {
    pipelines.push_back(request.pipeline);
    if (!std::filesystem::exists(maps / (request.pipeline + kSuffix), error)) {
      std::string known;
      for (const std::string& p : MappedPipelines(maps)) known += (known.empty() ? "" : ", ") + p;
      FailAt(maps / (request.pipeline + kSuffix),
             "does not exist (pipelines with a semantic map: " + (known.empty() ? "none" : known) +
                 ")");
    }
  } else {
    pipelines = MappedPipelines(maps);
    if (pipelines.empty()) {
      FailAt(maps, std::string("no <pipeline>") + kSuffix +
                       ": no pipeline of this run wrote a semantic map");
    }
  }

  std::string out;
  std::vector<std::string> missing;
  std::set<std::string, decltype(&slam::RoomNumberLess)> known(&slam::RoomNumberLess);
  for (const std::string& pipeline : pipelines) {
    const std::vector<slam::SemanticMapEntry> map = ReadMap(maps / (pipeline + kSuffix));
    const auto it = std::find_if(map.begin(), map.end(), [&](const slam::SemanticMapEntry& e) {
      return e.room == request.room;
    });
    if (it == map.end()) {
      missing.push_back(pipeline);
      for (const slam::SemanticMapEntry& e : map) known.insert(e.room);
      continue;
    }
    out += pipeline + ": room " + request.room +
           Format(" at x %.3f m (1-sigma %.3f m), y %.3f m (1-sigma %.3f m)",
                  it->position_in_world.x(), std::sqrt(it->covariance(0, 0)),
                  it->position_in_world.y(), std::sqrt(it->covariance(1, 1))) +
           ", landmark " + std::to_string(it->landmark_id) + "\n";
  }
  if (out.empty()) {
    std::string listed;
    std::size_t n = 0;
    for (const std::string& room : known) {
      if (n++ == kMaxListedRooms) {
        listed += ", ... (" + std::to_string(known.size()) + " in all)";
        break;
      }
      listed += (listed.empty() ? "" : ", ") + room;
    }
    const std::string whose =
        pipelines.size() == 1 ? "the " + pipelines[0] + " map" : "any of the run's semantic maps";
    throw InputError(SourceLocation{"command line", 0, 0}, "ROOM",
                     "room '" + request.room + "' is not in " + whose +
                         " (known rooms: " + (listed.empty() ? "none" : listed) + ")");
  }
  for (const std::string& pipeline : missing) {
    out += pipeline + ": room " + request.room + " is not in its map\n";
  }
  return out;
}

}  // namespace corridorsim
