#include "worlds/world_options.h"

#include <algorithm>
#include <cstdio>
#include <tuple>

#include "common/enum_names.h"
#include "common/io/options_yaml.h"
#include "common/options_checker.h"

#include "worlds/layout.h"

namespace corridorsim::worlds {
namespace {

using Checker = OptionsChecker;
const auto& Num = FormatNumber;

}  // namespace

constexpr EnumName<Layout> kLayoutNames[] = {{Layout::kStraight, "straight"},
                                             {Layout::kLTurn, "l_turn"},
                                             {Layout::kTJunction, "t_junction"},
                                             {Layout::kLoop, "loop"}};

std::string LayoutName(Layout layout) { return NameOf(kLayoutNames, layout); }

constexpr EnumName<WallFinish> kWallFinishNames[] = {{WallFinish::kSpeckled, "speckled"},
                                                     {WallFinish::kPlain, "plain"}};

std::string WallFinishName(WallFinish finish) { return NameOf(kWallFinishNames, finish); }

namespace {

const OptionTable<DoorOptions>& DoorOptionsTable() {
  return StaticOptionTable<DoorOptions>([](OptionTable<DoorOptions>& t) {
    using D = DoorOptions;
    t.Add("count", &D::count, "",
          "doorways on the side walls, both sides together (allocated by usable wall length)")
        .AtLeast(0, "must not be negative")
        .Range(0, 10000);
    t.Add("width_m", &D::width_m, "m", "clear opening between the two frame columns")
        .Greater(0)
        .Range(0, 5);
    t.Add("height_m", &D::height_m, "m", "top of the opening = underside of the top bar")
        .Greater(0)
        .Range(0, 10);
    t.Add("frame_width_m", &D::frame_width_m, "m", "width of each column along the wall")
        .Greater(0)
        .Range(0, 1);
    t.Add("bar_height_m", &D::bar_height_m, "m", "height of the top bar").Greater(0).Range(0, 1);
    t.Add("frame_protrusion_m", &D::frame_protrusion_m, "m",
          "how far columns and bar stand out of the wall")
        .AtLeast(0)
        .Range(0, 0.5);
    t.Add("min_gap_m", &D::min_gap_m, "m", "least wall between two doorways and from wall ends")
        .Greater(0)
        .Range(0.2, 100);
    t.Add("open_weight", &D::open_weight, "",
          "relative frequency of open doors (leaf swung into a room); a door whose room would not "
          "fit behind its wall is closed")
        .AtLeast(0)
        .Note("the three weights not all 0");
    t.Add("closed_weight", &D::closed_weight, "",
          "relative frequency of closed doors (leaf in the opening)")
        .AtLeast(0);
    t.Add("empty_weight", &D::empty_weight, "",
          "relative frequency of doorways without a leaf, into a room")
        .AtLeast(0);
    t.Add("room_depth_m", &D::room_depth_m, "m", "rooms behind open and empty doorways")
        .Greater(0)
        .Range(0, 20);
    t.Add("room_width_m", &D::room_width_m, "m", "").Greater(0).Range(0, 20);
    t.Add("room_height_m", &D::room_height_m, "m", "room ceiling height")
        .Greater(0)
        .Range(0, 20)
        .Note("above the doors with their top bar");
  });
}

const OptionTable<PlateOptions>& PlateOptionsTable() {
  return StaticOptionTable<PlateOptions>([](OptionTable<PlateOptions>& t) {
    using P = PlateOptions;
    t.Add("count", &P::count, "", "door plates, each beside its own door")
        .AtLeast(0, "must not be negative")
        .Note("at most doors.count; all textures at most 1 GiB");
    t.Add("center_height_m", &P::center_height_m, "m", "plate centre above the floor")
        .Note("plates between the floor and the ceiling");
    t.Add("width_m", &P::width_m, "m", "nominal plate size")
        .Greater(0)
        .Range(0.02, 2)
        .Note("fits beside its door within doors.min_gap_m");
    t.Add("height_m", &P::height_m, "m", "")
        .Greater(0)
        .Range(0.02, 2)
        .Note("within a factor of 10 of width_m");
    t.Add("size_jitter", &P::size_jitter, "", "relative size variation per plate")
        .RangeOpenHigh(0, 0.5);
    t.Add("gap_from_frame_m", &P::gap_from_frame_m, "m",
          "wall between the door frame and the plate")
        .AtLeast(0);
    t.Add("first_floor", &P::first_floor, "",
          "floor digit of room numbers; 0 draws it from the seed")
        .Range(0, 9, "must lie in [0, 9] (0 draws it from the seed)");
  });
}

const OptionTable<LampOptions>& LampOptionsTable() {
  return StaticOptionTable<LampOptions>([](OptionTable<LampOptions>& t) {
    using L = LampOptions;
    t.Add("spacing_m", &L::spacing_m, "m",
          "mean distance between ceiling lamps along each corridor axis")
        .Range(0.5, 100)
        .Note("lamps, vents, sprinklers, smoke detectors at most 20000 together");
    t.Add("spacing_jitter_m", &L::spacing_jitter_m, "m",
          "uniform jitter of each lamp along the axis")
        .Note("[0, spacing_m / 4)");
    t.Add("circular_fraction", &L::circular_fraction, "",
          "share of circular lamps (P3's lamp feature); the rest are panels")
        .Range(0, 1);
    t.Add("radius_min_m", &L::radius_min_m, "m", "circular lamp radius range (P3)")
        .Greater(0)
        .Range(0.02, 2);
    t.Add("radius_max_m", &L::radius_max_m, "m", "")
        .Note(">= radius_min_m; twice it below width_m and spacing_m");
    t.Add("panel_length_m", &L::panel_length_m, "m", "rectangular panel lamps (which P3 rejects)")
        .Greater(0)
        .Range(0.05, 5)
        .Note("below spacing_m");
    t.Add("panel_width_m", &L::panel_width_m, "m", "")
        .Greater(0)
        .Range(0.05, 5)
        .Note("below width_m");
    t.Add("off_fraction", &L::off_fraction, "", "lamps switched off").Range(0, 1);
    t.Add("reflector_fraction", &L::reflector_fraction, "",
          "share of circular lamps mirrored by a polished wall panel (P3 Fig. 3)")
        .Range(0, 1);
    t.Add("reflector_height_m", &L::reflector_height_m, "m",
          "that panel, reaching down from the ceiling")
        .Note("(0, height_m - 0.3)");
    t.Add("reflector_length_m", &L::reflector_length_m, "m", "its length along the wall")
        .Greater(0)
        .Range(0, 10);
    t.Add("room_lamps", &L::room_lamps, "", "one circular lamp in the ceiling of every room");
  });
}

const OptionTable<CeilingOptions>& CeilingOptionsTable() {
  return StaticOptionTable<CeilingOptions>([](OptionTable<CeilingOptions>& t) {
    using C = CeilingOptions;
    t.Add("tile_size_m", &C::tile_size_m, "m", "ceiling tiles; seam crossings are corner features")
        .AtLeast(0.1, "must be at least 0.1 m")
        .Range(0.1, 2)
        .Note("at most 1e6 tile corners over the corridors");
    t.Add("vent_spacing_m", &C::vent_spacing_m, "m",
          "square vents beside the lamps (4 corner features each)")
        .Greater(0)
        .Range(0.5, 100);
    t.Add("vent_size_m", &C::vent_size_m, "m", "")
        .Greater(0)
        .Range(0.05, 2)
        .Note("fits between the lamps and the walls");
    t.Add("smoke_detector_spacing_m", &C::smoke_detector_spacing_m, "m", "")
        .Greater(0)
        .Range(0.5, 100);
    t.Add("sprinkler_spacing_m", &C::sprinkler_spacing_m, "m", "").Greater(0).Range(0.5, 100);
    t.Add("plain_fraction", &C::plain_fraction, "",
          "chance that a stretch of corridor ceiling is plain plaster without tiles (no tile "
          "corners: P3's corner-poor places)")
        .Range(0, 1);
    t.Add("plain_stretch_m", &C::plain_stretch_m, "m",
          "length of those stretches along the corridor (each drawn plain or tiled)")
        .Greater(0)
        .Range(0.5, 100);
  });
}

const OptionTable<DistractorOptions>& DistractorOptionsTable() {
  return StaticOptionTable<DistractorOptions>([](OptionTable<DistractorOptions>& t) {
    using X = DistractorOptions;
    for (const auto& [key, member, doc] :
         {std::tuple{"posters", &X::posters, "posters with digits on the walls"},
          {"notice_boards", &X::notice_boards, "cork boards with notes carrying numbers"},
          {"bookshelves", &X::bookshelves, "door-like candidates standing against walls"},
          {"cabinets", &X::cabinets, "door-like candidates too"},
          {"fire_extinguishers", &X::fire_extinguishers, ""}}) {
      t.Add(key, member, "", doc)
          .AtLeast(0, "must not be negative")
          .Range(0, kMaxDistractors)
          .Note("all kinds together at most 2000");
    }
  });
}

}  // namespace

const OptionTable<AppearanceOptions>& AppearanceOptionsTable() {
  return StaticOptionTable<AppearanceOptions>([](OptionTable<AppearanceOptions>& t) {
    using A = AppearanceOptions;
    t.Add("surface_brightness", &A::surface_brightness, "",
          "relative spread of the wall, floor, ceiling and door colours' brightness, each drawn "
          "U(1 - s, 1 + s) per world")
        .Range(0, 0.9, "must lie in [0, 0.9]");
    t.Add("surface_tint", &A::surface_tint, "",
          "relative spread of each RGB channel of those colours (their hue), U(1 - s, 1 + s)")
        .Range(0, 0.5, "must lie in [0, 0.5]");
    t.Add("lamp_brightness", &A::lamp_brightness, "",
          "relative spread of the lamps' light, U(1 - s, 1 + s) per world")
        .Range(0, 0.9, "must lie in [0, 0.9]");
    t.Add("lamp_temperature_min_k", &A::lamp_temperature_min_k, "K",
          "lamps' colour temperature drawn in [min, max] per world (a black body's colour); "
          "0 and 0: white lamps")
        .ZeroOr(1500, 15000, "must be 0 or lie in [1500, 15000] K (got {})");
    t.Add("lamp_temperature_max_k", &A::lamp_temperature_max_k, "K", "see above")
        .ZeroOr(1500, 15000, "must be 0 or lie in [1500, 15000] K (got {})");
    t.Add("plate_colours", &A::plate_colours, "",
          "door plates in random colour pairs (luminance contrast at least 100 of 255) instead "
          "of the six palettes");
    t.Add("plate_height_jitter_m", &A::plate_height_jitter_m, "m",
          "each plate's centre height varies by U(-j, j)")
        .Range(0, 0.4, "must lie in [0, 0.4] m");
    t.Add("distractor_density", &A::distractor_density, "",
          "each distractor count is a maximum; a world keeps round(count U(1 - s, 1))")
        .Range(0, 1, "must lie in [0, 1]");
    t.Add("camera_exposure", &A::camera_exposure, "",
          "every camera's exposure gain x U(1 - s, 1 + s) per world")
        .Range(0, 0.9, "must lie in [0, 0.9]");
    t.Add("camera_noise", &A::camera_noise, "",
          "cameras with shot noise: read noise x m and full well / m, m in U(1, 1 + s) per world")
        .Range(0, 10, "must lie in [0, 10]");
    t.Add("camera_blur_max_px", &A::camera_blur_max_px, "px",
          "colour cameras' motion blur drawn U(0, max) px per world (added to their own)")
        .Range(0, 20, "must lie in [0, 20] px");
  });
}

bool AppearanceOptions::Any() const {
  return surface_brightness > 0 || surface_tint > 0 || lamp_brightness > 0 ||
         lamp_temperature_max_k > 0 || plate_colours || plate_height_jitter_m > 0 ||
         distractor_density > 0 || camera_exposure > 0 || camera_noise > 0 ||
         camera_blur_max_px > 0;
}

std::optional<OptionsProblem> AppearanceOptions::Check() const {
  if (auto problem = CheckOptionBounds(AppearanceOptionsTable(), *this)) return problem;
  if ((lamp_temperature_min_k == 0) != (lamp_temperature_max_k == 0) ||
      lamp_temperature_min_k > lamp_temperature_max_k) {
    return OptionsProblem{"lamp_temperature_max_k",
                          "lamp_temperature_min_k and lamp_temperature_max_k are both 0 (white "
                          "lamps) or a range with min <= max"};
  }
  return std::nullopt;
}

const OptionTable<WorldOptions>& WorldOptionsTable() {
  return StaticOptionTable<WorldOptions>([](OptionTable<WorldOptions>& t) {
    using W = WorldOptions;
    t.AddEnum("layout", &W::layout, kLayoutNames, "the corridor's shape (see docs/frames.md)");
    t.Add("length_m", &W::length_m, "m",
          "straight: length; L: first leg; T: main corridor; loop: extent along x (centre line)")
        .Greater(0)
        .Range(0, 2000)
        .Note("longer than width_m (loop: twice)");
    t.Add("second_length_m", &W::second_length_m, "m",
          "L: second leg (turning left); T: branch to the left from the middle; loop: extent "
          "along y")
        .Note("not straight: (0, 2000], longer than width_m (loop: twice)");
    t.Add("width_m", &W::width_m, "m", "wall to wall").Greater(0).Range(0, 20);
    t.Add("height_m", &W::height_m, "m", "floor to ceiling")
        .Greater(0)
        .Range(0, 20)
        .Note("above the doors with their top bar");
    t.Add("wall_thickness_m", &W::wall_thickness_m, "m", "").Greater(0).Range(0.02, 1);
    t.Add("texture_px_per_m", &W::texture_px_per_m, "px/m",
          "resolution of wall, floor and ceiling textures")
        .Range(20, 1000);
    t.AddEnum("wall_finish", &W::wall_finish, kWallFinishNames,
              "the corridor walls' paint: speckled (blotches, speckles, scuffs: corner features) "
              "or plain (smooth paint, next to no corners; a corner-poor corridor with "
              "ceiling.plain_fraction); rooms stay speckled");
    t.AddSection("doors", &W::doors, DoorOptionsTable(), "doorways, their frames and rooms");
    t.AddSection("plates", &W::plates, PlateOptionsTable(), "door plates");
    t.AddSection("lamps", &W::lamps, LampOptionsTable(), "ceiling lamps");
    t.AddSection("ceiling", &W::ceiling, CeilingOptionsTable(), "ceiling fixtures");
    t.AddSection("distractors", &W::distractors, DistractorOptionsTable(),
                 "objects that detectors must reject");
  });
}

std::optional<OptionsProblem> WorldOptions::Check() const {
  if (auto problem = CheckOptionBounds(WorldOptionsTable(), *this)) return problem;
  if (auto problem = appearance.Check()) {  // a scenario reports it under `appearance:`
    problem->key = "appearance." + problem->key;
    return problem;
  }
  // Rules across fields, in the order they are reported.
  Checker c;
  if (layout != Layout::kStraight) {
    c.Positive(second_length_m, "second_length_m");
    c.Require(second_length_m > width_m, "second_length_m",
              "must be longer than the corridor width (" + Num(width_m) + " m)");
  }
  c.Require(length_m > width_m, "length_m",
            "must be longer than the corridor width (" + Num(width_m) + " m)");
  if (layout == Layout::kLoop) {  // both sides longer than twice the width: the loop has an inside
    c.Require(length_m > 2 * width_m, "length_m",
              "a loop needs both sides longer than twice the width so that it has an inside");
    c.Require(second_length_m > 2 * width_m, "second_length_m",
              "a loop needs both sides longer than twice the width so that it has an inside");
  }

  const DoorOptions& d = doors;
  c.Require(d.open_weight + d.closed_weight + d.empty_weight > 0, "doors",
            "the open, closed and empty weights must not all be 0");
  const double door_top = d.height_m + d.bar_height_m;
  c.Require(height_m > door_top, "height_m",
            "the ceiling (" + Num(height_m) + " m) is lower than the doors with their top bar (" +
                Num(door_top) + " m)");
  c.Require(d.room_height_m > door_top, "doors.room_height_m",
            "the room ceiling (" + Num(d.room_height_m) +
                " m) is lower than the doors with their top bar (" + Num(door_top) + " m)");

  const PlateOptions& p = plates;
  c.Require(p.count <= d.count, "plates.count",
            std::to_string(p.count) + " plates need a door each, but there are only " +
                std::to_string(d.count) + " doors (doors.count)");
  const double max_plate_w = p.width_m * (1 + p.size_jitter);
  const double max_plate_h = p.height_m * (1 + p.size_jitter);
  c.Require(p.gap_from_frame_m + max_plate_w + 0.05 <= d.min_gap_m, "plates.width_m",
            "a plate of up to " + Num(max_plate_w) + " m beside its door (gap_from_frame_m " +
                Num(p.gap_from_frame_m) +
                ") does not fit in the wall between doors (doors.min_gap_m " + Num(d.min_gap_m) +
                ")");
  c.Require(
      p.center_height_m - max_plate_h / 2 > 0 && p.center_height_m + max_plate_h / 2 < height_m,
      "plates.center_height_m", "plates must lie between the floor and the ceiling");

  const LampOptions& l = lamps;
  c.Require(l.spacing_jitter_m >= 0 && l.spacing_jitter_m < l.spacing_m / 4,
            "lamps.spacing_jitter_m", "must lie in [0, spacing_m / 4)");
  c.Require(l.radius_max_m >= l.radius_min_m, "lamps.radius_max_m",
            "must not be smaller than radius_min_m");
  c.Require(2 * l.radius_max_m < width_m && 2 * l.radius_max_m < l.spacing_m, "lamps.radius_max_m",
            "lamps must fit the corridor width and their spacing");
  c.Require(l.panel_width_m < width_m, "lamps.panel_width_m",
            "panel lamps must be narrower than the corridor (" + Num(width_m) + " m)");
  c.Require(l.panel_length_m < l.spacing_m, "lamps.panel_length_m",
            "panel lamps must be shorter than the lamp spacing (" + Num(l.spacing_m) + " m)");
  c.Require(l.reflector_height_m > 0 && l.reflector_height_m < height_m - 0.3,
            "lamps.reflector_height_m", "must be positive and end at least 0.3 m above the floor");

  const CeilingOptions& ce = ceiling;
  const double lamp_extent = std::max(l.radius_max_m, l.panel_width_m / 2);
  c.Require(lamp_extent + 0.1 + ce.vent_size_m + 0.05 < width_m / 2, "ceiling.vent_size_m",
            "vents beside the lamps must fit between the lamps and the walls");

  // Bounds that keep generation finite and affordable (each patch, tile, lamp and texel costs).
  if (layout != Layout::kStraight) c.InRange(second_length_m, 0.0, 2000.0, "second_length_m");
  c.Require(p.width_m <= 10 * p.height_m && p.height_m <= 10 * p.width_m, "plates.height_m",
            "a plate's width and height must lie within a factor of 10 of each other");

  if (c.problem()) return c.problem();

  // Budgets: what the generator's loops and textures cost, before any of it runs.
  const WorldBudget b = WorldBudgetOf(*this);
  const DistractorOptions& x = distractors;
  const double distractor_count =
      double(x.posters) + x.notice_boards + x.bookshelves + x.cabinets + x.fire_extinguishers;
  c.Require(b.tile_corners <= kMaxTileCorners, "ceiling.tile_size_m",
            "the ceiling of " + Num(b.centre_line_m) + " m of corridor " + Num(width_m) +
                " m wide has about " + Num(b.tile_corners) + " tile corners, more than " +
                Num(kMaxTileCorners) + " (got tile_size_m " + Num(ce.tile_size_m) + ")");
  const double min_spacing = std::min(
      {l.spacing_m, ce.vent_spacing_m, ce.sprinkler_spacing_m, ce.smoke_detector_spacing_m});
  const std::string spacing_key = min_spacing == l.spacing_m         ? "lamps.spacing_m"
                                  : min_spacing == ce.vent_spacing_m ? "ceiling.vent_spacing_m"
                                  : min_spacing == ce.sprinkler_spacing_m
                                      ? "ceiling.sprinkler_spacing_m"
                                      : "ceiling.smoke_detector_spacing_m";
  c.Require(b.ceiling_fixtures <= kMaxCeilingFixtures, spacing_key,
            "lamps, vents, sprinklers and smoke detectors along " + Num(b.centre_line_m) +
                " m of corridor come to about " + Num(b.ceiling_fixtures) + ", more than " +
                Num(kMaxCeilingFixtures) + " (got " + Num(min_spacing) + " m)");
  c.Require(distractor_count <= kMaxDistractors, "distractors",
            "at most " + Num(kMaxDistractors) + " distractors of all kinds together (got " +
                Num(distractor_count) + ")");
  c.Require(b.texture_bytes <= kMaxTextureBytes,
            b.plate_texture_bytes > b.distractor_texture_bytes ? "plates.count" : "distractors",
            "the textures (walls, floor, ceiling, " + std::to_string(p.count) + " plates, " +
                Num(distractor_count) + " distractors) need " +
                Num(b.texture_bytes / double(1 << 20)) + " MiB, more than " +
                Num(kMaxTextureBytes / double(1 << 20)) + " MiB (got " +
                (b.plate_texture_bytes > b.distractor_texture_bytes
                     ? std::to_string(p.count) + " plates"
                     : Num(distractor_count) + " distractors") +
                ")");
  if (c.problem()) return c.problem();
  LayoutPlan plan;
  return PlanLayout(*this, 1, &plan);
}

WorldBudget WorldBudgetOf(const WorldOptions& o) {
  WorldBudget b;
  const bool straight = o.layout == Layout::kStraight;
  const double segments = straight ? 1 : o.layout == Layout::kLoop ? 4 : 2;
  b.centre_line_m = o.layout == Layout::kLoop ? 2 * (o.length_m + o.second_length_m)
                    : straight                ? o.length_m
                                              : o.length_m + o.second_length_m;
  // Tile seams every tile_size_m both ways over each segment's floor.
  const double tile = o.ceiling.tile_size_m;
  b.tile_corners = (b.centre_line_m / tile + segments) * (o.width_m / tile + 1);
  // Each fixture kind along every segment (one more per segment for where the row starts), and a
  // lamp per room.
  for (const double spacing : {o.lamps.spacing_m, o.ceiling.vent_spacing_m,
                               o.ceiling.sprinkler_spacing_m, o.ceiling.smoke_detector_spacing_m}) {
    b.ceiling_fixtures += b.centre_line_m / spacing + segments;
  }
  if (o.lamps.room_lamps) b.ceiling_fixtures += o.doors.count;
  // RGB texels: the base textures as the generator sizes them (worlds/generator.cpp), a plate
  // texture 128 px high with its widest aspect, and each distractor's texture 256 px wide at
  // the largest height its kind draws.
  const double px = o.texture_px_per_m;
  auto square = [](double side) { return side * side * 3; };
  b.texture_bytes = 3 * square(std::floor(px * 2.0)) + square(std::floor(px * tile) * 4) +
                    128 * 256 * 3 + square(96);
  const double jitter = o.plates.size_jitter;
  const double aspect = o.plates.width_m / o.plates.height_m * (1 + jitter) / (1 - jitter);
  b.plate_texture_bytes = o.plates.count * 128 * std::max(32.0, std::ceil(128 * aspect) + 1) * 3;
  const DistractorOptions& x = o.distractors;
  b.distractor_texture_bytes =
      256 * 3 *
      (x.bookshelves * (256 * 2.0 / 0.8 + 1) + x.cabinets * (256 * 1.9 / 0.8 + 1) +
       x.notice_boards * (256 * 0.9 / 1.2 + 1) + x.posters * (256 * 1.414 + 1));
  b.texture_bytes += b.plate_texture_bytes + b.distractor_texture_bytes;
  return b;
}

void ParseWorldOptions(YamlMap& map, WorldOptions& options) {
  ReadOptions(map, WorldOptionsTable(), options);
}

}  // namespace corridorsim::worlds
