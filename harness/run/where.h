#pragma once
// `corridorsim where ROOM --run DIR`: where room ROOM is, as each pipeline of a finished run mapped
// it (DIR/maps/<pipeline>_semantic.json, slam/mapping/semantic_map.h): x, y with their 1-sigma.

#include <filesystem>
#include <string>

namespace corridorsim {

struct WhereRequest {
  std::string room;               // room number, as on the plate
  std::filesystem::path run_dir;  // a run folder (`corridorsim run --out`)
  std::string pipeline;           // only this pipeline's map; "" = every map of the run
};

/// The lines `where` prints. Throws InputError (exit 2) when the run folder, its maps/ or the
/// pipeline's semantic map is missing or malformed (file:line:column: key: ...), or when no map
/// knows the room (naming the rooms they know).
std::string LocateRoom(const WhereRequest& request);

}  // namespace corridorsim
