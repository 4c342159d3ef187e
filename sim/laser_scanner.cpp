#include "sim/laser_scanner.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/options_checker.h"
#include "common/random.h"
#include "sim/sensor_mount.h"

namespace corridorsim::sim {

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
// A sensor on the robot sits within this distance of its origin along each axis (m).
constexpr double kMaxMountOffsetM = 10.0;

// The number of beams of the angles, in double so that absurd values cannot overflow an int.
double BeamCountOf(const LaserOptions& o) {
  return std::round((o.angle_max_deg - o.angle_min_deg) / o.resolution_deg) + 1.0;
}

}  // namespace

int LaserOptions::BeamCount() const { return static_cast<int>(BeamCountOf(*this)); }

std::optional<OptionsProblem> LaserOptions::Check() const {
  if (auto problem = CheckOptionBounds(LaserOptionsTable(), *this)) return problem;
  OptionsChecker c;
  // The bounds above hold, so the period is representable; && keeps FromSeconds from a bad phase.
  c.Require(
      phase_s >= 0 && phase_s * rate_hz < 1 && FromSeconds(phase_s) < PeriodFromRateHz(rate_hz),
      "phase_s", "must lie in [0, 1 / rate_hz) (got " + FormatNumber(phase_s) + " s)");
  for (const auto& [key, value] :
       {std::pair{"mount.x_m", mount.x_m}, std::pair{"mount.y_m", mount.y_m},
        std::pair{"mount.z_m", mount.z_m}}) {
    c.InRange(value, -kMaxMountOffsetM, kMaxMountOffsetM, key);
  }
  c.Require(angle_max_deg > angle_min_deg, "angle_max_deg",
            "must be greater than angle_min_deg (got " + FormatNumber(angle_max_deg) +
                " <= " + FormatNumber(angle_min_deg) + ")");
  // The beams of one sweep are fired over one turn of the mirror, each direction once.
  c.Require(angle_max_deg - angle_min_deg + resolution_deg <= 360, "angle_max_deg",
            "the sweep must fit in one turn: (angle_max_deg - angle_min_deg) + resolution_deg "
            "<= 360 (got " +
                FormatNumber(angle_max_deg - angle_min_deg + resolution_deg) + ")");
  c.Require(
      BeamCountOf(*this) <= kMaxLaserBeams, "resolution_deg",
      "gives more than 4096 beams over the field (got " + FormatNumber(BeamCountOf(*this)) + ")");
  c.Require(range_min_m < range_max_m, "range_min_m",
            "must be less than range_max_m (got " + FormatNumber(range_min_m) +
                " >= " + FormatNumber(range_max_m) + ")");
  return c.problem();
}

LaserScanner::LaserScanner(const worlds::World& world, const LaserOptions& options,
                           std::uint64_t seed)
    : options_(options),
      seed_(seed),
      stream_name_("sim.laser." + options.id),
      beam_count_(0),
      period_ns_(0),
      phase_ns_(0),
      time_increment_ns_(0),
      world_(&world) {
  CheckOrDie(!options.Check(), "LaserScanner", "the options must pass Check()");
  beam_count_ = options.BeamCount();
  period_ns_ = PeriodFromRateHz(options.rate_hz);
  phase_ns_ = FromSeconds(options.phase_s);
  time_increment_ns_ = static_cast<TimeNs>(
      std::llround(static_cast<double>(period_ns_) * options.resolution_deg / 360.0));
  for (int i = 0; i < beam_count_; ++i) {
    const double angle = BeamAngleRad(i);
    beam_in_laser_.emplace_back(std::cos(angle), std::sin(angle), 0.0);
  }
  // The triangles in double, corners unshared (the float meshes convert exactly).
  std::vector<Eigen::Vector3d> corners;
  for (std::size_t m = 0; m < world.meshes.size(); ++m) {
    const worlds::Mesh& mesh = world.meshes[m];
    for (const std::uint32_t index : mesh.indices) {
      CheckOrDie(index < mesh.positions.size(), "LaserScanner", "a mesh index out of range");
      corners.push_back(mesh.positions[index].cast<double>());
    }
    mesh_of_triangle_.insert(mesh_of_triangle_.end(), mesh.triangle_count(), static_cast<int>(m));
  }
  grid_ = std::make_unique<RayGrid>(std::move(corners));
}

LaserScanner::~LaserScanner() = default;

double LaserScanner::BeamAngleRad(int beam) const {
  return (options_.angle_min_deg + beam * options_.resolution_deg) * kDegToRad;
}

BeamTruth LaserScanner::Cast(int beam, const SE3& world_from_laser) const {
  CheckOrDie(beam >= 0 && beam < beam_count_, "LaserScanner::Cast", "beam out of range");
  BeamTruth truth;
  const Eigen::Vector3d direction =
      world_from_laser.quaternion() * beam_in_laser_[static_cast<std::size_t>(beam)];
  const RayHit hit =
      grid_->Nearest(world_from_laser.translation(), direction, options_.range_max_m);
  truth.range_m = hit.t;  // +inf when nothing was hit
  if (hit.triangle < 0) return truth;
  const worlds::Mesh& mesh = world_->meshes[static_cast<std::size_t>(
      mesh_of_triangle_[static_cast<std::size_t>(hit.triangle)])];
  truth.instance_id = mesh.instance_id;
  truth.semantic_class = mesh.semantic_class;
  // The incidence from the triangle's own geometric normal (either side).
  const Eigen::Vector3d& normal = grid_->normal(hit.triangle);
  const double cos_incidence = std::abs(normal.dot(direction)) / normal.norm();
  truth.incidence_rad = std::acos(std::min(1.0, cos_incidence));
  return truth;
}

LaserScan LaserScanner::Measure(TimeNs sweep_stamp_ns, std::uint64_t sweep_index,
                                const std::vector<BeamTruth>& beams) const {
  CheckOrDie(beams.size() == static_cast<std::size_t>(beam_count_), "LaserScanner::Measure",
             "one truth per beam");
  LaserScan scan;
  scan.stamp_ns = sweep_stamp_ns;
  scan.sensor_id = options_.id;
  scan.angle_min_rad = options_.angle_min_deg * kDegToRad;
  scan.angle_increment_rad = options_.resolution_deg * kDegToRad;
  scan.time_increment_ns = time_increment_ns_;
  scan.scan_time_ns = period_ns_;
  scan.range_min_m = options_.range_min_m;
  scan.range_max_m = options_.range_max_m;
  scan.ranges_m.resize(beams.size());

  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const double max_incidence_rad = options_.max_incidence_deg * kDegToRad;
  // Each effect has its own stream, and draws once per beam whatever the beam hit, so a beam's
  // noise depends on (seed, sweep, beam) alone: switching dropouts on leaves the ranges' noise.
  const RandomStream sweep_rng(seed_, sweep_index, stream_name_);
  RandomStream range_rng = sweep_rng.Derive("range");
  RandomStream dropout_rng = sweep_rng.Derive("dropout");
  const bool draw_range = options_.noise && options_.range_sigma_m > 0;
  const bool draw_dropout = options_.noise && options_.dropout_probability > 0;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const double gaussian = draw_range ? range_rng.StandardNormalZiggurat() : 0.0;
    const bool dropped = draw_dropout && dropout_rng.Uniform01() < options_.dropout_probability;
    const BeamTruth& truth = beams[i];
    float& out = scan.ranges_m[i];
    if (!(truth.range_m <= options_.range_max_m)) {
      out = kInf;  // nothing within range: no return to lose
    } else if (truth.incidence_rad > max_incidence_rad || dropped) {
      out = kNaN;
    } else {
      const double range = truth.range_m + options_.range_sigma_m * gaussian;
      out = range > options_.range_max_m   ? kInf
            : range < options_.range_min_m ? -kInf
                                           : static_cast<float>(range);
    }
  }
  return scan;
}

}  // namespace corridorsim::sim
