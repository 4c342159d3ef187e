#pragma once
// WorldOptions: everything that shapes a procedurally generated corridor world. Defaults in code
// reproduce P1's corridor (55 m long, 2.4 m wide, 2.7 m high, 14 door plates); a scenario's
// `world:` section overrides what it names.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"

namespace corridorsim::worlds {

enum class Layout { kStraight, kLTurn, kTJunction, kLoop };
/// The corridor walls' paint: speckled (blotches, speckles and scuffs: corner features) or plain
/// (smooth paint, next to no corners). Rooms keep the speckled paint.
enum class WallFinish { kSpeckled, kPlain };

struct DoorOptions {
  int count = 16;                    // doorways along the side walls, both sides together
  double width_m = 0.9;              // clear opening between the two frame columns
  double height_m = 2.1;             // top of the opening = underside of the top bar
  double frame_width_m = 0.08;       // width of each column along the wall
  double bar_height_m = 0.08;        // height of the top bar above the opening
  double frame_protrusion_m = 0.03;  // how far columns and bar stand out of the wall face
  double min_gap_m = 1.2;            // minimum wall between two doorways, and from wall ends
  double open_weight = 0.3;          // relative frequency of open doors (leaf swung into the room)
  double closed_weight = 0.5;        // relative frequency of closed doors (leaf in the opening)
  double empty_weight = 0.2;         // relative frequency of doorways without a leaf
  double room_depth_m = 3.5;         // rooms behind open and empty doorways
  double room_width_m = 3.0;
  double room_height_m = 2.6;  // room ceiling height (may differ from the corridor's)
};

struct PlateOptions {
  int count = 14;                // door plates, each beside its own door (P1: 14)
  double center_height_m = 1.6;  // height of the plate centre above the floor
  double width_m = 0.22;         // nominal plate size; each plate varies by +-size_jitter
  double height_m = 0.12;
  double size_jitter = 0.15;      // relative size variation, in [0, 0.5)
  double gap_from_frame_m = 0.1;  // wall between the door frame and the plate edge
  int first_floor = 0;            // floor digit of room numbers; 0 draws it from the seed
};

struct LampOptions {
  double spacing_m = 3.0;          // mean distance between ceiling lamps along a corridor axis
  double spacing_jitter_m = 0.3;   // uniform jitter of each lamp's position along the axis
  double circular_fraction = 0.7;  // circular lamps (P3's lamp feature); the rest are panels
  double radius_min_m = 0.15;      // circular lamp radius range (P3)
  double radius_max_m = 0.3;
  double panel_length_m = 1.2;  // rectangular panel lamps (rejected by P3's detector)
  double panel_width_m = 0.3;
  double off_fraction = 0.0;  // lamps switched off (dark scenarios)
  double reflector_fraction =
      0.15;  // circular lamps mirrored by a reflective wall strip (P3 Fig. 3)
  double reflector_height_m = 1.5;  // polished wall panel reaching down from the ceiling
  double reflector_length_m = 2.0;  // its length along the wall, centred on the lamp
  bool room_lamps = true;           // one circular lamp in the ceiling of every room
};

struct CeilingOptions {
  double tile_size_m = 0.6;     // ceiling tiles; their seam crossings are corner features
  double vent_spacing_m = 8.0;  // mean spacing of square vents along each corridor axis
  double vent_size_m = 0.45;
  double smoke_detector_spacing_m = 10.0;
  double sprinkler_spacing_m = 3.6;
  // Stretches of plain (plastered) ceiling without tiles: corner-poor places like those where
  // P3's corner-only SLAM "observed only a few" corners (P3 section V, Fig. 18a).
  double plain_fraction = 0.0;   // chance that a stretch of the corridor ceiling is plain
  double plain_stretch_m = 4.0;  // length of each stretch along the corridor
};

struct DistractorOptions {
  int posters = 4;        // posters with digits on the walls
  int notice_boards = 2;  // cork boards with notes carrying numbers
  int bookshelves = 2;    // door-like candidates standing against walls
  int cabinets = 2;
  int fire_extinguishers = 3;
};

/// Appearance randomisation (domain randomisation): what varies from world to world, drawn from
/// the world seed's own streams ("worlds.appearance", and "worlds.appearance.plate" per plate), so
/// the layout, lamps and textures draw what they draw without it. Every spread 0 (the defaults)
/// leaves a world as it is without randomisation. World::appearance records what was drawn.
struct AppearanceOptions {
  double surface_brightness = 0.0;      // wall, floor, ceiling, door colours x U(1 - s, 1 + s) each
  double surface_tint = 0.0;            // and each RGB channel of them x U(1 - s, 1 + s) (hue)
  double lamp_brightness = 0.0;         // every lamp's light and brightness x U(1 - s, 1 + s)
  double lamp_temperature_min_k = 0.0;  // lamps' colour temperature U(min, max) K; 0: white
  double lamp_temperature_max_k = 0.0;
  bool plate_colours = false;          // plates in random colour pairs of high contrast
  double plate_height_jitter_m = 0.0;  // each plate's centre height + U(-j, j)
  double distractor_density = 0.0;     // each distractor count x U(1 - s, 1) (counts are maxima)
  double camera_exposure = 0.0;        // every camera's exposure gain x U(1 - s, 1 + s)
  double camera_noise = 0.0;  // noisy cameras' read noise x m and full well / m, m in U(1, 1 + s)
  double camera_blur_max_px = 0.0;  // colour cameras' motion blur U(0, max) px (horizontal)

  std::optional<OptionsProblem> Check() const;
  /// Whether anything varies (a spread, a temperature range or plate colours is set).
  bool Any() const;
};

/// The keys of a scenario's `appearance:` map.
const OptionTable<AppearanceOptions>& AppearanceOptionsTable();

struct WorldOptions {
  Layout layout = Layout::kStraight;
  // Corridor centre-line lengths. straight: length_m. L-turn: first leg length_m, second leg
  // (turning left) second_length_m. T-junction: main corridor length_m, branch to the left from
  // its middle second_length_m. loop: rectangle of length_m (x) by second_length_m (y).
  double length_m = 55.0;
  double second_length_m = 20.0;
  double width_m = 2.4;   // wall to wall
  double height_m = 2.7;  // floor to ceiling
  double wall_thickness_m = 0.15;
  int texture_px_per_m = 200;  // resolution of wall, floor and ceiling textures
  WallFinish wall_finish = WallFinish::kSpeckled;
  DoorOptions doors;
  PlateOptions plates;
  LampOptions lamps;
  CeilingOptions ceiling;
  DistractorOptions distractors;
  AppearanceOptions appearance;  // the scenario's `appearance:` section

  /// The first problem that makes this options impossible to generate, or nothing.
  std::optional<OptionsProblem> Check() const;
};

/// What a world costs, estimated from its options before it is generated (upper bounds where
/// the generator's counts depend on the seed). WorldOptions::Check refuses more than the
/// budgets below, naming the key that sets the count.
struct WorldBudget {
  double centre_line_m = 0;             // corridor centre lines together
  double tile_corners = 0;              // ceiling tile seam crossings (ground-truth corner points)
  double ceiling_fixtures = 0;          // lamps, vents, sprinklers and smoke detectors
  double texture_bytes = 0;             // RGB texels of every texture (base, plates, distractors)
  double plate_texture_bytes = 0;       // of those, the door plates'
  double distractor_texture_bytes = 0;  // and the distractors'
};
WorldBudget WorldBudgetOf(const WorldOptions& options);

/// Budgets: the generator tests every tile corner and every fixture against the fixtures placed
/// before it, and keeps every texture in memory (the renderer uploads a copy).
inline constexpr double kMaxTileCorners = 1'000'000;
inline constexpr double kMaxCeilingFixtures = 20'000;
inline constexpr double kMaxDistractors = 2'000;  // all kinds together
inline constexpr double kMaxTextureBytes = double(1 << 30);

/// The keys of a `world:` map: parsing, bounds, the echo and docs/scenarios.md's tables.
const OptionTable<WorldOptions>& WorldOptionsTable();

/// Reads the keys present in a `world:` map onto `options` (STYLE item 4). Unknown keys, wrong
/// types: InputError. Call `Check()` after all files of an include chain are applied.
void ParseWorldOptions(YamlMap& map, WorldOptions& options);

std::string LayoutName(Layout layout);
std::string WallFinishName(WallFinish finish);

}  // namespace corridorsim::worlds
