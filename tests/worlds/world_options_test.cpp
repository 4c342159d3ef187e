// Tests worlds/world_options.cpp: WorldOptions::Check() rules (key and gist of each message) and
// ParseWorldOptions (every documented key lands in the struct; unknown keys and wrong types fail).
#include "worlds/world_options.h"

#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/broken_options.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/parsed_options.h"

namespace corridorsim::worlds {
namespace {

using test::Contains;

// The problem Check() reports for the default options changed by `change`.
OptionsProblem ProblemOf(const std::function<void(WorldOptions&)>& change) {
  return test::ProblemOf<WorldOptions>(change);
}

// A rule of WorldOptions::Check: a change to the defaults that breaks it, the key of the problem
// and a part of its message.
struct Rule {
  const char* name;
  std::function<void(WorldOptions&)> change;
  const char* key;
  const char* gist;
};

// Each rule's change makes Check() report its key, with its gist in the message.
void CheckEachRule(const std::vector<Rule>& rules) {
  for (const Rule& rule : rules) {
    DYNAMIC_SECTION(rule.name) {
      const OptionsProblem p = ProblemOf(rule.change);
      CHECK(p.key == rule.key);
      INFO("message: " << p.message);
      CHECK(Contains(p.message, rule.gist));
    }
  }
}

TEST_CASE("the default options passes Check", "[worlds][world_options]") {
  const WorldOptions options;
  const auto problem = options.Check();
  INFO((problem ? problem->key + ": " + problem->message : std::string()));
  CHECK_FALSE(problem);
}

TEST_CASE("the defaults of every layout pass Check", "[worlds][world_options]") {
  for (const Layout layout :
       {Layout::kStraight, Layout::kLTurn, Layout::kTJunction, Layout::kLoop}) {
    WorldOptions options;
    options.layout = layout;
    const auto problem = options.Check();
    INFO(LayoutName(layout) << ": " << (problem ? problem->key + ": " + problem->message : ""));
    CHECK_FALSE(problem);
  }
}

TEST_CASE("zero and negative corridor sizes name their key", "[worlds][world_options]") {
  for (const double bad : {0.0, -1.0}) {
    INFO("value " << bad);
    OptionsProblem p = ProblemOf([&](WorldOptions& s) { s.width_m = bad; });
    CHECK(p.key == "width_m");
    CHECK(Contains(p.message, "must be greater than 0"));
    p = ProblemOf([&](WorldOptions& s) { s.height_m = bad; });
    CHECK(p.key == "height_m");
    CHECK(Contains(p.message, "must be greater than 0"));
    p = ProblemOf([&](WorldOptions& s) { s.length_m = bad; });
    CHECK(p.key == "length_m");
    CHECK(Contains(p.message, "must be greater than 0"));
    p = ProblemOf([&](WorldOptions& s) { s.wall_thickness_m = bad; });
    CHECK(p.key == "wall_thickness_m");
    p = ProblemOf([&](WorldOptions& s) {
      s.layout = Layout::kLTurn;
      s.second_length_m = bad;
    });
    CHECK(p.key == "second_length_m");
    CHECK(Contains(p.message, "must be greater than 0"));
  }
  CHECK(ProblemOf([](WorldOptions& s) { s.width_m = -2.5; }).message ==
        "must be greater than 0 (got -2.5)");
}

TEST_CASE("zero and negative door and plate sizes name their key", "[worlds][world_options]") {
  for (const double bad : {0.0, -0.5}) {
    INFO("value " << bad);
    OptionsProblem p = ProblemOf([&](WorldOptions& s) { s.doors.width_m = bad; });
    CHECK(p.key == "doors.width_m");
    CHECK(Contains(p.message, "must be greater than 0"));
    p = ProblemOf([&](WorldOptions& s) { s.plates.width_m = bad; });
    CHECK(p.key == "plates.width_m");
    CHECK(Contains(p.message, "must be greater than 0"));
    p = ProblemOf([&](WorldOptions& s) { s.plates.height_m = bad; });
    CHECK(p.key == "plates.height_m");
    CHECK(Contains(p.message, "must be greater than 0"));
  }
}

TEST_CASE("a ceiling lower than the doors is a problem with height_m", "[worlds][world_options]") {
  const OptionsProblem p = ProblemOf([](WorldOptions& s) { s.height_m = 2.0; });
  CHECK(p.key == "height_m");
  CHECK(p.message == "the ceiling (2 m) is lower than the doors with their top bar (2.18 m)");
  // Exactly at the top of the bar is still too low: the bar needs the ceiling above it.
  CHECK(ProblemOf([](WorldOptions& s) {
          s.height_m = s.doors.height_m + s.doors.bar_height_m;
        }).key == "height_m");
}

TEST_CASE("a room ceiling lower than the doors is a problem with doors.room_height_m",
          "[worlds][world_options]") {
  const OptionsProblem p = ProblemOf([](WorldOptions& s) { s.doors.room_height_m = 2.1; });
  CHECK(p.key == "doors.room_height_m");
  CHECK(Contains(p.message, "room ceiling (2.1 m) is lower than the doors"));
}

TEST_CASE("more plates than doors is a problem with plates.count", "[worlds][world_options]") {
  const OptionsProblem p = ProblemOf([](WorldOptions& s) { s.plates.count = 17; });
  CHECK(p.key == "plates.count");
  CHECK(p.message == "17 plates need a door each, but there are only 16 doors (doors.count)");
  // As many plates as doors is fine.
  WorldOptions options;
  options.plates.count = options.doors.count;
  CHECK_FALSE(options.Check());
}

TEST_CASE("plates that do not fit between doors are a problem with plates.width_m",
          "[worlds][world_options]") {
  // 0.1 gap + 0.95 * 1.15 + 0.05 > 1.2 m of wall between doors.
  const OptionsProblem p = ProblemOf([](WorldOptions& s) { s.plates.width_m = 0.95; });
  CHECK(p.key == "plates.width_m");
  CHECK(Contains(p.message, "does not fit in the wall between doors"));
  CHECK(Contains(p.message, "doors.min_gap_m 1.2"));
  // The same plates fit when the doors leave more wall between them.
  WorldOptions options;
  options.plates.width_m = 0.95;
  options.doors.min_gap_m = 1.4;
  CHECK_FALSE(options.Check());
}

TEST_CASE("a lamp radius_max_m below radius_min_m is a problem with lamps.radius_max_m",
          "[worlds][world_options]") {
  const OptionsProblem p = ProblemOf([](WorldOptions& s) {
    s.lamps.radius_min_m = 0.25;
    s.lamps.radius_max_m = 0.2;
  });
  CHECK(p.key == "lamps.radius_max_m");
  CHECK(p.message == "must not be smaller than radius_min_m");
}

TEST_CASE("fractions outside [0, 1] name their key", "[worlds][world_options]") {
  struct Case {
    const char* key;
    double LampOptions::*field;
  };
  const Case cases[] = {{"lamps.circular_fraction", &LampOptions::circular_fraction},
                        {"lamps.off_fraction", &LampOptions::off_fraction},
                        {"lamps.reflector_fraction", &LampOptions::reflector_fraction}};
  for (const Case& c : cases) {
    for (const double bad : {-0.1, 1.5}) {
      INFO(c.key << " = " << bad);
      const OptionsProblem p = ProblemOf([&](WorldOptions& s) { s.lamps.*c.field = bad; });
      CHECK(p.key == c.key);
      CHECK(Contains(p.message, "must lie in [0, 1]"));
    }
    for (const double good : {0.0, 1.0}) {
      WorldOptions options;
      options.lamps.*c.field = good;
      CHECK_FALSE(options.Check());
    }
  }
}

// Every other rule of WorldOptions::Check, one row each: the change, the key, a part of the
// message.
TEST_CASE("every Check rule reports its key and says what is wrong", "[worlds][world_options]") {
  CheckEachRule({
      {"second leg not longer than the width",
       [](WorldOptions& s) {
         s.layout = Layout::kTJunction;
         s.second_length_m = 2.4;
       },
       "second_length_m", "longer than the corridor width"},
      {"corridor not longer than its width", [](WorldOptions& s) { s.length_m = 2.0; }, "length_m",
       "longer than the corridor width (2.4 m)"},
      {"loop without an inside",
       [](WorldOptions& s) {
         s.layout = Layout::kLoop;
         s.length_m = 30;
         s.second_length_m = 4.0;
       },
       "second_length_m", "a loop needs both sides longer than twice the width"},
      {"loop too short along x",
       [](WorldOptions& s) {
         s.layout = Layout::kLoop;
         s.length_m = 4.0;
         s.second_length_m = 30;
       },
       "length_m", "a loop needs both sides longer than twice the width"},
      {"corridor longer than 2 km", [](WorldOptions& s) { s.length_m = 2500; }, "length_m",
       "must lie in [0, 2000]"},
      {"sprinklers closer than 0.5 m",
       [](WorldOptions& s) { s.ceiling.sprinkler_spacing_m = 1e-20; },
       "ceiling.sprinkler_spacing_m", "must lie in [0.5, 100]"},
      {"lamps closer than 0.5 m", [](WorldOptions& s) { s.lamps.spacing_m = 1e-14; },
       "lamps.spacing_m", "must lie in [0.5, 100]"},
      {"ceiling tiles of a kilometre", [](WorldOptions& s) { s.ceiling.tile_size_m = 1000; },
       "ceiling.tile_size_m", "must lie in [0.1, 2]"},
      {"a wall a kilometre thick", [](WorldOptions& s) { s.wall_thickness_m = 1e6; },
       "wall_thickness_m", "must lie in [0.02, 1]"},
      {"a needle-thin plate", [](WorldOptions& s) { s.plates.height_m = 1e-7; }, "plates.height_m",
       "must lie in [0.02, 2]"},
      {"texture resolution too low", [](WorldOptions& s) { s.texture_px_per_m = 19; },
       "texture_px_per_m", "must lie in [20, 1000] (got 19)"},
      {"texture resolution too high", [](WorldOptions& s) { s.texture_px_per_m = 1001; },
       "texture_px_per_m", "must lie in [20, 1000]"},
      {"negative door count", [](WorldOptions& s) { s.doors.count = -1; }, "doors.count",
       "must not be negative"},
      {"door height", [](WorldOptions& s) { s.doors.height_m = 0; }, "doors.height_m",
       "must be greater than 0"},
      {"frame width", [](WorldOptions& s) { s.doors.frame_width_m = -0.01; }, "doors.frame_width_m",
       "must be greater than 0"},
      {"bar height", [](WorldOptions& s) { s.doors.bar_height_m = 0; }, "doors.bar_height_m",
       "must be greater than 0"},
      {"frame protrusion", [](WorldOptions& s) { s.doors.frame_protrusion_m = -0.01; },
       "doors.frame_protrusion_m", "must not be negative"},
      {"door gap", [](WorldOptions& s) { s.doors.min_gap_m = 0; }, "doors.min_gap_m",
       "must be greater than 0"},
      {"open weight", [](WorldOptions& s) { s.doors.open_weight = -1; }, "doors.open_weight",
       "must not be negative"},
      {"closed weight", [](WorldOptions& s) { s.doors.closed_weight = -1; }, "doors.closed_weight",
       "must not be negative"},
      {"empty weight", [](WorldOptions& s) { s.doors.empty_weight = -1; }, "doors.empty_weight",
       "must not be negative"},
      {"all door weights zero",
       [](WorldOptions& s) {
         s.doors.open_weight = s.doors.closed_weight = s.doors.empty_weight = 0;
       },
       "doors", "must not all be 0"},
      {"room depth", [](WorldOptions& s) { s.doors.room_depth_m = 0; }, "doors.room_depth_m",
       "must be greater than 0"},
      {"room width", [](WorldOptions& s) { s.doors.room_width_m = 0; }, "doors.room_width_m",
       "must be greater than 0"},
      {"room height", [](WorldOptions& s) { s.doors.room_height_m = 0; }, "doors.room_height_m",
       "must be greater than 0"},
      {"negative plate count", [](WorldOptions& s) { s.plates.count = -1; }, "plates.count",
       "must not be negative"},
      {"plate size jitter too large", [](WorldOptions& s) { s.plates.size_jitter = 0.5; },
       "plates.size_jitter", "must lie in [0, 0.5) (got 0.5)"},
      {"negative plate size jitter", [](WorldOptions& s) { s.plates.size_jitter = -0.1; },
       "plates.size_jitter", "must lie in [0, 0.5)"},
      {"negative plate gap", [](WorldOptions& s) { s.plates.gap_from_frame_m = -0.1; },
       "plates.gap_from_frame_m", "must not be negative"},
      {"plate below the floor", [](WorldOptions& s) { s.plates.center_height_m = 0.05; },
       "plates.center_height_m", "between the floor and the ceiling"},
      {"plate above the ceiling", [](WorldOptions& s) { s.plates.center_height_m = 2.68; },
       "plates.center_height_m", "between the floor and the ceiling"},
      {"floor digit too large", [](WorldOptions& s) { s.plates.first_floor = 10; },
       "plates.first_floor", "must lie in [0, 9]"},
      {"negative floor digit", [](WorldOptions& s) { s.plates.first_floor = -1; },
       "plates.first_floor", "must lie in [0, 9]"},
      {"lamp spacing", [](WorldOptions& s) { s.lamps.spacing_m = 0; }, "lamps.spacing_m",
       "must lie in [0.5, 100] (got 0)"},
      {"lamp jitter too large", [](WorldOptions& s) { s.lamps.spacing_jitter_m = 0.75; },
       "lamps.spacing_jitter_m", "[0, spacing_m / 4)"},
      {"negative lamp jitter", [](WorldOptions& s) { s.lamps.spacing_jitter_m = -0.1; },
       "lamps.spacing_jitter_m", "[0, spacing_m / 4)"},
      {"lamp radius_min", [](WorldOptions& s) { s.lamps.radius_min_m = 0; }, "lamps.radius_min_m",
       "must be greater than 0"},
      {"lamp wider than the corridor", [](WorldOptions& s) { s.lamps.radius_max_m = 1.25; },
       "lamps.radius_max_m", "fit the corridor width and their spacing"},
      {"lamp wider than its spacing",
       [](WorldOptions& s) {
         s.lamps.spacing_m = 0.5;
         s.lamps.spacing_jitter_m = 0;
       },
       "lamps.radius_max_m", "fit the corridor width and their spacing"},
      {"panel length", [](WorldOptions& s) { s.lamps.panel_length_m = 0; }, "lamps.panel_length_m",
       "must be greater than 0"},
      {"panel width", [](WorldOptions& s) { s.lamps.panel_width_m = 0; }, "lamps.panel_width_m",
       "must be greater than 0"},
      {"panel longer than the spacing", [](WorldOptions& s) { s.lamps.panel_length_m = 3.0; },
       "lamps.panel_length_m", "shorter than the lamp spacing"},
      {"panel wider than the corridor", [](WorldOptions& s) { s.lamps.panel_width_m = 2.5; },
       "lamps.panel_width_m", "narrower than the corridor"},
      {"reflector height reaching the floor",
       [](WorldOptions& s) { s.lamps.reflector_height_m = 2.5; }, "lamps.reflector_height_m",
       "at least 0.3 m above the floor"},
      {"reflector height zero", [](WorldOptions& s) { s.lamps.reflector_height_m = 0; },
       "lamps.reflector_height_m", "must be positive"},
      {"reflector length", [](WorldOptions& s) { s.lamps.reflector_length_m = 0; },
       "lamps.reflector_length_m", "must be greater than 0"},
      {"ceiling tiles too small", [](WorldOptions& s) { s.ceiling.tile_size_m = 0.05; },
       "ceiling.tile_size_m", "at least 0.1 m"},
      {"vent spacing", [](WorldOptions& s) { s.ceiling.vent_spacing_m = 0; },
       "ceiling.vent_spacing_m", "must be greater than 0"},
      {"vent size", [](WorldOptions& s) { s.ceiling.vent_size_m = 0; }, "ceiling.vent_size_m",
       "must be greater than 0"},
      {"vents that do not fit beside the lamps",
       [](WorldOptions& s) { s.ceiling.vent_size_m = 0.8; }, "ceiling.vent_size_m",
       "must fit between the lamps and the walls"},
      {"smoke detector spacing", [](WorldOptions& s) { s.ceiling.smoke_detector_spacing_m = 0; },
       "ceiling.smoke_detector_spacing_m", "must be greater than 0"},
      {"sprinkler spacing", [](WorldOptions& s) { s.ceiling.sprinkler_spacing_m = -1; },
       "ceiling.sprinkler_spacing_m", "must be greater than 0"},
      {"negative posters", [](WorldOptions& s) { s.distractors.posters = -1; },
       "distractors.posters", "must not be negative"},
      {"negative notice boards", [](WorldOptions& s) { s.distractors.notice_boards = -1; },
       "distractors.notice_boards", "must not be negative"},
      {"negative bookshelves", [](WorldOptions& s) { s.distractors.bookshelves = -1; },
       "distractors.bookshelves", "must not be negative"},
      {"negative cabinets", [](WorldOptions& s) { s.distractors.cabinets = -1; },
       "distractors.cabinets", "must not be negative"},
      {"negative fire extinguishers",
       [](WorldOptions& s) { s.distractors.fire_extinguishers = -1; },
       "distractors.fire_extinguishers", "must not be negative"},
      // The floor plan's own problems come through Check too.
      {"more doors than fit", [](WorldOptions& s) { s.doors.count = 47; }, "doors.count",
       "doorways do not fit on the side walls"},
      {"a door wider than every wall",
       [](WorldOptions& s) {
         s.length_m = 5;  // 2.6 m of usable wall
         s.doors.width_m = 3;
       },
       "doors.width_m", "wider than every wall segment"},
  });
}

TEST_CASE("the generator's loop counts and textures are bounded before it runs",
          "[worlds][world_options]") {
  // The documented maxima with the default ceiling pass: a 2 km loop 20 m wide (10 s to generate).
  WorldOptions largest;
  largest.layout = Layout::kLoop;
  largest.length_m = largest.second_length_m = 2000;
  largest.width_m = largest.height_m = 20;
  CHECK_FALSE(largest.Check());
  CHECK(WorldBudgetOf(largest).tile_corners <= kMaxTileCorners);
  CHECK(WorldBudgetOf(WorldOptions{}).texture_bytes < 8e6);

  CheckEachRule({
      // 4 million tile corners, each tested against the fixtures near it (it hung for minutes).
      {"tiny tiles over a 2 km corridor",
       [](WorldOptions& s) {
         s.length_m = 2000;
         s.width_m = 20;
         s.height_m = 20;
         s.ceiling.tile_size_m = 0.1;
       },
       "ceiling.tile_size_m", "tile corners, more than 1e+06 (got tile_size_m 0.1)"},
      {"fixtures every half metre around a 8 km loop",
       [](WorldOptions& s) {
         s.layout = Layout::kLoop;
         s.length_m = s.second_length_m = 2000;
         s.lamps.radius_min_m = 0.05;
         s.lamps.radius_max_m = 0.1;
         s.lamps.panel_length_m = 0.3;
         s.lamps.spacing_jitter_m = 0;
         s.lamps.spacing_m = s.ceiling.vent_spacing_m = 0.5;
       },
       "lamps.spacing_m", "more than 20000 (got 0.5 m)"},
      {"three thousand distractors",
       [](WorldOptions& s) { s.distractors.posters = s.distractors.notice_boards = 1500; },
       "distractors", "at most 2000 distractors of all kinds together (got 3007)"},
      {"a distractor kind beyond the total", [](WorldOptions& s) { s.distractors.posters = 2001; },
       "distractors.posters", "must lie in [0, 2000]"},
      // 10000 plates 10 times wider than high: 4.9 GB of textures.
      {"wide plates on every door",
       [](WorldOptions& s) {
         s.length_m = 2000;
         s.doors.count = s.plates.count = 10000;
         s.doors.min_gap_m = 2.5;
         s.plates.width_m = 1.0;
         s.plates.height_m = 0.1;
         s.plates.center_height_m = 1.2;
       },
       "plates.count", "MiB, more than 1024 MiB (got 10000 plates)"},
      {"bookshelves in the finest textures",
       [](WorldOptions& s) {
         s.length_m = 2000;
         s.texture_px_per_m = 1000;
         s.ceiling.tile_size_m = 2.0;  // a ceiling texture of 8000 x 8000 px
         s.distractors.bookshelves = 1900;
       },
       "distractors", "MiB, more than 1024 MiB (got 1911 distractors)"},
  });
}

TEST_CASE("Check reports the first problem in the order of the options",
          "[worlds][world_options]") {
  const OptionsProblem p = ProblemOf([](WorldOptions& s) {
    s.lamps.radius_min_m = 0;
    s.width_m = 0;
  });
  CHECK(p.key == "width_m");
}

TEST_CASE("layout names are the scenario file's names", "[worlds][world_options]") {
  CHECK(LayoutName(Layout::kStraight) == "straight");
  CHECK(LayoutName(Layout::kLTurn) == "l_turn");
  CHECK(LayoutName(Layout::kTJunction) == "t_junction");
  CHECK(LayoutName(Layout::kLoop) == "loop");
}

// A `world:` map setting every documented key to a value that differs from its default.
const char* const kAllKeys = R"(world:
  layout: loop
  length_m: 31.5
  second_length_m: 17.5
  width_m: 2.6
  height_m: 2.9
  wall_thickness_m: 0.2
  texture_px_per_m: 150
  doors:
    count: 12
    width_m: 1.0
    height_m: 2.05
    frame_width_m: 0.1
    bar_height_m: 0.07
    frame_protrusion_m: 0.04
    min_gap_m: 1.3
    open_weight: 0.25
    closed_weight: 0.55
    empty_weight: 0.35
    room_depth_m: 3.2
    room_width_m: 2.8
    room_height_m: 2.5
  plates:
    count: 9
    center_height_m: 1.55
    width_m: 0.2
    height_m: 0.1
    size_jitter: 0.1
    gap_from_frame_m: 0.12
    first_floor: 3
  lamps:
    spacing_m: 2.8
    spacing_jitter_m: 0.2
    circular_fraction: 0.6
    radius_min_m: 0.12
    radius_max_m: 0.25
    panel_length_m: 1.1
    panel_width_m: 0.25
    off_fraction: 0.1
    reflector_fraction: 0.2
    reflector_height_m: 1.4
    reflector_length_m: 1.8
    room_lamps: false
  ceiling:
    tile_size_m: 0.5
    vent_spacing_m: 7.0
    vent_size_m: 0.4
    smoke_detector_spacing_m: 9.0
    sprinkler_spacing_m: 3.2
  distractors:
    posters: 5
    notice_boards: 1
    bookshelves: 3
    cabinets: 0
    fire_extinguishers: 4
)";

TEST_CASE("ParseWorldOptions reads every documented key", "[worlds][world_options]") {
  const YamlDocument doc = YamlDocument::FromString(kAllKeys, "all_keys.yaml");
  SourceMap sources;
  YamlMap root(doc, doc.root, "", &sources);
  YamlMap world = root.Map("world");
  WorldOptions s;
  ParseWorldOptions(world, s);
  CHECK_NOTHROW(root.RejectUnknownKeys());

  CHECK(s.layout == Layout::kLoop);
  CHECK(s.length_m == 31.5);
  CHECK(s.second_length_m == 17.5);
  CHECK(s.width_m == 2.6);
  CHECK(s.height_m == 2.9);
  CHECK(s.wall_thickness_m == 0.2);
  CHECK(s.texture_px_per_m == 150);

  CHECK(s.doors.count == 12);
  CHECK(s.doors.width_m == 1.0);
  CHECK(s.doors.height_m == 2.05);
  CHECK(s.doors.frame_width_m == 0.1);
  CHECK(s.doors.bar_height_m == 0.07);
  CHECK(s.doors.frame_protrusion_m == 0.04);
  CHECK(s.doors.min_gap_m == 1.3);
  CHECK(s.doors.open_weight == 0.25);
  CHECK(s.doors.closed_weight == 0.55);
  CHECK(s.doors.empty_weight == 0.35);
  CHECK(s.doors.room_depth_m == 3.2);
  CHECK(s.doors.room_width_m == 2.8);
  CHECK(s.doors.room_height_m == 2.5);

  CHECK(s.plates.count == 9);
  CHECK(s.plates.center_height_m == 1.55);
  CHECK(s.plates.width_m == 0.2);
  CHECK(s.plates.height_m == 0.1);
  CHECK(s.plates.size_jitter == 0.1);
  CHECK(s.plates.gap_from_frame_m == 0.12);
  CHECK(s.plates.first_floor == 3);

  CHECK(s.lamps.spacing_m == 2.8);
  CHECK(s.lamps.spacing_jitter_m == 0.2);
  CHECK(s.lamps.circular_fraction == 0.6);
  CHECK(s.lamps.radius_min_m == 0.12);
  CHECK(s.lamps.radius_max_m == 0.25);
  CHECK(s.lamps.panel_length_m == 1.1);
  CHECK(s.lamps.panel_width_m == 0.25);
  CHECK(s.lamps.off_fraction == 0.1);
  CHECK(s.lamps.reflector_fraction == 0.2);
  CHECK(s.lamps.reflector_height_m == 1.4);
  CHECK(s.lamps.reflector_length_m == 1.8);
  CHECK(s.lamps.room_lamps == false);

  CHECK(s.ceiling.tile_size_m == 0.5);
  CHECK(s.ceiling.vent_spacing_m == 7.0);
  CHECK(s.ceiling.vent_size_m == 0.4);
  CHECK(s.ceiling.smoke_detector_spacing_m == 9.0);
  CHECK(s.ceiling.sprinkler_spacing_m == 3.2);

  CHECK(s.distractors.posters == 5);
  CHECK(s.distractors.notice_boards == 1);
  CHECK(s.distractors.bookshelves == 3);
  CHECK(s.distractors.cabinets == 0);
  CHECK(s.distractors.fire_extinguishers == 4);

  // The parsed options is a valid one, and every key's line is recorded for later problems.
  const auto problem = s.Check();
  INFO((problem ? problem->key + ": " + problem->message : std::string()));
  CHECK_FALSE(problem);
  const SourceLocation plates_count = sources.Find("world.plates.count", SourceLocation{});
  CHECK(plates_count.file == "all_keys.yaml");
  CHECK(plates_count.line == 24);
  CHECK(plates_count.column == 5);
  CHECK(sources.Find("world.distractors.fire_extinguishers", SourceLocation{}).line == 55);
}

TEST_CASE("ParseWorldOptions leaves keys that are absent at their defaults",
          "[worlds][world_options]") {
  const WorldOptions s = test::ParsedOptions(
      ParseWorldOptions, "doors:\n  count: 4\nplates:\n  count: 2\n", "few.yaml", "world");
  const WorldOptions defaults;
  CHECK(s.doors.count == 4);
  CHECK(s.plates.count == 2);
  CHECK(s.layout == defaults.layout);
  CHECK(s.length_m == defaults.length_m);
  CHECK(s.doors.width_m == defaults.doors.width_m);
  CHECK(s.plates.center_height_m == defaults.plates.center_height_m);
  CHECK(s.lamps.room_lamps == defaults.lamps.room_lamps);
}

TEST_CASE("ParseWorldOptions rejects unknown keys in every section", "[worlds][world_options]") {
  for (const char* section : {"doors", "plates", "lamps", "ceiling", "distractors"}) {
    const std::string text = std::string(section) + ":\n  colour: red\n";
    const InputError e = test::ParseErrorOf(ParseWorldOptions, text, "unknown.yaml", "world");
    CHECK(e.key() == "world." + std::string(section) + ".colour");
    CHECK(e.location().line == 2);
    CHECK(e.location().column == 3);
    CHECK(Contains(e.message(), "unknown key"));
  }
  const InputError e =
      test::ParseErrorOf(ParseWorldOptions, "length_m: 3\nlenght: 4\n", "top.yaml", "world");
  CHECK(std::string(e.what()).rfind("top.yaml:2:1: world.lenght: unknown key (known keys here: ",
                                    0) == 0);
}

TEST_CASE("ParseWorldOptions rejects an unknown layout listing the valid ones",
          "[worlds][world_options]") {
  const InputError e =
      test::ParseErrorOf(ParseWorldOptions, "layout: u_turn\n", "layout.yaml", "world");
  CHECK(std::string(e.what()) ==
        "layout.yaml:1:1: world.layout: unknown value 'u_turn' (expected one of: straight, l_turn, "
        "t_junction, loop)");
}

TEST_CASE("ParseWorldOptions rejects wrong types naming the key", "[worlds][world_options]") {
  struct Case {
    const char* yaml;
    const char* what;
  };
  const Case cases[] = {
      {"length_m: long\n", "types.yaml:1:1: world.length_m: expected a finite number, got 'long'"},
      {"doors:\n  count: 2.5\n",
       "types.yaml:2:3: world.doors.count: expected an integer, got '2.5'"},
      {"lamps:\n  room_lamps: sometimes\n",
       "types.yaml:2:3: world.lamps.room_lamps: expected true or false, got 'sometimes'"},
      {"doors: 3\n", "types.yaml:1:1: world.doors: expected a map of keys"},
      {"plates:\n  count: [1, 2]\n",
       "types.yaml:2:3: world.plates.count: expected an integer, got a list"},
  };
  for (const Case& c : cases) {
    CHECK(
        std::string(test::ParseErrorOf(ParseWorldOptions, c.yaml, "types.yaml", "world").what()) ==
        c.what);
  }
}

}  // namespace
}  // namespace corridorsim::worlds
