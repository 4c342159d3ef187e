// Tests appearance randomisation (worlds::AppearanceOptions): without it a world is what it was;
// each factor draws within its range from the world seed's own stream, changes only what it
// names, and is recorded; plates keep their contrast; lamp colours follow the temperature.
#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "worlds/world.h"
#include "worlds/world_io.h"

namespace corridorsim::worlds {
namespace {

bool SameMaterials(const World& a, const World& b) {
  if (a.materials.size() != b.materials.size()) return false;
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    if (a.materials[i].diffuse != b.materials[i].diffuse ||
        a.materials[i].emission != b.materials[i].emission) {
      return false;
    }
  }
  return true;
}

bool SameGeometry(const World& a, const World& b) {
  if (a.meshes.size() != b.meshes.size()) return false;
  for (std::size_t i = 0; i < a.meshes.size(); ++i) {
    if (a.meshes[i].positions != b.meshes[i].positions) return false;
  }
  return true;
}

TEST_CASE("without appearance randomisation a world is what it was", "[worlds][appearance]") {
  const World world = Generate(WorldOptions{}, 4);
  const AppearanceDraw& d = world.appearance;
  CHECK(d.wall == Eigen::Vector3f::Ones());
  CHECK(d.floor == Eigen::Vector3f::Ones());
  CHECK(d.ceiling == Eigen::Vector3f::Ones());
  CHECK(d.door == Eigen::Vector3f::Ones());
  CHECK(d.lamp_brightness == 1.0);
  CHECK(d.lamp_temperature_k == 0.0);
  CHECK(d.lamp_colour == Eigen::Vector3f::Ones());
  CHECK(d.distractor_density == 1.0);
  CHECK(d.camera_exposure == 1.0);
  CHECK(d.camera_noise == 1.0);
  CHECK(d.camera_blur_px == 0.0);
  CHECK(!WorldOptions{}.appearance.Any());
  for (const DoorPlate& p : world.plates)
    CHECK(p.center.z() == WorldOptions{}.plates.center_height_m);
}

TEST_CASE("surface colours vary within their spread and leave everything else alone",
          "[worlds][appearance]") {
  WorldOptions options;
  options.appearance.surface_brightness = 0.3;
  options.appearance.surface_tint = 0.1;
  const World plain = Generate(WorldOptions{}, 4);
  const World varied = Generate(options, 4);
  CHECK(SameGeometry(plain, varied));
  CHECK(plain.textures.size() == varied.textures.size());
  for (std::size_t i = 0; i < plain.textures.size(); ++i) {
    CHECK(plain.textures[i].image.data == varied.textures[i].image.data);
  }
  CHECK(!SameMaterials(plain, varied));
  for (const Eigen::Vector3f& c : {varied.appearance.wall, varied.appearance.floor,
                                   varied.appearance.ceiling, varied.appearance.door}) {
    CHECK(c.minCoeff() >= 0.7f * 0.9f - 1e-6f);
    CHECK(c.maxCoeff() <= 1.3f * 1.1f + 1e-6f);
  }
  // The wall material carries the drawn multiplier.
  for (const Mesh& m : varied.meshes) {
    if (m.semantic_class != SemanticClass::kWall || m.name.rfind("wall_", 0) != 0) continue;
    CHECK(varied.materials[static_cast<std::size_t>(m.material)].diffuse == varied.appearance.wall);
    break;
  }
  // Deterministic per seed, and other seeds draw other values.
  CHECK(Generate(options, 4).appearance.wall == varied.appearance.wall);
  CHECK(Generate(options, 5).appearance.wall != varied.appearance.wall);
}

TEST_CASE("turning one factor on leaves the other factors' draws as they were",
          "[worlds][appearance]") {
  WorldOptions a, b;
  a.appearance.lamp_brightness = 0.5;
  b.appearance.lamp_brightness = 0.5;
  b.appearance.camera_exposure = 0.4;
  const World wa = Generate(a, 9), wb = Generate(b, 9);
  CHECK(wa.appearance.lamp_brightness == wb.appearance.lamp_brightness);
  CHECK(wa.appearance.lamp_brightness != 1.0);
  CHECK(wa.appearance.camera_exposure == 1.0);
  CHECK(wb.appearance.camera_exposure != 1.0);
}

TEST_CASE("lamp colour follows the drawn colour temperature", "[worlds][appearance]") {
  const Eigen::Vector3f warm = BlackBodyColour(2700), daylight = BlackBodyColour(6500),
                        cold = BlackBodyColour(12000);
  CHECK(warm.x() == 1.0f);
  CHECK(warm.z() < 0.5f * warm.x());
  CHECK(daylight.minCoeff() > 0.85f);
  CHECK(cold.z() == 1.0f);
  CHECK(cold.x() < cold.z());
  WorldOptions options;
  options.appearance.lamp_temperature_min_k = 2700;
  options.appearance.lamp_temperature_max_k = 4000;
  const World world = Generate(options, 2);
  CHECK(world.appearance.lamp_temperature_k >= 2700);
  CHECK(world.appearance.lamp_temperature_k <= 4000);
  CHECK(world.appearance.lamp_colour == BlackBodyColour(world.appearance.lamp_temperature_k));
}

TEST_CASE("random plate colours keep the number readable, and heights jitter within range",
          "[worlds][appearance]") {
  WorldOptions options;
  options.appearance.plate_colours = true;
  options.appearance.plate_height_jitter_m = 0.2;
  const World plain = Generate(WorldOptions{}, 6);
  const World world = Generate(options, 6);
  REQUIRE(world.plates.size() == plain.plates.size());
  int moved = 0;
  for (std::size_t i = 0; i < world.plates.size(); ++i) {
    const DoorPlate& p = world.plates[i];
    CHECK(std::abs(p.center.z() - options.plates.center_height_m) <= 0.2 + 1e-12);
    moved += p.center.z() != plain.plates[i].center.z();
    CHECK(p.room_number == plain.plates[i].room_number);
    CHECK(p.center.head<2>() == plain.plates[i].center.head<2>());
    // The plate texture: its two most frequent colours (plate and text) differ in luminance.
    const Image8& t = world.textures[static_cast<std::size_t>(p.texture)].image;
    const auto luma = [&](std::size_t k) {
      return 0.2126 * t.data[3 * k] + 0.7152 * t.data[3 * k + 1] + 0.0722 * t.data[3 * k + 2];
    };
    const std::size_t pixels = static_cast<std::size_t>(t.width) * t.height;
    const double background = luma(static_cast<std::size_t>(t.width) * (t.height / 2) + 1);
    double far = 0;
    for (std::size_t k = 0; k < pixels; ++k) far = std::max(far, std::abs(luma(k) - background));
    CHECK(far >= 95);  // the text (anti-aliasing rounds a little)
  }
  CHECK(moved == static_cast<int>(world.plates.size()));
  CHECK(SameMaterials(plain, world));  // plates change their textures, not the materials
}

TEST_CASE("distractor density keeps a fraction of each count", "[worlds][appearance]") {
  WorldOptions options;
  options.distractors.posters = 8;
  options.appearance.distractor_density = 0.8;
  const World world = Generate(options, 12);
  const double kept = world.appearance.distractor_density;
  CHECK(kept >= 0.2);
  CHECK(kept <= 1.0);
  const auto posters =
      std::count_if(world.distractors.begin(), world.distractors.end(),
                    [](const Distractor& d) { return d.semantic_class == SemanticClass::kPoster; });
  CHECK(posters == std::lround(8 * kept));
}

TEST_CASE("ground_truth.json records what appearance randomisation drew", "[worlds][appearance]") {
  WorldOptions options;
  options.appearance.camera_blur_max_px = 3;
  const World world = Generate(options, 1);
  const auto j = GroundTruthJson(world);
  REQUIRE(j.contains("appearance"));
  CHECK(j["appearance"]["camera_blur_px"].get<double>() ==
        Approx(world.appearance.camera_blur_px).margin(1e-6));
  CHECK(j["appearance"]["wall"].size() == 3);
}

TEST_CASE("appearance options refuse what cannot be drawn", "[worlds][appearance]") {
  AppearanceOptions a;
  a.lamp_temperature_min_k = 5000;
  a.lamp_temperature_max_k = 3000;
  REQUIRE(a.Check());
  CHECK(a.Check()->key == "lamp_temperature_max_k");
  AppearanceOptions b;
  b.lamp_temperature_min_k = 3000;  // max 0
  CHECK(b.Check());
  AppearanceOptions c;
  c.surface_brightness = 0.95;
  REQUIRE(c.Check());
  CHECK(c.Check()->key == "surface_brightness");
  WorldOptions w;
  w.appearance.camera_noise = 11;
  REQUIRE(w.Check());
  CHECK(w.Check()->key == "appearance.camera_noise");
}

}  // namespace
}  // namespace corridorsim::worlds
