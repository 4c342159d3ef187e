#include "worlds/world_options.h"

#include "common/options_checker.h"

#include <algorithm>
#include <cstdio>

#include "worlds/layout.h"

namespace corridorsim::worlds {
namespace {

using Checker = OptionsChecker;
const auto& Num = FormatNumber;

}  // namespace

std::string LayoutName(Layout layout) {
  switch (layout) {
    case Layout::kStraight:
      return "straight";
    case Layout::kLTurn:
      return "l_turn";
    case Layout::kTJunction:
      return "t_junction";
    case Layout::kLoop:
      return "loop";
  }
  return "?";
}

std::optional<OptionsProblem> WorldOptions::Check() const {
  Checker c;
  c.Positive(length_m, "length_m");
  if (layout != Layout::kStraight) {
    c.Positive(second_length_m, "second_length_m");
    c.Require(second_length_m > width_m, "second_length_m",
              "must be longer than the corridor width (" + Num(width_m) + " m)");
  }
  c.Positive(width_m, "width_m");
  c.Positive(height_m, "height_m");
  c.Positive(wall_thickness_m, "wall_thickness_m");
  c.Require(length_m > width_m, "length_m",
            "must be longer than the corridor width (" + Num(width_m) + " m)");
  if (layout == Layout::kLoop) {  // both sides longer than twice the width: the loop has an inside
    c.Require(length_m > 2 * width_m, "length_m",
              "a loop needs both sides longer than twice the width so that it has an inside");
    c.Require(second_length_m > 2 * width_m, "second_length_m",
              "a loop needs both sides longer than twice the width so that it has an inside");
  }
  c.Require(texture_px_per_m >= 20 && texture_px_per_m <= 1000, "texture_px_per_m",
            "must lie in [20, 1000] (got " + std::to_string(texture_px_per_m) + ")");

  const DoorOptions& d = doors;
  c.Require(d.count >= 0, "doors.count", "must not be negative");
  c.Positive(d.width_m, "doors.width_m");
  c.Positive(d.height_m, "doors.height_m");
  c.Positive(d.frame_width_m, "doors.frame_width_m");
  c.Positive(d.bar_height_m, "doors.bar_height_m");
  c.NonNegative(d.frame_protrusion_m, "doors.frame_protrusion_m");
  c.Positive(d.min_gap_m, "doors.min_gap_m");
  c.NonNegative(d.open_weight, "doors.open_weight");
  c.NonNegative(d.closed_weight, "doors.closed_weight");
  c.NonNegative(d.empty_weight, "doors.empty_weight");
  c.Require(d.open_weight + d.closed_weight + d.empty_weight > 0, "doors",
            "the open, closed and empty weights must not all be 0");
  c.Positive(d.room_depth_m, "doors.room_depth_m");
  c.Positive(d.room_width_m, "doors.room_width_m");
  c.Positive(d.room_height_m, "doors.room_height_m");
  const double door_top = d.height_m + d.bar_height_m;
  c.Require(height_m > door_top, "height_m",
            "the ceiling (" + Num(height_m) + " m) is lower than the doors with their top bar (" +
                Num(door_top) + " m)");
  c.Require(d.room_height_m > door_top, "doors.room_height_m",
            "the room ceiling (" + Num(d.room_height_m) +
                " m) is lower than the doors with their top bar (" + Num(door_top) + " m)");

  const PlateOptions& p = plates;
  c.Require(p.count >= 0, "plates.count", "must not be negative");
  c.Require(p.count <= d.count, "plates.count",
            std::to_string(p.count) + " plates need a door each, but there are only " +
                std::to_string(d.count) + " doors (doors.count)");
  c.Positive(p.width_m, "plates.width_m");
  c.Positive(p.height_m, "plates.height_m");
  c.Require(p.size_jitter >= 0 && p.size_jitter < 0.5, "plates.size_jitter",
            "must lie in [0, 0.5) (got " + Num(p.size_jitter) + ")");
  c.NonNegative(p.gap_from_frame_m, "plates.gap_from_frame_m");
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
  c.Require(p.first_floor >= 0 && p.first_floor <= 9, "plates.first_floor",
            "must lie in [0, 9] (0 draws it from the seed)");

  const LampOptions& l = lamps;
  c.InRange(l.spacing_m, 0.5, 100.0, "lamps.spacing_m");
  c.Require(l.spacing_jitter_m >= 0 && l.spacing_jitter_m < l.spacing_m / 4,
            "lamps.spacing_jitter_m", "must lie in [0, spacing_m / 4)");
  c.Fraction(l.circular_fraction, "lamps.circular_fraction");
  c.Positive(l.radius_min_m, "lamps.radius_min_m");
  c.Require(l.radius_max_m >= l.radius_min_m, "lamps.radius_max_m",
            "must not be smaller than radius_min_m");
  c.Require(2 * l.radius_max_m < width_m && 2 * l.radius_max_m < l.spacing_m, "lamps.radius_max_m",
            "lamps must fit the corridor width and their spacing");
  c.Positive(l.panel_length_m, "lamps.panel_length_m");
  c.Positive(l.panel_width_m, "lamps.panel_width_m");
  c.Require(l.panel_width_m < width_m, "lamps.panel_width_m",
            "panel lamps must be narrower than the corridor (" + Num(width_m) + " m)");
  c.Require(l.panel_length_m < l.spacing_m, "lamps.panel_length_m",
            "panel lamps must be shorter than the lamp spacing (" + Num(l.spacing_m) + " m)");
  c.Fraction(l.off_fraction, "lamps.off_fraction");
  c.Fraction(l.reflector_fraction, "lamps.reflector_fraction");
  c.Require(l.reflector_height_m > 0 && l.reflector_height_m < height_m - 0.3,
            "lamps.reflector_height_m", "must be positive and end at least 0.3 m above the floor");
  c.Positive(l.reflector_length_m, "lamps.reflector_length_m");

  const CeilingOptions& ce = ceiling;
  c.Require(ce.tile_size_m >= 0.1, "ceiling.tile_size_m", "must be at least 0.1 m");
  c.Positive(ce.vent_spacing_m, "ceiling.vent_spacing_m");
  c.Positive(ce.vent_size_m, "ceiling.vent_size_m");
  const double lamp_extent = std::max(l.radius_max_m, l.panel_width_m / 2);
  c.Require(lamp_extent + 0.1 + ce.vent_size_m + 0.05 < width_m / 2, "ceiling.vent_size_m",
            "vents beside the lamps must fit between the lamps and the walls");
  c.Positive(ce.smoke_detector_spacing_m, "ceiling.smoke_detector_spacing_m");
  c.Positive(ce.sprinkler_spacing_m, "ceiling.sprinkler_spacing_m");

  const DistractorOptions& x = distractors;
  c.Require(x.posters >= 0, "distractors.posters", "must not be negative");
  c.Require(x.notice_boards >= 0, "distractors.notice_boards", "must not be negative");
  c.Require(x.bookshelves >= 0, "distractors.bookshelves", "must not be negative");
  c.Require(x.cabinets >= 0, "distractors.cabinets", "must not be negative");
  c.Require(x.fire_extinguishers >= 0, "distractors.fire_extinguishers", "must not be negative");

  // Bounds that keep generation finite and affordable (each patch, tile, lamp and texel costs).
  c.InRange(length_m, 0.0, 2000.0, "length_m");
  if (layout != Layout::kStraight) c.InRange(second_length_m, 0.0, 2000.0, "second_length_m");
  c.InRange(width_m, 0.0, 20.0, "width_m");
  c.InRange(height_m, 0.0, 20.0, "height_m");
  c.InRange(wall_thickness_m, 0.02, 1.0, "wall_thickness_m");
  c.InRange(d.count, 0, 10000, "doors.count");
  c.InRange(d.width_m, 0.0, 5.0, "doors.width_m");
  c.InRange(d.height_m, 0.0, 10.0, "doors.height_m");
  c.InRange(d.frame_width_m, 0.0, 1.0, "doors.frame_width_m");
  c.InRange(d.bar_height_m, 0.0, 1.0, "doors.bar_height_m");
  c.InRange(d.frame_protrusion_m, 0.0, 0.5, "doors.frame_protrusion_m");
  c.InRange(d.min_gap_m, 0.2, 100.0, "doors.min_gap_m");
  c.InRange(d.room_depth_m, 0.0, 20.0, "doors.room_depth_m");
  c.InRange(d.room_width_m, 0.0, 20.0, "doors.room_width_m");
  c.InRange(d.room_height_m, 0.0, 20.0, "doors.room_height_m");
  c.InRange(p.width_m, 0.02, 2.0, "plates.width_m");
  c.InRange(p.height_m, 0.02, 2.0, "plates.height_m");
  c.Require(p.width_m <= 10 * p.height_m && p.height_m <= 10 * p.width_m, "plates.height_m",
            "a plate's width and height must lie within a factor of 10 of each other");
  c.InRange(l.radius_min_m, 0.02, 2.0, "lamps.radius_min_m");
  c.InRange(l.panel_length_m, 0.05, 5.0, "lamps.panel_length_m");
  c.InRange(l.panel_width_m, 0.05, 5.0, "lamps.panel_width_m");
  c.InRange(l.reflector_length_m, 0.0, 10.0, "lamps.reflector_length_m");
  c.InRange(ce.tile_size_m, 0.1, 2.0, "ceiling.tile_size_m");
  c.InRange(ce.vent_spacing_m, 0.5, 100.0, "ceiling.vent_spacing_m");
  c.InRange(ce.vent_size_m, 0.05, 2.0, "ceiling.vent_size_m");
  c.InRange(ce.smoke_detector_spacing_m, 0.5, 100.0, "ceiling.smoke_detector_spacing_m");
  c.InRange(ce.sprinkler_spacing_m, 0.5, 100.0, "ceiling.sprinkler_spacing_m");
  for (const auto& [count, key] : {std::pair{x.posters, "distractors.posters"},
                                   {x.notice_boards, "distractors.notice_boards"},
                                   {x.bookshelves, "distractors.bookshelves"},
                                   {x.cabinets, "distractors.cabinets"},
                                   {x.fire_extinguishers, "distractors.fire_extinguishers"}}) {
    c.InRange(count, 0, 10000, key);
  }

  if (c.problem()) return c.problem();
  LayoutPlan plan;
  return PlanLayout(*this, 1, &plan);
}

void ParseWorldOptions(YamlMap& map, WorldOptions& s) {
  map.ReadEnum("layout", s.layout,
               {{"straight", Layout::kStraight},
                {"l_turn", Layout::kLTurn},
                {"t_junction", Layout::kTJunction},
                {"loop", Layout::kLoop}});
  map.Read("length_m", s.length_m);
  map.Read("second_length_m", s.second_length_m);
  map.Read("width_m", s.width_m);
  map.Read("height_m", s.height_m);
  map.Read("wall_thickness_m", s.wall_thickness_m);
  map.Read("texture_px_per_m", s.texture_px_per_m);

  YamlMap d = map.Map("doors");
  d.Read("count", s.doors.count);
  d.Read("width_m", s.doors.width_m);
  d.Read("height_m", s.doors.height_m);
  d.Read("frame_width_m", s.doors.frame_width_m);
  d.Read("bar_height_m", s.doors.bar_height_m);
  d.Read("frame_protrusion_m", s.doors.frame_protrusion_m);
  d.Read("min_gap_m", s.doors.min_gap_m);
  d.Read("open_weight", s.doors.open_weight);
  d.Read("closed_weight", s.doors.closed_weight);
  d.Read("empty_weight", s.doors.empty_weight);
  d.Read("room_depth_m", s.doors.room_depth_m);
  d.Read("room_width_m", s.doors.room_width_m);
  d.Read("room_height_m", s.doors.room_height_m);
  d.RejectUnknownKeys();

  YamlMap p = map.Map("plates");
  p.Read("count", s.plates.count);
  p.Read("center_height_m", s.plates.center_height_m);
  p.Read("width_m", s.plates.width_m);
  p.Read("height_m", s.plates.height_m);
  p.Read("size_jitter", s.plates.size_jitter);
  p.Read("gap_from_frame_m", s.plates.gap_from_frame_m);
  p.Read("first_floor", s.plates.first_floor);
  p.RejectUnknownKeys();

  YamlMap l = map.Map("lamps");
  l.Read("spacing_m", s.lamps.spacing_m);
  l.Read("spacing_jitter_m", s.lamps.spacing_jitter_m);
  l.Read("circular_fraction", s.lamps.circular_fraction);
  l.Read("radius_min_m", s.lamps.radius_min_m);
  l.Read("radius_max_m", s.lamps.radius_max_m);
  l.Read("panel_length_m", s.lamps.panel_length_m);
  l.Read("panel_width_m", s.lamps.panel_width_m);
  l.Read("off_fraction", s.lamps.off_fraction);
  l.Read("reflector_fraction", s.lamps.reflector_fraction);
  l.Read("reflector_height_m", s.lamps.reflector_height_m);
  l.Read("reflector_length_m", s.lamps.reflector_length_m);
  l.Read("room_lamps", s.lamps.room_lamps);
  l.RejectUnknownKeys();

  YamlMap c = map.Map("ceiling");
  c.Read("tile_size_m", s.ceiling.tile_size_m);
  c.Read("vent_spacing_m", s.ceiling.vent_spacing_m);
  c.Read("vent_size_m", s.ceiling.vent_size_m);
  c.Read("smoke_detector_spacing_m", s.ceiling.smoke_detector_spacing_m);
  c.Read("sprinkler_spacing_m", s.ceiling.sprinkler_spacing_m);
  c.RejectUnknownKeys();

  YamlMap x = map.Map("distractors");
  x.Read("posters", s.distractors.posters);
  x.Read("notice_boards", s.distractors.notice_boards);
  x.Read("bookshelves", s.distractors.bookshelves);
  x.Read("cabinets", s.distractors.cabinets);
  x.Read("fire_extinguishers", s.distractors.fire_extinguishers);
  x.RejectUnknownKeys();

  map.RejectUnknownKeys();
}

}  // namespace corridorsim::worlds
