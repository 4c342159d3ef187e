#include "render/noise.h"

#include <cmath>
#include <cstring>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/broken_options.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/parsed_options.h"
#include "tests/support/test_cameras.h"

namespace corridorsim::render {
namespace {

// Noise statistics must match their models within this relative error (sample sizes are chosen so
// that the sampling error is a few percent at most).
constexpr double kStatRelTol = 0.10;

constexpr double kRadPerDeg = std::numbers::pi / 180;

using test::Kinect;

PinholeRadTan Narrow(int size, double f) {
  PinholeRadTan k;
  k.width = k.height = size;
  k.fx = k.fy = f;
  k.cx = k.cy = 0.5 * (size - 1);
  return k;
}

Eigen::Vector3d Ray(const PinholeRadTan& k, int u, int v) {
  return {(u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0};
}

// Depth (z) of the plane through `point` with normal `normal`; 0 where the ray misses it.
ImageF PlaneDepth(const PinholeRadTan& k, const Eigen::Vector3d& normal,
                  const Eigen::Vector3d& point) {
  ImageF depth(k.width, k.height);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const double t = normal.dot(point) / normal.dot(Ray(k, u, v));
      depth.at(u, v) = t > 0 ? static_cast<float>(t) : 0.0f;
    }
  }
  return depth;
}

// Normal of a plane turned by `angle_deg` about the camera's y axis from fronto-parallel: the
// incidence angle on the optical axis is `angle_deg`.
Eigen::Vector3d TiltedNormal(double angle_deg) {
  return {std::sin(angle_deg * kRadPerDeg), 0.0, -std::cos(angle_deg * kRadPerDeg)};
}

DepthNoiseOptions AllDepthStagesOff() {
  DepthNoiseOptions o;
  o.min_m = 0.0;
  o.max_m = 100.0;
  o.quantise = false;
  o.axial = false;
  o.lateral_sigma_px = 0.0;
  o.grazing = false;
  o.random_dropout = 0.0;
  return o;
}

// A depth scene with a bit of everything: a tilted plane, a box in front of it, invalid pixels.
ImageF MixedScene(const PinholeRadTan& k) {
  ImageF depth = PlaneDepth(k, TiltedNormal(50), {0, 0, 3});
  for (int v = 100; v < 300; ++v) {
    for (int u = 200; u < 400; ++u) depth.at(u, v) = 1.5f + 0.001f * static_cast<float>(u - 200);
  }
  for (int v = 0; v < 40; ++v) {
    for (int u = 0; u < 60; ++u) depth.at(u, v) = 0.0f;
  }
  return depth;
}

double StdNormalTail(double a) { return 0.5 * std::erfc(a / std::numbers::sqrt2); }

TEST_CASE("depth noise with every stage off returns the input bit for bit", "[render][noise]") {
  const PinholeRadTan k = Kinect();
  const ImageF input = MixedScene(k);
  ImageF depth = input;
  RandomStream rng(1, 0, "test.depth");
  ApplyDepthNoise(AllDepthStagesOff(), k, rng, &depth);
  REQUIRE(depth.data.size() == input.data.size());
  CHECK(std::memcmp(depth.data.data(), input.data.data(), input.data.size() * sizeof(float)) == 0);
}

TEST_CASE("axial noise on a fronto-parallel plane has the standard deviation of its model",
          "[render][noise]") {
  const PinholeRadTan k = Kinect();
  DepthNoiseOptions o = AllDepthStagesOff();
  o.axial = true;
  for (const double z : {1.0, 2.0, 4.0}) {
    ImageF depth = PlaneDepth(k, {0, 0, -1}, {0, 0, z});
    const ImageF truth = depth;
    RandomStream rng(2, 0, "test.axial." + std::to_string(z));
    ApplyDepthNoise(o, k, rng, &depth);
    double sum = 0, sum2 = 0;
    for (std::size_t i = 0; i < depth.data.size(); ++i) {
      const double e = double(depth.data[i]) - truth.data[i];
      sum += e;
      sum2 += e * e;
    }
    const double n = static_cast<double>(depth.data.size());
    const double sigma_model = o.axial_a_m + o.axial_b * (z - o.axial_z0_m) * (z - o.axial_z0_m);
    CAPTURE(z);
    CHECK(std::abs(sum / n) < 0.01 * sigma_model);
    CHECK(std::sqrt(sum2 / n - (sum / n) * (sum / n)) == Approx(sigma_model).epsilon(kStatRelTol));
  }
}

TEST_CASE("quantised depths are fx * baseline / (k / subpixel) and err by at most half a step",
          "[render][noise]") {
  const PinholeRadTan k = Kinect();
  DepthNoiseOptions o = AllDepthStagesOff();
  o.quantise = true;
  const double fb = k.fx * o.baseline_m;
  // A plane receding from 1.2 m to infinity: many disparity steps.
  ImageF depth = PlaneDepth(k, TiltedNormal(60), {0, 0, 2.0});
  const ImageF truth = depth;
  RandomStream rng(3, 0, "test.quantise");
  ApplyDepthNoise(o, k, rng, &depth);
  std::set<float> values;
  int checked = 0;
  for (std::size_t i = 0; i < depth.data.size(); ++i) {
    const double z = truth.data[i], zq = depth.data[i];
    if (z < 0.5 || z > 8.0) continue;  // the sensor's range (the plane recedes to infinity)
    REQUIRE(zq > 0);
    const double steps = fb / zq * o.subpixel;  // the disparity in 1/subpixel px steps
    REQUIRE(std::abs(steps - std::round(steps)) < 1e-3);
    // |1/zq - 1/z| <= 1/(2 subpixel fb): half a disparity step.
    REQUIRE(std::abs(zq - z) <= z * zq / (2.0 * o.subpixel * fb) * (1 + 1e-5));
    values.insert(depth.data[i]);
    ++checked;
  }
  CHECK(checked > 100000);
  CHECK(values.size() > 100);  // many distinct steps, each one of the grid values
}

TEST_CASE("lateral noise frays a depth edge with the probabilities of a rounded Gaussian shift",
          "[render][noise]") {
  PinholeRadTan k = Narrow(16, 525.0);
  k.height = 50000;  // many rows: each column's statistics are over 50000 draws
  DepthNoiseOptions o = AllDepthStagesOff();
  o.lateral_sigma_px = 0.8;
  ImageF depth(k.width, k.height, 1.0f);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 8; u < 16; ++u) depth.at(u, v) = 2.0f;
  }
  RandomStream rng(4, 0, "test.lateral");
  ApplyDepthNoise(o, k, rng, &depth);
  std::vector<double> other(16, 0.0);  // per column: fraction of values from the other side
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < 16; ++u) {
      const float z = depth.at(u, v);
      REQUIRE((z == 1.0f || z == 2.0f));
      other[u] += (z == 1.0f) != (u < 8);
    }
  }
  for (double& f : other) f /= k.height;
  const double sigma = o.lateral_sigma_px;
  // A pixel d columns from the edge (d = 1 next to it) crosses when round(shift) >= d.
  for (int d = 1; d <= 2; ++d) {
    const double expected = StdNormalTail((d - 0.5) / sigma);
    CAPTURE(d);
    CHECK(other[8 - d] == Approx(expected).epsilon(kStatRelTol));
    CHECK(other[7 + d] == Approx(expected).epsilon(kStatRelTol));
  }
  // Shifts are clamped to ceil(4 sigma) = 4 px: columns 5 and more from the edge never change.
  for (int u : {0, 1, 2, 3, 12, 13, 14, 15}) CHECK(other[u] == 0.0);
}

TEST_CASE("grazing dropouts remove a plane tilted beyond the maximum angle and keep a facing one",
          "[render][noise]") {
  DepthNoiseOptions o = AllDepthStagesOff();
  o.grazing = true;
  SECTION("tilted 85 deg: everything dropped") {
    const PinholeRadTan k = Narrow(64, 2000.0);  // +-0.9 deg across the image
    ImageF depth = PlaneDepth(k, TiltedNormal(85), {0, 0, 2});
    RandomStream rng(5, 0, "test.grazing");
    ApplyDepthNoise(o, k, rng, &depth);
    for (const float z : depth.data) REQUIRE(z == 0.0f);
  }
  SECTION("fronto-parallel at full field of view: nothing dropped") {
    const PinholeRadTan k = Kinect();
    const ImageF input = PlaneDepth(k, {0, 0, -1}, {0, 0, 2});
    ImageF depth = input;
    RandomStream rng(5, 0, "test.grazing");
    ApplyDepthNoise(o, k, rng, &depth);
    CHECK(depth.data == input.data);
  }
  SECTION("tilted 74 deg: dropped with the probability of the linear ramp") {
    const PinholeRadTan k = Narrow(128, 2000.0);  // incidence 72.2 to 75.8 deg
    const Eigen::Vector3d normal = TiltedNormal(74);
    ImageF depth = PlaneDepth(k, normal, {0, 0, 2});
    RandomStream rng(5, 0, "test.grazing_ramp");
    ApplyDepthNoise(o, k, rng, &depth);
    double expected = 0, dropped = 0;
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        const Eigen::Vector3d ray = Ray(k, u, v);
        const double theta_deg = std::acos(std::abs(normal.dot(ray)) / ray.norm()) / kRadPerDeg;
        expected += (theta_deg - o.grazing_start_deg) / (o.grazing_max_deg - o.grazing_start_deg);
        dropped += depth.at(u, v) == 0.0f;
      }
    }
    CHECK(dropped == Approx(expected).epsilon(kStatRelTol));
  }
}

TEST_CASE("depths outside the valid range become invalid, the others stay", "[render][noise]") {
  const PinholeRadTan k = Kinect();
  DepthNoiseOptions o = AllDepthStagesOff();
  o.min_m = 0.5;
  o.max_m = 8.0;
  ImageF depth(k.width, k.height);
  RandomStream fill(6, 0, "test.range_fill");
  for (float& z : depth.data) z = static_cast<float>(fill.Uniform(0.0, 10.0));
  depth.data[0] = 0.5f;  // both ends are valid
  depth.data[1] = 8.0f;
  depth.data[2] = std::nanf("");
  const ImageF input = depth;
  RandomStream rng(6, 0, "test.range");
  ApplyDepthNoise(o, k, rng, &depth);
  int beyond = 0;
  for (std::size_t i = 0; i < input.data.size(); ++i) {
    const float z = input.data[i];
    const bool valid = z >= 0.5f && z <= 8.0f;
    beyond += z > 8.0f;
    REQUIRE(depth.data[i] == (valid ? z : 0.0f));
  }
  CHECK(beyond > 1000);
  // The range alone (a camera with its noise off) invalidates exactly the same pixels.
  ImageF range_only = input;
  ApplyDepthRange(o, &range_only);
  CHECK(range_only.data == depth.data);
}

TEST_CASE("random dropouts remove the stated fraction of pixels", "[render][noise]") {
  const PinholeRadTan k = Kinect();
  DepthNoiseOptions o = AllDepthStagesOff();
  o.random_dropout = 0.2;
  ImageF depth = PlaneDepth(k, {0, 0, -1}, {0, 0, 3});
  RandomStream rng(7, 0, "test.dropout");
  ApplyDepthNoise(o, k, rng, &depth);
  double dropped = 0;
  for (const float z : depth.data) dropped += z == 0.0f;
  CHECK(dropped / double(depth.data.size()) == Approx(0.2).epsilon(kStatRelTol));
}

TEST_CASE("depth noise is a function of its stream", "[render][noise]") {
  const PinholeRadTan k = Kinect();
  const DepthNoiseOptions o;  // the Xtion defaults: every stage on
  const ImageF input = MixedScene(k);
  ImageF a = input, b = input, c = input;
  RandomStream rng_a(8, 0, "camera.front"), rng_b(8, 0, "camera.front"),
      rng_c(8, 1, "camera.front");
  ApplyDepthNoise(o, k, rng_a, &a);
  ApplyDepthNoise(o, k, rng_b, &b);
  ApplyDepthNoise(o, k, rng_c, &c);
  CHECK(a.data == b.data);
  CHECK(a.data != c.data);
  CHECK(a.data != input.data);
}

Image8 RandomImage(int width, int height, std::uint64_t seed) {
  Image8 image(width, height, 3);
  RandomStream fill(seed, 0, "test.image");
  for (auto& v : image.data) v = static_cast<std::uint8_t>(fill.UniformInt(0, 255));
  return image;
}

TEST_CASE("rgb noise with every stage off returns the input bit for bit", "[render][noise]") {
  const Image8 input = RandomImage(64, 48, 9);
  Image8 image = input;
  RandomStream rng(9, 0, "test.rgb");
  ApplyRgbNoise(RgbNoiseOptions{}, rng, &image);
  CHECK(image.data == input.data);
  RgbNoiseOptions blur_without_motion;
  blur_without_motion.motion_blur_px = 5;
  ApplyRgbNoise(blur_without_motion, rng, &image, {0, 0});
  CHECK(image.data == input.data);
}

// Sample variance of every channel value of `image` around its sample mean.
std::pair<double, double> MeanAndVariance(const Image8& image) {
  double sum = 0, sum2 = 0;
  for (const auto v : image.data) {
    sum += v;
    sum2 += double(v) * v;
  }
  const double n = static_cast<double>(image.data.size());
  return {sum / n, sum2 / n - (sum / n) * (sum / n)};
}

TEST_CASE("shot and read noise on a flat grey image follow the Poisson-Gaussian model",
          "[render][noise]") {
  struct Case {
    int dn;
    double full_well, read;
  };
  for (const Case c : {Case{128, 1000, 10}, Case{50, 2000, 0}, Case{200, 20000, 20}}) {
    Image8 image(640, 480, 3);
    std::fill(image.data.begin(), image.data.end(), static_cast<std::uint8_t>(c.dn));
    RgbNoiseOptions o;
    o.full_well_electrons = c.full_well;
    o.read_noise_electrons = c.read;
    RandomStream rng(10, 0, "test.shot");
    ApplyRgbNoise(o, rng, &image);
    const auto [mean, var] = MeanAndVariance(image);
    const double read_dn = c.read * 255 / c.full_well;
    const double model = c.dn * 255 / c.full_well + read_dn * read_dn;
    CAPTURE(c.dn, c.full_well, c.read);
    CHECK(mean == Approx(c.dn).margin(0.05));
    CHECK(var == Approx(model).epsilon(kStatRelTol));
  }
}

TEST_CASE("vignetting darkens the corners by the stated fraction", "[render][noise]") {
  Image8 image(101, 81, 3);
  std::fill(image.data.begin(), image.data.end(), std::uint8_t{200});
  RgbNoiseOptions o;
  o.vignetting = 0.3;
  RandomStream rng(11, 0, "test.vignetting");
  ApplyRgbNoise(o, rng, &image);
  for (const auto& [x, y] : {std::pair{0, 0}, {100, 0}, {0, 80}, {100, 80}}) {
    CHECK(image.Pixel(x, y)[0] == 140);
  }
  CHECK(image.Pixel(50, 40)[0] == 200);
  // Radial quadratic: the middle of the top edge at r^2 = 40^2 of the corner's 50^2 + 40^2.
  CHECK(image.Pixel(50, 0)[1] == std::lround(200 * (1 - 0.3 * 1600.0 / 4100.0)));
}

TEST_CASE("exposure scales the signal and saturates at 255", "[render][noise]") {
  Image8 image(4, 2, 3);
  for (std::size_t i = 0; i < image.data.size(); ++i) image.data[i] = i % 2 ? 100 : 200;
  RgbNoiseOptions o;
  o.exposure = 0.5;
  RandomStream rng(12, 0, "test.exposure");
  Image8 darker = image;
  ApplyRgbNoise(o, rng, &darker);
  o.exposure = 2.0;
  Image8 brighter = image;
  ApplyRgbNoise(o, rng, &brighter);
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    CHECK(darker.data[i] == image.data[i] / 2);
    CHECK(brighter.data[i] == (i % 2 ? 200 : 255));
  }
}

TEST_CASE("motion blur spreads a bright pixel over the stated length along the direction",
          "[render][noise]") {
  RgbNoiseOptions o;
  o.motion_blur_px = 8;
  const int size = 41, centre = 20;
  auto blurred_dot = [&](const Eigen::Vector2d& direction) {
    Image8 image(size, size, 3);
    std::fill_n(image.Pixel(centre, centre), 3, std::uint8_t{255});
    RandomStream rng(13, 0, "test.blur");
    ApplyRgbNoise(o, rng, &image, direction);
    return image;
  };
  SECTION("horizontal and vertical: a box of 8 px, half weights at its ends") {
    for (const bool vertical : {false, true}) {
      const Image8 image = blurred_dot(vertical ? Eigen::Vector2d(0, -2) : Eigen::Vector2d(3, 0));
      int total = 0;
      for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
          const int along = vertical ? y - centre : x - centre;
          const int across = vertical ? x - centre : y - centre;
          const int v = image.Pixel(x, y)[0];
          total += v;
          CAPTURE(vertical, x, y);
          CHECK(image.Pixel(x, y)[2] == v);
          if (across != 0 || std::abs(along) > 4) {
            CHECK(v == 0);
          } else if (std::abs(along) == 4) {
            CHECK(v == Approx(255.0 / 16).margin(1));
          } else {
            CHECK(v == Approx(255.0 / 8).margin(1));
          }
        }
      }
      CHECK(total == Approx(255).margin(5));
    }
  }
  SECTION("diagonal: along the diagonal, over the same length") {
    const Image8 image = blurred_dot({1, 1});
    int total = 0;
    double farthest = 0;
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        const int v = image.Pixel(x, y)[0];
        if (v == 0) continue;
        total += v;
        const double along = (x - centre + y - centre) / std::numbers::sqrt2;
        const double across = (x - centre - (y - centre)) / std::numbers::sqrt2;
        CAPTURE(x, y);
        CHECK(std::abs(across) <= 1.0);
        CHECK(std::abs(along) <= o.motion_blur_px / 2 + 1);
        farthest = std::max(farthest, std::abs(along));
      }
    }
    CHECK(farthest >= o.motion_blur_px / 2 - 1);
    CHECK(total == Approx(255).margin(12));
  }
  SECTION("a flat image stays flat") {
    Image8 image(size, size, 3);
    std::fill(image.data.begin(), image.data.end(), std::uint8_t{77});
    const Image8 input = image;
    RandomStream rng(13, 0, "test.blur_flat");
    ApplyRgbNoise(o, rng, &image, {0.3, 0.7});
    CHECK(image.data == input.data);
  }
}

TEST_CASE("rgb noise is a function of its stream", "[render][noise]") {
  RgbNoiseOptions o;
  o.full_well_electrons = 6000;
  o.read_noise_electrons = 6;
  o.vignetting = 0.2;
  o.motion_blur_px = 3;
  const Image8 input = RandomImage(160, 120, 14);
  Image8 a = input, b = input, c = input;
  RandomStream rng_a(14, 0, "camera.upward"), rng_b(14, 0, "camera.upward"),
      rng_c(14, 0, "camera.front");
  ApplyRgbNoise(o, rng_a, &a, {0.6, 0.8});
  ApplyRgbNoise(o, rng_b, &b, {0.6, 0.8});
  ApplyRgbNoise(o, rng_c, &c, {0.6, 0.8});
  CHECK(a.data == b.data);
  CHECK(a.data != c.data);
}

TEST_CASE("Check accepts the defaults and names the first bad depth noise value",
          "[render][noise]") {
  test::CheckEachBrokenOption<DepthNoiseOptions>({
      {[](DepthNoiseOptions& o) { o.min_m = -0.1; }, "min_m"},
      {[](DepthNoiseOptions& o) { o.max_m = o.min_m; }, "max_m"},
      {[](DepthNoiseOptions& o) { o.baseline_m = 0; }, "baseline_m"},
      {[](DepthNoiseOptions& o) { o.subpixel = 0; }, "subpixel"},
      {[](DepthNoiseOptions& o) { o.axial_a_m = -0.001; }, "axial_a_m"},
      {[](DepthNoiseOptions& o) { o.axial_b = -1; }, "axial_b"},
      {[](DepthNoiseOptions& o) { o.lateral_sigma_px = -0.5; }, "lateral_sigma_px"},
      {[](DepthNoiseOptions& o) { o.grazing_start_deg = 80; }, "grazing_max_deg"},
      {[](DepthNoiseOptions& o) { o.grazing_max_deg = 95; }, "grazing_max_deg"},
      {[](DepthNoiseOptions& o) { o.random_dropout = 1.5; }, "random_dropout"},
      {[](DepthNoiseOptions& o) { o.random_dropout = -0.1; }, "random_dropout"},
  });
}

TEST_CASE("Check accepts the defaults and names the first bad rgb noise value", "[render][noise]") {
  test::CheckEachBrokenOption<RgbNoiseOptions>({
      {[](RgbNoiseOptions& o) { o.exposure = 0; }, "exposure"},
      {[](RgbNoiseOptions& o) { o.vignetting = 1.2; }, "vignetting"},
      {[](RgbNoiseOptions& o) { o.full_well_electrons = -1; }, "full_well_electrons"},
      {[](RgbNoiseOptions& o) { o.read_noise_electrons = 5; }, "read_noise_electrons"},
      {[](RgbNoiseOptions& o) {
         o.full_well_electrons = 1000;
         o.read_noise_electrons = -1;
       },
       "read_noise_electrons"},
      {[](RgbNoiseOptions& o) { o.motion_blur_px = -2; }, "motion_blur_px"},
  });
}

TEST_CASE("noise options parse their keys over the defaults", "[render][noise]") {
  const DepthNoiseOptions d = test::ParsedOptions(
      ParseDepthNoiseOptions, "max_m: 4.5\nquantise: false\nsubpixel: 4\nlateral_sigma_px: 0.5\n",
      "depth.yaml", "depth_noise");
  CHECK(d.max_m == 4.5);
  CHECK_FALSE(d.quantise);
  CHECK(d.subpixel == 4);
  CHECK(d.lateral_sigma_px == 0.5);
  CHECK(d.min_m == DepthNoiseOptions{}.min_m);

  const RgbNoiseOptions r = test::ParsedOptions(
      ParseRgbNoiseOptions,
      "full_well_electrons: 6000\nread_noise_electrons: 6\nmotion_blur_px: 2.5\n", "rgb.yaml",
      "rgb_noise");
  CHECK(r.full_well_electrons == 6000);
  CHECK(r.read_noise_electrons == 6);
  CHECK(r.motion_blur_px == 2.5);
  CHECK(r.exposure == 1.0);
}

TEST_CASE("noise options reject unknown keys naming file, line, column and key",
          "[render][noise]") {
  const InputError e = test::ParseErrorOf(ParseDepthNoiseOptions, "max_m: 4.5\naxial_sigma: 0.1\n",
                                          "noise.yaml", "camera.depth_noise");
  CHECK(std::string(e.what()).rfind(
            "noise.yaml:2:1: camera.depth_noise.axial_sigma: unknown key (known keys here: ", 0) ==
        0);

  const InputError e2 = test::ParseErrorOf(ParseRgbNoiseOptions, "exposure: 2\ngain: 3\n",
                                           "noise.yaml", "camera.rgb_noise");
  CHECK(std::string(e2.what()).rfind(
            "noise.yaml:2:1: camera.rgb_noise.gain: unknown key (known keys here: ", 0) == 0);

  CHECK(std::string(test::ParseErrorOf(ParseDepthNoiseOptions, "subpixel: 2.5\n", "noise.yaml",
                                       "depth_noise")
                        .what()) ==
        "noise.yaml:1:1: depth_noise.subpixel: expected an integer, got '2.5'");
}

}  // namespace
}  // namespace corridorsim::render
