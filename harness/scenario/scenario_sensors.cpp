// The `sensors:` section: any number of named sensors of three kinds (docs/sensors.md). The
// default cameras (front, lateral, upward) are always there; a new name makes a sensor of the
// kind its `type:` says, from that kind's defaults, where it is first named (a base file of the
// include chain, or the file itself); later documents change it like any other key. Each kind
// keeps its own table (render/camera_options.cpp, and the IMU's and the laser scanner's in sim/).

#include <algorithm>
#include <cstddef>
#include <string>

#include "common/io/input_text.h"
#include "common/io/options_yaml.h"
#include "common/options_checker.h"
#include "harness/scenario/scenario.h"

namespace corridorsim {
namespace {

// Every sensor names its files, CSV columns and topics: a short identifier.
constexpr std::size_t kMaxSensorNameBytes = 32;
// Bounds on what one scenario may name, per kind (each camera is also bounded by the rig's
// memory budget, render::RigOptions::Check).
constexpr std::size_t kMaxCameras = 16;
constexpr std::size_t kMaxImus = 8;
constexpr std::size_t kMaxLasers = 8;

bool ValidSensorName(const std::string& name) {
  if (name.empty() || name.size() > kMaxSensorNameBytes) return false;
  if (!(name[0] >= 'a' && name[0] <= 'z')) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

template <class Options>
bool HasNamed(const std::vector<Options>& sensors, const std::string& name) {
  return std::any_of(sensors.begin(), sensors.end(),
                     [&](const Options& o) { return o.id == name; });
}

bool HasSensor(const Scenario& s, const std::string& name) {
  return s.rig.Find(name) != nullptr || HasNamed(s.imus, name) || HasNamed(s.lasers, name);
}

template <class Options>
void AddSensor(YamlMap& sensors, const std::string& name, std::vector<Options>& kind,
               std::size_t max, const char* what) {
  if (kind.size() >= max) sensors.Fail(name, "more than " + std::to_string(max) + " " + what);
  Options o;
  o.id = name;
  kind.push_back(o);
}

// The first pass over a `sensors:` map: each name no sensor has yet becomes a sensor of its
// `type:`, with that kind's defaults; the kinds' tables then read every sensor's keys.
void AddNewSensors(YamlMap& sensors, Scenario& s) {
  for (const std::string& name : sensors.Keys()) {
    if (HasSensor(s, name)) continue;
    if (!ValidSensorName(name)) {
      sensors.Fail(name,
                   "a sensor's name is 1 to 32 characters of a-z, 0-9 and _, starting with "
                   "a letter (it names the sensor's files)");
    }
    YamlMap sensor = sensors.Map(name);
    std::string type;
    if (!sensor.Has("type")) {
      sensors.Fail(name,
                   "no sensor has this name: a new sensor needs `type: camera`, `imu` or "
                   "`laser` (the default cameras are front, lateral and upward)");
    }
    sensor.Read("type", type);
    if (type == "camera") {
      if (s.rig.cameras.size() >= kMaxCameras) {
        sensors.Fail(name, "more than " + std::to_string(kMaxCameras) + " cameras");
      }
      s.rig.cameras.push_back(render::NewCameraOptions(name));
    } else if (type == "imu") {
      AddSensor(sensors, name, s.imus, kMaxImus, "IMUs");
    } else if (type == "laser") {
      AddSensor(sensors, name, s.lasers, kMaxLasers, "laser scanners");
    } else {
      sensor.Fail("type", "unknown sensor type '" + InputExcerpt(type) +
                              "' (expected one of: camera, imu, laser)");
    }
  }
}

}  // namespace

const OptionTable<Scenario>& ScenarioSensorsTable() {
  return StaticOptionTable<Scenario>([](OptionTable<Scenario>& t) {
    // No key of its own: it documents nothing (the kinds' tables do).
    t.AddCustom(
        "", "", &AddNewSensors, [](const Scenario&, OptionsYamlWriter&) {},
        [](const Scenario&) { return std::vector<OptionDocRow>{}; });
    t.AddNamedSections(
        "", [](Scenario& s) -> std::vector<render::CameraOptions>& { return s.rig.cameras; },
        render::CameraOptionsTable(), [](const render::CameraOptions& c) { return c.id; },
        "the cameras, by name");
    t.AddNamedSections(
        "", &Scenario::imus, sim::ImuOptionsTable(), [](const sim::ImuOptions& o) { return o.id; },
        "the IMUs, by name");
    t.AddNamedSections(
        "", &Scenario::lasers, sim::LaserOptionsTable(),
        [](const sim::LaserOptions& o) { return o.id; }, "the laser scanners, by name");
  });
}

std::optional<OptionsProblem> Scenario::CheckSensors() const {
  if (auto problem = rig.Check()) return problem;
  // The physics rate is checked with `robot:` (after `sensors:`): until it passes, there is no
  // physics step to hold an IMU's period against (a rate of 0 has none).
  const bool physics_valid = !robot.Check();
  for (const sim::ImuOptions& imu : imus) {
    if (auto problem = imu.Check()) {
      return OptionsProblem{imu.id + "." + problem->key, problem->message};
    }
    if (!physics_valid) continue;
    // Sampled at physics step ends only, where the state is exact (sim/motion_sensors.h).
    const TimeNs step_ns = robot.physics_step_ns();
    const TimeNs period_ns = PeriodFromRateHz(imu.rate_hz);
    if (period_ns % step_ns != 0) {
      return OptionsProblem{
          imu.id + ".rate_hz",
          "an IMU samples at physics step ends: 1 / rate_hz must be a whole number of physics "
          "steps (" +
              FormatNumber(ToSeconds(step_ns) * 1e3) + " ms at robot.physics_rate_hz " +
              FormatNumber(robot.physics_rate_hz) + "; got " + FormatNumber(imu.rate_hz) + " Hz)"};
    }
    if (FromSeconds(imu.phase_s) % step_ns != 0) {
      return OptionsProblem{imu.id + ".phase_s", "must be a whole number of physics steps (" +
                                                     FormatNumber(ToSeconds(step_ns) * 1e3) +
                                                     " ms; got " + FormatNumber(imu.phase_s) +
                                                     " s)"};
    }
  }
  for (const sim::LaserOptions& laser : lasers) {
    if (auto problem = laser.Check()) {
      return OptionsProblem{laser.id + "." + problem->key, problem->message};
    }
  }
  return std::nullopt;
}

}  // namespace corridorsim
