// render_probe: renders a hand-made textured corridor (about 3,000 triangles, lamps, 8 lights)
// at 640 x 480 with one backend and prints an FNV-1a hash of the colour, depth and id images, so
// that tests/render/lp_threads_test.cmake can compare runs under different LP_NUM_THREADS.
//
//   render_probe <osmesa|egl>                 prints "<backend> <hash>" (8 lights)
//   render_probe <osmesa|egl> --bench FRAMES  also times FRAMES draws (render + read back)
//   ... --width W                              renders W x (3/4 W) instead of 640 x 480
//   ... --lights N                             draws with the N first lights (0..16; the
//                                              corridor has 10)
//
// Exit codes: 0 ok, 2 bad arguments, 3 the backend cannot be created here.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/software_rasterizer.h"
#include "tests/support/hand_built_scene.h"

namespace {

using corridorsim::Image8;
using corridorsim::SE3;
using namespace corridorsim::render;

constexpr double kLengthM = 30.0, kHalfWidthM = 1.0, kHeightM = 2.5;
constexpr int kSegments = 30;    // drawables along the corridor, per surface
constexpr int kCellsAlong = 3;   // quads along x per segment
constexpr int kCellsAcross = 4;  // quads across each surface
constexpr double kLampSpacingM = 3.0;

Image8 Checker(int size, int cell, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image8 image(size, size, 3);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const int shade = ((x / cell) + (y / cell)) % 2 == 0 ? 0 : 60;
      std::uint8_t* p = image.Pixel(x, y);
      p[0] = std::uint8_t(std::max(0, r - shade));
      p[1] = std::uint8_t(std::max(0, g - shade));
      p[2] = std::uint8_t(std::max(0, b - shade) ^ std::uint8_t(y & 7));
    }
  }
  return image;
}

// Adds a grid of quads over a rectangle `origin + s * axis_s + t * axis_t` (s, t in [0, 1]).
void AddSurface(Scene* scene, const Eigen::Vector3f& origin, const Eigen::Vector3f& axis_s,
                const Eigen::Vector3f& axis_t, int cells_s, int cells_t, int material,
                std::uint32_t instance_id, std::uint8_t semantic_class) {
  Eigen::Vector3f normal = axis_s.cross(axis_t).normalized();
  // Face the corridor's centre line (y = 0, z = height / 2).
  const Eigen::Vector3f centre = origin + 0.5f * (axis_s + axis_t);
  const Eigen::Vector3f inward(0, -centre.y(), float(kHeightM / 2) - centre.z());
  if (normal.dot(inward) < 0) normal = -normal;
  const auto first_index = std::uint32_t(scene->indices.size());
  const auto first_vertex = std::uint32_t(scene->vertices.size());
  Eigen::AlignedBox3f bounds;
  for (int j = 0; j <= cells_t; ++j) {
    for (int i = 0; i <= cells_s; ++i) {
      const float s = float(i) / float(cells_s), t = float(j) / float(cells_t);
      const Eigen::Vector3f p = origin + s * axis_s + t * axis_t;
      // One texture repeat per metre.
      scene->vertices.push_back(
          corridorsim::test::UnlitVertex(*scene, p, normal, s * axis_s.norm(), t * axis_t.norm()));
      bounds.extend(p);
    }
  }
  for (int j = 0; j < cells_t; ++j) {
    for (int i = 0; i < cells_s; ++i) {
      const std::uint32_t a = first_vertex + std::uint32_t(j * (cells_s + 1) + i);
      const std::uint32_t b = a + 1, c = a + std::uint32_t(cells_s + 1), d = c + 1;
      for (std::uint32_t index : {a, b, d, a, d, c}) scene->indices.push_back(index);
    }
  }
  corridorsim::test::AppendDrawable(scene, first_index, bounds, material, instance_id,
                                    semantic_class);
}

Scene CorridorScene() {
  Scene scene;
  scene.textures = {Checker(256, 32, 200, 190, 170), Checker(256, 16, 120, 110, 100),
                    Checker(128, 64, 230, 230, 230)};
  SceneMaterial wall, floor, ceiling, lamp;
  wall.texture = 0;
  floor.texture = 1;
  ceiling.texture = 2;
  lamp.diffuse = Eigen::Vector3f(0.3f, 0.3f, 0.3f);
  lamp.emission = Eigen::Vector3f(1.2f, 1.2f, 1.1f);
  scene.materials = {wall, floor, ceiling, lamp};
  const float seg = float(kLengthM / kSegments), w = float(kHalfWidthM), h = float(kHeightM);
  std::uint32_t id = 1;
  for (int s = 0; s < kSegments; ++s) {
    const float x = float(s) * seg;
    const Eigen::Vector3f along(seg, 0, 0);
    AddSurface(&scene, {x, -w, 0}, along, {0, 2 * w, 0}, kCellsAlong, kCellsAcross, 1, id++, 1);
    AddSurface(&scene, {x, -w, h}, along, {0, 2 * w, 0}, kCellsAlong, kCellsAcross, 2, id++, 3);
    AddSurface(&scene, {x, w, 0}, along, {0, 0, h}, kCellsAlong, kCellsAcross, 0, id++, 2);
    AddSurface(&scene, {x, -w, 0}, along, {0, 0, h}, kCellsAlong, kCellsAcross, 0, id++, 2);
  }
  for (double x = 1.5; x < kLengthM; x += kLampSpacingM) {
    const float lx = float(x);
    AddSurface(&scene, {lx - 0.3f, -0.15f, h - 0.01f}, {0.6f, 0, 0}, {0, 0.3f, 0}, 1, 1, 3, id++,
               8);
    PointLight light;
    light.position = Eigen::Vector3f(lx, 0, h - 0.05f);
    light.intensity = Eigen::Vector3f(1, 1, 1);
    light.lamp_id = int(scene.lights.size());
    scene.lights.push_back(light);
  }
  return scene;
}

View ProbeView(int width) {
  View view;
  // Robot at x = 0.5 looking down the corridor, camera 1.2 m up, yawed 5 deg and pitched 3 deg.
  const SE3 world_from_body = SE3::FromYawPitchRoll(0.0873, 0.0524, 0.0, {0.5, 0.1, 1.2});
  Eigen::Matrix3d body_from_optical;
  body_from_optical.col(0) = Eigen::Vector3d(0, -1, 0);
  body_from_optical.col(1) = Eigen::Vector3d(0, 0, -1);
  body_from_optical.col(2) = Eigen::Vector3d(1, 0, 0);
  view.world_from_camera = world_from_body * SE3(body_from_optical, Eigen::Vector3d::Zero());
  // 640 x 480 with fx = fy = 380 px, scaled to `width` (4:3).
  const double scale = width / 640.0;
  view.width = width;
  view.height = width * 3 / 4;
  view.fx = view.fy = 380.0 * scale;
  view.cx = 0.5 * view.width - 0.5;
  view.cy = 0.5 * view.height - 0.5;
  return view;
}

std::uint64_t Fnv1a(std::uint64_t hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace

int main(int argc, char** argv) {
  PinSoftwareRasterizer();  // Mesa's environment, before any thread
  const char* usage =
      "usage: render_probe <osmesa|egl> [--bench FRAMES] [--lights N] [--width W]\n";
  if (argc < 2 || argc % 2 != 0) {
    std::fputs(usage, stderr);
    return 2;
  }
  const std::string name = argv[1];
  if (name != "osmesa" && name != "egl") {
    std::fprintf(stderr, "render_probe: unknown backend '%s' (osmesa or egl)\n", name.c_str());
    return 2;
  }
  int frames = 0, light_count = 8, width = 640;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const int value = std::atoi(argv[i + 1]);
    if (flag == "--bench" && value > 0) {
      frames = value;
    } else if (flag == "--lights" && value >= 0 && value <= 16) {
      light_count = value;
    } else if (flag == "--width" && value >= 8 && value % 4 == 0) {
      width = value;
    } else {
      std::fputs(usage, stderr);
      return 2;
    }
  }
  const BackendKind kind = name == "osmesa" ? BackendKind::kOsMesa : BackendKind::kEgl;
  std::unique_ptr<Backend> backend;
  try {
    backend = CreateBackend(kind);
  } catch (const RenderError& e) {
    std::fprintf(stderr, "render_probe: %s\n", e.what());
    return 3;
  }
  const Scene scene = CorridorScene();
  backend->Upload(scene);
  std::vector<int> drawables(scene.drawables.size());
  for (std::size_t i = 0; i < drawables.size(); ++i) drawables[i] = int(i);
  std::vector<int> lights;
  for (int i = 0; i < light_count && i < int(scene.lights.size()); ++i) lights.push_back(i);
  const View view = ProbeView(width);
  RenderedView out;
  backend->Draw(view, drawables, lights, &out);

  std::uint64_t hash = 14695981039346656037ull;
  hash = Fnv1a(hash, out.rgb.data.data(), out.rgb.data.size());
  hash = Fnv1a(hash, out.depth_m.data.data(), out.depth_m.data.size() * sizeof(float));
  hash = Fnv1a(hash, out.instance.data(), out.instance.size() * sizeof(std::uint32_t));
  hash = Fnv1a(hash, out.semantic.data(), out.semantic.size());
  std::printf("%s %016llx\n", name.c_str(), static_cast<unsigned long long>(hash));

  if (frames > 0) {
    std::vector<double> ms;
    const std::clock_t cpu_start = std::clock();
    for (int i = 0; i < frames; ++i) {
      const auto start = std::chrono::steady_clock::now();
      backend->Draw(view, drawables, lights, &out);
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
    }
    // Process CPU time (all llvmpipe threads) per frame: a load-independent measure of the work.
    const double cpu_ms = 1000.0 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC / frames;
    std::sort(ms.begin(), ms.end());
    std::printf(
        "%s: %zu triangles, %zu drawables, %zu lights, %dx%d, %d frames: wall median %.2f ms, "
        "min %.2f ms; CPU %.2f ms per frame\n",
        name.c_str(), scene.triangle_count(), drawables.size(), lights.size(), view.width,
        view.height, frames, ms[ms.size() / 2], ms.front(), cpu_ms);
  }
  return 0;
}
