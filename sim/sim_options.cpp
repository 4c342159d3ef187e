// The scenario keys of the simulation (robot:, odometry:): one table per options struct,
// with each key's unit, bounds and doc (common/options_table.h). The structs, their Check() and
// the code that reads them stay in their own files.

#include "common/options_table.h"
#include "sim/odometry.h"
#include "sim/robot.h"

namespace corridorsim::sim {

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

}  // namespace corridorsim::sim
