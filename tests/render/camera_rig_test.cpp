// Tests the camera rig without GL: mounts, the rig's options and checks (render/camera_options),
// budgets (render/camera_budget), placement (render/camera_placement), and the remap of distorted
// and fisheye cameras onto their pinhole passes (render/camera_renderer, render/remap_kernel).
#include "render/camera_rig.h"
#include "render/camera_budget.h"
#include "render/camera_placement.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <catch2/catch.hpp>

#include "common/random.h"
#include "render/remap_kernel.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/option_bounds.h"

namespace corridorsim::render {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDeg = std::numbers::pi / 180.0;

TEST_CASE("mounts point the optical axis by yaw and pitch, image x horizontal", "[render][rig]") {
  const SE3 front = Mount{0.2, 0, 0.4, 0, 0, 0}.RobotFromCamera();
  CHECK((front.rotation().col(2) - Vector3d(1, 0, 0)).norm() < 1e-12);   // z forward
  CHECK((front.rotation().col(0) - Vector3d(0, -1, 0)).norm() < 1e-12);  // x right
  CHECK((front.rotation().col(1) - Vector3d(0, 0, -1)).norm() < 1e-12);  // y down
  CHECK((front.translation() - Vector3d(0.2, 0, 0.4)).norm() < 1e-12);

  const SE3 up = Mount{0, 0, 0.4, 0, 90, 0}.RobotFromCamera();
  CHECK((up.rotation().col(2) - Vector3d(0, 0, 1)).norm() < 1e-12);
  CHECK((up.rotation().col(0) - Vector3d(0, -1, 0)).norm() < 1e-12);

  const SE3 lateral = Mount{0, 0.1, 0.5, 90, 25, 0}.RobotFromCamera();
  CHECK((lateral.rotation().col(2) - Vector3d(0, std::cos(25 * kDeg), std::sin(25 * kDeg))).norm() <
        1e-12);
  CHECK(std::abs(lateral.rotation().col(0).z()) < 1e-12);  // no roll: image x stays horizontal
  CHECK(std::abs(lateral.rotation().determinant() - 1.0) < 1e-12);

  const SE3 rolled = Mount{0, 0, 0, 0, 0, 90}.RobotFromCamera();
  CHECK((rolled.rotation().col(0) - Vector3d(0, 0, -1)).norm() < 1e-12);
}

TEST_CASE("the default rig is P1's front RGB-D and lateral camera plus P3's upward fisheye",
          "[render][rig]") {
  const RigOptions rig = RigOptions::Default();
  REQUIRE(rig.cameras.size() == 3);
  CHECK_FALSE(rig.Check());
  const CameraOptions& front = *rig.Find("front");
  CHECK(front.depth);
  REQUIRE(front.model.pinhole() != nullptr);
  CHECK(front.model.width() == 640);
  CHECK(front.model.height() == 480);
  CHECK(front.model.HorizontalFovRad() / kDeg == Approx(58).margin(1e-9));
  CHECK(front.model.VerticalFovRad() / kDeg == Approx(45).margin(1.5));
  const CameraModel& up = rig.Find("upward")->model;
  REQUIRE(up.kannala_brandt() != nullptr);
  CHECK(up.FieldOfViewRad() / kDeg == Approx(110).margin(1e-9));
}

TEST_CASE("each fisheye pixel samples the pass pixel that sees along the same ray",
          "[render][rig]") {
  for (const double fov : {110.0, 130.0}) {
    CameraOptions camera_options = RigOptions::Default().cameras[2];
    camera_options.model = KannalaBrandt::FromFov(320, 240, fov * kDeg);
    const CameraRenderer renderer(camera_options);
    const std::vector<View> passes = renderer.Passes(SE3());
    CHECK(passes.size() >= 5);  // the up face and the four side faces it reaches into
    for (int v = 0; v < 240; v += 7) {
      for (int u = 0; u < 320; u += 7) {
        const auto hit = renderer.Lookup(u, v);
        REQUIRE(hit);
        const View& pass = passes[static_cast<std::size_t>(hit->first)];
        const Vector2d q = hit->second;
        CHECK(q.x() >= 0);
        CHECK(q.y() >= 0);
        CHECK(q.x() <= pass.width - 1);
        CHECK(q.y() <= pass.height - 1);
        const Vector3d ray_in_pass((q.x() - pass.cx) / pass.fx, (q.y() - pass.cy) / pass.fy, 1.0);
        const Vector3d ray = (pass.world_from_camera.rotation() * ray_in_pass).normalized();
        const Vector3d expected = camera_options.model.Unproject(Vector2d(u, v)).normalized();
        CHECK((ray - expected).norm() < 1e-5);
      }
    }
  }
}

TEST_CASE("an undistorted pinhole camera is drawn in one exact pass", "[render][rig]") {
  const CameraRenderer renderer(RigOptions::Default().cameras[0]);
  const std::vector<View> passes = renderer.Passes(SE3());
  REQUIRE(passes.size() == 1);
  CHECK(passes[0].width == 640);
  const auto hit = renderer.Lookup(100, 50);
  REQUIRE(hit);
  CHECK(hit->second == Vector2d(100, 50));
}

TEST_CASE("a distorted pinhole camera samples one wider pass along its rays", "[render][rig]") {
  CameraOptions camera_options = RigOptions::Default().cameras[1];
  PinholeRadTan p = *camera_options.model.pinhole();
  p.k1 = -0.28;
  p.k2 = 0.07;
  p.p1 = 1e-4;
  camera_options.model = p;
  const CameraRenderer renderer(camera_options);
  const std::vector<View> passes = renderer.Passes(SE3());
  REQUIRE(passes.size() == 1);
  for (const auto& [u, v] : {std::pair{0, 0}, {639, 479}, {320, 240}, {10, 400}}) {
    const auto hit = renderer.Lookup(u, v);
    REQUIRE(hit);
    const View& pass = passes[0];
    const Vector3d ray =
        Vector3d((hit->second.x() - pass.cx) / pass.fx, (hit->second.y() - pass.cy) / pass.fy, 1.0)
            .normalized();
    CHECK((ray - camera_options.model.Unproject(Vector2d(u, v)).normalized()).norm() < 1e-5);
  }
}

// Changes the pinhole parameters of `camera`'s model.
void ChangePinhole(CameraOptions& camera, const std::function<void(PinholeRadTan&)>& change) {
  PinholeRadTan p = *camera.model.pinhole();
  change(p);
  camera.model = p;
}

// Changes the fisheye parameters of `camera`'s model.
void ChangeFisheye(CameraOptions& camera, const std::function<void(KannalaBrandt&)>& change) {
  KannalaBrandt k = *camera.model.kannala_brandt();
  change(k);
  camera.model = k;
}

TEST_CASE("the rig rejects impossible cameras naming the key", "[render][rig]") {
  const auto fisheye_179_deg = [](RigOptions& rig) {
    rig.cameras[2].model = KannalaBrandt::FromFov(640, 480, 179.0 * kDeg);
  };
  {
    RigOptions rig = RigOptions::Default();
    fisheye_179_deg(rig);
    CHECK_FALSE(rig.Check());
  }
  struct ImpossibleCamera {
    std::function<void(RigOptions&)> change;  // applied to the default rig
    std::string key;                          // that Check names
  };
  const std::vector<ImpossibleCamera> cases = {
      {[&](RigOptions& rig) {
         fisheye_179_deg(rig);
         ChangeFisheye(rig.cameras[2],
                       [](KannalaBrandt& k) { k.fx = k.fy = 480 / std::numbers::pi; });  // 180 deg
       },
       "upward.fov_deg"},
      {[](RigOptions& rig) {
         rig.cameras[0].model = PinholeRadTan::FromFov(640, 480, 150.0 * kDeg);
       },
       "front.fov_deg"},
      {[](RigOptions& rig) {
         ChangePinhole(rig.cameras[1], [](PinholeRadTan& p) { p.width = 0; });
       },
       "lateral.width"},
      // Sizes whose passes or remap tables could not be allocated.
      {[](RigOptions& rig) {
         ChangePinhole(rig.cameras[0], [](PinholeRadTan& p) { p.width = 100000; });
       },
       "front.width"},
      {[](RigOptions& rig) {
         ChangeFisheye(rig.cameras[2], [](KannalaBrandt& k) { k.fx = 1e10; });
       },
       "upward.fx"},
      {[](RigOptions& rig) { rig.cameras[0].rgb_noise.motion_blur_px = 1e5; },
       "front.noise.rgb.motion_blur_px"},
      {[](RigOptions& rig) { rig.cameras[0].rgb_noise.exposure = 1e30; },
       "front.noise.rgb.exposure"},
  };
  for (const ImpossibleCamera& impossible : cases) {
    INFO("expected key " << impossible.key);
    RigOptions rig = RigOptions::Default();
    impossible.change(rig);
    REQUIRE(rig.Check());
    CHECK(rig.Check()->key == impossible.key);
  }
}

TEST_CASE("every bound of the sensors and render options names its key and the value",
          "[render][rig]") {
  RigOptions rig = RigOptions::Default();
  test::CheckEveryBoundNamesKeyAndValue(SensorsOptionsTable(), &rig, "",
                                        [&] { return rig.Check(); });
  test::CheckEveryBoundNamesKeyAndValue(RenderOptionsTable(), &rig, "",
                                        [&] { return rig.CheckRender(); });
}

TEST_CASE("the rig's own checks name the focal length that is wrong and give its value",
          "[render][rig]") {
  struct Case {
    std::function<void(RigOptions&)> change;
    std::string key, got;
  };
  const std::vector<Case> cases = {
      {[](RigOptions& rig) {
         ChangeFisheye(rig.cameras[2], [](KannalaBrandt& k) { k.fy = 1e10; });
       },
       "upward.fy", "got 1e+10"},
      {[](RigOptions& rig) {
         ChangeFisheye(rig.cameras[2], [](KannalaBrandt& k) { k.fx = 1e10; });
       },
       "upward.fx", "got 1e+10"},
      {[](RigOptions& rig) { ChangePinhole(rig.cameras[0], [](PinholeRadTan& p) { p.fy = 2e5; }); },
       "front.fy", "got 200000"},
      {[](RigOptions& rig) { ChangePinhole(rig.cameras[1], [](PinholeRadTan& p) { p.fy = 0; }); },
       "lateral.fy", "got 0"},
      {[](RigOptions& rig) { ChangePinhole(rig.cameras[1], [](PinholeRadTan& p) { p.fx = -3; }); },
       "lateral.fx", "got -3"},
      {[](RigOptions& rig) {
         ChangePinhole(rig.cameras[0], [](PinholeRadTan& p) { p.height = 9000; });
       },
       "front.height", "got 640x9000"},
      {[](RigOptions& rig) { rig.cameras[0].depth_noise.max_m = 0.5; }, "front.noise.depth.max_m",
       "got 0.5"},
      {[](RigOptions& rig) { rig.cameras[0].rgb_noise.read_noise_electrons = 6; },
       "front.noise.rgb.read_noise_electrons", "got 6"},
  };
  for (const Case& c : cases) {
    INFO("expected key " << c.key);
    RigOptions rig = RigOptions::Default();
    c.change(rig);
    const std::optional<OptionsProblem> problem = rig.Check();
    REQUIRE(problem);
    CHECK(problem->key == c.key);
    CHECK_THAT(problem->message, Catch::Contains(c.got));
  }
}

TEST_CASE("camera rates give periods that fit int64 ns and at most one frame per physics step",
          "[render][rig]") {
  for (const double bad : {1e-10, 0.0, -1.0, 101.0, 1000.0, std::nan("")}) {
    INFO("rate_hz " << bad);
    RigOptions rig = RigOptions::Default();
    rig.cameras[0].rate_hz = bad;
    const auto problem = rig.Check();
    REQUIRE(problem);
    CHECK(problem->key == "front.rate_hz");
  }
  RigOptions rig = RigOptions::Default();
  rig.cameras[0].rate_hz = 1e-10;  // a period of 1e10 s overflowed int64 ns: drive never ended
  CHECK(rig.Check()->message.find("(got 1e-10)") != std::string::npos);
  for (const double ok : {1e-6, 0.5, 30.0, 100.0}) {
    rig.cameras[0].rate_hz = ok;
    CHECK_FALSE(rig.Check());
  }
  rig.cameras[0].rate_hz = 1e-6;  // the longest period, 1e6 s: the phase may reach it
  rig.cameras[0].phase_s = 999999.0;
  CHECK_FALSE(rig.Check());
}

// The largest pass each of `renderer`'s passes has, and how many.
CameraBudget PlannedPasses(const CameraOptions& camera) {
  const CameraRenderer renderer(camera);
  CameraBudget b;
  for (const View& v : renderer.Passes(SE3())) {
    b.pass_width_px = std::max(b.pass_width_px, v.width);
    b.pass_height_px = std::max(b.pass_height_px, v.height);
    ++b.passes;
  }
  return b;
}

TEST_CASE("a camera's budget bounds the passes its renderer plans, before planning",
          "[render][rig]") {
  const RigOptions rig = RigOptions::Default();
  // Undistorted pinhole: its image; distorted pinhole: exactly the window its rays reach.
  const CameraBudget front = CameraBudgetOf(rig.cameras[0]);
  CHECK(front.pass_width_px == 640);
  CHECK(front.pass_height_px == 480);
  for (const auto& [k1, k2, p1] : {std::tuple{-0.28, 0.07, 1e-4}, {0.1, 0.0, -2e-3}}) {
    CameraOptions camera = rig.cameras[1];
    // The bindings captured by copy under names of their own (clang 14 captures no binding).
    ChangePinhole(camera,
                  [a = k1, b = k2, c = p1](PinholeRadTan& p) { p.k1 = a, p.k2 = b, p.p1 = c; });
    INFO("k1 " << k1);
    REQUIRE_FALSE(camera.model.Check());
    const CameraBudget planned = PlannedPasses(camera), budget = CameraBudgetOf(camera);
    CHECK(planned.passes == 1);
    CHECK(budget.pass_width_px == planned.pass_width_px);
    CHECK(budget.pass_height_px == planned.pass_height_px);
  }
  // Fisheye: the crops of its cube faces, automatic or given.
  for (const int face_px : {0, 300}) {
    CameraOptions camera = rig.cameras[2];
    camera.cube_face_px = face_px;
    const CameraBudget planned = PlannedPasses(camera), budget = CameraBudgetOf(camera);
    INFO("cube_face_px " << face_px);
    CHECK(planned.passes <= budget.passes);
    CHECK(planned.pass_width_px <= budget.pass_width_px);
    CHECK(planned.pass_height_px <= budget.pass_height_px);
    CHECK(budget.pass_width_px <= planned.pass_width_px + 8);  // tight: one face's full crop
  }
}

TEST_CASE("a rig beyond the pass size or memory it may use is refused before it is planned",
          "[render][rig]") {
  // The largest undistorted pinhole renders (3 GB); three of them do not fit the rig's budget.
  RigOptions rig = RigOptions::Default();
  rig.cameras[0].model = PinholeRadTan::FromFov(8192, 8192, 90.0 * kDeg);
  REQUIRE_FALSE(rig.Check());
  CHECK(CameraBudgetOf(rig.cameras[0]).bytes < kMaxRigBytes);
  rig.cameras[1].model = PinholeRadTan::FromFov(8192, 8192, 90.0 * kDeg);
  REQUIRE_FALSE(rig.Check());
  rig.cameras[2].model = KannalaBrandt::FromFov(6398, 6398, 179.0 * kDeg);
  rig.cameras[2].cube_face_px = 4096;
  auto problem = rig.Check();
  REQUIRE(problem);
  CHECK(problem->key == "upward.width");
  CHECK(problem->message.find("GiB") != std::string::npos);
  CHECK(problem->message.find("(got 6398x6398 px)") != std::string::npos);
  rig.cameras[2].enabled = false;  // a disabled camera costs nothing
  CHECK_FALSE(rig.Check());

  // A barrel-distorted pinhole at the largest size: its undistorted pass is wider than any pass
  // may be (it used to be planned for seconds, then fail to allocate).
  rig = RigOptions::Default();
  rig.cameras[0].model = PinholeRadTan::FromFov(8192, 8192, 130.0 * kDeg);
  ChangePinhole(rig.cameras[0], [](PinholeRadTan& p) { p.k1 = -0.01; });
  REQUIRE_FALSE(rig.cameras[0].model.Check());
  problem = rig.Check();
  REQUIRE(problem);
  CHECK(problem->key == "front.distortion");
  CHECK(problem->message.find("more than the 8192 px") != std::string::npos);
}

// A backend that draws nothing and has a small size limit (a GL driver with less than 8192 px).
class SmallBackend final : public Backend {
 public:
  BackendKind kind() const override { return BackendKind::kEgl; }
  BackendInfo info() const override { return {"test", "a backend that draws nothing", "0"}; }
  void Upload(const Scene&) override {}
  void Draw(const View&, std::span<const int>, std::span<const int>, RenderedView*) override {}
  void DrawPasses(std::span<const DrawRequest>) override {}
  int max_view_px() const override { return 512; }
};

TEST_CASE("a camera the backend cannot draw is refused when the rig is made", "[render][rig]") {
  const Scene scene;
  SmallBackend backend;
  RigOptions rig = RigOptions::Default();
  for (CameraOptions& c : rig.cameras) c.model = PinholeRadTan::FromFov(320, 240, 60.0 * kDeg);
  CHECK_NOTHROW(Rig{rig, scene, backend});
  rig.cameras[1].model = PinholeRadTan::FromFov(640, 480, 60.0 * kDeg);
  try {
    Rig refused(rig, scene, backend);
    FAIL("a 640 px camera was accepted by a backend of 512 px");
  } catch (const RenderError& e) {
    CHECK(std::string(e.what()).find("sensors.lateral") != std::string::npos);
    CHECK(std::string(e.what()).find("at most 512 px") != std::string::npos);
  }
}

TEST_CASE("changing a camera's model needs its field of view too", "[render][rig]") {
  const auto doc = YamlDocument::FromString("lateral:\n  model: kannala_brandt\n", "m.yaml");
  YamlMap map(doc, doc.root, "sensors", nullptr);
  RigOptions rig = RigOptions::Default();
  const InputError e = test::InputErrorOf([&] { ParseSensors(map, rig); });
  CHECK(std::string(e.what()).rfind("m.yaml:2:3: sensors.lateral.model: changing the camera model",
                                    0) == 0);
}

TEST_CASE("resizing a pinhole without fov_deg keeps its field of view, portrait or landscape",
          "[render][rig]") {
  RigOptions rig = RigOptions::Default();
  rig.cameras[0].model = PinholeRadTan::FromFov(640, 480, 58.0 * kDeg);  // landscape
  rig.cameras[1].model = PinholeRadTan::FromFov(480, 640, 45.0 * kDeg);  // portrait
  const RigOptions before = rig;
  const auto doc = YamlDocument::FromString(
      "front: {width: 320, height: 240}\nlateral: {width: 240, height: 320}\n", "s.yaml");
  YamlMap map(doc, doc.root, "sensors", nullptr);
  ParseSensors(map, rig);
  REQUIRE_FALSE(rig.Check());
  for (std::size_t k = 0; k < 2; ++k) {
    const CameraModel& old_model = before.cameras[k].model;
    const CameraModel& resized = rig.cameras[k].model;
    INFO(rig.cameras[k].id);
    CHECK(resized.width() == old_model.width() / 2);
    CHECK(resized.height() == old_model.height() / 2);
    CHECK(resized.HorizontalFovRad() == Approx(old_model.HorizontalFovRad()).epsilon(1e-12));
    CHECK(resized.VerticalFovRad() == Approx(old_model.VerticalFovRad()).epsilon(1e-12));
  }
}

TEST_CASE("sensors are parsed from YAML; unknown cameras and keys are errors", "[render][rig]") {
  const auto doc = YamlDocument::FromString(
      "front:\n"
      "  rate_hz: 5\n"
      "  width: 320\n"
      "  height: 240\n"
      "  fov_deg: 60\n"
      "  mount: {x_m: 0.3, z_m: 0.5}\n"
      "upward:\n"
      "  model: kannala_brandt\n"
      "  fov_deg: 130\n"
      "  distortion: [0.01, -0.002, 0.0, 0.0]\n"
      "lateral:\n"
      "  enabled: false\n",
      "s.yaml");
  RigOptions rig = RigOptions::Default();
  YamlMap map(doc, doc.root, "sensors", nullptr);
  ParseSensors(map, rig);
  CHECK(rig.Find("front")->rate_hz == 5);
  const CameraModel& f = rig.Find("front")->model;
  REQUIRE(f.pinhole() != nullptr);
  CHECK(f.width() == 320);
  CHECK(f.HorizontalFovRad() / kDeg == Approx(60));
  CHECK(rig.Find("front")->mount.x_m == 0.3);
  CHECK(rig.Find("front")->mount.z_m == 0.5);
  REQUIRE(rig.Find("upward")->model.kannala_brandt() != nullptr);
  const KannalaBrandt& k = *rig.Find("upward")->model.kannala_brandt();
  CHECK(k.fx == Approx(480 / (130 * kDeg)));  // fov_deg sets the focal length before distortion
  CHECK(k.k1 == 0.01);
  CHECK_FALSE(rig.Find("lateral")->enabled);
  CHECK_FALSE(rig.Check());

  const auto bad = YamlDocument::FromString("rear:\n  enabled: true\n", "bad.yaml");
  YamlMap bad_map(bad, bad.root, "sensors", nullptr);
  RigOptions rig2 = RigOptions::Default();
  const InputError e = test::InputErrorOf([&] { ParseSensors(bad_map, rig2); });
  CHECK(std::string(e.what()).rfind("bad.yaml:1:1: sensors.rear: unknown key", 0) == 0);

  const auto short_distortion =
      YamlDocument::FromString("upward:\n  distortion: [0.1]\n", "d.yaml");
  YamlMap d_map(short_distortion, short_distortion.root, "sensors", nullptr);
  RigOptions rig3 = RigOptions::Default();
  const InputError e2 = test::InputErrorOf([&] { ParseSensors(d_map, rig3); });
  CHECK(std::string(e2.what()).rfind("d.yaml:2:3: sensors.upward.distortion:", 0) == 0);
}

TEST_CASE("a camera mounted inside a wall is rejected at its mount", "[render][rig]") {
  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 7);
  RigOptions rig = RigOptions::Default();
  const SE3 robot = SE3::FromSE2(SE2(10.0, 0.0, 0.0));
  CHECK_FALSE(CheckCameraPlacement(world, rig, robot));
  rig.cameras[1].mount.y_m = 1.25;  // 5 cm into the left wall (inner face at y = 1.2)
  const auto problem = CheckCameraPlacement(world, rig, robot);
  REQUIRE(problem);
  CHECK(problem->key == "lateral.mount");
}

TEST_CASE("the remap's vector bilinear blend gives the scalar loop's bytes", "[render][rig]") {
  using detail::RemapEntry;
  // Two passes of random texels; entries anywhere, including the buffers' last pixels (a read
  // past a pass would show under the sanitizers), extreme weights and invalid entries.
  RandomStream rng(11, 0, "test.remap");
  const int widths[2] = {37, 64}, heights[2] = {23, 9};
  std::vector<std::vector<std::uint8_t>> rgb(2);
  std::vector<detail::PassImages> passes(2);
  for (std::size_t k = 0; k < 2; ++k) {
    rgb[k].resize(std::size_t(widths[k]) * std::size_t(heights[k]) * 3);
    for (std::uint8_t& b : rgb[k]) b = std::uint8_t(rng.UniformInt(0, 255));
    passes[k].rgb = rgb[k].data();
    passes[k].width = std::size_t(widths[k]);
  }
  std::vector<RemapEntry> remap(20000);
  for (std::size_t i = 0; i < remap.size(); ++i) {
    RemapEntry& e = remap[i];
    e.pass = std::uint8_t(rng.UniformInt(0, 1));
    const int w = widths[e.pass], h = heights[e.pass];
    const int x = i % 7 == 0 ? w - 2 : int(rng.UniformInt(0, w - 2));
    const int y = i % 11 == 0 ? h - 2 : int(rng.UniformInt(0, h - 2));
    e.top_left = std::uint32_t(y * w + x);
    const std::uint8_t extremes[3] = {0, 1, 255};
    e.wx = i % 5 == 0 ? extremes[i % 3] : std::uint8_t(rng.UniformInt(0, 255));
    e.wy = i % 3 == 0 ? extremes[i % 3] : std::uint8_t(rng.UniformInt(0, 255));
    e.nearest = i % 13 == 0 ? RemapEntry::kInvalid : std::uint8_t(rng.UniformInt(0, 3));
  }
  std::vector<std::uint8_t> vector_out(remap.size() * 3, 1), scalar_out(remap.size() * 3, 2);
  detail::BilinearRgb(remap, passes, vector_out.data());
  detail::BilinearRgbScalar(remap, passes, scalar_out.data());
  CHECK(vector_out == scalar_out);

  // The scalar loop itself: zero weights give the top-left texel, half a right weight the
  // rounded mean of the row's two texels, invalid entries black.
  const std::uint8_t texels[12] = {10, 20, 30, 11, 21, 31, 200, 100, 0, 255, 255, 255};
  const detail::PassImages block{texels, nullptr, nullptr, nullptr, 2};
  const std::vector<RemapEntry> probes = {
      {0, 0, 0, 0, 0}, {0, 128, 0, 0, 0}, {0, 0, 128, 0, 0}, {0, 0, 0, 0, RemapEntry::kInvalid}};
  std::uint8_t out[12];
  detail::BilinearRgbScalar(probes, std::span(&block, 1), out);
  CHECK(std::vector<int>(out, out + 12) ==
        std::vector<int>{10, 20, 30, 11, 21, 31, 105, 60, 15, 0, 0, 0});
}

}  // namespace
}  // namespace corridorsim::render
