#pragma once
// Procedurally drawn, seeded textures (RGB, row 0 on top). Surfaces carry enough texture that
// corner detectors find features; plates carry legible room numbers in seeded styles.

#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/image.h"
#include "common/random.h"

namespace corridorsim::worlds {

/// Painted plaster: a seeded pale colour, blotches, speckles and scuffs. Covers period_px square.
Image8 MakeWallTexture(RandomStream& rng, int size_px);
/// Smooth paint without speckles or scuffs (world.wall_finish: plain): a seeded pale colour with
/// faint large blotches, next to no corner features.
Image8 MakePlainWallTexture(RandomStream& rng, int size_px);
/// Linoleum tiles with seams and speckles; `tiles` tiles across the texture.
Image8 MakeFloorTexture(RandomStream& rng, int size_px, int tiles);
/// Suspended-ceiling tiles: `tiles` x `tiles` tiles with dark seams on tile borders (the seam
/// crossings are corner features) and perforation dots.
Image8 MakeCeilingTexture(RandomStream& rng, int size_px, int tiles);
/// Smooth plaster ceiling of a room, with faint speckles.
Image8 MakeRoomCeilingTexture(RandomStream& rng, int size_px);
/// Wood grain for door leaves.
Image8 MakeDoorTexture(RandomStream& rng, int width_px, int height_px);

struct PlateStyle {
  std::string font;  // Hershey font name
  int border_px = 0;
  int width_px = 0;  // texture size
  int height_px = 0;
  // The number region: the bounding box of the drawn text pixels, texture px (x right, y down,
  // row 0 on top), min inclusive, max exclusive. Measured from the drawn image: draws nothing.
  int number_x0_px = 0, number_y0_px = 0, number_x1_px = 0, number_y1_px = 0;
};
/// A door plate showing `room_number` in a seeded style; aspect = width / height of the plate.
/// `colours` (plate, text; RGB 0-255) replace the palette's (appearance randomisation); the
/// palette is drawn either way, so the stream stays where it would be.
Image8 MakePlateTexture(
    RandomStream& rng, const std::string& room_number, double aspect, PlateStyle* style,
    const std::optional<std::array<Eigen::Vector3d, 2>>& colours = std::nullopt);
/// A poster with a headline, blocks of colour and a number (`text`).
Image8 MakePosterTexture(RandomStream& rng, const std::string& text, int width_px, int height_px);
/// A cork notice board with pinned notes, one of which shows `text`.
Image8 MakeNoticeBoardTexture(RandomStream& rng, const std::string& text, int width_px,
                              int height_px);
/// Front of a bookshelf: shelves with rows of book spines.
Image8 MakeBookshelfTexture(RandomStream& rng, int width_px, int height_px);
/// Front of a metal cabinet: two doors, handles, a label.
Image8 MakeCabinetTexture(RandomStream& rng, int width_px, int height_px);
/// A ventilation grille.
Image8 MakeVentTexture(int size_px);

}  // namespace corridorsim::worlds
