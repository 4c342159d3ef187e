#include "worlds/world_io.h"

#include <charconv>
#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "worlds/ground_truth_fields.h"
#include "worlds/image_io.h"
#include "worlds/map_plot.h"

namespace corridorsim::worlds {
namespace {

using Json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// ground_truth.json

// Rounds to kGroundTruthResolutionM with the project's stable JSON rounding (-0 becomes 0, the
// shortest decimal text), so equal worlds print equal bytes.
static_assert(1.0 / json_steps::kMetres == kGroundTruthResolutionM);
double Rounded(double v) { return RoundToStep(v, json_steps::kMetres); }

Json Vec(const Eigen::Vector2d& v) { return RoundedJson(v, json_steps::kMetres); }
Json Vec(const Eigen::Vector3d& v) { return RoundedJson(v, json_steps::kMetres); }

// A field's value as ground_truth.json holds it: lengths and coordinates rounded, enums by name.
Json FieldJson(int v) { return v; }
Json FieldJson(bool v) { return v; }
Json FieldJson(double v) { return Rounded(v); }
Json FieldJson(const std::string& v) { return v; }
Json FieldJson(const Eigen::Vector2d& v) { return Vec(v); }
Json FieldJson(const Eigen::Vector3d& v) { return Vec(v); }
Json FieldJson(LampShape v) { return LampShapeName(v); }
Json FieldJson(DoorState v) { return DoorStateName(v); }
Json FieldJson(CornerKind v) { return CornerKindName(v); }
Json FieldJson(SemanticClass v) { return SemanticClassName(v); }

// The fields of `item` that it carries, in the order of its list (ground_truth_fields.h).
template <class T>
Json ElementJson(const T& item) {
  Json j;
  ground_truth_fields::Fields<T>::Visit([&](const char* key, auto member, const auto&... only) {
    if ((only.holds(item) && ...)) j[key] = FieldJson(std::invoke(member, item));
  });
  return j;
}

Json PlateJson(const World& world, const DoorPlate& plate) {
  Json j = ElementJson(plate);
  if (plate.texture >= 0 && plate.texture < static_cast<int>(world.textures.size())) {
    j["texture"] = "textures/" + world.textures[plate.texture].name + ".png";
    j["font"] = plate.font;
    j["border_px"] = plate.border_px;
  }
  j["number_region"] = {{"min", Vec(plate.number_min_in_face)},
                        {"max", Vec(plate.number_max_in_face)}};
  return j;
}

Json DoorJson(const Doorway& door) {
  Json j = ElementJson(door);
  if (door.room) {
    Json room;
    room["min"] = Vec(Eigen::Vector2d(door.room->footprint.min()));
    room["max"] = Vec(Eigen::Vector2d(door.room->footprint.max()));
    room["ceiling_height"] = Rounded(door.room->ceiling_height_m);
    j["room"] = std::move(room);
  }
  return j;
}

Json CountsJson(const World& world) {
  int open = 0, closed = 0, empty = 0, rooms = 0, lamps_on = 0;
  for (const Doorway& door : world.doors) {
    open += door.state == DoorState::kOpen ? 1 : 0;
    closed += door.state == DoorState::kClosed ? 1 : 0;
    empty += door.state == DoorState::kEmpty ? 1 : 0;
    rooms += door.room ? 1 : 0;
  }
  for (const Lamp& lamp : world.lamps) lamps_on += lamp.on ? 1 : 0;
  Json j;
  j["plates"] = world.plates.size();
  j["lamps"] = world.lamps.size();
  j["lamps_on"] = lamps_on;
  j["doors"] = world.doors.size();
  j["doors_open"] = open;
  j["doors_closed"] = closed;
  j["doors_empty"] = empty;
  j["rooms"] = rooms;
  j["corridor_segments"] = world.segments.size();
  j["walls"] = world.walls.size();
  j["reflectors"] = world.reflectors.size();
  j["corner_points"] = world.corner_points.size();
  j["distractors"] = world.distractors.size();
  j["meshes"] = world.meshes.size();
  j["triangles"] = world.triangle_count();
  j["materials"] = world.materials.size();
  j["textures"] = world.textures.size();
  j["collision_boxes"] = world.collision_boxes.size();
  return j;
}

template <class T, class F>
Json ArrayOf(const std::vector<T>& items, F&& to_json) {
  Json array = Json::array();
  for (const T& item : items) array.push_back(to_json(item));
  return array;
}

// ---------------------------------------------------------------------------------------------
// world.obj / world.mtl

// Fixed "%.5f"-style formatting that does not depend on the locale; -0.00000 prints as 0.00000.
void AppendFixed(std::string& out, double v) {
  char buffer[64];
  const auto [end, error] =
      std::to_chars(buffer, buffer + sizeof(buffer), v, std::chars_format::fixed, 5);
  if (error != std::errc()) throw std::invalid_argument("world.obj: number out of range");
  std::string_view text(buffer, static_cast<std::size_t>(end - buffer));
  if (text == "-0.00000") text = "0.00000";
  out += text;
}

template <class Vector>
void AppendLine(std::string& out, std::string_view tag, const Vector& v) {
  out += tag;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    out += ' ';
    AppendFixed(out, static_cast<double>(v[i]));
  }
  out += '\n';
}

// OBJ/MTL names end at whitespace: replace it.
std::string ObjName(const std::string& name, std::string_view fallback, std::size_t index) {
  if (name.empty()) return std::string(fallback) + "_" + std::to_string(index);
  std::string out = name;
  for (char& c : out) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
  }
  return out;
}

void CheckTextureNames(const World& world) {
  std::set<std::string> seen;
  for (const Texture& texture : world.textures) {
    const std::string& name = texture.name;
    const bool bad = name.empty() || name == "." || name == ".." ||
                     name.find_first_of("/\\ \t\n\r") != std::string::npos;
    if (bad) throw std::invalid_argument("texture name '" + name + "' is not a valid file stem");
    if (!seen.insert(name).second) {
      throw std::invalid_argument("texture name '" + name + "' is used twice");
    }
  }
}

std::string MtlText(const World& world) {
  std::string out = "# corridorsim world materials\n";
  for (std::size_t i = 0; i < world.materials.size(); ++i) {
    const Material& material = world.materials[i];
    const double specular = static_cast<double>(material.specular);
    out += "\nnewmtl " + ObjName(material.name, "material", i) + "\n";
    AppendLine(out, "Ka", Eigen::Vector3d::Zero());  // Blender reads Ka as metallic
    AppendLine(out, "Kd", material.diffuse);
    AppendLine(out, "Ks", Eigen::Vector3d::Constant(specular));
    AppendLine(out, "Ns", Eigen::Matrix<double, 1, 1>(10.0 + 490.0 * specular));
    AppendLine(out, "Ke", material.emission);
    out += "d 1.00000\nillum 2\n";
    if (material.texture >= 0) {
      if (material.texture >= static_cast<int>(world.textures.size())) {
        throw std::invalid_argument("material '" + material.name + "' names texture " +
                                    std::to_string(material.texture) + ", which does not exist");
      }
      out += "map_Kd textures/" + world.textures[material.texture].name + ".png\n";
    }
  }
  return out;
}

void CheckMesh(const World& world, const Mesh& mesh) {
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument("world.obj: mesh '" + mesh.name + "': " + what);
  };
  const std::size_t n = mesh.positions.size();
  if (!mesh.normals.empty() && mesh.normals.size() != n) fail("normal count != position count");
  if (!mesh.uvs.empty() && mesh.uvs.size() != n) fail("uv count != position count");
  if (mesh.indices.size() % 3 != 0) fail("index count is not a multiple of 3");
  for (const std::uint32_t index : mesh.indices) {
    if (index >= n) fail("index " + std::to_string(index) + " out of range");
  }
  if (mesh.material >= static_cast<int>(world.materials.size())) fail("material out of range");
}

std::string ObjText(const World& world) {
  std::size_t vertex_total = 0, index_total = 0;
  for (const Mesh& mesh : world.meshes) {
    CheckMesh(world, mesh);
    vertex_total += mesh.positions.size();
    index_total += mesh.indices.size();
  }
  std::string out;
  out.reserve(vertex_total * 100 + index_total * 12 + 1024);
  out += "# corridorsim world: layout " + LayoutName(world.options.layout) + ", seed " +
         std::to_string(world.seed) + "\n# frame W: x along the corridor, y left, z up; metres\n";
  out += "mtllib world.mtl\n";

  // OBJ indices are 1-based and global over the file: running offsets per attribute.
  std::size_t v_offset = 0, vt_offset = 0, vn_offset = 0;
  for (std::size_t m = 0; m < world.meshes.size(); ++m) {
    const Mesh& mesh = world.meshes[m];
    out += "\no " + ObjName(mesh.name, "mesh", m) + "\n";
    if (mesh.material >= 0) {
      out += "usemtl " +
             ObjName(world.materials[mesh.material].name, "material",
                     static_cast<std::size_t>(mesh.material)) +
             "\n";
    }
    for (const Eigen::Vector3f& p : mesh.positions) AppendLine(out, "v", p);
    for (const Eigen::Vector2f& uv : mesh.uvs) AppendLine(out, "vt", uv);
    for (const Eigen::Vector3f& n : mesh.normals) AppendLine(out, "vn", n);
    const bool has_uv = !mesh.uvs.empty();
    const bool has_normal = !mesh.normals.empty();
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      out += 'f';
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t i = mesh.indices[t + k];
        out += ' ';
        out += std::to_string(v_offset + i + 1);
        if (has_uv || has_normal) {
          out += '/';
          if (has_uv) out += std::to_string(vt_offset + i + 1);
          if (has_normal) out += '/' + std::to_string(vn_offset + i + 1);
        }
      }
      out += '\n';
    }
    v_offset += mesh.positions.size();
    vt_offset += mesh.uvs.size();
    vn_offset += mesh.normals.size();
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// PNG

// Image8 is RGB(A) with row 0 on top; OpenCV wants BGR(A). Fixed compression: same bytes each run.

}  // namespace

// What appearance randomisation drew (AppearanceDraw), multipliers to 1e-6.
Json AppearanceJson(const AppearanceDraw& d) {
  const auto rgb = [](const Eigen::Vector3f& c) {
    return Json::array({RoundToStep(c.x(), 1e6), RoundToStep(c.y(), 1e6), RoundToStep(c.z(), 1e6)});
  };
  Json j;
  j["wall"] = rgb(d.wall);
  j["floor"] = rgb(d.floor);
  j["ceiling"] = rgb(d.ceiling);
  j["door"] = rgb(d.door);
  j["lamp_brightness"] = RoundToStep(d.lamp_brightness, 1e6);
  j["lamp_temperature_k"] = RoundToStep(d.lamp_temperature_k, 1e3);
  j["lamp_colour"] = rgb(d.lamp_colour);
  j["distractor_density"] = RoundToStep(d.distractor_density, 1e6);
  j["camera_exposure"] = RoundToStep(d.camera_exposure, 1e6);
  j["camera_noise"] = RoundToStep(d.camera_noise, 1e6);
  j["camera_blur_px"] = RoundToStep(d.camera_blur_px, 1e6);
  return j;
}

nlohmann::ordered_json GroundTruthJson(const World& world) {
  Json j;
  j["seed"] = world.seed;
  j["layout"] = LayoutName(world.options.layout);
  if (world.bounds.isEmpty()) {
    j["bounds"] = nullptr;
  } else {
    j["bounds"] = {{"min", Vec(Eigen::Vector3d(world.bounds.min()))},
                   {"max", Vec(Eigen::Vector3d(world.bounds.max()))}};
  }
  j["door_plates"] = ArrayOf(world.plates, [&](const DoorPlate& p) { return PlateJson(world, p); });
  j["lamps"] = ArrayOf(world.lamps, ElementJson<Lamp>);
  j["doors"] = ArrayOf(world.doors, DoorJson);
  j["corridor_segments"] = ArrayOf(world.segments, ElementJson<CorridorSegment>);
  j["walls"] = ArrayOf(world.walls, ElementJson<Wall>);
  j["reflectors"] = ArrayOf(world.reflectors, ElementJson<Reflector>);
  j["corner_points"] = ArrayOf(world.corner_points, ElementJson<CornerPoint>);
  j["distractors"] = ArrayOf(world.distractors, ElementJson<Distractor>);
  j["counts"] = CountsJson(world);
  j["appearance"] = AppearanceJson(world.appearance);
  return j;
}

void WriteWorldFiles(const World& world, const std::filesystem::path& dir) {
  CheckTextureNames(world);
  // Build every text before writing anything, so a broken world leaves no partial folder.
  const std::string mtl = MtlText(world);
  const std::string obj = ObjText(world);
  const std::string ground_truth = JsonFileText(GroundTruthJson(world));

  EnsureWritableDirectory(dir);
  if (!world.textures.empty()) {
    const std::filesystem::path texture_dir = dir / "textures";
    EnsureWritableDirectory(texture_dir);
    std::set<std::string> written;
    for (const Texture& texture : world.textures) {
      const std::filesystem::path path = texture_dir / (texture.name + ".png");
      WriteFileAtomic(path, EncodePng(texture.image, path.string()));
      written.insert(path.filename().string());
    }
    // textures/ belongs to the world files: drop PNGs of an earlier world written here, so the
    // folder always matches world.mtl.
    for (const auto& entry : std::filesystem::directory_iterator(texture_dir)) {
      if (entry.is_regular_file() && entry.path().extension() == ".png" &&
          !written.count(entry.path().filename().string())) {
        std::filesystem::remove(entry.path());
      }
    }
  }
  WriteFileAtomic(dir / "world.mtl", mtl);
  WriteFileAtomic(dir / "world.obj", obj);
  WriteFileAtomic(dir / "ground_truth.json", ground_truth);
  const std::filesystem::path map_path = dir / "map.png";
  WriteFileAtomic(map_path, EncodePng(RenderMap(world), map_path.string()));
}

}  // namespace corridorsim::worlds
