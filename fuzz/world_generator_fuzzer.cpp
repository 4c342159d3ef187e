// libFuzzer target: a scenario's `world:` (with `appearance:` and `seed:`) through the option
// validation the scenario loader runs on them, then worlds::Generate (docs/fuzzing.md).
//
// One input is a YAML document whose root holds at most the keys `world`, `appearance` and
// `seed`, as in a scenario file (other inputs are skipped: the scenario loader has its own
// target). They are read with the tables the scenario's table holds for them
// (worlds::WorldOptionsTable, worlds::AppearanceOptionsTable, as sections with their Check()s, as
// harness/scenario/scenario.cpp declares them) and checked as LoadScenario checks them
// (CheckOptionBounds: every bound, then WorldOptions::Check and AppearanceOptions::Check); a world
// that passes is generated from the seed (an impossible layout is an OptionsError, which
// GenerateWorld reports as an InputError). Only the worlds library is linked, so the target builds
// in minutes.
//
// Bad input must end in an InputError or, for options that pass Check(), an OptionsError.
// Anything else escaping (another exception type) is a bug: the target aborts and libFuzzer
// saves the input. So is a crash, a leak, or an input slower than 1 s or needing more than 2 GiB
// (-timeout=1 -rss_limit_mb=2048). The options' own budgets (WorldOptions::Check: a million tile
// corners, 20,000 fixtures, 1 GiB of textures) admit worlds that take seconds to generate, as a
// long run may; the fuzzer skips (-1) a world whose WorldBudgetOf exceeds the budgets below, so
// that one input stays under 1 s and 2 GiB in the ASan build.

#include <cstdint>
#include <exception>
#include <string>

#include "common/error.h"
#include "common/io/options_yaml.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "fuzz/fuzz_checks.h"
#include "worlds/world.h"
#include "worlds/world_options.h"

namespace {

using corridorsim::fuzz::Bug;
using corridorsim::worlds::WorldOptions;

// The fuzz budgets (worlds::WorldBudget). Textures dominate the cost (P1's default corridor, at
// 200 px/m with its 14 plates and 13 distractors, takes seconds in the ASan build): the budget
// keeps a world of about 60 m at low texture resolution with a few plates and distractors.
constexpr double kFuzzCentreLineM = 60;
constexpr double kFuzzTileCorners = 2'000;
constexpr double kFuzzCeilingFixtures = 200;
constexpr double kFuzzTextureBytes = 1 << 20;
constexpr int kFuzzDoors = 12;
constexpr int kFuzzPlates = 8;

// What an input sets: the scenario's `seed`, `world` and `appearance`
// (harness/scenario/scenario.h).
struct WorldSpec {
  std::uint64_t seed = 1;
  WorldOptions world;
};

// The scenario table's rows for them (harness/scenario/scenario.cpp, ScenarioOptionsTable).
const corridorsim::OptionTable<WorldSpec>& WorldSpecTable() {
  return corridorsim::StaticOptionTable<WorldSpec>([](corridorsim::OptionTable<WorldSpec>& t) {
    t.Add("seed", &WorldSpec::seed, "", "seed of the world's random streams");
    t.AddSection("world", &WorldSpec::world, corridorsim::worlds::WorldOptionsTable(), "the world",
                 &WorldOptions::Check);
    t.AddSection(
        "appearance",
        [](WorldSpec& s) -> corridorsim::worlds::AppearanceOptions& { return s.world.appearance; },
        corridorsim::worlds::AppearanceOptionsTable(), "appearance randomisation",
        &corridorsim::worlds::AppearanceOptions::Check);
  });
}

// Whether the root holds no key but world, appearance and seed (a root that is not a map: true,
// so that the reader reports it as it would).
bool WorldKeysOnly(const corridorsim::YamlDocument& doc) {
  if (!doc.root.IsMap()) return true;
  for (const auto& entry : doc.root) {
    if (!entry.first.IsScalar()) return true;
    const std::string& key = entry.first.Scalar();
    if (key != "world" && key != "appearance" && key != "seed") return false;
  }
  return true;
}

bool WithinFuzzBudget(const WorldOptions& world) {
  const corridorsim::worlds::WorldBudget b = corridorsim::worlds::WorldBudgetOf(world);
  return b.centre_line_m <= kFuzzCentreLineM && b.tile_corners <= kFuzzTileCorners &&
         b.ceiling_fixtures <= kFuzzCeilingFixtures && b.texture_bytes <= kFuzzTextureBytes &&
         world.doors.count <= kFuzzDoors && world.plates.count <= kFuzzPlates;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  WorldSpec spec;
  try {
    const corridorsim::YamlDocument doc = corridorsim::YamlDocument::FromString(text, "world.yaml");
    if (!WorldKeysOnly(doc)) return -1;
    corridorsim::SourceMap sources;
    corridorsim::YamlMap root(doc, doc.root, "", &sources);
    corridorsim::ReadOptions(root, WorldSpecTable(), spec);
    // LoadScenario's check: the bounds and each section's Check().
    if (corridorsim::CheckOptionBounds(WorldSpecTable(), spec)) return 0;
  } catch (const corridorsim::InputError&) {
    return 0;  // bad input, reported as it should be
  } catch (const std::exception& e) {
    Bug(std::string("reading the world options threw something other than InputError: ") +
        e.what());
  }
  if (!WithinFuzzBudget(spec.world)) return -1;
  try {
    const corridorsim::worlds::World world = corridorsim::worlds::Generate(spec.world, spec.seed);
    (void)world;
  } catch (const corridorsim::OptionsError&) {
    return 0;  // options that pass Check() but leave no room (the layout, the placement)
  } catch (const std::exception& e) {
    Bug(std::string("worlds::Generate threw something other than OptionsError: ") + e.what());
  }
  return 0;
}
