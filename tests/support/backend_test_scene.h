// The hand-built view of the backend tests (tests/render/backend_test.cpp,
// backend_egl_device_test.cpp): a tilted textured wall and a small emissive quad, seen by a camera
// whose pose is not the identity, drawn whole, and every property of its image that does not
// depend on the backend; with the tolerances of those tests.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "render/backend.h"
#include "tests/support/hand_built_scene.h"

namespace corridorsim::render::backend_tests {

// Tolerances of these tests.
inline constexpr double kDepthTolM = 1e-3;     // rendered z against the ray/plane hit
inline constexpr double kEdgeTolPx = 0.5;      // rasterised edge against the pinhole projection
inline constexpr int kCrossBackendRgbTol = 2;  // OSMesa against EGL, per channel
inline constexpr double kCrossBackendIdShare = 0.999;  // share of pixels with identical ids

inline constexpr int kWidth = 640, kHeight = 480;
inline constexpr double kF = 400.0, kCx = 320.0,
                        kCy = 240.0;          // pixel (320, 240) is on the optical axis
inline constexpr double kWallZAtAxisM = 3.0;  // camera z of the wall where the optical axis hits it
inline constexpr double kWallTan = 0.25;      // wall plane in the camera frame: z = 3 + 0.25 x
inline constexpr std::uint32_t kWallId = 7, kLampId = 9;
inline constexpr std::uint8_t kWallClass = 2, kLampClass = 7;
// Pixel edges chosen a quarter pixel off the pixel centres, so that an error of half a pixel
// moves the edge to another column or row.
inline constexpr double kWallLeftU = 161.25, kWallRightU = 427.75;  // at every row
inline constexpr double kWallTopV = 100.25, kWallBottomV = 380.75;  // at column 320 (x = 0)
inline constexpr double kLampLeftU = 280.25, kLampRightU = 360.75, kLampTopV = 30.25,
                        kLampBottomV = 80.75;
inline constexpr double kLampZM = 2.0;

// Camera at (1, 2, 0.5) in the world looking along world +x: optical x = world -y, y = world -z.
inline SE3 WorldFromCamera() {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d(0, -1, 0);
  r.col(1) = Eigen::Vector3d(0, 0, -1);
  r.col(2) = Eigen::Vector3d(1, 0, 0);
  return SE3(r, Eigen::Vector3d(1, 2, 0.5));
}

inline View TestView() {
  View view;
  view.world_from_camera = WorldFromCamera();
  view.width = kWidth;
  view.height = kHeight;
  view.fx = view.fy = kF;
  view.cx = kCx;
  view.cy = kCy;
  return view;
}

// Camera z where the pixel ray through (u, v) meets the wall plane z = z0 + tan * x.
inline double WallZAtPixel(double u) { return kWallZAtAxisM / (1.0 - (u - kCx) / kF * kWallTan); }

// A quad given by camera-frame corners (bottom-left, bottom-right, top-right, top-left as seen
// in the image), appended with UVs (0,0) at the bottom-left and (1,1) at the top-right.
inline void AddQuad(Scene* scene, const std::array<Eigen::Vector3d, 4>& corners_in_camera,
                    int material, std::uint32_t instance_id, std::uint8_t semantic_class) {
  const SE3 world_from_camera = WorldFromCamera();
  const Eigen::Vector3d e1 = corners_in_camera[1] - corners_in_camera[0];
  const Eigen::Vector3d e2 = corners_in_camera[3] - corners_in_camera[0];
  // Facing the camera (towards -z); y points down in the optical frame, so the order flips.
  Eigen::Vector3d n_in_camera = e2.cross(e1).normalized();
  if (n_in_camera.z() > 0) n_in_camera = -n_in_camera;
  const Eigen::Vector3d n_in_world = world_from_camera.rotation() * n_in_camera;
  constexpr float kUv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const auto first_vertex = std::uint32_t(scene->vertices.size());
  const auto first_index = std::uint32_t(scene->indices.size());
  Eigen::AlignedBox3f bounds;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f p = (world_from_camera * corners_in_camera[i]).cast<float>();
    scene->vertices.push_back(
        test::UnlitVertex(*scene, p, n_in_world.cast<float>(), kUv[i][0], kUv[i][1]));
    bounds.extend(p);
  }
  for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) scene->indices.push_back(first_vertex + i);
  test::AppendDrawable(scene, first_index, bounds, material, instance_id, semantic_class);
}

// Wall (drawable 0, textured: top half red, bottom half green), lamp quad (drawable 1, emissive),
// one light between the camera and the wall.
inline Scene TestScene() {
  Scene scene;
  Image8 texture(64, 64, 3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      std::uint8_t* p = texture.Pixel(x, y);
      const bool top = y < 32;
      const bool check = ((x / 8) + (y / 8)) % 2 == 0;
      p[0] = std::uint8_t(top ? (check ? 230 : 180) : 30);
      p[1] = std::uint8_t(top ? 30 : (check ? 230 : 180));
      p[2] = 30;
    }
  }
  scene.textures.push_back(texture);
  SceneMaterial wall;
  wall.diffuse = Eigen::Vector3f(0.8f, 0.8f, 0.8f);
  wall.texture = 0;
  SceneMaterial lamp;
  lamp.diffuse = Eigen::Vector3f(0.2f, 0.2f, 0.2f);
  lamp.emission = Eigen::Vector3f(1.5f, 1.5f, 1.5f);
  scene.materials = {wall, lamp};

  // Wall: vertical edges at constant u; top and bottom edges at constant camera y.
  const double y_top = (kWallTopV - kCy) / kF * kWallZAtAxisM;
  const double y_bottom = (kWallBottomV - kCy) / kF * kWallZAtAxisM;
  const double z_left = WallZAtPixel(kWallLeftU), z_right = WallZAtPixel(kWallRightU);
  const double x_left = (kWallLeftU - kCx) / kF * z_left;
  const double x_right = (kWallRightU - kCx) / kF * z_right;
  AddQuad(&scene,
          {Eigen::Vector3d(x_left, y_bottom, z_left), Eigen::Vector3d(x_right, y_bottom, z_right),
           Eigen::Vector3d(x_right, y_top, z_right), Eigen::Vector3d(x_left, y_top, z_left)},
          0, kWallId, kWallClass);

  auto lamp_point = [](double u, double v) {
    return Eigen::Vector3d((u - kCx) / kF * kLampZM, (v - kCy) / kF * kLampZM, kLampZM);
  };
  AddQuad(&scene,
          {lamp_point(kLampLeftU, kLampBottomV), lamp_point(kLampRightU, kLampBottomV),
           lamp_point(kLampRightU, kLampTopV), lamp_point(kLampLeftU, kLampTopV)},
          1, kLampId, kLampClass);

  PointLight light;
  light.position = (WorldFromCamera() * Eigen::Vector3d(0.2, -0.3, 1.0)).cast<float>();
  light.intensity = Eigen::Vector3f(1.0f, 1.0f, 1.0f);
  light.lamp_id = 1;
  scene.lights.push_back(light);
  return scene;
}

inline const std::vector<int> kAllDrawables = {0, 1};
inline const std::vector<int> kAllLights = {0};

inline RenderedView Render(Backend& backend, const View& view = TestView()) {
  RenderedView out;
  backend.Draw(view, kAllDrawables, kAllLights, &out);
  return out;
}

inline std::size_t Index(int x, int y) { return std::size_t(y) * kWidth + x; }

// Checks every property of the test image that does not depend on the backend.
inline void CheckTestImage(const RenderedView& image) {
  REQUIRE(image.rgb.width == kWidth);
  REQUIRE(image.rgb.height == kHeight);
  REQUIRE(image.rgb.channels == 3);
  REQUIRE(image.rgb.data.size() == std::size_t(kWidth) * kHeight * 3);
  REQUIRE(image.depth_m.width == kWidth);
  REQUIRE(image.depth_m.height == kHeight);
  REQUIRE(image.instance.size() == std::size_t(kWidth) * kHeight);
  REQUIRE(image.semantic.size() == std::size_t(kWidth) * kHeight);

  // Depth: on the optical axis the wall is exactly 3 m away; elsewhere z of the ray/plane hit.
  CHECK(image.depth_m.at(320, 240) == Approx(kWallZAtAxisM).margin(kDepthTolM));
  for (const auto& [u, v] : {std::pair{200, 300}, std::pair{410, 130}, std::pair{170, 370}}) {
    INFO("pixel " << u << ", " << v);
    CHECK(image.depth_m.at(u, v) == Approx(WallZAtPixel(u)).margin(kDepthTolM));
  }
  CHECK(image.depth_m.at(320, 50) == Approx(kLampZM).margin(kDepthTolM));
  CHECK(image.depth_m.at(5, 5) == 0.0f);
  CHECK(image.depth_m.at(630, 470) == 0.0f);

  // Ids on the wall and the lamp, 0 around them.
  CHECK(image.instance[Index(320, 240)] == kWallId);
  CHECK(image.semantic[Index(320, 240)] == kWallClass);
  CHECK(image.instance[Index(320, 50)] == kLampId);
  CHECK(image.semantic[Index(320, 50)] == kLampClass);
  CHECK(image.instance[Index(5, 5)] == 0);
  CHECK(image.semantic[Index(5, 5)] == 0);
  CHECK(image.instance[Index(600, 240)] == 0);

  // Edges land where the pinhole model puts them: the first covered column c has its centre
  // (u = c) right of the projected edge and the one before it left of it.
  // Walks from pixel (x, y) in steps (dx, dy) to the image border; the walked coordinate of the
  // first pixel showing `id`, or -1.
  auto first_along = [&](int x, int y, int dx, int dy, std::uint32_t id) {
    for (; x >= 0 && x < kWidth && y >= 0 && y < kHeight; x += dx, y += dy) {
      if (image.instance[Index(x, y)] == id) return dx != 0 ? x : y;
    }
    return -1;
  };
  auto first_column_with = [&](int row, std::uint32_t id) { return first_along(0, row, 1, 0, id); };
  auto last_column_with = [&](int row, std::uint32_t id) {
    return first_along(kWidth - 1, row, -1, 0, id);
  };
  auto first_row_with = [&](int column, std::uint32_t id) {
    return first_along(column, 0, 0, 1, id);
  };
  auto last_row_with = [&](int column, std::uint32_t id) {
    return first_along(column, kHeight - 1, 0, -1, id);
  };
  for (int row : {150, 240, 330}) {
    INFO("row " << row);
    const int left = first_column_with(row, kWallId);
    const int right = last_column_with(row, kWallId);
    CHECK(std::abs((left - 0.5) - kWallLeftU) <= kEdgeTolPx);
    CHECK(std::abs((right + 0.5) - kWallRightU) <= kEdgeTolPx);
    CHECK(left == int(std::ceil(kWallLeftU)));
    CHECK(right == int(std::floor(kWallRightU)));
  }
  CHECK(first_row_with(320, kWallId) == int(std::ceil(kWallTopV)));
  CHECK(last_row_with(320, kWallId) == int(std::floor(kWallBottomV)));
  CHECK(first_column_with(50, kLampId) == int(std::ceil(kLampLeftU)));
  CHECK(last_column_with(50, kLampId) == int(std::floor(kLampRightU)));
  CHECK(first_row_with(320, kLampId) == int(std::ceil(kLampTopV)));
  CHECK(last_row_with(320, kLampId) == int(std::floor(kLampBottomV)));
  // The wall's top edge is at constant camera y: away from the axis it projects to
  // v = fy y / z + cy with the z of that column.
  for (int column : {170, 420}) {
    INFO("column " << column);
    const double y_top = (kWallTopV - kCy) / kF * kWallZAtAxisM;
    const double v_top = kF * y_top / WallZAtPixel(column) + kCy;
    CHECK(std::abs((first_row_with(column, kWallId) - 0.5) - v_top) <= kEdgeTolPx);
  }
}

}  // namespace corridorsim::render::backend_tests
