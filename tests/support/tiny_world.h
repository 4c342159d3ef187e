// A small World built by hand, for tests of code that consumes worlds (files, plots, renderers)
// without running the generator. Frame W: one 6 m corridor along +x, 2.4 m wide, 2.7 m high.
#pragma once

#include <cstdint>

#include "worlds/world.h"

namespace corridorsim::test {

/// Ids used by TinyWorld() (unique across all ground-truth entries, as in generated worlds).
struct TinyWorldIds {
  static constexpr int kSegment = 1;
  static constexpr int kRightWall = 2;   // y = -1.2, inward normal +y
  static constexpr int kLeftWall = 3;    // y = +1.2, inward normal -y
  static constexpr int kClosedDoor = 4;  // on the right wall, room "101", no room behind it
  static constexpr int kOpenDoor = 5;    // on the left wall, room "102" behind it
  static constexpr int kPlate = 6;       // beside the closed door, "101"
  static constexpr int kCircularLamp = 7;
  static constexpr int kPanelLamp = 8;
  static constexpr int kCorner = 9;
  static constexpr int kPoster = 10;
  static constexpr int kReflector = 11;
};

/// One 6 m straight segment, 2 side walls, a closed door (with plate "101" and its 64x32
/// texture) and an open door into a room, one circular and one panel lamp, a reflector, one
/// corner point, one poster, and two meshes (floor quad, plate quad) with two materials.
inline worlds::World TinyWorld() {
  using Eigen::Vector2d;
  using Eigen::Vector3d;
  using Eigen::Vector3f;
  using Ids = TinyWorldIds;
  worlds::World world;
  world.seed = 7;
  world.options.layout = worlds::Layout::kStraight;
  world.options.length_m = 6.0;
  world.options.width_m = 2.4;
  world.options.height_m = 2.7;
  world.options.wall_thickness_m = 0.15;

  // Plate texture: white with a black border and three dark digit-like bars.
  worlds::Texture plate_texture{"plate_101", Image8(64, 32, 3)};
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool border = x < 2 || y < 2 || x >= 62 || y >= 30;
      const bool digit = y >= 8 && y < 24 && (x % 18) >= 10 && (x % 18) < 14;
      const std::uint8_t v = (border || digit) ? 0 : 255;
      std::uint8_t* p = plate_texture.image.Pixel(x, y);
      p[0] = v;
      p[1] = v;
      p[2] = static_cast<std::uint8_t>(border ? 0 : v);
    }
  }
  world.textures.push_back(plate_texture);

  worlds::Material floor_material;
  floor_material.name = "floor";
  floor_material.diffuse = Vector3f(0.6f, 0.6f, 0.55f);
  worlds::Material plate_material;
  plate_material.name = "plate_101";
  plate_material.specular = 0.2f;
  plate_material.texture = 0;
  world.materials = {floor_material, plate_material};

  worlds::CorridorSegment segment;
  segment.id = Ids::kSegment;
  segment.start = Vector2d(0, 0);
  segment.end = Vector2d(6, 0);
  segment.width_m = 2.4;
  segment.height_m = 2.7;
  world.segments.push_back(segment);

  worlds::Wall right;
  right.id = Ids::kRightWall;
  right.start = Vector2d(0, -1.2);
  right.end = Vector2d(6, -1.2);
  right.inward_normal = Vector2d(0, 1);
  right.segment_id = Ids::kSegment;
  right.side_wall = true;
  worlds::Wall left;
  left.id = Ids::kLeftWall;
  left.start = Vector2d(6, 1.2);
  left.end = Vector2d(0, 1.2);
  left.inward_normal = Vector2d(0, -1);
  left.segment_id = Ids::kSegment;
  left.side_wall = true;
  world.walls = {right, left};

  worlds::Doorway closed;
  closed.id = Ids::kClosedDoor;
  closed.state = worlds::DoorState::kClosed;
  closed.wall_id = Ids::kRightWall;
  closed.column_a = Vector2d(1.0, -1.2);
  closed.column_b = Vector2d(1.98, -1.2);
  closed.inward_normal = Vector2d(0, 1);
  closed.width_m = 0.9;
  closed.top_height_m = 2.1;
  closed.column_width_m = 0.08;
  closed.room_number = "101";
  worlds::Doorway open;
  open.id = Ids::kOpenDoor;
  open.state = worlds::DoorState::kOpen;
  open.wall_id = Ids::kLeftWall;
  open.column_a = Vector2d(4.5, 1.2);
  open.column_b = Vector2d(3.52, 1.2);
  open.inward_normal = Vector2d(0, -1);
  open.width_m = 0.9;
  open.top_height_m = 2.1;
  open.column_width_m = 0.08;
  open.room = worlds::Room{Eigen::AlignedBox2d(Vector2d(2.5, 1.35), Vector2d(5.5, 4.85)), 2.6};
  open.room_number = "102";
  world.doors = {closed, open};

  worlds::DoorPlate plate;
  plate.id = Ids::kPlate;
  plate.door_id = Ids::kClosedDoor;
  plate.room_number = "101";
  plate.center = Vector3d(2.3, -1.19, 1.6);
  plate.normal = Vector3d(0, 1, 0);
  plate.size_m = Vector2d(0.22, 0.12);
  plate.texture = 0;
  world.plates.push_back(plate);

  worlds::Lamp circular;
  circular.id = Ids::kCircularLamp;
  circular.shape = worlds::LampShape::kCircular;
  circular.center = Vector3d(3.0, 0.0, 2.7);
  circular.radius_m = 0.2;
  worlds::Lamp panel;
  panel.id = Ids::kPanelLamp;
  panel.shape = worlds::LampShape::kPanel;
  panel.center = Vector3d(5.0, 0.0, 2.7);
  panel.size_m = Vector2d(1.2, 0.3);
  panel.on = false;
  world.lamps = {circular, panel};

  worlds::Reflector reflector;
  reflector.id = Ids::kReflector;
  reflector.wall_id = Ids::kRightWall;
  reflector.mirrored_lamp_id = Ids::kCircularLamp;
  reflector.center = Vector3d(3.0, -1.2, 2.55);
  reflector.size_m = Vector2d(1.0, 0.3);
  reflector.apparent_lamp_center = Vector3d(3.0, -2.4, 2.7);
  world.reflectors.push_back(reflector);

  world.corner_points.push_back(
      {Ids::kCorner, worlds::CornerKind::kTileSeam, Vector3d(0.6, 0.6, 2.7)});

  worlds::Distractor poster;
  poster.id = Ids::kPoster;
  poster.semantic_class = worlds::SemanticClass::kPoster;
  poster.wall_id = Ids::kLeftWall;
  poster.center = Vector3d(1.5, 1.195, 1.5);
  poster.size_m = Vector3d(0.6, 0.01, 0.8);
  poster.normal = Vector3d(0, -1, 0);
  poster.text = "42";
  world.distractors.push_back(poster);

  // Meshes: the floor (untextured) and the plate's front face (textured), counter-clockwise
  // seen from the side their normals point to.
  worlds::Mesh floor;
  floor.name = "floor_1";
  floor.material = 0;
  floor.instance_id = Ids::kSegment;
  floor.semantic_class = worlds::SemanticClass::kFloor;
  floor.positions = {Vector3f(0, -1.2f, 0), Vector3f(6, -1.2f, 0), Vector3f(6, 1.2f, 0),
                     Vector3f(0, 1.2f, 0)};
  floor.normals.assign(4, Vector3f::UnitZ());
  floor.uvs = {Eigen::Vector2f(0, 0), Eigen::Vector2f(6, 0), Eigen::Vector2f(6, 2.4f),
               Eigen::Vector2f(0, 2.4f)};
  floor.indices = {0, 1, 2, 0, 2, 3};
  worlds::Mesh plate_mesh;
  plate_mesh.name = "plate_6";
  plate_mesh.material = 1;
  plate_mesh.instance_id = Ids::kPlate;
  plate_mesh.semantic_class = worlds::SemanticClass::kDoorPlate;
  plate_mesh.positions = {Vector3f(2.41f, -1.19f, 1.54f), Vector3f(2.19f, -1.19f, 1.54f),
                          Vector3f(2.19f, -1.19f, 1.66f), Vector3f(2.41f, -1.19f, 1.66f)};
  plate_mesh.normals.assign(4, Vector3f::UnitY());
  plate_mesh.uvs = {Eigen::Vector2f(0, 0), Eigen::Vector2f(1, 0), Eigen::Vector2f(1, 1),
                    Eigen::Vector2f(0, 1)};
  plate_mesh.indices = {0, 1, 2, 0, 2, 3};
  for (worlds::Mesh* mesh : {&floor, &plate_mesh}) {
    for (const Vector3f& p : mesh->positions) mesh->bounds.extend(p);
  }
  world.meshes = {floor, plate_mesh};

  world.bounds = Eigen::AlignedBox3d(Vector3d(-0.15, -1.35, 0.0), Vector3d(6.15, 5.0, 2.7));
  return world;
}

}  // namespace corridorsim::test
