#pragma once
// The files of a world: the render geometry as Wavefront OBJ/MTL with PNG textures (opens in
// MeshLab and Blender), the semantic ground truth as JSON and a top-down plan (map.png). All
// output is byte-identical for the same world.

#include <filesystem>

#include <nlohmann/json.hpp>

#include "worlds/world.h"

namespace corridorsim::worlds {

/// Every length and coordinate in ground_truth.json is rounded to this step (m), so the text is
/// stable and readable.
inline constexpr double kGroundTruthResolutionM = 1e-6;

/// The semantic ground truth of `world` in frame W (metres): seed, layout, bounds, door_plates,
/// lamps, doors, corridor_segments, walls, reflectors, corner_points, distractors and counts, in
/// that order (ordered_json keeps insertion order, so the dump is deterministic).
nlohmann::ordered_json GroundTruthJson(const World& world);

/// Writes world.obj, world.mtl, textures/<texture name>.png, ground_truth.json and map.png into
/// `dir` (created if needed). Each file is written atomically. Throws std::runtime_error naming
/// the file on I/O failure, std::invalid_argument for a world with broken references.
void WriteWorldFiles(const World& world, const std::filesystem::path& dir);

}  // namespace corridorsim::worlds
