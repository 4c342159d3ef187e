// Rendering a generated world through the rig: exact depth against known walls, labels against
// geometry, ground-truth points where they appear in the image, determinism and memory.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include <catch2/catch.hpp>

#include "render/backend.h"
#include "render/camera_budget.h"
#include "render/camera_placement.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "render/scene.h"
#include "tests/support/tolerances.h"
#include "worlds/world.h"

namespace corridorsim::render {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDeg = std::numbers::pi / 180.0;

struct Fixture {
  worlds::World world = worlds::Generate(worlds::WorldOptions{}, 7);
  Scene scene = BuildScene(world);
  std::unique_ptr<Backend> backend = CreateBackend(BackendKind::kOsMesa);
  Fixture() { backend->Upload(scene); }
};

Fixture& Shared() {
  static Fixture f;
  return f;
}

CameraOptions Exact(CameraOptions camera_options) {
  camera_options.noise = false;
  return camera_options;
}

// A camera with a forward pinhole at `world_from_camera`, rendered exactly.
CameraFrame RenderWith(const CameraOptions& camera_options, const SE3& world_from_camera) {
  CameraRenderer camera(Exact(camera_options));
  CameraFrame frame;
  camera.Render(Shared().scene, *Shared().backend, world_from_camera, &frame);
  return frame;
}

// The ground truth of a rendered frame, with its labels for occlusion.
FrameTruth TruthOf(const CameraOptions& camera_options, const CameraFrame& frame,
                   const SE3& world_from_robot) {
  FrameTruthInput input;
  input.world = &Shared().world;
  input.camera_id = camera_options.id;
  input.model = camera_options.model;
  input.world_from_camera = frame.world_from_camera;
  input.world_from_robot = world_from_robot;
  input.instance = &frame.instance;
  return ComputeFrameTruth(input);
}

// Distance along the optical axis to the plane {p : n.p = d} for the ray through pixel (u, v).
double DepthToPlane(const PinholeRadTan& k, const SE3& world_from_camera, double u, double v,
                    const Vector3d& n, double d) {
  const Vector3d ray_c((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
  const Vector3d ray_w = world_from_camera.rotation() * ray_c;
  const Vector3d c = world_from_camera.translation();
  const double t = (d - n.dot(c)) / n.dot(ray_w);
  return t;  // ray_c has z = 1, so t is the depth along the optical axis
}

TEST_CASE("noise-free depth equals the distance to the known walls within 1 mm", "[render][gl]") {
  const worlds::World& world = Shared().world;
  const CameraOptions camera_options = RigOptions::Default().cameras[0];
  const PinholeRadTan& k = *camera_options.model.pinhole();
  // A robot at x = 20 looking along +x; the camera is 0.45 m up.
  const SE3 world_from_robot = SE3::FromSE2(SE2(20.0, 0.0, 0.0));
  const SE3 world_from_camera = world_from_robot * camera_options.mount.RobotFromCamera();
  const CameraFrame frame = RenderWith(camera_options, world_from_camera);
  REQUIRE(frame.depth_m.width == k.width);
  int checked = 0;
  for (int v = 0; v < k.height; v += 9) {
    for (int u = 0; u < k.width; u += 11) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      const auto cls = static_cast<worlds::SemanticClass>(frame.semantic[i]);
      double expected = -1;
      if (cls == worlds::SemanticClass::kFloor) {
        expected = DepthToPlane(k, world_from_camera, u, v, Vector3d::UnitZ(), 0.0);
      } else if (cls == worlds::SemanticClass::kCeiling) {
        expected =
            DepthToPlane(k, world_from_camera, u, v, Vector3d::UnitZ(), world.options.height_m);
      } else if (cls == worlds::SemanticClass::kWall) {
        // Side walls at y = +-width/2 (their faces); the end wall at x = length.
        const Vector3d ray =
            world_from_camera.rotation() * Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
        const Vector3d c = world_from_camera.translation();
        const double tl = (world.options.width_m / 2 - c.y()) / ray.y();
        const double tr = (-world.options.width_m / 2 - c.y()) / ray.y();
        const double te = (world.options.length_m - c.x()) / ray.x();
        double t = 1e9;
        for (const double cand : {tl, tr, te}) {
          if (cand > 0 && cand < t) t = cand;
        }
        expected = t;
      } else {
        continue;
      }
      INFO("pixel " << u << "," << v << " class " << int(frame.semantic[i]));
      CHECK(std::abs(frame.depth_m.data[i] - expected) < 1e-3);
      ++checked;
    }
  }
  CHECK(checked > 1000);
}

TEST_CASE("label images agree with the geometry", "[render][gl]") {
  const CameraOptions camera_options = RigOptions::Default().cameras[0];
  const PinholeRadTan& k = *camera_options.model.pinhole();
  const SE3 world_from_camera =
      SE3::FromSE2(SE2(20.0, 0.0, 0.0)) * camera_options.mount.RobotFromCamera();
  const CameraFrame frame = RenderWith(camera_options, world_from_camera);
  const std::size_t centre = static_cast<std::size_t>(k.height / 2) * k.width + k.width / 2;
  // Straight ahead, the robot sees the end wall of the corridor ...
  CHECK(frame.semantic[centre] == static_cast<std::uint8_t>(worlds::SemanticClass::kWall));
  const std::size_t bottom = static_cast<std::size_t>(k.height - 1) * k.width + k.width / 2;
  // ... below it the floor, above it the ceiling (or a lamp on it).
  CHECK(frame.semantic[bottom] == static_cast<std::uint8_t>(worlds::SemanticClass::kFloor));
  const auto top = static_cast<worlds::SemanticClass>(frame.semantic[k.width / 2]);
  CHECK((top == worlds::SemanticClass::kCeiling || top == worlds::SemanticClass::kLampCircular ||
         top == worlds::SemanticClass::kLampPanel));
  // Every labelled pixel's instance id belongs to a drawable of that class.
  std::map<std::uint32_t, std::set<std::uint8_t>> classes_of;
  for (const Drawable& d : Shared().scene.drawables)
    classes_of[d.instance_id].insert(d.semantic_class);
  for (std::size_t i = 0; i < frame.instance.size(); i += 37) {
    if (frame.instance[i] == 0) continue;
    REQUIRE(classes_of.count(frame.instance[i]));
    CHECK(classes_of[frame.instance[i]].count(frame.semantic[i]));
  }
}

// The centroid of an object's labelled pixels against its projected centre.
Vector2d LabelCentroid(const CameraFrame& frame, int width, std::uint32_t id, int* count) {
  Vector2d sum = Vector2d::Zero();
  *count = 0;
  for (std::size_t i = 0; i < frame.instance.size(); ++i) {
    if (frame.instance[i] != id) continue;
    sum += Vector2d(static_cast<double>(i % width), static_cast<double>(i / width));
    ++*count;
  }
  return *count ? Vector2d(sum / *count) : sum;
}

TEST_CASE("a door plate seen straight on appears where its corners project, within 0.5 px",
          "[render][gl]") {
  const worlds::World& world = Shared().world;
  const worlds::DoorPlate& plate = world.plates.front();
  CameraOptions camera_options = RigOptions::Default().cameras[1];
  camera_options.model = PinholeRadTan::FromFov(640, 480, 60 * kDeg);
  const PinholeRadTan& k = *camera_options.model.pinhole();
  // Camera 1.0 m in front of the plate, at its height, looking at it.
  const Vector3d n = plate.normal;
  const Vector3d c = plate.center + 1.0 * n;
  Eigen::Matrix3d r;
  r.col(2) = -n;
  r.col(1) = -Vector3d::UnitZ();
  r.col(0) = r.col(1).cross(r.col(2));
  const SE3 world_from_camera(r, c);
  const CameraFrame frame = RenderWith(camera_options, world_from_camera);
  const FrameTruth truth = TruthOf(camera_options, frame, world_from_camera);
  const PlateTruth* seen = nullptr;
  for (const auto& p : truth.plates) {
    if (p.id == plate.id) seen = &p;
  }
  REQUIRE(seen);
  int count = 0;
  const Vector2d centroid =
      LabelCentroid(frame, k.width, static_cast<std::uint32_t>(plate.id), &count);
  REQUIRE(count > 100);
  CHECK((centroid - seen->center_px).norm() < 0.5);
  // The labelled region spans the projected corners: its extreme pixel centres lie within
  // half a pixel inside the projected outline.
  int u0 = k.width, u1 = -1, v0 = k.height, v1 = -1;
  for (std::size_t i = 0; i < frame.instance.size(); ++i) {
    if (frame.instance[i] != static_cast<std::uint32_t>(plate.id)) continue;
    const int u = static_cast<int>(i % k.width), v = static_cast<int>(i / k.width);
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  CHECK(std::abs(u0 - seen->bbox_min_px.x()) <= 1.0);
  CHECK(std::abs(u1 - seen->bbox_max_px.x()) <= 1.0);
  CHECK(std::abs(v0 - seen->bbox_min_px.y()) <= 1.0);
  CHECK(std::abs(v1 - seen->bbox_max_px.y()) <= 1.0);
  CHECK(u0 >= seen->bbox_min_px.x() - 0.5);
  CHECK(u1 <= seen->bbox_max_px.x() + 0.5);
}

TEST_CASE("a lamp seen by the upward fisheye appears where the camera model puts it",
          "[render][gl]") {
  const worlds::World& world = Shared().world;
  for (const double fov : {110.0, 130.0}) {
    CameraOptions camera_options = RigOptions::Default().cameras[2];
    camera_options.model = KannalaBrandt::FromFov(640, 480, fov * kDeg);
    const CameraRenderer renderer(camera_options);
    int checked = 0;
    for (const worlds::Lamp& lamp : world.lamps) {
      if (lamp.shape != worlds::LampShape::kCircular || lamp.room_door_id >= 0) continue;
      if (lamp.center.x() < 5 || lamp.center.x() > 45 || checked >= 3) continue;
      // The camera 1.2 m along the corridor from the lamp, 0.4 m above the floor, looking up:
      // the lamp is well off-axis.
      const SE3 world_from_robot = SE3::FromSE2(SE2(lamp.center.x() - 1.2, 0.0, 0.0));
      const SE3 world_from_camera = world_from_robot * camera_options.mount.RobotFromCamera();
      const CameraFrame frame = RenderWith(camera_options, world_from_camera);
      const FrameTruth truth = TruthOf(camera_options, frame, world_from_robot);
      const LampTruth* seen = nullptr;
      for (const auto& l : truth.lamps) {
        if (l.id == lamp.id && !l.reflection) seen = &l;
      }
      REQUIRE(seen);
      REQUIRE_FALSE(seen->cut_by_border);
      // An off-axis disc's image centroid is not the projection of its centre: compare the
      // labelled pixels' centroid with the area-weighted mean of the projected disc.
      Vector2d weighted = Vector2d::Zero();
      double total = 0.0;
      const SE3 camera_from_world = world_from_camera.Inverse();
      const Eigen::Matrix<double, 3, 2> d_camera_d_disc =
          camera_from_world.rotation().leftCols<2>();
      for (int a = -60; a <= 60; ++a) {
        for (int b = -60; b <= 60; ++b) {
          const Vector2d q(a / 60.0, b / 60.0);
          if (q.norm() > 1) continue;
          const Vector3d p = lamp.center + Vector3d(q.x(), q.y(), 0) * lamp.radius_m;
          Eigen::Matrix<double, 2, 3> J;
          const auto px = camera_options.model.Project(camera_from_world * p, &J);
          REQUIRE(px);
          const double w = std::abs((J * d_camera_d_disc).determinant());
          weighted += w * *px;
          total += w;
        }
      }
      const Vector2d expected = weighted / total;
      int count = 0;
      const Vector2d centroid =
          LabelCentroid(frame, 640, static_cast<std::uint32_t>(lamp.id), &count);
      REQUIRE(count > 50);
      INFO("fov " << fov << " lamp " << lamp.id << " centroid " << centroid.transpose()
                  << " expected " << expected.transpose());
      CHECK((centroid - expected).norm() < 0.5);
      CHECK((seen->center_px - expected).norm() < 0.1 * seen->radius_px);
      ++checked;
    }
    CHECK(checked == 3);
  }
}

TEST_CASE("the upward fisheye's truth depth puts what each pixel sees on its surface",
          "[render][gl]") {
  const worlds::World& world = Shared().world;
  for (const double fov : {110.0, 130.0}) {
    CameraOptions camera_options = RigOptions::Default().cameras[2];
    REQUIRE(camera_options.truth_depth);  // on by default: upward corners are scored with it
    REQUIRE_FALSE(camera_options.depth);  // frame truth only, not a sensor
    camera_options.model = KannalaBrandt::FromFov(320, 240, fov * kDeg);
    const SE2 pose(17.3, 0.2, 0.4);
    const CameraFrame frame =
        RenderWith(camera_options, SE3::FromSE2(pose) * camera_options.mount.RobotFromCamera());
    REQUIRE(frame.depth_m.width == 320);
    REQUIRE(frame.depth_m.height == 240);
    const Vector3d c = frame.world_from_camera.translation();
    std::vector<double> errors;  // relative range error of the seen point along the pixel's ray
    for (int v = 1; v < 239; ++v) {
      for (int u = 1; u < 319; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * 320 + u;
        const auto cls = static_cast<worlds::SemanticClass>(frame.semantic[i]);
        // Away from label edges (the depth is the nearest pass pixel's, a little off this ray).
        bool interior = true;
        for (const std::size_t j : {i - 1, i + 1, i - 320, i + 320}) {
          interior = interior && frame.semantic[j] == frame.semantic[i];
        }
        const float z = frame.depth_m.data[i];
        if (!interior || !(z > 0.0f)) continue;
        const Vector3d b = camera_options.model.Unproject(Vector2d(u, v));
        REQUIRE(b.z() > 0.0);
        const Vector3d ray = frame.world_from_camera.rotation() * b.normalized();
        const double seen_range = double(z) / b.normalized().z();
        // The exact range to the ceiling plane, or to the corridor's side walls.
        double exact = -1.0;
        if (cls == worlds::SemanticClass::kCeiling) {
          exact = (world.options.height_m - c.z()) / ray.z();
        } else if (cls == worlds::SemanticClass::kWall) {
          const double side = ray.y() > 0 ? world.options.width_m / 2 : -world.options.width_m / 2;
          exact = (side - c.y()) / ray.y();
          const Vector3d p = c + exact * ray;
          if (p.x() < 1 || p.x() > 40 || p.z() > world.options.height_m) continue;
          if (std::abs(seen_range - exact) > 0.05 * exact) continue;  // a doorway's reveal
        } else {
          continue;
        }
        errors.push_back(std::abs(seen_range - exact) / exact);
      }
    }
    REQUIRE(errors.size() > 20000);
    std::sort(errors.begin(), errors.end());
    const double median = errors[errors.size() / 2];
    const double worst = errors.back();
    INFO("fov " << fov << ": " << errors.size() << " pixels, relative range error median " << median
                << ", worst " << worst);
    // The depth is the nearest pass pixel's (up to half a pass pixel off this ray): on a surface
    // seen at a grazing angle that is a few per cent of the range; a wrong scale from pass depth
    // to camera depth would be tens of per cent across the image.
    CHECK(median < 2e-3);
    CHECK(worst < 0.05);
  }
}

TEST_CASE("every pixel of the upward fisheye sees something inside the corridor", "[render][gl]") {
  for (const double fov : {110.0, 130.0}) {
    CameraOptions camera_options = RigOptions::Default().cameras[2];
    camera_options.model = KannalaBrandt::FromFov(320, 240, fov * kDeg);
    for (const SE2& pose : {SE2(5, 0, 0), SE2(39, -0.3, 0), SE2(27, 0.4, 1.2)}) {
      const CameraFrame frame =
          RenderWith(camera_options, SE3::FromSE2(pose) * camera_options.mount.RobotFromCamera());
      const CameraRenderer renderer(camera_options);
      int empty = 0, valid = 0;
      for (int v = 0; v < 240; ++v) {
        for (int u = 0; u < 320; ++u) {
          if (!renderer.Lookup(u, v)) continue;
          ++valid;
          empty += frame.instance[static_cast<std::size_t>(v) * 320 + u] == 0;
        }
      }
      INFO("fov " << fov << " pose " << pose.x() << "," << pose.y());
      CHECK(valid > 0);
      CHECK(empty == 0);
    }
  }
}

TEST_CASE("a fisheye leaves unshaded only pass pixels its remap never reads", "[render][gl]") {
  auto inside = [](const PixelRect& r, int x, int y) {
    return r.x0 <= x && x < r.x1 && r.y0 <= y && y < r.y1;
  };
  for (const double fov : {110.0, 130.0}) {
    CameraOptions camera_options = Exact(RigOptions::Default().cameras[2]);
    camera_options.model = KannalaBrandt::FromFov(320, 240, fov * kDeg);
    const CameraRenderer camera(camera_options);
    const std::vector<View> views =
        camera.Passes(SE3::FromSE2(SE2(9, 0.2, 0.4)) * camera_options.mount.RobotFromCamera());
    INFO("fov " << fov);
    // Every output pixel's bilinear block lies outside its pass's unused rectangles.
    std::size_t unused_pixels = 0, read_in_unused = 0;
    for (std::size_t k = 0; k < views.size(); ++k) {
      for (const PixelRect& r : camera.unused_pixels(k)) {
        unused_pixels += std::size_t(r.x1 - r.x0) * std::size_t(r.y1 - r.y0);
      }
    }
    for (int v = 0; v < 240; ++v) {
      for (int u = 0; u < 320; ++u) {
        const auto sample = camera.Lookup(u, v);
        if (!sample) continue;
        const int x = int(std::floor(sample->second.x())), y = int(std::floor(sample->second.y()));
        for (const PixelRect& r : camera.unused_pixels(std::size_t(sample->first))) {
          read_in_unused += inside(r, x, y) || inside(r, x + 1, y) || inside(r, x, y + 1) ||
                            inside(r, x + 1, y + 1);
        }
      }
    }
    CHECK(unused_pixels > camera.pass_pixel_count() / 10);  // the cropped side faces' corners
    CHECK(read_in_unused == 0);
    // Drawn with and without them, each pass is the same outside the unused rectangles.
    for (std::size_t k = 0; k < views.size(); ++k) {
      const std::vector<int> visible = VisibleDrawables(Shared().scene, views[k]);
      RenderedView full, masked;
      Shared().backend->Draw(views[k], visible, {}, &full);
      const DrawRequest request{views[k], visible, {}, &masked, camera.unused_pixels(k)};
      Shared().backend->DrawPasses(std::span<const DrawRequest>(&request, 1));
      std::size_t differing = 0;
      for (int y = 0; y < views[k].height; ++y) {
        for (int x = 0; x < views[k].width; ++x) {
          const auto& rects = camera.unused_pixels(k);
          if (std::any_of(rects.begin(), rects.end(),
                          [&](const PixelRect& r) { return inside(r, x, y); })) {
            continue;
          }
          const std::size_t i = std::size_t(y) * std::size_t(views[k].width) + std::size_t(x);
          differing += full.instance[i] != masked.instance[i] ||
                       full.semantic[i] != masked.semantic[i] ||
                       !std::equal(&full.rgb.data[3 * i], &full.rgb.data[3 * i + 3],
                                   &masked.rgb.data[3 * i]) ||
                       full.depth_m.data[i] != masked.depth_m.data[i];
        }
      }
      INFO("pass " << k);
      CHECK(differing == 0);
    }
  }
  // A pinhole draws every pixel of its one pass.
  CHECK(CameraRenderer(RigOptions::Default().cameras[0]).unused_pixels(0).empty());
}

TEST_CASE("unused rectangles outside the view are rejected before drawing", "[render][gl]") {
  CameraOptions camera_options = Exact(RigOptions::Default().cameras[2]);
  const CameraRenderer camera(camera_options);
  const View view =
      camera.Passes(SE3::FromSE2(SE2(9, 0, 0)) * camera_options.mount.RobotFromCamera())[0];
  RenderedView out;
  for (const PixelRect bad :
       {PixelRect{0, 0, view.width + 1, 4}, PixelRect{5, 5, 5, 9}, PixelRect{-1, 0, 3, 3}}) {
    const DrawRequest request{view, {}, {}, &out, std::span<const PixelRect>(&bad, 1)};
    CHECK_THROWS_AS(Shared().backend->DrawPasses(std::span<const DrawRequest>(&request, 1)),
                    std::invalid_argument);
  }
  CHECK(out.rgb.data.empty());
}

TEST_CASE("with back faces culled no pixel looks through a seam into the void",
          "[render][gl][heavy]") {
  // Every pinhole pixel inside a closed corridor hits a surface: a pixel with no instance would
  // be a face culled from where it can be seen, or a seam that touches instead of crossing.
  RigOptions rig = RigOptions::Default();
  for (CameraOptions& c : rig.cameras) c = Exact(c);
  for (const std::uint64_t seed : {2u, 5u}) {
    const worlds::World world = worlds::Generate(worlds::WorldOptions{}, seed);
    const Scene scene = BuildScene(world);
    Shared().backend->Upload(scene);
    Rig renderer(rig, scene, *Shared().backend);
    std::vector<CameraFrame> frames;
    int rendered = 0;
    for (int i = 0; i < 50; ++i) {
      for (const double yaw : {0.0, std::numbers::pi, 1.2, -2.0}) {
        const SE3 pose = SE3::FromSE2(SE2(1.0 + 1.05 * i, 0.25 * std::sin(i), yaw));
        if (CheckCameraPlacement(world, rig, pose)) continue;
        renderer.Render(pose, 1, 0, &frames);
        ++rendered;
        for (std::size_t c = 0; c < 2; ++c) {  // front and lateral: pinholes, every pixel valid
          const auto empty = std::count(frames[c].instance.begin(), frames[c].instance.end(), 0u);
          INFO("seed " << seed << " pose " << i << " yaw " << yaw << " " << frames[c].camera_id);
          REQUIRE(empty == 0);
        }
      }
    }
    CHECK(rendered > 100);
  }
  Shared().backend->Upload(Shared().scene);  // the shared fixture's scene again
}

TEST_CASE("the nearest-mip texture filter changes colours only, and only a little",
          "[render][gl]") {
  SceneOptions options;
  options.texture_filter = TextureFilter::kNearestMip;
  const Scene nearest_mip = BuildScene(Shared().world, options);
  const std::unique_ptr<Backend> backend = CreateBackend(BackendKind::kOsMesa);
  backend->Upload(nearest_mip);
  const CameraOptions front = Exact(RigOptions::Default().cameras[0]);
  const SE3 pose = SE3::FromSE2(SE2(6, 0.2, 0.1)) * front.mount.RobotFromCamera();
  CameraRenderer camera(front);
  CameraFrame fast, again;
  camera.Render(nearest_mip, *backend, pose, &fast);
  camera.Render(nearest_mip, *backend, pose, &again);
  const CameraFrame trilinear = RenderWith(front, pose);
  CHECK(fast.rgb.data == again.rgb.data);  // deterministic
  CHECK(fast.instance == trilinear.instance);
  CHECK(fast.depth_m.data == trilinear.depth_m.data);
  std::size_t differing = 0;
  double total = 0;
  for (std::size_t i = 0; i < fast.rgb.data.size(); ++i) {
    const int d = std::abs(int(fast.rgb.data[i]) - int(trilinear.rgb.data[i]));
    differing += d != 0;
    total += d;
  }
  CHECK(differing > 1000);  // the floor far ahead is minified
  INFO("differing " << differing << " mean " << total / double(fast.rgb.data.size()));
  CHECK(total / double(fast.rgb.data.size()) < 3.0);  // mean change of a channel, in DN
}

TEST_CASE("rendering the same frame twice gives identical bytes", "[render][gl][determinism]") {
  const RigOptions rig_options = RigOptions::Default();
  Rig rig(rig_options, Shared().scene, *Shared().backend);
  std::vector<CameraFrame> a, b;
  const SE3 pose = SE3::FromSE2(SE2(12.0, 0.3, 0.2));
  rig.Render(pose, 5, 3, &a);
  rig.Render(pose, 5, 3, &b);
  REQUIRE(a.size() == 3);
  for (std::size_t k = 0; k < a.size(); ++k) {
    CHECK(a[k].rgb.data == b[k].rgb.data);
    CHECK(a[k].instance == b[k].instance);
    CHECK(a[k].noisy_depth_m.data == b[k].noisy_depth_m.data);
  }
  // Another frame index draws other noise.
  std::vector<CameraFrame> c;
  rig.Render(pose, 5, 4, &c);
  CHECK(c[0].noisy_depth_m.data != a[0].noisy_depth_m.data);
  CHECK(c[0].depth_m.data == a[0].depth_m.data);
}

TEST_CASE("a depth camera without noise reports only depths inside its valid range",
          "[render][gl]") {
  // The calibration tells a pipeline [min_m, max_m] (harness/scenario/calibration.h): with the
  // noise off the depth must keep to it as the noise model does.
  RigOptions rig_options = RigOptions::Default();
  CameraOptions& front = rig_options.cameras[0];
  front.noise = false;
  front.depth_noise.min_m = 1.5;
  front.depth_noise.max_m = 4.0;
  Rig rig(rig_options, Shared().scene, *Shared().backend);
  CameraFrame frame;
  rig.RenderCamera(0, SE3::FromSE2(SE2(12.0, 0.3, 0.2)), 5, 3, &frame);
  REQUIRE(frame.noisy_depth_m.data.size() == frame.depth_m.data.size());
  int near = 0, inside = 0, beyond = 0;
  for (std::size_t i = 0; i < frame.depth_m.data.size(); ++i) {
    const float z = frame.depth_m.data[i];
    const bool valid = z >= 1.5f && z <= 4.0f;
    near += z > 0.0f && z < 1.5f;
    inside += valid;
    beyond += z > 4.0f;
    REQUIRE(frame.noisy_depth_m.data[i] == (valid ? z : 0.0f));
  }
  // The view down the corridor holds all three (the floor at the bottom rows lies nearer than 1.5
  // m).
  CHECK(near > 100);
  CHECK(inside > 1000);
  CHECK(beyond > 1000);
}

TEST_CASE("the whole rig, its noise overlapped with rendering, equals each camera rendered alone",
          "[render][gl][determinism]") {
  RigOptions rig_options = RigOptions::Default();
  rig_options.cameras[0].rgb_noise.full_well_electrons = 6000;  // noise on every camera
  rig_options.cameras[1].rgb_noise.full_well_electrons = 6000;
  rig_options.cameras[2].rgb_noise.read_noise_electrons = 6;
  rig_options.cameras[2].rgb_noise.full_well_electrons = 6000;
  Rig rig(rig_options, Shared().scene, *Shared().backend);
  std::vector<CameraFrame> together;
  const SE3 pose = SE3::FromSE2(SE2(20.0, -0.2, 2.9));
  rig.Render(pose, 11, 7, &together);
  REQUIRE(together.size() == 3);
  for (std::size_t k = 0; k < together.size(); ++k) {
    CameraFrame alone;
    rig.RenderCamera(k, pose, 11, 7, &alone);
    INFO(alone.camera_id);
    CHECK(alone.rgb.data == together[k].rgb.data);
    CHECK(alone.noisy_depth_m.data == together[k].noisy_depth_m.data);
    CHECK(alone.instance == together[k].instance);
  }
}

long ResidentKiB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

TEST_CASE("memory does not grow over ten thousand frames", "[render][gl][slow][heavy]") {
  RigOptions rig_options = RigOptions::Default();
  // Small images keep the test short; the per-frame code paths are the same.
  rig_options.cameras[0].model = PinholeRadTan::FromFov(64, 48, 58 * kDeg);
  rig_options.cameras[1].model = PinholeRadTan::FromFov(64, 48, 60 * kDeg);
  rig_options.cameras[2].model = KannalaBrandt::FromFov(64, 48, 110 * kDeg);
  Rig rig(rig_options, Shared().scene, *Shared().backend);
  std::vector<CameraFrame> frames;
  // Warm-up: llvmpipe keeps the scenes and heap pages a batch of passes needs up to a high-water
  // mark that depends on how far its threads lag behind (on the machine's load); then ten
  // thousand frames must not grow the process.
  constexpr int kWarmup = 2000, kFrames = 10000;
  long after_warmup = 0;
  for (int i = 0; i < kWarmup + kFrames; ++i) {
    const SE3 pose =
        SE3::FromSE2(SE2(2.0 + 0.004 * i, 0.2 * std::sin(i * 0.01), 0.1 * std::cos(i * 0.02)));
    rig.Render(pose, 1, static_cast<std::uint64_t>(i), &frames);
    if (i + 1 == kWarmup) after_warmup = ResidentKiB();
  }
  const long end = ResidentKiB();
  INFO("RSS after the warm-up " << after_warmup << " KiB, " << kFrames << " frames later " << end
                                << " KiB");
  CHECK(end - after_warmup < 4096);
}

TEST_CASE("cameras at the largest pass side the rig allows render on the default backend",
          "[render][gl]") {
  // 8192 px (kMaxPassPx) along one side, few along the other: the GL limits are per side; the
  // area is bounded by the rig's memory budget (an 8192 x 8192 depth camera, 3 GB, renders too).
  CameraOptions wide = RigOptions::Default().cameras[0];
  CameraOptions tall = wide;
  wide.model = PinholeRadTan::FromFov(kMaxPassPx, 8, 90.0 * kDeg);
  // 140 degrees vertically (a pinhole must see less than 150 on its widest side).
  tall.model = PinholeRadTan::FromFov(8, kMaxPassPx, 2 * std::atan(4 * std::tan(70 * kDeg) / 4096));
  // A fisheye's largest cube face: cube_face_px 4096 and its crop border.
  CameraOptions fisheye = RigOptions::Default().cameras[2];
  fisheye.model = KannalaBrandt::FromFov(64, 48, 110.0 * kDeg);
  fisheye.cube_face_px = 4096;
  RigOptions rig = RigOptions::Default();
  rig.cameras = {wide, tall, fisheye};
  rig.cameras[1].id = "lateral", rig.cameras[2].id = "upward";
  const auto problem = rig.Check();
  INFO((problem ? problem->key + ": " + problem->message : std::string()));
  REQUIRE_FALSE(problem);
  CHECK(CameraBudgetOf(fisheye).pass_width_px == 4103);
  const SE3 world_from_robot = SE3::FromSE2(SE2(20.0, 0.0, 0.0));
  for (const CameraOptions& camera : rig.cameras) {
    INFO(camera.id);
    const CameraFrame frame = RenderWith(camera, world_from_robot * camera.mount.RobotFromCamera());
    REQUIRE(frame.rgb.width == camera.model.width());
    REQUIRE(frame.rgb.height == camera.model.height());
    // Walls, floor and ceiling everywhere the corridor is seen: every pixel hits something.
    CHECK(std::count(frame.instance.begin(), frame.instance.end(), 0u) == 0);
  }
}

}  // namespace
}  // namespace corridorsim::render
