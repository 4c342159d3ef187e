#pragma once
// Reading a world's semantic ground truth back from ground_truth.json (a run folder's world.json,
// the same document): what scoring a map needs without regenerating the world, e.g. `corridorsim
// evaluate` scoring a landmark map offline. The file is one corridorsim wrote, but it is read as
// user input: every missing or mistyped field is an InputError naming the file and the field.

#include <string>
#include <string_view>

#include "worlds/world.h"

namespace corridorsim::worlds {

/// The landmark truth of `text` (the contents of `file`, GroundTruthJson's document): seed, door
/// plates (id, door_id, room_number, center, normal, size), lamps (id, shape, center, radius or
/// size, on, room_door_id), doors (id, state, columns, top_height, width, column_width,
/// inward_normal, room_number), reflectors (id, wall_id, mirrored_lamp_id, center, size,
/// apparent_lamp_center) and corner points (id, kind, position). Geometry, meshes, textures and
/// the other entries stay empty. Throws InputError (nesting and size bounded before parsing).
World ParseGroundTruthJson(std::string_view text, const std::string& file);

}  // namespace corridorsim::worlds
