// Generated worlds for the tests that consume them: the default world of a layout and seed,
// generated once per test binary, and a bare straight corridor (walls, floor, ceiling and lamps,
// nothing else) for tests of motion and sensing.
#pragma once

#include <cstdint>
#include <map>
#include <utility>

#include "worlds/world.h"

namespace corridorsim::test {

/// The world of the default options with `layout`, generated from `seed` on the first call and
/// kept for the rest of the test binary.
inline const worlds::World& GeneratedWorld(std::uint64_t seed,
                                           worlds::Layout layout = worlds::Layout::kStraight) {
  static std::map<std::pair<worlds::Layout, std::uint64_t>, worlds::World> worlds;
  const auto key = std::make_pair(layout, seed);
  auto it = worlds.find(key);
  if (it == worlds.end()) {
    worlds::WorldOptions options;
    options.layout = layout;
    it = worlds.emplace(key, worlds::Generate(options, seed)).first;
  }
  return it->second;
}

/// The default options with a straight corridor `length_m` long and neither doors, plates nor
/// distractors in it (2.4 m wide: the walls at y = +-1.2).
inline worlds::WorldOptions BareCorridorOptions(double length_m) {
  worlds::WorldOptions options;
  options.length_m = length_m;
  options.doors.count = 0;
  options.plates.count = 0;
  options.distractors = worlds::DistractorOptions{0, 0, 0, 0, 0};
  return options;
}

}  // namespace corridorsim::test
