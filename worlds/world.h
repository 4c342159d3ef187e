#pragma once
// World: the fixed description of a generated corridor (MuJoCo's mjModel): render geometry,
// materials and textures, collision boxes and semantic ground truth, all as plain data. It is
// built once by worlds::Generate and passed around as `const World&`.
//
// Frame W (docs/frames.md): x along the first corridor, y to the left, z up, origin on the floor
// at the start of the first corridor's centre line. All lengths in metres.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/image.h"
#include "worlds/world_options.h"

namespace corridorsim::worlds {

/// Per-pixel class of label images; values are stable (they are written into files).
enum class SemanticClass : std::uint8_t {
  kUnknown = 0,
  kFloor = 1,
  kWall = 2,
  kCeiling = 3,
  kDoorFrame = 4,  // columns and top bar
  kDoorLeaf = 5,
  kDoorPlate = 6,
  kLampCircular = 7,
  kLampPanel = 8,
  kReflector = 9,  // reflective strip and the mirrored view behind it
  kVent = 10,
  kSmokeDetector = 11,
  kSprinkler = 12,
  kPoster = 13,
  kNoticeBoard = 14,
  kBookshelf = 15,
  kCabinet = 16,
  kFireExtinguisher = 17,
  kRoom = 18,  // floor, walls and ceiling of a room behind a doorway
};
std::string SemanticClassName(SemanticClass c);

enum class DoorState { kClosed, kOpen, kEmpty };
std::string DoorStateName(DoorState s);

enum class LampShape { kCircular, kPanel };
std::string LampShapeName(LampShape s);

enum class CornerKind { kTileSeam, kVent, kSmokeDetector, kSprinkler };
std::string CornerKindName(CornerKind k);

struct Texture {
  std::string name;  // file stem, unique in the world
  Image8 image;      // RGB
};

struct Material {
  std::string name;                            // unique in the world
  Eigen::Vector3f diffuse{0.8f, 0.8f, 0.8f};   // linear RGB in [0, 1], multiplies the texture
  Eigen::Vector3f emission{0.0f, 0.0f, 0.0f};  // emitted radiance, RGB; non-zero for lit lamps
  float specular = 0.0f;                       // 0 matte .. 1 mirror-like highlight
  int texture = -1;                            // index into World::textures, -1 for none
};

/// Triangles of one object with one material. UVs are in texture repeats (GL_REPEAT).
struct Mesh {
  std::string name;
  int material = -1;    // index into World::materials
  int instance_id = 0;  // stable object id, shared with the ground-truth entry
  SemanticClass semantic_class = SemanticClass::kUnknown;
  std::vector<Eigen::Vector3f> positions;  // world frame
  std::vector<Eigen::Vector3f> normals;    // unit, world frame
  std::vector<Eigen::Vector2f> uvs;
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise from outside
  Eigen::AlignedBox3f bounds;          // of positions, for culling

  std::size_t triangle_count() const { return indices.size() / 3; }
};

/// Axis-aligned box for the physics layer (every solid of these worlds is axis-aligned).
struct CollisionBox {
  Eigen::Vector3d center;
  Eigen::Vector3d half_extents;
  int instance_id = 0;
  SemanticClass semantic_class = SemanticClass::kUnknown;
};

/// A straight piece of corridor between two points of its centre line.
struct CorridorSegment {
  int id = 0;
  Eigen::Vector2d start;  // centre line, floor level
  Eigen::Vector2d end;
  double width_m = 0.0;
  double height_m = 0.0;
  /// Unit axis direction: the vanishing direction of this corridor (P1 eq. 19).
  Eigen::Vector2d direction() const { return (end - start).normalized(); }
};

/// A straight run of corridor wall face (the boundary of the walkable area).
struct Wall {
  int id = 0;
  Eigen::Vector2d start;  // on the wall's inner face
  Eigen::Vector2d end;
  Eigen::Vector2d inward_normal;  // unit, points into the corridor; left of start->end
  int segment_id = 0;             // corridor segment the wall belongs to
  bool side_wall = false;         // parallel to its segment's axis (doors go only on these)
  double length() const { return (end - start).norm(); }
  Eigen::Vector2d tangent() const { return (end - start).normalized(); }
};

/// A room behind an open or empty doorway, with its own floor, walls and ceiling.
struct Room {
  Eigen::AlignedBox2d footprint;  // inner floor area, world x-y
  double ceiling_height_m = 0.0;
};

/// A doorway: two frame columns and a top bar (the door feature of P2/P3).
struct Doorway {
  int id = 0;
  DoorState state = DoorState::kClosed;
  int wall_id = 0;
  Eigen::Vector2d column_a;       // centre of the first column on the wall's inner face (x-y)
  Eigen::Vector2d column_b;       // centre of the second column, along the wall's tangent
  Eigen::Vector2d inward_normal;  // into the corridor
  double width_m = 0.0;           // clear opening between the columns
  double top_height_m = 0.0;      // top of the opening = underside of the top bar
  double column_width_m = 0.0;
  std::optional<Room> room;  // open and empty doorways lead into a room
  std::string room_number;   // the number of the room, whether or not it has a plate
};

struct DoorPlate {
  int id = 0;
  int door_id = 0;          // the doorway it belongs to
  std::string room_number;  // unique in the world
  Eigen::Vector3d center;   // centre of the plate's front face
  Eigen::Vector3d normal;   // unit, out of the front face (into the corridor)
  Eigen::Vector2d size_m;   // width along the wall, height
  int texture = -1;
  std::string font;   // style of the seeded plate design: Hershey font name
  int border_px = 0;  // border width on the 128 px high texture, 0 for none
  // The number region (the drawn digits' bounding box, what P1's detector finds) in the plate
  // face's own coordinates, metres: origin at `center`, x along right = z x normal, y up (+z).
  Eigen::Vector2d number_min_in_face{0, 0};
  Eigen::Vector2d number_max_in_face{0, 0};
};

struct Lamp {
  int id = 0;
  LampShape shape = LampShape::kCircular;
  Eigen::Vector3d center;        // centre of the emitting face
  double radius_m = 0.0;         // circular lamps
  Eigen::Vector2d size_m{0, 0};  // panel lamps: extent along world x and y
  bool on = true;
  int room_door_id = -1;  // lamps in a room's ceiling: the doorway of that room
};

/// A reflective strip along the top of a wall that mirrors a circular lamp (P3 Fig. 3b/3c).
/// The renderer sees the mirrored lamp through the strip; P3 treats it as a lamp.
struct Reflector {
  int id = 0;
  int wall_id = 0;
  int mirrored_lamp_id = 0;
  Eigen::Vector3d center;                // centre of the strip on the wall face
  Eigen::Vector2d size_m;                // length along the wall, height
  Eigen::Vector3d apparent_lamp_center;  // the lamp's centre mirrored in the wall plane
};

struct CornerPoint {
  int id = 0;
  CornerKind kind = CornerKind::kTileSeam;
  Eigen::Vector3d position;
};

struct Distractor {
  int id = 0;
  SemanticClass semantic_class = SemanticClass::kPoster;
  int wall_id = 0;
  Eigen::Vector3d center;  // centre of the object's box
  Eigen::Vector3d size_m;  // along the wall, out of the wall, height
  Eigen::Vector3d normal;  // unit, into the corridor
  std::string text;        // digits printed on posters and notes ("" for none)
};

/// What appearance randomisation drew for this world (AppearanceOptions); all 1 (0 for the
/// temperature and blur) without it. Recorded in ground_truth.json.
struct AppearanceDraw {
  Eigen::Vector3f wall{1, 1, 1};  // colour multipliers of the surfaces (rooms' too)
  Eigen::Vector3f floor{1, 1, 1};
  Eigen::Vector3f ceiling{1, 1, 1};
  Eigen::Vector3f door{1, 1, 1};
  double lamp_brightness = 1.0;
  double lamp_temperature_k = 0.0;       // 0: white
  Eigen::Vector3f lamp_colour{1, 1, 1};  // of that temperature, brightest channel 1
  double distractor_density = 1.0;
  double camera_exposure = 1.0;  // multiplies each camera's exposure gain
  double camera_noise = 1.0;     // read noise x, full well / (cameras with shot noise)
  double camera_blur_px = 0.0;   // motion blur added to each colour camera's
};

/// A black body's colour at `kelvin` (1500-15000 K), linear RGB with its brightest channel 1:
/// Tanner Helland's fit of black-body sRGB colours, linearised with gamma 2.2.
Eigen::Vector3f BlackBodyColour(double kelvin);

struct World {
  WorldOptions options;
  std::uint64_t seed = 0;
  AppearanceDraw appearance;

  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<CollisionBox> collision_boxes;

  // Semantic ground truth. Ids are unique across all of these and equal the instance_id of
  // the meshes that draw the object.
  std::vector<CorridorSegment> segments;
  std::vector<Wall> walls;
  std::vector<Doorway> doors;
  std::vector<DoorPlate> plates;
  std::vector<Lamp> lamps;
  std::vector<Reflector> reflectors;
  std::vector<CornerPoint> corner_points;
  std::vector<Distractor> distractors;

  Eigen::AlignedBox3d bounds;  // of all geometry

  std::size_t triangle_count() const;
};

/// Generates the world of `options` and `seed` (Check() must pass; throws OptionsError otherwise or
/// when the seeded layout cannot place what the options asks for).
World Generate(const WorldOptions& options, std::uint64_t seed);

}  // namespace corridorsim::worlds
