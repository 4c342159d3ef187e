// The scenario keys of the simulation (robot:, its odometry:, path:, and the IMUs and laser
// scanners of sensors:): one table per options struct, with each key's unit, bounds and doc
// (common/options_table.h). The structs, their Check() and the code that reads them stay in their
// own files.

#include "common/io/options_yaml.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"
#include "sim/odometry.h"
#include "sim/robot.h"
#include "sim/robot_path.h"
#include "sim/sensor_mount.h"

namespace corridorsim::sim {

const OptionTable<render::Mount>& BodyMountOptionsTable() {
  return StaticOptionTable<render::Mount>([](OptionTable<render::Mount>& t) {
    using M = render::Mount;
    t.Add("x_m", &M::x_m, "m", "position in the robot frame (x forward)");
    t.Add("y_m", &M::y_m, "m", "y left");
    t.Add("z_m", &M::z_m, "m", "z up");
    t.Add("yaw_deg", &M::yaw_deg, "deg", "heading of the sensor's x axis (0 forward, 90 left)")
        .Range(-360, 360);
    t.Add("pitch_deg", &M::pitch_deg, "deg", "elevation of its x axis (0 horizontal, 90 up)")
        .Range(-90, 90);
    t.Add("roll_deg", &M::roll_deg, "deg", "turns the sensor about its x axis").Range(-360, 360);
  });
}

const OptionTable<RobotOptions>& RobotOptionsTable() {
  return StaticOptionTable<RobotOptions>([](OptionTable<RobotOptions>& t) {
    using R = RobotOptions;
    t.Add("body_length_m", &R::body_length_m, "m", "overall length, wheels included")
        .Range(0.1, 3)
        .Note("longer than wheel_diameter_m");
    t.Add("body_width_m", &R::body_width_m, "m", "overall width, wheels included")
        .Range(0.1, 2)
        .Note("at least wheelbase_m + wheel_width_m");
    t.Add("body_height_m", &R::body_height_m, "m", "floor to top plate")
        .Range(0.1, 2)
        .Note("higher than wheel_diameter_m");
    t.Add("mass_kg", &R::mass_kg, "kg", "whole robot").Range(2, 500);
    t.Add("wheel_diameter_m", &R::wheel_diameter_m, "m",
          "driven wheels, nominal (what odometry and the controller assume)")
        .Range(0.02, 1);
    t.Add("wheel_width_m", &R::wheel_width_m, "m", "").Range(0.005, 0.3);
    t.Add("wheelbase_m", &R::wheelbase_m, "m",
          "nominal distance between the wheels' mid-planes (B of P1 eq. 13)")
        .Range(0.05, 2);
    t.Add("wheel_friction", &R::wheel_friction, "",
          "Coulomb coefficient of the wheel-floor contact (traction limit: wheels can slip)")
        .Range(0.05, 3);
    t.Add("max_wheel_torque_nm", &R::max_wheel_torque_nm, "N m", "per wheel motor")
        .Range(0.01, 1000);
    t.Add("max_wheel_speed_rps", &R::max_wheel_speed_rps, "rad/s", "per wheel motor")
        .Range(0.1, 200);
    t.Add("physics_rate_hz", &R::physics_rate_hz, "Hz",
          "fixed physics step (its period rounded to the nanosecond)")
        .Range(100, 20000);
    t.Add("control_rate_hz", &R::control_rate_hz, "Hz",
          "path follower and motor commands, at the first physics step at or after each n / "
          "control_rate_hz")
        .Note("[1, physics_rate_hz]");
    t.AddSection("odometry", &R::odometry, OdometryOptionsTable(),
                 "the wheel encoders and their errors", &OdometryOptions::Check);
  });
}

const OptionTable<RobotPathOptions>& RobotPathOptionsTable() {
  return StaticOptionTable<RobotPathOptions>([](OptionTable<RobotPathOptions>& t) {
    using P = RobotPathOptions;
    t.AddEnum("kind", &P::kind, kPathKindNames, "what the robot drives (below)");
    t.Add("speed_mps", &P::speed_mps, "m/s",
          "cruise speed on straight legs (P1: 0.34 m/s; P3 drove at 0.30)")
        .Range(0.01, kMaxPathSpeedMps);
    t.Add("acceleration_mps2", &P::acceleration_mps2, "m/s^2",
          "speed ramps up and down (before every turn and the goal)")
        .Range(0.01, 10);
    t.Add("turn_rate_dps", &P::turn_rate_dps, "deg/s", "yaw rate of in-place turns")
        .Range(1, kMaxPathTurnRateDps);
    t.Add("turn_acceleration_dps2", &P::turn_acceleration_dps2, "deg/s^2",
          "yaw-rate ramps of in-place turns")
        .Range(1, 3000);
    t.Add("lateral_offset_m", &P::lateral_offset_m, "m",
          "straight legs run this far to the left of the direction of travel (negative: right); "
          "UMBmark: moves the whole square left")
        .Range(-100, 100);
    t.Add("end_margin_m", &P::end_margin_m, "m",
          "where the robot starts and turns, measured from the corridor ends (loop: where it "
          "starts along the first side)")
        .Range(0, 1000);
    t.Add("laps", &P::laps, "", "`round_trip`: repetitions; `loop`: laps; UMBmark: squares")
        .Range(1, 1000);
    t.Add("umbmark_side_m", &P::umbmark_side_m, "m",
          "side of the UMBmark square (Borenstein's 4 m needs a corridor 4.7 m wide)")
        .Range(0.1, 100);
    t.AddCustom(
        "commands", "`script` only: rows [duration_s, linear_mps, angular_dps]",
        [](YamlMap& map, P& options) {
          std::vector<std::vector<double>> rows;
          if (map.Read("commands", rows, 3)) {
            options.commands.clear();
            for (const std::vector<double>& row : rows)
              options.commands.push_back({row[0], row[1], row[2]});
          }
        },
        [](const P& options, OptionsYamlWriter& out) {
          std::string rows;
          for (const VelocityCommand& c : options.commands) {
            rows +=
                (rows.empty() ? "" : ", ") + YamlList({c.duration_s, c.linear_mps, c.angular_dps});
          }
          out.Scalar("commands", "[" + rows + "]");
        },
        [](const P&) {
          return std::vector<OptionDocRow>{
              {"commands", "s, m/s, deg/s", "`[]`",
               "at most 10000 rows; duration_s in [0.001, 1e6] (the rows' sum at most 1e6), "
               "linear_mps in [-1.2, 1.2], angular_dps in [-300, 300]",
               "`script` only: rows `[duration_s, linear_mps, angular_dps]`, e.g. `[[10, 0.3, "
               "0], "
               "[3, 0, 30]]`, driven in order (angular_dps positive counter-clockwise)"}};
        });
  });
}

const OptionTable<OdometryOptions>& OdometryOptionsTable() {
  return StaticOptionTable<OdometryOptions>([](OptionTable<OdometryOptions>& t) {
    using O = OdometryOptions;
    // At least 1 Hz: the slips of one message are drawn one by one (at most slip_rate_per_m
    // times the wheels' travel in a period: 100 / m * 100 m/s * 1 s), and real encoders report
    // far faster.
    t.Add("rate_hz", &O::rate_hz, "Hz",
          "odometry messages per second; stamps at n periods, the period being 1 / rate_hz "
          "rounded to the nanosecond")
        .Range(1, 1000, "must lie in [1, 1000] Hz (got {})");
    // At most kMaxTicksPerRevolution: a 0.6 um tick on a 195 mm wheel, finer than any wheel.
    t.Add("ticks_per_revolution", &O::ticks_per_revolution, "",
          "encoder counts per wheel turn (0 = no quantisation); at most 1e6, a 0.6 um tick on "
          "the Pioneer's 195 mm wheel, finer than anything a wheel measures")
        .Range(0, kMaxTicksPerRevolution, "must lie in [0, 1000000] (0 = no quantisation; got {})");
    // Real robots stay within a few per cent of 1; beyond a factor 2 the wheels are not one model.
    t.Add("diameter_ratio", &O::diameter_ratio, "",
          "Borenstein's E_d = D_R / D_L of the real wheels (their mean stays nominal)")
        .Range(0.5, 2);
    t.Add("wheelbase_ratio", &O::wheelbase_ratio, "", "E_b = real / nominal wheelbase")
        .Range(0.5, 2);
    // k = 0.1 m is a 30 cm standard deviation after 1 m: far beyond any wheel.
    t.Add(
         "random_k_m", &O::random_k_m, "m",
         "k: each wheel's reported distance gets variance k |s| (m^2 per m, the form of P1 eq. 17)")
        .Range(0, 0.1);
    // The slip count per message is drawn from this rate: the upper bound keeps it small.
    t.Add("slip_rate_per_m", &O::slip_rate_per_m, "1/m",
          "slip events per metre travelled (Poisson)")
        .Range(0, 100);
    t.Add("slip_mean_m", &O::slip_mean_m, "m",
          "mean extra distance a slipping wheel reports (exponential)")
        .RangeOpenLow(0, 1, "must lie in (0, 1] m (got {})");
  });
}

const OptionTable<ImuOptions>& ImuOptionsTable() {
  return StaticOptionTable<ImuOptions>([](OptionTable<ImuOptions>& t) {
    using O = ImuOptions;
    render::AddSensorTypeKey(t, "imu");
    t.Add("enabled", &O::enabled, "", "false: the IMU is not simulated");
    t.Add("rate_hz", &O::rate_hz, "Hz",
          "samples per second, at physics step ends (the period a whole number of steps)")
        .RangeOpenLow(0, 1000, "must lie in (0, 1000] Hz (got {})");
    t.Add("phase_s", &O::phase_s, "s", "first sample at this time, then every 1 / rate_hz")
        .AtLeast(0)
        .Note("[0, 1 / rate_hz)");
    t.AddSection("mount", &O::mount, BodyMountOptionsTable(),
                 "where the IMU sits: its body axes (x forward, y left, z up at zero angles)");
    t.Add("noise", &O::noise, "", "apply the errors below (false: the exact samples, biases 0)");
    // Upper bounds: 100 times the worst consumer MEMS parts, still finite and sane.
    t.Add("gyroscope_noise_density", &O::gyroscope_noise_density, "rad/s/sqrt(Hz)",
          "white noise sigma_g (Kalibr); per sample N(0, sigma_g^2 / dt)")
        .Range(0, 0.1);
    t.Add("gyroscope_random_walk", &O::gyroscope_random_walk, "rad/s^2/sqrt(Hz)",
          "bias random walk sigma_bg (Kalibr); per sample b += sigma_bg sqrt(dt) N(0, 1)")
        .Range(0, 0.1);
    t.Add("accelerometer_noise_density", &O::accelerometer_noise_density, "m/s^2/sqrt(Hz)",
          "white noise sigma_a (Kalibr)")
        .Range(0, 1);
    t.Add("accelerometer_random_walk", &O::accelerometer_random_walk, "m/s^3/sqrt(Hz)",
          "bias random walk sigma_ba (Kalibr)")
        .Range(0, 1);
    t.Add("gyroscope_bias_rad_s", &O::gyroscope_bias_rad_s, "rad/s",
          "initial gyroscope bias [x, y, z]")
        .Note("3 values, each in [-1, 1]");
    t.Add("accelerometer_bias_m_s2", &O::accelerometer_bias_m_s2, "m/s^2",
          "initial accelerometer bias [x, y, z]")
        .Note("3 values, each in [-5, 5]");
    t.Add("gyroscope_scale", &O::gyroscope_scale, "", "scale factor of each axis [x, y, z]")
        .Note("3 values, each in (0.5, 2)");
    t.Add("accelerometer_scale", &O::accelerometer_scale, "", "scale factor of each axis [x, y, z]")
        .Note("3 values, each in (0.5, 2)");
    t.Add("gyroscope_misalignment_rad", &O::gyroscope_misalignment_rad, "rad",
          "non-orthogonal axes [y towards x, z towards x, z towards y] (sim/imu.h)")
        .Note("3 values, each in (-0.1, 0.1)");
    t.Add("accelerometer_misalignment_rad", &O::accelerometer_misalignment_rad, "rad",
          "non-orthogonal axes [y towards x, z towards x, z towards y] (sim/imu.h)")
        .Note("3 values, each in (-0.1, 0.1)");
    t.Add("gyroscope_range_rad_s", &O::gyroscope_range_rad_s, "rad/s",
          "saturation: each axis clamped to +-range (default 1000 deg/s, ADIS16448)")
        .RangeOpenLow(0, 100, "must lie in (0, 100] rad/s (got {})");
    t.Add("accelerometer_range_m_s2", &O::accelerometer_range_m_s2, "m/s^2",
          "saturation: each axis clamped to +-range (default 18 g, ADIS16448)")
        .RangeOpenLow(0, 2000, "must lie in (0, 2000] m/s^2 (got {})");
  });
}

const OptionTable<LaserOptions>& LaserOptionsTable() {
  return StaticOptionTable<LaserOptions>([](OptionTable<LaserOptions>& t) {
    using L = LaserOptions;
    render::AddSensorTypeKey(t, "laser");
    t.Add("enabled", &L::enabled, "", "false leaves the scanner out of the run");
    // At most 100 Hz, as the cameras (one sweep per physics step at the slowest physics rate);
    // at least 1e-6 Hz: a period of at most 1e6 s, the longest run.
    t.Add("rate_hz", &L::rate_hz, "Hz",
          "sweeps per second (SICK LMS200 at 0.5 deg: 37.5); sweeps are stamped every 1 / "
          "rate_hz rounded to the nanosecond")
        .Range(kMinSensorRateHz, 100,
               "must lie in [1e-06, 100] Hz: a period of at most 1e+06 s (got {})");
    t.Add("phase_s", &L::phase_s, "s",
          "stamp of the first sweep; sweeps are stamped at `phase_s + k / rate_hz`, rounded to "
          "the nanosecond")
        .Note("[0, 1 / rate_hz)");
    t.AddSection("mount", &L::mount, BodyMountOptionsTable(),
                 "where the scanner sits on the robot: its x axis the 0 deg beam, z the normal of "
                 "the scan plane (docs/frames.md)");
    t.Add("angle_min_deg", &L::angle_min_deg, "deg",
          "angle of the first beam about the scanner's z axis (0 along x, counter-clockwise)")
        .Range(-180, 180);
    t.Add("angle_max_deg", &L::angle_max_deg, "deg",
          "angle of the last beam (the beams keep resolution_deg apart: the last one lies at the "
          "nearest multiple of it)")
        .Range(-180, 180)
        .Note("> angle_min_deg; (angle_max_deg - angle_min_deg) + resolution_deg <= 360");
    // 0.01 deg is finer than any planar scanner (the LMS200 resolves 0.25 deg); it keeps the time
    // between beams at least 278 ns at 100 Hz.
    t.Add("resolution_deg", &L::resolution_deg, "deg",
          "angle between two beams; beams = round((angle_max_deg - angle_min_deg) / "
          "resolution_deg) + 1")
        .Range(0.01, 90)
        .Note("at most 4096 beams");
    t.Add("range_min_m", &L::range_min_m, "m", "nearer returns read -inf (REP 117)")
        .RangeOpenHigh(0, kMaxLaserRangeM)
        .Note("< range_max_m");
    t.Add("range_max_m", &L::range_max_m, "m",
          "no return within it reads +inf (REP 117); the LMS200's cm mode: 80")
        .RangeOpenLow(0, kMaxLaserRangeM);
    t.Add("noise", &L::noise, "", "range noise and dropouts (false: exact ranges)");
    t.Add("range_sigma_m", &L::range_sigma_m, "m",
          "standard deviation of the Gaussian range noise (LMS200: about 0.01)")
        .Range(0, 1);
    t.Add("max_incidence_deg", &L::max_incidence_deg, "deg",
          "a beam meeting a surface more obliquely than this, from its normal, returns nothing "
          "(NaN); 90 keeps every return")
        .RangeOpenLow(0, 90);
    t.Add("dropout_probability", &L::dropout_probability, "",
          "each return is lost (NaN) with this probability")
        .Range(0, 1);
  });
}

}  // namespace corridorsim::sim
