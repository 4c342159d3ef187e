#pragma once
// A planar laser scanner (issue 53) ray cast against the world's meshes, the way a SICK LMS200
// on the papers' Pioneer 3-DX sees the corridor. Truth, noise and sensing are separate stages
// (STYLE item 9): Cast gives a beam's exact return, Measure turns a sweep of them into the
// LaserScan the scanner reports (common/sensor_messages.h, REP 117 ranges).
//
// Timing: the mirror turns once per sweep period, and the beams are fired as it passes their
// angles, so beam i of the sweep stamped t fires at t + i * time_increment_ns with
//   time_increment_ns = round(period_ns * resolution_deg / 360)   (to the nearest nanosecond),
// and is cast from where the scanner is at that instant (the caller gives that pose per beam:
// the robot moves during a sweep). Sweeps are stamped at phase_ns + k * period_ns.
//
// Sensing model, per beam, in this order (Measure):
//   1. no surface within range_max_m (truth +inf)                       -> +inf
//   2. incidence (angle from the surface normal) above max_incidence_deg -> NaN (lost)
//   3. with `noise`: a dropout, probability dropout_probability          -> NaN (lost)
//   4. with `noise`: range + N(0, range_sigma_m)
//   5. the (noisy) range above range_max_m -> +inf, below range_min_m -> -inf.
// `noise: false` gives the exact ranges (rounded to float), the sensing limits (1, 2, 5) kept.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "render/camera_options.h"
#include "sim/ray_grid.h"
#include "worlds/world.h"

namespace corridorsim::sim {

/// The most beams one sweep may have.
inline constexpr int kMaxLaserBeams = 4096;
/// The longest range a scanner may report (m).
inline constexpr double kMaxLaserRangeM = 100.0;

/// One planar scanner. The defaults are a SICK LMS200 (Technical Description, 8 008 970): a 180
/// deg field at 0.5 deg resolution (361 beams), its cm mode (ranges up to 80 m, 10 mm resolution),
/// mounted on a Pioneer 3-DX's top plate.
struct LaserOptions {
  std::string id = "laser";  // the sensor's name (scenario key, message sensor_id, noise stream)
  bool enabled = true;
  // Sweeps per second: the LMS200's mirror turns at 75 Hz, and at 0.5 deg it interlaces two
  // turns of 1 deg steps, delivering a full sweep every 26.7 ms (its 26 ms response time at 0.5
  // deg): 37.5 Hz. This model fires one sweep's beams over one period (above).
  double rate_hz = 37.5;
  double phase_s = 0.0;  // the first sweep's stamp, in [0, 1 / rate_hz)
  // Scan plane 0.30 m above the floor, 0.16 m ahead of the axle: an LMS200 standing on the
  // Pioneer 3-DX's top plate (0.237 m, RobotOptions::body_height_m) near its front edge, level.
  render::Mount mount{0.16, 0.0, 0.30, 0.0, 0.0, 0.0};
  // Beam i points at angle_min_deg + i * resolution_deg about the scanner's z axis (0 along its x
  // axis, counter-clockwise); beams = round((angle_max_deg - angle_min_deg) / resolution_deg) + 1.
  double angle_min_deg = -90.0;
  double angle_max_deg = 90.0;
  double resolution_deg = 0.5;
  // Returns nearer than range_min_m read -inf. The data sheet gives no minimum; 0.1 m keeps the
  // scanner's own housing out.
  double range_min_m = 0.1;
  double range_max_m = 80.0;  // the LMS200's cm mode: 80 m (its mm mode stops at 8.1 m)
  bool noise = true;          // range noise and dropouts; false: exact ranges
  // 1 sigma of the range: the LMS200's cm-mode resolution, the order of its statistical error
  // (Ye and Borenstein, "Characterization of a 2-D laser scanner for mobile robot obstacle
  // negotiation", ICRA 2002).
  double range_sigma_m = 0.01;
  // A beam meeting a surface more obliquely than this (from the surface normal) returns nothing:
  // a model choice (the echo of a matte wall fades as the cosine of the incidence, Lambert), not a
  // data sheet figure; 90 keeps every return.
  double max_incidence_deg = 85.0;
  double dropout_probability = 0.0;  // each return is lost (NaN) with this probability

  /// The number of beams the angles give (the options must pass Check()).
  int BeamCount() const;
  /// The first problem (key relative to the sensor, e.g. "angle_max_deg"), or nothing.
  std::optional<OptionsProblem> Check() const;
};

/// The keys of one scanner (not its `type` and id, which the sensors' map holds): parsing,
/// bounds, echo, docs. The mount is a section with BodyMountOptionsTable()'s keys.
const OptionTable<LaserOptions>& LaserOptionsTable();

/// The exact return of one beam.
struct BeamTruth {
  double range_m = 0.0;  // from the scanner's origin; +inf: nothing within range_max_m
  int instance_id = 0;   // what it hit (the mesh's instance id; 0 for nothing)
  worlds::SemanticClass semantic_class = worlds::SemanticClass::kUnknown;
  double incidence_rad = 0.0;  // angle between the beam and the surface normal, [0, pi / 2]
};

/// A scanner over one world: its own grid of all the world's triangles (walls, doors in their
/// state, floor and ceiling, rooms, furniture, plates), for ray casts only (sim/ray_grid.h).
class LaserScanner {
 public:
  /// `options` must pass Check(); `world` must outlive the scanner. `seed`: the run's seed (noise:
  /// "sim.laser.<id>").
  LaserScanner(const worlds::World& world, const LaserOptions& options, std::uint64_t seed);
  ~LaserScanner();
  LaserScanner(const LaserScanner&) = delete;
  LaserScanner& operator=(const LaserScanner&) = delete;

  int beam_count() const { return beam_count_; }
  TimeNs period_ns() const { return period_ns_; }
  TimeNs phase_ns() const { return phase_ns_; }
  TimeNs time_increment_ns() const { return time_increment_ns_; }
  const LaserOptions& options() const { return options_; }
  /// The angle of beam `beam` about the scanner's z axis (rad).
  double BeamAngleRad(int beam) const;

  /// The exact return of beam `beam` cast from the scanner's pose `world_from_laser` (the nearest
  /// hit along its direction in the scanner's x-y plane). Safe to call from several threads.
  BeamTruth Cast(int beam, const SE3& world_from_laser) const;

  /// The scan the scanner reports for the sweep stamped `sweep_stamp_ns` (its `sweep_index`-th)
  /// whose beams returned `beams` (beam_count() of them): the model at the top of this file. Its
  /// draws come from RandomStream(seed, sweep_index, "sim.laser.<id>") alone, so one sweep's
  /// noise does not depend on the sweeps before it.
  LaserScan Measure(TimeNs sweep_stamp_ns, std::uint64_t sweep_index,
                    const std::vector<BeamTruth>& beams) const;

 private:
  LaserOptions options_;
  std::uint64_t seed_;
  std::string stream_name_;  // "sim.laser.<id>"
  int beam_count_;
  TimeNs period_ns_;
  TimeNs phase_ns_;
  TimeNs time_increment_ns_;
  const worlds::World* world_;
  std::vector<Eigen::Vector3d> beam_in_laser_;  // each beam's unit direction, scanner frame
  std::vector<int> mesh_of_triangle_;           // the grid's triangle -> index into World::meshes
  std::unique_ptr<RayGrid> grid_;
};

}  // namespace corridorsim::sim
