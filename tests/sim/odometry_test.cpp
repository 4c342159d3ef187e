// Tests sim/odometry.cpp: exact quantised odometry without errors, the random error's statistics
// against P1 eq. 17 over many seeds, slips at their configured rate, determinism and the
// independence of the error sources' random streams, Borenstein's systematic errors, option
// checks and parsing.

#include "sim/odometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/gamma.hpp>
#include <boost/math/distributions/poisson.hpp>
#include <catch2/catch.hpp>

#include "common/wheel_odometry_model.h"
#include "tests/support/broken_options.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/option_bounds.h"
#include "tests/support/parsed_options.h"
#include "tests/support/tolerances.h"

namespace corridorsim::sim {
namespace {

using test::kOdometryRoundingM;
using test::kStatConfidence;

constexpr double kPi = std::numbers::pi;
constexpr double kDiameterM = 0.195;  // a Pioneer 3-DX wheel
constexpr double kRadiusM = 0.5 * kDiameterM;
constexpr double kWheelbaseM = 0.33;
constexpr TimeNs kPeriodNs = 20'000'000;  // 50 Hz
constexpr double kLowTail = 0.5 * (1.0 - kStatConfidence);
constexpr double kHighTail = 1.0 - kLowTail;

TimeNs StampOf(int i) { return static_cast<TimeNs>(i) * kPeriodNs; }

// Cumulative wheel angles (rad) of a drive that speeds up, slows down and reverses.
double WanderingLeftAngle(int i) {
  const double t = ToSeconds(StampOf(i));
  return 3.0 * t + 40.0 * std::sin(0.13 * t);
}
double WanderingRightAngle(int i) {
  const double t = ToSeconds(StampOf(i));
  return 2.5 * t - 30.0 * std::sin(0.07 * t);
}

// Cumulative wheel angles (rad) of a monotone drive at varying speed: the left wheel forward, the
// right wheel backward (so |s| matters, not s).
double ForwardLeftAngle(int i) { return 0.5 * i + 0.2 * std::sin(0.3 * i); }
double BackwardRightAngle(int i) { return -(0.3 * i + 0.1 * std::sin(0.5 * i)); }

// The defaults have P1's random error (k = 1e-4); error-free is explicit.
OdometryOptions ErrorFree() {
  OdometryOptions options;
  options.random_k_m = 0.0;
  return options;
}

TEST_CASE("an error-free odometer reports each interval's travel within one tick, in whole ticks",
          "[sim][odometry]") {
  WheelOdometer odometer(ErrorFree(), kDiameterM, 1);
  const double tick_m = kPi * kDiameterM / OdometryOptions{}.ticks_per_revolution;
  REQUIRE(odometer.tick_length_m() == Approx(tick_m).epsilon(1e-15));
  for (int i = 1; i <= 2000; ++i) {
    const WheelOdometry m =
        odometer.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i));
    INFO("message " << i);
    CHECK(m.stamp_ns == StampOf(i));
    CHECK(m.interval_ns == kPeriodNs);
    const double true_left_m = (WanderingLeftAngle(i) - WanderingLeftAngle(i - 1)) * kRadiusM;
    const double true_right_m = (WanderingRightAngle(i) - WanderingRightAngle(i - 1)) * kRadiusM;
    CHECK(std::abs(m.left_distance_m - true_left_m) < tick_m);
    CHECK(std::abs(m.right_distance_m - true_right_m) < tick_m);
    CHECK(m.left_distance_m == static_cast<double>(m.left_ticks) * odometer.tick_length_m());
    CHECK(m.right_distance_m == static_cast<double>(m.right_ticks) * odometer.tick_length_m());
  }
}

TEST_CASE("summed error-free reports never drift more than one tick over 10000 messages",
          "[sim][odometry]") {
  WheelOdometer odometer(ErrorFree(), kDiameterM, 1);
  const double tick_m = odometer.tick_length_m();
  std::int64_t left_ticks = 0, right_ticks = 0;
  double left_sum_m = 0.0, right_sum_m = 0.0;
  double worst_lag_m = 0.0;
  for (int i = 1; i <= 10'000; ++i) {
    const WheelOdometry m =
        odometer.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i));
    left_ticks += m.left_ticks;
    right_ticks += m.right_ticks;
    left_sum_m += m.left_distance_m;
    right_sum_m += m.right_distance_m;
    // The count is floor(M / tick) of the cumulative distance M: it lags M by [0, 1) tick.
    const double left_lag_m =
        WanderingLeftAngle(i) * kRadiusM - static_cast<double>(left_ticks) * tick_m;
    const double right_lag_m =
        WanderingRightAngle(i) * kRadiusM - static_cast<double>(right_ticks) * tick_m;
    worst_lag_m = std::max({worst_lag_m, std::abs(left_lag_m), std::abs(right_lag_m)});
    REQUIRE(left_lag_m >= -kOdometryRoundingM);
    REQUIRE(left_lag_m < tick_m + kOdometryRoundingM);
    REQUIRE(right_lag_m >= -kOdometryRoundingM);
    REQUIRE(right_lag_m < tick_m + kOdometryRoundingM);
    REQUIRE(std::abs(left_sum_m - static_cast<double>(left_ticks) * tick_m) < kOdometryRoundingM);
    REQUIRE(std::abs(right_sum_m - static_cast<double>(right_ticks) * tick_m) < kOdometryRoundingM);
  }
  // The drive covered hundreds of metres (tens of thousands of ticks) back and forth.
  CHECK(std::abs(WanderingLeftAngle(10'000)) * kRadiusM > 50.0);
  CHECK(worst_lag_m > 0.5 * tick_m);
}

TEST_CASE("without quantisation an error-free odometer reports the travel itself and no ticks",
          "[sim][odometry]") {
  OdometryOptions options = ErrorFree();
  options.ticks_per_revolution = 0;
  WheelOdometer odometer(options, kDiameterM, 1);
  CHECK(odometer.tick_length_m() == 0.0);
  for (int i = 1; i <= 1000; ++i) {
    const WheelOdometry m =
        odometer.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i));
    CHECK(m.left_distance_m ==
          Approx((WanderingLeftAngle(i) - WanderingLeftAngle(i - 1)) * kRadiusM)
              .margin(kOdometryRoundingM));
    CHECK(m.right_distance_m ==
          Approx((WanderingRightAngle(i) - WanderingRightAngle(i - 1)) * kRadiusM)
              .margin(kOdometryRoundingM));
    CHECK(m.left_ticks == 0);
    CHECK(m.right_ticks == 0);
  }
}

// Normalised random errors (sum reported - true) / sqrt(k |s|) of both wheels after `messages`
// messages of the monotone drive, one odometer per seed; also their raw values (m).
struct RandomErrors {
  std::vector<double> normalised;
  std::vector<double> raw_m;
};
RandomErrors RandomErrorsOverSeeds(double k_m, int messages, int seeds, std::uint64_t run_index) {
  OdometryOptions options;
  options.ticks_per_revolution = 0;  // the random error alone
  options.random_k_m = k_m;
  RandomErrors errors;
  for (int seed = 0; seed < seeds; ++seed) {
    WheelOdometer odometer(options, kDiameterM, static_cast<std::uint64_t>(seed), run_index);
    double left_sum_m = 0.0, right_sum_m = 0.0;
    for (int i = 1; i <= messages; ++i) {
      const WheelOdometry m =
          odometer.Measure(StampOf(i), ForwardLeftAngle(i), BackwardRightAngle(i));
      left_sum_m += m.left_distance_m;
      right_sum_m += m.right_distance_m;
    }
    const double left_true_m = ForwardLeftAngle(messages) * kRadiusM;
    const double right_true_m = BackwardRightAngle(messages) * kRadiusM;
    for (const auto& [sum_m, true_m] :
         {std::pair{left_sum_m, left_true_m}, std::pair{right_sum_m, right_true_m}}) {
      errors.raw_m.push_back(sum_m - true_m);
      errors.normalised.push_back((sum_m - true_m) / std::sqrt(k_m * std::abs(true_m)));
    }
  }
  return errors;
}

double SumOfSquares(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v * v;
  return sum;
}

TEST_CASE("random wheel errors have variance k |s| (P1 eq. 17): chi-square over 2000 seeds",
          "[sim][odometry][statistics]") {
  const double k_m = 1e-4;
  for (const int messages : {25, 100}) {
    INFO(messages << " messages");
    const RandomErrors errors = RandomErrorsOverSeeds(k_m, messages, 2000, 0);
    const double dof = static_cast<double>(errors.normalised.size());
    const boost::math::chi_squared chi2(dof);
    const double sum_sq = SumOfSquares(errors.normalised);
    CHECK(sum_sq > boost::math::quantile(chi2, kLowTail));
    CHECK(sum_sq < boost::math::quantile(chi2, kHighTail));
    // Unbiased: the mean of dof standard normals lies within the normal quantile / sqrt(dof).
    double mean = 0.0;
    for (const double z : errors.normalised) mean += z / dof;
    CHECK(std::abs(mean) < 2.576 / std::sqrt(dof));  // 2.576: the 99.5 % normal quantile
  }
}

TEST_CASE("the random error's spread grows with the square root of the distance",
          "[sim][odometry][statistics]") {
  // About four times the distance: about four times the variance. Separate run indices keep the
  // samples independent; the ratio of the mean squares is then 4 F(n, n) for zero-mean normal
  // errors.
  const double k_m = 1e-4;
  const RandomErrors short_run = RandomErrorsOverSeeds(k_m, 25, 2000, 1);
  const RandomErrors long_run = RandomErrorsOverSeeds(k_m, 100, 2000, 2);
  const double distance_ratio = std::abs(ForwardLeftAngle(100) / ForwardLeftAngle(25));
  REQUIRE(distance_ratio > 3.5);  // the long run is about four times as far
  const double n = static_cast<double>(short_run.raw_m.size());
  // Compare per wheel (the wheels' distances differ); each wheel's errors are every other entry.
  for (const int wheel : {0, 1}) {
    INFO((wheel == 0 ? "left" : "right") << " wheel");
    double short_sq = 0.0, long_sq = 0.0;
    for (std::size_t i = static_cast<std::size_t>(wheel); i < short_run.raw_m.size(); i += 2) {
      short_sq += short_run.raw_m[i] * short_run.raw_m[i];
      long_sq += long_run.raw_m[i] * long_run.raw_m[i];
    }
    const double wheel_distance_ratio =
        wheel == 0 ? distance_ratio : std::abs(BackwardRightAngle(100) / BackwardRightAngle(25));
    const boost::math::fisher_f f(0.5 * n, 0.5 * n);
    const double ratio = (long_sq / short_sq) / wheel_distance_ratio;
    CHECK(ratio > boost::math::quantile(f, kLowTail));
    CHECK(ratio < boost::math::quantile(f, kHighTail));
  }
}

// Drives `messages` messages of the wandering drive and collects every slip.
struct SlipRun {
  std::vector<WheelOdometry> messages;
  std::vector<std::vector<SlipEvent>> slips;  // per message
  double mean_travel_m = 0.0;                 // sum of (|delta_l| + |delta_r|) / 2
};
SlipRun DriveWithSlips(const OdometryOptions& options, std::uint64_t seed, int messages) {
  WheelOdometer odometer(options, kDiameterM, seed);
  SlipRun run;
  for (int i = 1; i <= messages; ++i) {
    std::vector<SlipEvent> slips;
    run.messages.push_back(
        odometer.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i), &slips));
    run.slips.push_back(slips);
    run.mean_travel_m += 0.5 * kRadiusM *
                         (std::abs(WanderingLeftAngle(i) - WanderingLeftAngle(i - 1)) +
                          std::abs(WanderingRightAngle(i) - WanderingRightAngle(i - 1)));
  }
  return run;
}

OdometryOptions SlipsOnly() {
  OdometryOptions options = ErrorFree();
  options.ticks_per_revolution = 0;
  options.slip_rate_per_m = 2.0;
  options.slip_mean_m = 0.02;
  return options;
}

TEST_CASE("slips occur at the configured rate per metre, on both wheels, with the mean size",
          "[sim][odometry][statistics]") {
  const OdometryOptions options = SlipsOnly();
  const SlipRun run = DriveWithSlips(options, 3, 20'000);
  std::int64_t events = 0, left_events = 0;
  double total_extra_m = 0.0;
  for (const auto& slips : run.slips) {
    for (const SlipEvent& slip : slips) {
      ++events;
      left_events += slip.left_wheel ? 1 : 0;
      total_extra_m += std::abs(slip.extra_distance_m);
    }
  }
  // The drive never stops a wheel over a whole message, so no event is dropped.
  const double expected = options.slip_rate_per_m * run.mean_travel_m;
  INFO(events << " slips over " << run.mean_travel_m << " m, expected " << expected);
  REQUIRE(expected > 200.0);
  const boost::math::poisson poisson(expected);
  CHECK(static_cast<double>(events) >= boost::math::quantile(poisson, kLowTail));
  CHECK(static_cast<double>(events) <= boost::math::quantile(poisson, kHighTail));
  const boost::math::binomial binomial(static_cast<double>(events), 0.5);
  CHECK(static_cast<double>(left_events) >= boost::math::quantile(binomial, kLowTail));
  CHECK(static_cast<double>(left_events) <= boost::math::quantile(binomial, kHighTail));
  // The sum of n exponentials with mean mu is Gamma(n, mu).
  const boost::math::gamma_distribution<> gamma(static_cast<double>(events), options.slip_mean_m);
  CHECK(total_extra_m > boost::math::quantile(gamma, kLowTail));
  CHECK(total_extra_m < boost::math::quantile(gamma, kHighTail));
}

TEST_CASE("each slip adds its extra distance to its wheel's report, in the direction of motion",
          "[sim][odometry]") {
  const int messages = 20'000;
  const SlipRun run = DriveWithSlips(SlipsOnly(), 4, messages);
  int slipped_messages = 0, backward_slips = 0;
  for (int i = 1; i <= messages; ++i) {
    const WheelOdometry& m = run.messages[std::size_t(i - 1)];
    const double true_left_m = (WanderingLeftAngle(i) - WanderingLeftAngle(i - 1)) * kRadiusM;
    const double true_right_m = (WanderingRightAngle(i) - WanderingRightAngle(i - 1)) * kRadiusM;
    double left_extra_m = 0.0, right_extra_m = 0.0;
    for (const SlipEvent& slip : run.slips[std::size_t(i - 1)]) {
      INFO("message " << i);
      CHECK(slip.stamp_ns == m.stamp_ns);
      CHECK(slip.extra_distance_m != 0.0);
      const double true_m = slip.left_wheel ? true_left_m : true_right_m;
      CHECK(std::signbit(slip.extra_distance_m) == std::signbit(true_m));
      backward_slips += slip.extra_distance_m < 0 ? 1 : 0;
      (slip.left_wheel ? left_extra_m : right_extra_m) += slip.extra_distance_m;
    }
    slipped_messages += run.slips[std::size_t(i - 1)].empty() ? 0 : 1;
    CHECK(m.left_distance_m - true_left_m == Approx(left_extra_m).margin(kOdometryRoundingM));
    CHECK(m.right_distance_m - true_right_m == Approx(right_extra_m).margin(kOdometryRoundingM));
  }
  CHECK(slipped_messages > 20);
  // The left wheel runs backward for about 17 m of the drive: about 17 backward slips expected.
  CHECK(backward_slips > 5);
}

TEST_CASE("a wheel that does not turn never slips", "[sim][odometry]") {
  WheelOdometer odometer(SlipsOnly(), kDiameterM, 5);
  int slips_seen = 0;
  for (int i = 1; i <= 5000; ++i) {
    std::vector<SlipEvent> slips;
    const WheelOdometry m = odometer.Measure(StampOf(i), 0.0, 0.3 * i, &slips);
    CHECK(m.left_distance_m == 0.0);
    for (const SlipEvent& slip : slips) CHECK_FALSE(slip.left_wheel);
    slips_seen += static_cast<int>(slips.size());
  }
  CHECK(slips_seen > 10);
}

OdometryOptions AllErrors() {
  OdometryOptions options;
  options.random_k_m = 1e-4;
  options.slip_rate_per_m = 1.0;
  return options;
}

bool SameMessage(const WheelOdometry& a, const WheelOdometry& b) {
  return a.stamp_ns == b.stamp_ns && a.interval_ns == b.interval_ns &&
         a.left_distance_m == b.left_distance_m && a.right_distance_m == b.right_distance_m &&
         a.left_ticks == b.left_ticks && a.right_ticks == b.right_ticks;
}

TEST_CASE("the same seed gives identical messages; another seed or run index does not",
          "[sim][odometry]") {
  WheelOdometer a(AllErrors(), kDiameterM, 11);
  WheelOdometer b(AllErrors(), kDiameterM, 11);
  WheelOdometer other_seed(AllErrors(), kDiameterM, 12);
  WheelOdometer other_run(AllErrors(), kDiameterM, 11, 1);
  int differ_seed = 0, differ_run = 0, slips_seen = 0;
  for (int i = 1; i <= 2000; ++i) {
    std::vector<SlipEvent> slips_a, slips_b;
    const WheelOdometry ma =
        a.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i), &slips_a);
    const WheelOdometry mb =
        b.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i), &slips_b);
    REQUIRE(SameMessage(ma, mb));
    REQUIRE(slips_a.size() == slips_b.size());
    for (std::size_t j = 0; j < slips_a.size(); ++j) {
      CHECK(slips_a[j].left_wheel == slips_b[j].left_wheel);
      CHECK(slips_a[j].extra_distance_m == slips_b[j].extra_distance_m);
    }
    slips_seen += static_cast<int>(slips_a.size());
    differ_seed += SameMessage(ma, other_seed.Measure(StampOf(i), WanderingLeftAngle(i),
                                                      WanderingRightAngle(i)))
                       ? 0
                       : 1;
    differ_run += SameMessage(ma, other_run.Measure(StampOf(i), WanderingLeftAngle(i),
                                                    WanderingRightAngle(i)))
                      ? 0
                      : 1;
  }
  CHECK(slips_seen > 0);
  CHECK(differ_seed > 100);
  CHECK(differ_run > 100);
}

TEST_CASE("switching slips on leaves the random-error draws unchanged, and vice versa",
          "[sim][odometry]") {
  OdometryOptions noise_only;
  noise_only.ticks_per_revolution = 0;
  noise_only.random_k_m = 1e-4;
  OdometryOptions noise_and_slips = noise_only;
  noise_and_slips.slip_rate_per_m = 2.0;
  const OdometryOptions slips_only = SlipsOnly();
  WheelOdometer without_slips(noise_only, kDiameterM, 21);
  WheelOdometer with_slips(noise_and_slips, kDiameterM, 21);
  WheelOdometer without_noise(slips_only, kDiameterM, 21);
  int slips_seen = 0;
  for (int i = 1; i <= 5000; ++i) {
    INFO("message " << i);
    std::vector<SlipEvent> slips, slips_without_noise;
    const WheelOdometry plain =
        without_slips.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i));
    const WheelOdometry slipped =
        with_slips.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i), &slips);
    without_noise.Measure(StampOf(i), WanderingLeftAngle(i), WanderingRightAngle(i),
                          &slips_without_noise);
    // The messages differ by exactly the slips: the random errors are the same draws.
    double left_extra_m = 0.0, right_extra_m = 0.0;
    for (const SlipEvent& slip : slips) {
      (slip.left_wheel ? left_extra_m : right_extra_m) += slip.extra_distance_m;
    }
    CHECK(slipped.left_distance_m - plain.left_distance_m ==
          Approx(left_extra_m).margin(kOdometryRoundingM));
    CHECK(slipped.right_distance_m - plain.right_distance_m ==
          Approx(right_extra_m).margin(kOdometryRoundingM));
    // And the slips are the same with and without the random error.
    REQUIRE(slips.size() == slips_without_noise.size());
    for (std::size_t j = 0; j < slips.size(); ++j) {
      CHECK(slips[j].left_wheel == slips_without_noise[j].left_wheel);
      CHECK(slips[j].extra_distance_m == slips_without_noise[j].extra_distance_m);
    }
    slips_seen += static_cast<int>(slips.size());
  }
  CHECK(slips_seen > 20);
}

TEST_CASE("RealWheelGeometry splits the nominal diameter by E_d as Borenstein does",
          "[sim][odometry]") {
  OdometryOptions options;
  options.diameter_ratio = 1.02;
  options.wheelbase_ratio = 1.05;
  const WheelGeometry real = RealWheelGeometry(options, kDiameterM, kWheelbaseM);
  CHECK(real.right_diameter_m / real.left_diameter_m == Approx(1.02).epsilon(1e-14));
  CHECK(0.5 * (real.left_diameter_m + real.right_diameter_m) == Approx(kDiameterM).epsilon(1e-14));
  CHECK(real.wheelbase_m == Approx(kWheelbaseM * 1.05).epsilon(1e-14));
  const WheelGeometry nominal = RealWheelGeometry(OdometryOptions{}, kDiameterM, kWheelbaseM);
  CHECK(nominal.left_diameter_m == kDiameterM);
  CHECK(nominal.right_diameter_m == kDiameterM);
  CHECK(nominal.wheelbase_m == kWheelbaseM);
}

TEST_CASE("the real geometry turns E_d into a curve and E_b into a heading error in odometry",
          "[sim][odometry]") {
  OdometryOptions options = ErrorFree();
  options.ticks_per_revolution = 0;
  options.diameter_ratio = 1.01;
  options.wheelbase_ratio = 1.04;
  const WheelGeometry real = RealWheelGeometry(options, kDiameterM, kWheelbaseM);

  // Straight 1 m on the ground: the encoders read left 1 m * D / D_L, right 1 m * D / D_R, so
  // the nominal odometry believes the robot turned right.
  {
    WheelOdometer odometer(options, kDiameterM, 1);
    const WheelOdometry m = odometer.Measure(kPeriodNs, 1.0 / (0.5 * real.left_diameter_m),
                                             1.0 / (0.5 * real.right_diameter_m));
    CHECK(m.left_distance_m / m.right_distance_m == Approx(1.01).epsilon(1e-12));
    const SE2 believed =
        ApplyWheelOdometry(SE2(), m.left_distance_m, m.right_distance_m, kWheelbaseM);
    CHECK(believed.yaw() < 0.0);
    CHECK(believed.yaw() ==
          Approx((m.right_distance_m - m.left_distance_m) / kWheelbaseM).epsilon(1e-12));
  }
  // A quarter turn in place on the ground: each wheel rolls b_real / 2 * pi / 2; the nominal
  // odometry believes the turn is E_b times larger.
  {
    WheelOdometer odometer(options, kDiameterM, 1);
    const double wheel_path_m = 0.5 * real.wheelbase_m * 0.5 * kPi;
    const WheelOdometry m =
        odometer.Measure(kPeriodNs, -wheel_path_m / (0.5 * real.left_diameter_m),
                         wheel_path_m / (0.5 * real.right_diameter_m));
    const SE2 believed =
        ApplyWheelOdometry(SE2(), m.left_distance_m, m.right_distance_m, kWheelbaseM);
    // Mean of the two wheels' readings: (D / D_L + D / D_R) / 2 = (E_d + 1)^2 / (4 E_d).
    const double diameter_factor = (1.01 + 1.0) * (1.01 + 1.0) / (4.0 * 1.01);
    CHECK(believed.yaw() == Approx(0.5 * kPi * 1.04 * diameter_factor).epsilon(1e-12));
  }
}

TEST_CASE("Check accepts the defaults and names the first bad odometry value", "[sim][odometry]") {
  CHECK_FALSE(AllErrors().Check());
  test::CheckEachBrokenOption<OdometryOptions>({
      {[](OdometryOptions& o) { o.rate_hz = 0; }, "rate_hz"},
      {[](OdometryOptions& o) { o.rate_hz = -50; }, "rate_hz"},
      {[](OdometryOptions& o) { o.rate_hz = 1e6; }, "rate_hz"},
      {[](OdometryOptions& o) { o.rate_hz = std::nan(""); }, "rate_hz"},
      // A period that overflows int64 ns (ran out of memory), or one whose slips per message
      // would be drawn by the million.
      {[](OdometryOptions& o) { o.rate_hz = 1e-10; }, "rate_hz"},
      {[](OdometryOptions& o) { o.rate_hz = 0.5; }, "rate_hz"},
      {[](OdometryOptions& o) { o.ticks_per_revolution = -1; }, "ticks_per_revolution"},
      {[](OdometryOptions& o) { o.ticks_per_revolution = 2'000'000; }, "ticks_per_revolution"},
      {[](OdometryOptions& o) { o.diameter_ratio = 0; }, "diameter_ratio"},
      {[](OdometryOptions& o) { o.diameter_ratio = -1.01; }, "diameter_ratio"},
      {[](OdometryOptions& o) { o.diameter_ratio = 3; }, "diameter_ratio"},
      {[](OdometryOptions& o) { o.wheelbase_ratio = 0; }, "wheelbase_ratio"},
      {[](OdometryOptions& o) { o.wheelbase_ratio = 2.5; }, "wheelbase_ratio"},
      {[](OdometryOptions& o) { o.random_k_m = -1e-4; }, "random_k_m"},
      {[](OdometryOptions& o) { o.random_k_m = 1.0; }, "random_k_m"},
      {[](OdometryOptions& o) { o.slip_rate_per_m = -0.1; }, "slip_rate_per_m"},
      {[](OdometryOptions& o) { o.slip_rate_per_m = 1e4; }, "slip_rate_per_m"},
      {[](OdometryOptions& o) { o.slip_mean_m = 0; }, "slip_mean_m"},
      {[](OdometryOptions& o) { o.slip_mean_m = 5; }, "slip_mean_m"},
  });
}

TEST_CASE("every bound of the odometry options names its key and the value", "[sim][odometry]") {
  OdometryOptions o;
  test::CheckEveryBoundNamesKeyAndValue(OdometryOptionsTable(), &o, "", [&] { return o.Check(); });
}

TEST_CASE("odometry options parse their keys over the defaults", "[sim][odometry]") {
  const OdometryOptions o = test::ParsedOptions(
      ParseOdometryOptions,
      "rate_hz: 20\nticks_per_revolution: 0\ndiameter_ratio: 1.005\nwheelbase_ratio: 0.98\n"
      "random_k_m: 0.0002\nslip_rate_per_m: 0.5\nslip_mean_m: 0.01\n",
      "odometry.yaml", "robot.odometry");
  CHECK(o.rate_hz == 20.0);
  CHECK(o.ticks_per_revolution == 0);
  CHECK(o.diameter_ratio == 1.005);
  CHECK(o.wheelbase_ratio == 0.98);
  CHECK(o.random_k_m == 0.0002);
  CHECK(o.slip_rate_per_m == 0.5);
  CHECK(o.slip_mean_m == 0.01);

  const OdometryOptions p = test::ParsedOptions(ParseOdometryOptions, "random_k_m: 0.001\n",
                                                "odometry.yaml", "robot.odometry");
  CHECK(p.random_k_m == 0.001);
  CHECK(p.ticks_per_revolution == OdometryOptions{}.ticks_per_revolution);
  CHECK(p.rate_hz == OdometryOptions{}.rate_hz);
}

TEST_CASE("odometry options reject unknown keys and wrong types naming file, line and key",
          "[sim][odometry]") {
  const InputError e =
      test::ParseErrorOf(ParseOdometryOptions, "random_k_m: 0.001\nslip_rate: 0.5\n",
                         "odometry.yaml", "robot.odometry");
  CHECK(std::string(e.what()).rfind(
            "odometry.yaml:2:1: robot.odometry.slip_rate: unknown key (known keys here: ", 0) == 0);

  CHECK(std::string(test::ParseErrorOf(ParseOdometryOptions, "ticks_per_revolution: 500.5\n",
                                       "odometry.yaml", "robot.odometry")
                        .what()) ==
        "odometry.yaml:1:1: robot.odometry.ticks_per_revolution: expected an integer, got "
        "'500.5'");
}

}  // namespace
}  // namespace corridorsim::sim
