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
/// plates, lamps, doors, reflectors and corner points, each with the fields that
/// worlds/ground_truth_fields.h lists (not a plate's texture and number region, nor a door's
/// room). Geometry, meshes, textures and the other entries stay empty. Throws InputError (nesting
/// and size bounded before parsing).
World ParseGroundTruthJson(std::string_view text, const std::string& file);

}  // namespace corridorsim::worlds
