// slam/features/ceiling_lamps.cpp: P3 section II's circular lamp test (eqs. 1-2) on drawn images
// (a disc, a panel, a disc cut by the border, a disc on a ceiling seen through a fisheye, glare,
// and the degenerate frames the issue names) and on rendered upward frames scored against the
// frame truth.
#include <cmath>

#include <catch2/catch.hpp>

#include "common/random.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "slam/features/ceiling_lamps.h"
#include "tests/support/upward_frames.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

Image8 Grey(int width, int height, std::uint8_t level) {
  Image8 image;
  image.width = width;
  image.height = height;
  image.channels = 1;
  image.data.assign(std::size_t(width) * std::size_t(height), level);
  return image;
}

// Pixels whose centre lies inside `inside(u, v)` set to `level`, 4x4 supersampled (antialiased
// as the renderer's edges are).
template <class Inside>
void Fill(Image8* image, std::uint8_t level, Inside inside) {
  for (int v = 0; v < image->height; ++v) {
    for (int u = 0; u < image->width; ++u) {
      int hits = 0;
      for (int i = 0; i < 16; ++i)
        hits += inside(u - 0.375 + 0.25 * (i % 4), v - 0.375 + 0.25 * (i / 4));
      std::uint8_t& p = image->data[std::size_t(v) * std::size_t(image->width) + std::size_t(u)];
      p = std::uint8_t(std::lround(p + (level - p) * hits / 16.0));
    }
  }
}

void Disc(Image8* image, double cu, double cv, double radius) {
  Fill(image, 255, [&](double u, double v) { return std::hypot(u - cu, v - cv) < radius; });
}

TEST_CASE("three-point centre: P3 eqs. 1-2 give the circle's centre; collinear points none",
          "[lamps]") {
  const Eigen::Vector2d c(3.0, -2.0);
  const auto on = [&](double a) {
    return Eigen::Vector2d(c + 5.0 * Eigen::Vector2d(std::cos(a), std::sin(a)));
  };
  // Two of the three points on a vertical chord: the slope form of eq. 1 would be infinite.
  const std::optional<Eigen::Vector2d> centre = slam::ThreePointCentre(on(0.3), on(-0.3), on(2.0));
  REQUIRE(centre);
  CHECK((*centre - c).norm() < 1e-9);
  CHECK_FALSE(slam::ThreePointCentre({0, 0}, {1, 1}, {2, 2}));
  CHECK_FALSE(slam::ThreePointCentre({0, 0}, {0, 0}, {2, 5}));
}

TEST_CASE("lamps: a disc is a circular lamp with its centre; a panel is rejected", "[lamps]") {
  Image8 image = Grey(320, 240, 150);
  Disc(&image, 100.3, 120.6, 18.0);
  Fill(&image, 255, [](double u, double v) { return u > 200 && u < 290 && v > 100 && v < 130; });
  const slam::CeilingLampDetection found =
      slam::DetectCeilingLamps(image, nullptr, slam::CeilingLampOptions{});
  REQUIRE(found.lamps.size() == 1);
  CHECK((found.lamps[0].center_px - Eigen::Vector2d(100.3, 120.6)).norm() < 0.5);
  CHECK(found.lamps[0].radius_px == Approx(18.0).margin(1.0));
  CHECK(found.lamps[0].sigma1_px < slam::CeilingLampOptions{}.k_conv_px);
  CHECK_FALSE(found.lamps[0].cut_by_border);
  REQUIRE(found.rejected.size() == 1);
  CHECK(std::string(found.rejected[0].rejection) == "not_circular");
  CHECK(found.rejected[0].sigma1_px > 10.0);
}

TEST_CASE("lamps: a disc cut by the border gives its true centre (P3 Fig. 3b)", "[lamps]") {
  Image8 image = Grey(320, 240, 150);
  Disc(&image, 40.0, 8.0, 20.0);  // centre 8 px below the top edge: a third of the disc is cut off
  const slam::CeilingLampDetection found =
      slam::DetectCeilingLamps(image, nullptr, slam::CeilingLampOptions{});
  REQUIRE(found.lamps.size() == 1);
  CHECK(found.lamps[0].cut_by_border);
  CHECK((found.lamps[0].center_px - Eigen::Vector2d(40.0, 8.0)).norm() < 1.0);
}

TEST_CASE("lamps: through a fisheye, a disc on the ceiling off the axis is found by the model",
          "[lamps]") {
  const CameraModel model = KannalaBrandt::FromFov(640, 480, 110.0 * M_PI / 180.0);
  // A 0.25 m disc on a ceiling 2.2 m above the camera, 2.0 m off the axis (42 deg): an ellipse
  // in the image.
  const Eigen::Vector3d centre(2.0, 0.6, 2.2);
  Image8 image = Grey(640, 480, 150);
  Fill(&image, 255, [&](double u, double v) {
    const Eigen::Vector3d b = model.Unproject({u, v});
    if (b.z() <= 0) return false;
    const Eigen::Vector3d p = b * centre.z() / b.z();
    return (p.head<2>() - centre.head<2>()).norm() < 0.25;
  });
  const Eigen::Vector2d truth = *model.Project(centre);
  const slam::CeilingLampDetection with_model =
      slam::DetectCeilingLamps(image, &model, slam::CeilingLampOptions{});
  REQUIRE(with_model.lamps.size() == 1);
  CHECK((with_model.lamps[0].center_px - truth).norm() < 0.5);
  // In the fisheye's pixels the three-point centres of the ellipse spread.
  const slam::CeilingLampDetection pixels =
      slam::DetectCeilingLamps(image, nullptr, slam::CeilingLampOptions{});
  CHECK(pixels.lamps.empty());
}

TEST_CASE("lamps: soft glare crossing the threshold in a circle is not a lamp", "[lamps]") {
  Image8 image = Grey(320, 240, 0);
  Fill(&image, 0, [](double, double) { return false; });
  for (int v = 0; v < 240; ++v) {
    for (int u = 0; u < 320; ++u) {
      const double r = std::hypot(u - 160.0, v - 120.0);
      image.data[std::size_t(v * 320 + u)] = std::uint8_t(std::clamp(250.0 - 0.8 * r, 0.0, 255.0));
    }
  }
  const slam::CeilingLampDetection found =
      slam::DetectCeilingLamps(image, nullptr, slam::CeilingLampOptions{});
  CHECK(found.lamps.empty());
  REQUIRE(found.rejected.size() == 1);
  CHECK(std::string(found.rejected[0].rejection) == "low_contrast");
}

TEST_CASE("lamps: black, flat, noise and full-of-lamps frames are handled and counted", "[lamps]") {
  const CameraModel model = KannalaBrandt::FromFov(640, 480, 110.0 * M_PI / 180.0);
  const slam::CeilingLampOptions options;
  // Black: no bright region at all.
  const slam::CeilingLampDetection black =
      slam::DetectCeilingLamps(Grey(640, 480, 0), &model, options);
  CHECK(black.regions == 0);
  CHECK(black.lamps.empty());
  // One flat colour above the threshold: one region, the whole frame, too large to be a lamp.
  const slam::CeilingLampDetection flat =
      slam::DetectCeilingLamps(Grey(640, 480, 255), &model, options);
  CHECK(flat.lamps.empty());
  CHECK(flat.regions == 0);
  // Pure noise: many tiny bright specks, none a lamp; the work is bounded by max_regions.
  Image8 noise = Grey(640, 480, 0);
  RandomStream rng(3, 0, "test.noise");
  for (std::uint8_t& p : noise.data) p = std::uint8_t(rng.UniformInt(0, 255));
  const slam::CeilingLampDetection specks = slam::DetectCeilingLamps(noise, &model, options);
  CHECK(specks.lamps.empty());
  CHECK(int(specks.lamps.size() + specks.rejected.size()) <= options.max_regions);
  // Full of lamps: a 9 x 7 grid of discs; every one is found, the test count is bounded.
  Image8 full = Grey(640, 480, 140);
  int drawn = 0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 7; ++j) {
      Disc(&full, 40.0 + 70.0 * i, 35.0 + 68.0 * j, 14.0);
      ++drawn;
    }
  }
  const slam::CeilingLampDetection many = slam::DetectCeilingLamps(full, nullptr, options);
  CHECK(many.regions == drawn);
  CHECK(int(many.lamps.size()) == drawn);
  slam::CeilingLampOptions few = options;
  few.max_regions = 10;
  const slam::CeilingLampDetection bounded = slam::DetectCeilingLamps(full, nullptr, few);
  CHECK(bounded.lamps.size() == 10);
  CHECK(bounded.regions_skipped == drawn - 10);
}

TEST_CASE("lamps: the same image gives the same lamps; another seed, nearly the same centres",
          "[lamps]") {
  Image8 image = Grey(320, 240, 150);
  Disc(&image, 100.3, 120.6, 18.0);
  Disc(&image, 220.0, 60.0, 12.0);
  slam::CeilingLampOptions options;
  const slam::CeilingLampDetection a = slam::DetectCeilingLamps(image, nullptr, options);
  const slam::CeilingLampDetection b = slam::DetectCeilingLamps(image, nullptr, options);
  REQUIRE(a.lamps.size() == 2);
  REQUIRE(b.lamps.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(a.lamps[i].center_px == b.lamps[i].center_px);
    CHECK(a.lamps[i].sigma1_px == b.lamps[i].sigma1_px);
  }
  options.seed = 99;
  const slam::CeilingLampDetection c = slam::DetectCeilingLamps(image, nullptr, options);
  REQUIRE(c.lamps.size() == 2);
  CHECK(c.lamps[0].center_px != a.lamps[0].center_px);
  CHECK((c.lamps[0].center_px - a.lamps[0].center_px).norm() < 0.5);
}

TEST_CASE("lamps: rendered upward frames, scored against the frame truth", "[lamps][render]") {
  // P3 environment A (scenarios/p3_lamps.yaml's world): circular lamps, panels and reflectors.
  worlds::WorldOptions world_options;
  world_options.length_m = 40.0;
  world_options.lamps.spacing_m = 2.5;
  world_options.lamps.circular_fraction = 0.7;
  world_options.lamps.reflector_fraction = 0.2;
  const worlds::World world = worlds::Generate(world_options, 4);
  test::UpwardFrames frames(world);
  const CameraModel& model = frames.model();
  int full = 0, found = 0, panels = 0, panels_rejected = 0, false_lamps = 0;
  double worst_px = 0.0;
  for (int k = 0; k < 12; ++k) {
    // Down the corridor's centre line, turning, so that lamps cross every part of the image.
    const SE3 world_from_robot = SE3::FromSE2(SE2(3.0 + 2.9 * k, 0.15 * (k % 3 - 1), 0.5 * k));
    render::CameraFrame frame;
    const render::FrameTruth truth = frames.Render(world_from_robot, std::uint64_t(k), &frame);
    const slam::CeilingLampDetection lamps =
        slam::DetectCeilingLamps(frame.rgb, &model, slam::CeilingLampOptions{});
    std::vector<bool> used(lamps.lamps.size(), false);
    for (const render::LampTruth& t : truth.lamps) {
      if (t.visible_fraction < 0.5) continue;
      std::optional<std::size_t> match;
      for (std::size_t i = 0; i < lamps.lamps.size(); ++i) {
        if ((lamps.lamps[i].center_px - t.center_px).norm() <= std::max(5.0, 0.5 * t.radius_px)) {
          match = i;
        }
      }
      if (match) used[*match] = true;
      const bool circular = t.shape == worlds::LampShape::kCircular;
      if (circular && t.on && !t.cut_by_border && t.visible_fraction >= 0.95) {
        ++full;
        if (match) {
          ++found;
          worst_px = std::max(worst_px, (lamps.lamps[*match].center_px - t.center_px).norm());
        }
      } else if (!circular) {
        ++panels;
        panels_rejected += !match;
      }
    }
    for (const bool u : used) false_lamps += !u;
  }
  INFO("fully visible circular lamps " << found << "/" << full << ", worst centre error "
                                       << worst_px << " px; panels rejected " << panels_rejected
                                       << "/" << panels << "; false lamps " << false_lamps);
  REQUIRE(full >= 10);
  CHECK(found >= 0.95 * full);
  CHECK(worst_px <= 2.0);
  CHECK(panels_rejected >= 0.95 * panels);
  CHECK(false_lamps == 0);
}

}  // namespace
}  // namespace corridorsim
