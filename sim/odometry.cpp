#include "sim/odometry.h"

#include <cassert>
#include <cmath>
#include <numbers>
#include <string>

#include "common/io/options_yaml.h"

namespace corridorsim::sim {

std::optional<OptionsProblem> OdometryOptions::Check() const {
  return CheckOptionBounds(OdometryOptionsTable(), *this);
}

void ParseOdometryOptions(YamlMap& map, OdometryOptions& options) {
  ReadOptions(map, OdometryOptionsTable(), options);
}

WheelGeometry RealWheelGeometry(const OdometryOptions& options, double nominal_diameter_m,
                                double nominal_wheelbase_m) {
  // Borenstein & Feng, UMBmark (1996): E_d = D_R / D_L with the mean diameter kept nominal.
  const double e_d = options.diameter_ratio;
  return WheelGeometry{2.0 * nominal_diameter_m / (e_d + 1.0),
                       2.0 * nominal_diameter_m * e_d / (e_d + 1.0),
                       nominal_wheelbase_m * options.wheelbase_ratio};
}

WheelOdometer::WheelOdometer(const OdometryOptions& options, double nominal_wheel_diameter_m,
                             std::uint64_t seed, std::uint64_t run_index)
    : options_(options),
      nominal_radius_m_(0.5 * nominal_wheel_diameter_m),
      tick_length_m_(options.ticks_per_revolution > 0
                         ? std::numbers::pi * nominal_wheel_diameter_m /
                               options.ticks_per_revolution
                         : 0.0),
      left_rng_(seed, run_index, "sim.odometry.left"),
      right_rng_(seed, run_index, "sim.odometry.right"),
      slip_rng_(seed, run_index, "sim.odometry.slip") {
  assert(!options.Check());
  assert(nominal_wheel_diameter_m > 0.0);
}

void WheelOdometer::Report(Wheel& wheel, double measured_m, double* distance_m,
                           std::int64_t* ticks) const {
  if (tick_length_m_ > 0.0) {
    // The count is taken on the cumulative distance, so quantisation error does not accumulate.
    const auto count = static_cast<std::int64_t>(std::floor(measured_m / tick_length_m_));
    *ticks = count - wheel.count;
    *distance_m = static_cast<double>(*ticks) * tick_length_m_;
    wheel.count = count;
  } else {
    *ticks = 0;
    *distance_m = measured_m - wheel.reported_m;
  }
  wheel.reported_m = measured_m;
}

WheelOdometry WheelOdometer::Measure(TimeNs stamp_ns, double left_angle_rad, double right_angle_rad,
                                     std::vector<SlipEvent>* slips) {
  assert(stamp_ns >= last_stamp_ns_);
  if (slips != nullptr) slips->clear();
  // Wheel travel over the interval as the encoders see it (nominal radius), m.
  const double left_delta_m = (left_angle_rad - left_.angle_rad) * nominal_radius_m_;
  const double right_delta_m = (right_angle_rad - right_.angle_rad) * nominal_radius_m_;

  // Random error, variance k |delta| per wheel (P1 eq. 17); nothing is drawn when k = 0.
  const double k = options_.random_k_m;
  if (k > 0.0) {
    if (left_delta_m != 0.0) {
      left_.error_m += left_rng_.Normal(0.0, std::sqrt(k * std::abs(left_delta_m)));
    }
    if (right_delta_m != 0.0) {
      right_.error_m += right_rng_.Normal(0.0, std::sqrt(k * std::abs(right_delta_m)));
    }
  }

  // Slips: a Poisson process over the mean wheel travel; each event on a uniformly chosen wheel,
  // an exponential extra distance in that wheel's direction of motion.
  if (options_.slip_rate_per_m > 0.0) {
    const double mean_travel_m = 0.5 * (std::abs(left_delta_m) + std::abs(right_delta_m));
    const std::int64_t events = slip_rng_.Poisson(options_.slip_rate_per_m * mean_travel_m);
    for (std::int64_t i = 0; i < events; ++i) {
      const bool left_wheel = slip_rng_.Bernoulli(0.5);
      const double extra_m = slip_rng_.Exponential(1.0 / options_.slip_mean_m);
      const double delta_m = left_wheel ? left_delta_m : right_delta_m;
      if (delta_m == 0.0) continue;  // a wheel that did not turn cannot slip
      const double signed_extra_m = std::copysign(extra_m, delta_m);
      (left_wheel ? left_ : right_).error_m += signed_extra_m;
      if (slips != nullptr) slips->push_back(SlipEvent{stamp_ns, left_wheel, signed_extra_m});
    }
  }

  WheelOdometry message;
  message.stamp_ns = stamp_ns;
  message.interval_ns = stamp_ns - last_stamp_ns_;
  // Measured cumulative distance M: the nominal conversion of the whole rotation plus the errors
  // so far (taken from the cumulative angle, so no rounding accumulates over the messages).
  Report(left_, left_angle_rad * nominal_radius_m_ + left_.error_m, &message.left_distance_m,
         &message.left_ticks);
  Report(right_, right_angle_rad * nominal_radius_m_ + right_.error_m, &message.right_distance_m,
         &message.right_ticks);
  left_.angle_rad = left_angle_rad;
  right_.angle_rad = right_angle_rad;
  last_stamp_ns_ = stamp_ns;
  return message;
}

}  // namespace corridorsim::sim
