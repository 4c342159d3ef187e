#pragma once
// Wheel encoders and their odometry errors (STYLE item 9: truth, noise and sensing are separate
// stages). The physics turns the wheels of a robot built with the *real* wheel geometry
// (RealWheelGeometry); the WheelOdometer converts their rotation with the *nominal* geometry, adds
// random and slip errors and quantises to encoder ticks, as a real robot's firmware would.
//
// Error model, per wheel (left and right alike):
//   - systematic (Borenstein's UMBmark): E_d = D_R / D_L of the real wheels with their mean
//     diameter nominal, and E_b = real / nominal wheelbase. They live in the physics, not here:
//     the encoder multiplies the real wheel's rotation by the nominal radius.
//   - random (P1 eq. 17): an interval in which the wheel turns by delta_angle adds
//     N(0, k |delta|) to the measured distance, delta = delta_angle * nominal radius (m).
//   - slip: a Poisson process over distance travelled. An interval holds
//     Poisson(slip_rate_per_m * (|delta_l| + |delta_r|) / 2) events; each picks a wheel uniformly
//     and adds Exponential(mean slip_mean_m) to its measured distance, in that wheel's direction
//     of motion over the interval (a wheel that did not turn cannot slip: that event is dropped).
//   - quantisation: the wheel keeps a continuous measured cumulative distance
//     M = nominal radius * angle + sum of the random and slip errors so far, and its encoder count
//     is floor(M / tick_length) on that cumulative value (tick_length = pi D / ticks per
//     revolution), so quantisation error never accumulates: the reported distances of any run of
//     messages sum to within one tick of the measured distance.
// Each error source draws from its own RandomStream ("sim.odometry.left", "sim.odometry.right",
// "sim.odometry.slip"), so switching one on or off leaves the others' numbers unchanged; a source
// that is off (k = 0, slip_rate_per_m = 0) draws nothing.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "common/random.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "common/wheel_odometry_model.h"

namespace corridorsim::sim {

/// Wheel encoder and odometry error options; the scenario key is `robot.odometry` (the caller
/// maps it). The defaults are a Pioneer 3-DX-like encoder with P1's random error (k = 1e-4, the
/// odometry pipeline's default k_m too) and no systematic error or slip.
struct OdometryOptions {
  double rate_hz = 50.0;  // odometry messages per second (read by the sensor clock)
  // Encoder ticks per wheel revolution; 0 = no quantisation (distances reported as measured).
  // Default: a 500-line quadrature encoder (2,000 counts per motor turn) behind a 19.7:1
  // gearhead, the Pioneer 3-DX's drive: 39,400 counts per wheel turn, 15.5 um of travel. (A coarse
  // encoder quantises the dead-reckoned heading to tick / wheelbase: 1,263 ticks gave 0.08 deg
  // steps, 15 mm of cross-track error over 10 m.)
  int ticks_per_revolution = 39400;
  double diameter_ratio = 1.0;   // E_d = D_R / D_L of the real wheels (Borenstein UMBmark)
  double wheelbase_ratio = 1.0;  // E_b = real wheelbase / nominal wheelbase
  // k: variance k |s| per wheel (m^2 per m travelled, P1 eq. 17); the pipeline's default too.
  double random_k_m = kDefaultWheelNoiseK_m;
  double slip_rate_per_m = 0.0;  // slip events per metre of mean wheel travel, 0 = none
  double slip_mean_m = 0.02;     // mean extra distance a slipping wheel reports (m, exponential)

  /// The first invalid value (key relative to this struct, e.g. "diameter_ratio"), or nullopt.
  std::optional<OptionsProblem> Check() const;
};

/// The keys of `robot.odometry` (parsing, bounds, echo, docs).
const OptionTable<OdometryOptions>& OdometryOptionsTable();

/// Reads the keys of OdometryOptions present in `map` over `options`; unknown keys are errors.
void ParseOdometryOptions(YamlMap& map, OdometryOptions& options);

/// The physical wheel geometry (m): the physics builds the robot with it, the encoders convert
/// with the nominal one, which is how the systematic errors appear.
struct WheelGeometry {
  double left_diameter_m;
  double right_diameter_m;
  double wheelbase_m;  // distance between the wheels' contact points (B in P1)
};

/// Borenstein's split of a nominal diameter D by E_d: D_L = 2 D / (E_d + 1), D_R = 2 D E_d /
/// (E_d + 1) (so D_R / D_L = E_d and (D_L + D_R) / 2 = D), and the wheelbase b E_b.
WheelGeometry RealWheelGeometry(const OdometryOptions& options, double nominal_diameter_m,
                                double nominal_wheelbase_m);

/// One slip: which wheel and how much distance it reported beyond its rotation (ground truth for
/// the run's metrics, never part of the sensor message).
struct SlipEvent {
  TimeNs stamp_ns;          // end of the interval in which it happened
  bool left_wheel;          // true: left wheel, false: right wheel
  double extra_distance_m;  // signed, in the wheel's direction of motion
};

/// The two wheel encoders of a differential-drive robot and their errors (model in the file
/// comment). Deterministic given (options, seed, run_index) and the sequence of Measure calls.
class WheelOdometer {
 public:
  /// `options` must pass Check(); `nominal_wheel_diameter_m` (> 0) is the diameter the encoders
  /// convert with. The wheel angles start at 0 rad at time 0.
  WheelOdometer(const OdometryOptions& options, double nominal_wheel_diameter_m, std::uint64_t seed,
                std::uint64_t run_index = 0);

  /// The message for the interval since the previous call (or since construction), given each
  /// wheel's cumulative rotation angle (rad, positive = forward) at `stamp_ns`, which must not be
  /// earlier than the previous stamp. `slips`, if given, is replaced by the interval's slips.
  WheelOdometry Measure(TimeNs stamp_ns, double left_angle_rad, double right_angle_rad,
                        std::vector<SlipEvent>* slips = nullptr);

  /// Length of one encoder tick along the ground (m); 0 without quantisation.
  double tick_length_m() const { return tick_length_m_; }

 private:
  // One encoder: its measured error so far and its last reported count.
  struct Wheel {
    double angle_rad = 0.0;   // cumulative rotation at the previous Measure (rad)
    double error_m = 0.0;     // random and slip errors accumulated into M (m)
    double reported_m = 0.0;  // M at the previous Measure (m)
    std::int64_t count = 0;   // floor(M / tick_length) at the previous Measure
  };
  // Converts the new measured cumulative distance into the interval's distance and ticks.
  void Report(Wheel& wheel, double measured_m, double* distance_m, std::int64_t* ticks) const;

  OdometryOptions options_;
  double nominal_radius_m_;
  double tick_length_m_;  // 0 without quantisation
  RandomStream left_rng_;
  RandomStream right_rng_;
  RandomStream slip_rng_;
  TimeNs last_stamp_ns_ = 0;
  Wheel left_;
  Wheel right_;
};

}  // namespace corridorsim::sim
