// Tests worlds/world_io.cpp and worlds/map_plot.cpp on the hand-built TinyWorld.
#include "worlds/world_io.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/tiny_world.h"
#include "worlds/map_plot.h"

namespace corridorsim::worlds {
namespace {

namespace fs = std::filesystem;
using Ids = test::TinyWorldIds;

// A fresh folder under the system temp folder, removed at the end of the test.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("corridorsim_world_io_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in.good());
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every regular file under `dir`, relative to it, sorted.
std::vector<std::string> ListFiles(const fs::path& dir) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) files.push_back(fs::relative(entry.path(), dir).string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void CheckVec(const nlohmann::ordered_json& j, std::vector<double> expected) {
  REQUIRE(j.is_array());
  REQUIRE(j.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK(j[i].get<double>() == Approx(expected[i]).margin(kGroundTruthResolutionM));
  }
}

TEST_CASE("ground truth json lists every semantic entry with its values", "[worlds][world_io]") {
  const World world = test::TinyWorld();
  const nlohmann::ordered_json j = GroundTruthJson(world);

  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  CHECK(keys == std::vector<std::string>{"seed", "layout", "bounds", "door_plates", "lamps",
                                         "doors", "corridor_segments", "walls", "reflectors",
                                         "corner_points", "distractors", "counts", "appearance"});
  CHECK(j["seed"] == 7);
  CHECK(j["layout"] == "straight");
  CheckVec(j["bounds"]["min"], {-0.15, -1.35, 0.0});
  CheckVec(j["bounds"]["max"], {6.15, 5.0, 2.7});

  REQUIRE(j["door_plates"].size() == 1);
  const auto& plate = j["door_plates"][0];
  CHECK(plate["id"] == Ids::kPlate);
  CHECK(plate["door_id"] == Ids::kClosedDoor);
  CHECK(plate["room_number"] == "101");
  CheckVec(plate["center"], {2.3, -1.19, 1.6});
  CheckVec(plate["normal"], {0, 1, 0});
  CheckVec(plate["size"], {0.22, 0.12});

  REQUIRE(j["lamps"].size() == 2);
  const auto& circular = j["lamps"][0];
  CHECK(circular["shape"] == "circular");
  CHECK(circular["radius"].get<double>() == Approx(0.2));
  CHECK_FALSE(circular.contains("size"));
  CHECK_FALSE(circular.contains("room_door_id"));
  CHECK(circular["on"] == true);
  const auto& panel = j["lamps"][1];
  CHECK(panel["shape"] == "panel");
  CheckVec(panel["size"], {1.2, 0.3});
  CHECK_FALSE(panel.contains("radius"));
  CHECK(panel["on"] == false);

  REQUIRE(j["doors"].size() == 2);
  const auto& closed = j["doors"][0];
  CHECK(closed["state"] == "closed");
  CHECK(closed["wall_id"] == Ids::kRightWall);
  CheckVec(closed["column_a"], {1.0, -1.2});
  CheckVec(closed["column_b"], {1.98, -1.2});
  CheckVec(closed["inward_normal"], {0, 1});
  CHECK(closed["width"].get<double>() == Approx(0.9));
  CHECK(closed["top_height"].get<double>() == Approx(2.1));
  CHECK(closed["column_width"].get<double>() == Approx(0.08));
  CHECK(closed["room_number"] == "101");
  CHECK_FALSE(closed.contains("room"));
  const auto& open = j["doors"][1];
  CHECK(open["state"] == "open");
  REQUIRE(open.contains("room"));
  CheckVec(open["room"]["min"], {2.5, 1.35});
  CheckVec(open["room"]["max"], {5.5, 4.85});
  CHECK(open["room"]["ceiling_height"].get<double>() == Approx(2.6));

  const auto& segment = j["corridor_segments"][0];
  CheckVec(segment["start"], {0, 0});
  CheckVec(segment["end"], {6, 0});
  CheckVec(segment["direction"], {1, 0});
  CHECK(segment["width"].get<double>() == Approx(2.4));
  CHECK(segment["height"].get<double>() == Approx(2.7));

  REQUIRE(j["walls"].size() == 2);
  CheckVec(j["walls"][1]["inward_normal"], {0, -1});
  CHECK(j["walls"][1]["side_wall"] == true);
  CHECK(j["walls"][1]["segment_id"] == Ids::kSegment);

  const auto& reflector = j["reflectors"][0];
  CHECK(reflector["mirrored_lamp_id"] == Ids::kCircularLamp);
  CheckVec(reflector["apparent_lamp_center"], {3.0, -2.4, 2.7});
  CheckVec(reflector["size"], {1.0, 0.3});

  CHECK(j["corner_points"][0]["kind"] == CornerKindName(CornerKind::kTileSeam));
  CheckVec(j["corner_points"][0]["position"], {0.6, 0.6, 2.7});

  const auto& poster = j["distractors"][0];
  CHECK(poster["class"] == SemanticClassName(SemanticClass::kPoster));
  CHECK(poster["wall_id"] == Ids::kLeftWall);
  CHECK(poster["text"] == "42");
  CheckVec(poster["size"], {0.6, 0.01, 0.8});

  const auto& counts = j["counts"];
  CHECK(counts["plates"] == 1);
  CHECK(counts["lamps"] == 2);
  CHECK(counts["doors"] == 2);
  CHECK(counts["doors_open"] == 1);
  CHECK(counts["doors_closed"] == 1);
  CHECK(counts["reflectors"] == 1);
  CHECK(counts["distractors"] == 1);
  CHECK(counts["triangles"] == 4);
}

TEST_CASE("ground truth coordinates are rounded to a micrometre", "[worlds][world_io]") {
  World world = test::TinyWorld();
  world.plates[0].center = Eigen::Vector3d(2.30000049, -1e-9, 1.6000004);
  world.lamps[1].room_door_id = Ids::kOpenDoor;
  const nlohmann::ordered_json j = GroundTruthJson(world);
  const auto& center = j["door_plates"][0]["center"];
  CHECK(center[0].get<double>() == 2.3);
  CHECK(center[1].get<double>() == 0.0);
  CHECK_FALSE(std::signbit(center[1].get<double>()));
  CHECK(center[2].get<double>() == 1.6);
  CHECK(j["lamps"][1]["room_door_id"] == Ids::kOpenDoor);
  // The shortest decimal form: no 2.3000000000000003, no -0.0.
  const std::string text = j.dump();
  CHECK(text.find("[2.3,0.0,1.6]") != std::string::npos);
}

TEST_CASE("world.obj parses back with every face index in range", "[worlds][world_io]") {
  const World world = test::TinyWorld();
  const ScratchDir dir("obj");
  WriteWorldFiles(world, dir.path());

  std::size_t positions = 0, uvs = 0, normals = 0, faces = 0;
  std::set<std::string> used_materials;
  std::vector<std::string> face_lines;
  std::istringstream obj(ReadFile(dir.path() / "world.obj"));
  bool has_mtllib = false;
  for (std::string line; std::getline(obj, line);) {
    std::istringstream tokens(line);
    std::string tag;
    tokens >> tag;
    if (tag == "v") ++positions;
    if (tag == "vt") ++uvs;
    if (tag == "vn") ++normals;
    if (tag == "f") {
      ++faces;
      face_lines.push_back(line);
    }
    if (tag == "mtllib") has_mtllib = line == "mtllib world.mtl";
    if (tag == "usemtl") {
      std::string name;
      tokens >> name;
      used_materials.insert(name);
    }
  }
  std::size_t mesh_vertices = 0;
  for (const Mesh& mesh : world.meshes) mesh_vertices += mesh.positions.size();
  CHECK(has_mtllib);
  CHECK(positions == mesh_vertices);
  CHECK(uvs == mesh_vertices);
  CHECK(normals == mesh_vertices);
  CHECK(faces == world.triangle_count());

  for (const std::string& line : face_lines) {
    std::istringstream tokens(line.substr(2));
    int corners = 0;
    for (std::string corner; tokens >> corner; ++corners) {
      std::size_t v = 0, vt = 0, vn = 0;
      char slash1 = 0, slash2 = 0;
      std::istringstream parts(corner);
      parts >> v >> slash1 >> vt >> slash2 >> vn;
      INFO(line);
      CHECK(slash1 == '/');
      CHECK(slash2 == '/');
      CHECK((v >= 1 && v <= positions));
      CHECK((vt >= 1 && vt <= uvs));
      CHECK((vn >= 1 && vn <= normals));
    }
    CHECK(corners == 3);
  }

  std::set<std::string> defined_materials;
  std::istringstream mtl(ReadFile(dir.path() / "world.mtl"));
  for (std::string line; std::getline(mtl, line);) {
    std::istringstream tokens(line);
    std::string tag, value;
    tokens >> tag >> value;
    if (tag == "newmtl") defined_materials.insert(value);
    if (tag == "map_Kd") CHECK(fs::is_regular_file(dir.path() / value));
  }
  CHECK(used_materials == std::set<std::string>{"floor", "plate_101"});
  CHECK(defined_materials == used_materials);
}

TEST_CASE("WriteWorldFiles writes every file and repeats them byte for byte",
          "[worlds][world_io]") {
  const World world = test::TinyWorld();
  const ScratchDir first("first");
  const ScratchDir second("second");
  WriteWorldFiles(world, first.path());
  WriteWorldFiles(world, second.path());

  const std::vector<std::string> expected = {"ground_truth.json", "map.png",
                                             "textures/plate_101.png", "world.mtl", "world.obj"};
  CHECK(ListFiles(first.path()) == expected);  // no temporary files left behind
  for (const std::string& file : expected) {
    INFO(file);
    const std::string bytes = ReadFile(first.path() / file);
    CHECK(!bytes.empty());
    CHECK(bytes == ReadFile(second.path() / file));
  }
  CHECK(nlohmann::ordered_json::parse(ReadFile(first.path() / "ground_truth.json")) ==
        GroundTruthJson(world));
}

TEST_CASE("map size follows px_per_m", "[worlds][map_plot]") {
  const World world = test::TinyWorld();
  const Image8 small = RenderMap(world, 100.0);
  const Image8 large = RenderMap(world, 200.0);
  REQUIRE(!small.empty());
  CHECK(small.channels == 3);
  CHECK(small.data.size() == std::size_t(small.width) * small.height * 3);
  const MapView view = ComputeMapView(world, 100.0);
  CHECK(view.px_per_m == 100.0);
  CHECK(small.width == view.width_px);
  CHECK(small.height == view.height_px);
  // The plan spans x in [-0.15, 6.15] (walls included); the title and legend above and below
  // it wrap to the width, so only the width grows exactly with the scale.
  CHECK(large.width - small.width == Approx(6.3 * 100.0).margin(2.0));
  CHECK(large.height > small.height + 500);
  // Automatic scale: the longest side wants 2400 px, clamped to 80 px/m.
  CHECK(ComputeMapView(world).px_per_m == 80.0);
  CHECK_THROWS_AS(RenderMap(world, 1e6), std::invalid_argument);
}

TEST_CASE("map is deterministic and flips y so that +y is up", "[worlds][map_plot]") {
  const World world = test::TinyWorld();
  CHECK(RenderMap(world, 60.0).data == RenderMap(world, 60.0).data);
  const MapView view = ComputeMapView(world, 60.0);
  const Eigen::Vector2d origin = view.ToPixel(Eigen::Vector2d(0, 0));
  const Eigen::Vector2d left = view.ToPixel(Eigen::Vector2d(0, 1));
  const Eigen::Vector2d ahead = view.ToPixel(Eigen::Vector2d(1, 0));
  CHECK(left.y() == Approx(origin.y() - 60.0));
  CHECK(ahead.x() == Approx(origin.x() + 60.0));
}

TEST_CASE("map writes the plate's room number next to the plate", "[worlds][map_plot]") {
  const World with_number = test::TinyWorld();
  World without_number = with_number;
  without_number.plates[0].room_number.clear();
  const double px_per_m = 100.0;
  const Image8 a = RenderMap(with_number, px_per_m);
  const Image8 b = RenderMap(without_number, px_per_m);
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);

  const MapView view = ComputeMapView(with_number, px_per_m);
  const Eigen::Vector2d plate_px = view.ToPixel(with_number.plates[0].center.head<2>());
  int near = 0, far = 0, below = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      if (std::equal(a.Pixel(x, y), a.Pixel(x, y) + 3, b.Pixel(x, y))) continue;
      const bool is_near = std::abs(x - plate_px.x()) < 60 && std::abs(y - plate_px.y()) < 60;
      (is_near ? near : far) += 1;
      below += y > plate_px.y() ? 1 : 0;  // outside the right wall is -y: down in the image
    }
  }
  CHECK(near > 30);
  CHECK(far == 0);
  CHECK(below == near);
}

}  // namespace
}  // namespace corridorsim::worlds
