// Tests sim/laser_scanner.cpp and its caster sim/ray_grid.cpp: every noise-free beam, from poses
// along the corridors and from random ones (tilted, in doorways, down the corridors), against an
// independent brute-force ray cast of the world's meshes (Moller-Trumbore over every triangle, no
// grid), the grid alone at several cell sizes, the incidence against the corridor's geometry, the
// sensing model (range noise statistics, REP 117 limits, grazing returns, dropouts), determinism,
// the option checks and the sweep's timing fields.

#include "sim/laser_scanner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <catch2/catch.hpp>

#include "common/random.h"
#include "sim/ray_grid.h"
#include "tests/support/broken_options.h"
#include "tests/support/generated_worlds.h"
#include "tests/support/generator_layouts.h"
#include "tests/support/option_bounds.h"
#include "tests/support/tolerances.h"

namespace corridorsim::sim {
namespace {

using test::kStatConfidence;
using worlds::SemanticClass;

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A scanner's beam against the brute-force cast: the meshes are float, so two exact casts of them
// differ by rounding only; 0.1 mm is the brief's bound (m).
constexpr double kBeamAgreementM = 1e-4;
// The incidence of a hit against the brute force's triangle normal (rad).
constexpr double kIncidenceAgreementRad = 1e-6;

// ---- The independent reference: Moller-Trumbore over every triangle of World::meshes --------

// One mesh's triangles in double, with the box that bounds them (computed here, from the
// positions, so the reference does not lean on the generator's bounds).
struct ReferenceMesh {
  const worlds::Mesh* mesh = nullptr;
  Eigen::AlignedBox3d box;
  std::vector<Eigen::Vector3d> corners;  // three per triangle
};

struct ReferenceWorld {
  std::vector<ReferenceMesh> meshes;
};

ReferenceWorld ReferenceOf(const worlds::World& world) {
  ReferenceWorld reference;
  for (const worlds::Mesh& mesh : world.meshes) {
    ReferenceMesh r;
    r.mesh = &mesh;
    for (const std::uint32_t index : mesh.indices) {
      r.corners.push_back(mesh.positions.at(index).cast<double>());
      r.box.extend(r.corners.back());
    }
    if (!r.corners.empty()) reference.meshes.push_back(std::move(r));
  }
  return reference;
}

// Whether the ray origin + t direction, t in [0, length], can meet `box` (slab test, padded).
bool RayMeetsBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& origin,
                 const Eigen::Vector3d& direction, double length) {
  constexpr double kPadM = 1e-3;
  double t0 = 0.0, t1 = length;
  for (int a = 0; a < 3; ++a) {
    const double lo = box.min()[a] - kPadM, hi = box.max()[a] + kPadM;
    if (std::abs(direction[a]) < 1e-300) {
      if (origin[a] < lo || origin[a] > hi) return false;
      continue;
    }
    double ta = (lo - origin[a]) / direction[a], tb = (hi - origin[a]) / direction[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Moller and Trumbore, "Fast, minimum storage ray/triangle intersection" (1997), both faces:
// the distance along the unit `direction`, or nothing.
std::optional<double> RayTriangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                  const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                                  const Eigen::Vector3d& v2) {
  const Eigen::Vector3d e1 = v1 - v0, e2 = v2 - v0;
  const Eigen::Vector3d p = direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-14) return std::nullopt;  // parallel to the triangle's plane
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = origin - v0;
  const double u = s.dot(p) * inv;
  // Barycentric coordinates admitted 1e-12 outside, so that no ray slips between two triangles
  // sharing an edge by rounding.
  constexpr double kWatertight = 1e-12;
  if (u < -kWatertight || u > 1.0 + kWatertight) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = direction.dot(q) * inv;
  if (v < -kWatertight || u + v > 1.0 + kWatertight) return std::nullopt;
  const double t = e2.dot(q) * inv;
  if (t <= 0.0) return std::nullopt;
  return t;
}

// Every hit within kBeamAgreementM of the nearest one (several when surfaces touch there).
struct ReferenceHit {
  double range_m = kInf;
  struct Candidate {
    int instance_id;
    SemanticClass semantic_class;
    double incidence_rad;
  };
  std::vector<Candidate> candidates;
};

ReferenceHit ReferenceCast(const ReferenceWorld& world, const Eigen::Vector3d& origin,
                           const Eigen::Vector3d& direction, double length) {
  struct Hit {
    double t;
    const ReferenceMesh* mesh;
    double incidence_rad;
  };
  std::vector<Hit> hits;
  for (const ReferenceMesh& m : world.meshes) {
    if (!RayMeetsBox(m.box, origin, direction, length)) continue;
    for (std::size_t i = 0; i < m.corners.size(); i += 3) {
      const auto t =
          RayTriangle(origin, direction, m.corners[i], m.corners[i + 1], m.corners[i + 2]);
      if (!t || *t > length + kBeamAgreementM) continue;
      const Eigen::Vector3d n =
          (m.corners[i + 1] - m.corners[i]).cross(m.corners[i + 2] - m.corners[i]).normalized();
      hits.push_back({*t, &m, std::acos(std::min(1.0, std::abs(n.dot(direction))))});
    }
  }
  ReferenceHit result;
  for (const Hit& h : hits) result.range_m = std::min(result.range_m, h.t);
  for (const Hit& h : hits) {
    if (h.t <= result.range_m + kBeamAgreementM) {
      result.candidates.push_back(
          {h.mesh->mesh->instance_id, h.mesh->mesh->semantic_class, h.incidence_rad});
    }
  }
  return result;
}

// ---- Poses along a world's corridors --------------------------------------------------------

SE3 LaserPose(const Eigen::Vector3d& position, double yaw, double pitch = 0.0, double roll = 0.0) {
  return SE3::FromYawPitchRoll(yaw, pitch, roll, position);
}

// A few dozen poses: along each corridor segment (varied heading, height, a little tilt so that
// floor and ceiling are hit too), and in front of plates, closed doors and floor-standing
// furniture, facing them at their height.
std::vector<SE3> PosesAlong(const worlds::World& world, std::uint64_t seed) {
  RandomStream rng(seed, 0, "tests.laser.poses");
  std::vector<SE3> poses;
  const double heights[] = {0.30, 0.30, 0.30, 0.9, 1.5};
  for (const worlds::CorridorSegment& s : world.segments) {
    const Eigen::Vector2d along = s.direction(), left(-along.y(), along.x());
    // At least two dozen along the corridors in all.
    const int per_segment = std::max(6, (24 + static_cast<int>(world.segments.size()) - 1) /
                                            static_cast<int>(world.segments.size()));
    for (int k = 0; k < per_segment; ++k) {
      const double f = (k + 0.5) / per_segment;
      const double offset = rng.Uniform(-1.0, 1.0) * (0.5 * s.width_m - 0.4);
      const Eigen::Vector2d xy = s.start + f * (s.end - s.start) + offset * left;
      const double z = heights[rng.UniformInt(0, 4)];
      // Every third scan plane stands steeply (rolled by 60 to 90 deg): floor and ceiling.
      const bool tilted = k % 3 == 2;
      const double roll = (k % 2 == 0 ? 1.0 : -1.0) * rng.Uniform(kPi / 3, kPi / 2);
      poses.push_back(LaserPose({xy.x(), xy.y(), z}, rng.Uniform(-kPi, kPi),
                                tilted ? rng.Uniform(-0.3, 0.3) : 0.0, tilted ? roll : 0.0));
    }
  }
  auto facing = [&](const Eigen::Vector3d& target, const Eigen::Vector3d& normal,
                    double distance_m) {
    const Eigen::Vector3d position = target + distance_m * normal;
    poses.push_back(LaserPose(position, std::atan2(-normal.y(), -normal.x())));
  };
  for (std::size_t i = 0; i < std::min<std::size_t>(3, world.plates.size()); ++i) {
    facing(world.plates[i].center, world.plates[i].normal, 0.8);
  }
  int doors = 0;
  for (const worlds::Doorway& d : world.doors) {
    if (d.state != worlds::DoorState::kClosed || doors++ == 3) continue;
    const Eigen::Vector2d mid = 0.5 * (d.column_a + d.column_b);
    facing({mid.x(), mid.y(), 1.0}, {d.inward_normal.x(), d.inward_normal.y(), 0.0}, 0.8);
  }
  int furniture = 0;
  for (const worlds::Distractor& d : world.distractors) {
    const bool standing = d.semantic_class == SemanticClass::kBookshelf ||
                          d.semantic_class == SemanticClass::kCabinet ||
                          d.semantic_class == SemanticClass::kFireExtinguisher;
    if (!standing || furniture++ == 4) continue;
    facing(d.center, d.normal, 0.5 * d.size_m.y() + 0.7);
  }
  return poses;
}

// What a comparison with the reference saw: the hits per class and the longest return.
struct Compared {
  std::map<SemanticClass, int> hits_by_class;
  double longest_m = 0.0;
};

// Casts every beam of a noise-free scanner with `options` from every pose of `poses` and compares
// each (range, instance, class, incidence) with the reference.
Compared CompareWithReference(const worlds::World& world, const std::vector<SE3>& poses,
                              LaserOptions options) {
  options.noise = false;
  const LaserScanner scanner(world, options, 1);
  const ReferenceWorld reference = ReferenceOf(world);
  Compared compared;
  int mismatches = 0, beams = 0;
  std::string first_mismatches;
  for (const SE3& pose : poses) {
    for (int i = 0; i < scanner.beam_count(); ++i) {
      const double angle = (options.angle_min_deg + i * options.resolution_deg) * kPi / 180.0;
      const Eigen::Vector3d direction =
          pose.rotation() * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
      const ReferenceHit expected =
          ReferenceCast(reference, pose.translation(), direction, options.range_max_m);
      const BeamTruth truth = scanner.Cast(i, pose);
      ++beams;
      bool ok = false;
      if (expected.range_m > options.range_max_m) {
        ok = truth.range_m == kInf && truth.instance_id == 0;
      } else if (std::abs(truth.range_m - expected.range_m) <= kBeamAgreementM) {
        for (const ReferenceHit::Candidate& c : expected.candidates) {
          ok = ok ||
               (c.instance_id == truth.instance_id && c.semantic_class == truth.semantic_class &&
                std::abs(c.incidence_rad - truth.incidence_rad) <= kIncidenceAgreementRad);
        }
      }
      if (ok) {
        if (truth.range_m < kInf) {
          ++compared.hits_by_class[truth.semantic_class];
          compared.longest_m = std::max(compared.longest_m, truth.range_m);
        }
        continue;
      }
      if (++mismatches <= 5) {
        std::ostringstream line;
        line << "beam " << i << " from (" << pose.translation().transpose() << "), yaw "
             << pose.rotation().eulerAngles(2, 1, 0).transpose() << ": scanner " << truth.range_m
             << " m, instance " << truth.instance_id << ", incidence " << truth.incidence_rad
             << "; reference " << expected.range_m << " m";
        for (const ReferenceHit::Candidate& c : expected.candidates) {
          line << ", instance " << c.instance_id << " incidence " << c.incidence_rad;
        }
        first_mismatches += line.str() + "\n";
      }
    }
  }
  INFO(beams << " beams compared; the first mismatches:\n" << first_mismatches);
  CHECK(mismatches == 0);
  CHECK(beams > 20 * scanner.beam_count());
  return compared;
}

// The default scanner from the poses of PosesAlong: how often each class was hit.
std::map<SemanticClass, int> CompareWithReference(const worlds::World& world, std::uint64_t seed) {
  return CompareWithReference(world, PosesAlong(world, seed), LaserOptions{}).hits_by_class;
}

TEST_CASE("every noise-free beam equals a brute-force ray cast of the world's meshes",
          "[sim][laser]") {
  SECTION("the default world") {
    const std::map<SemanticClass, int> hits = CompareWithReference(test::GeneratedWorld(1), 1);
    CHECK(hits.count(SemanticClass::kWall) == 1);
    CHECK(hits.count(SemanticClass::kFloor) == 1);
    CHECK(hits.count(SemanticClass::kCeiling) == 1);
    CHECK(hits.count(SemanticClass::kDoorLeaf) == 1);
    CHECK(hits.count(SemanticClass::kDoorPlate) == 1);
    const int furniture = (hits.count(SemanticClass::kBookshelf) ? 1 : 0) +
                          (hits.count(SemanticClass::kCabinet) ? 1 : 0) +
                          (hits.count(SemanticClass::kFireExtinguisher) ? 1 : 0);
    CHECK(furniture > 0);
  }
  SECTION("a loop") {
    static const worlds::World loop = worlds::Generate(test::LayoutOptions()[3], 2);
    const std::map<SemanticClass, int> hits = CompareWithReference(loop, 2);
    CHECK(hits.count(SemanticClass::kWall) == 1);
    CHECK(hits.count(SemanticClass::kDoorLeaf) == 1);
    CHECK(hits.count(SemanticClass::kDoorPlate) == 1);
  }
}

// Random poses over a world: anywhere in the corridors at any height, level, slightly tilted (a
// robot on a bump) or in any orientation; on the centre line facing along a corridor (beams
// to its far end); and in and before doorways of every state, facing through them or obliquely
// at their frames (beams that end on a column's edge or pass it by a hair).
std::vector<SE3> RandomPoses(const worlds::World& world, std::uint64_t seed, int count) {
  RandomStream rng(seed, 0, "tests.laser.random_poses");
  std::vector<SE3> poses;
  const auto segments = static_cast<std::int64_t>(world.segments.size());
  for (int k = 0; k < count; ++k) {
    const worlds::CorridorSegment& s =
        world.segments[static_cast<std::size_t>(rng.UniformInt(0, segments - 1))];
    const Eigen::Vector2d along = s.direction(), left(-along.y(), along.x());
    const double f = rng.Uniform(0.0, 1.0);
    const double offset = rng.Uniform(-1.0, 1.0) * (0.5 * s.width_m - 0.05);
    const Eigen::Vector2d xy = s.start + f * (s.end - s.start) + offset * left;
    const double z = rng.Uniform(0.05, s.height_m - 0.05);
    const double yaw = rng.Uniform(-kPi, kPi);
    switch (k % 4) {
      case 0:  // level
        poses.push_back(LaserPose({xy.x(), xy.y(), z}, yaw));
        break;
      case 1:  // tilted a little
        poses.push_back(LaserPose({xy.x(), xy.y(), z}, yaw, rng.Uniform(-0.05, 0.05),
                                  rng.Uniform(-0.05, 0.05)));
        break;
      case 2:  // any orientation
        poses.push_back(LaserPose({xy.x(), xy.y(), z}, yaw, rng.Uniform(-kPi / 2, kPi / 2),
                                  rng.Uniform(-kPi, kPi)));
        break;
      default: {  // near a corridor's end, facing along it, near the centre line
        const Eigen::Vector2d from =
            s.start + rng.Uniform(0.2, 2.0) * along + rng.Uniform(-0.3, 0.3) * left;
        poses.push_back(LaserPose({from.x(), from.y(), rng.Uniform(0.1, 1.0)},
                                  std::atan2(along.y(), along.x()) + rng.Uniform(-0.02, 0.02),
                                  rng.Uniform(-0.002, 0.002), 0.0));
      }
    }
  }
  for (const worlds::Doorway& d : world.doors) {
    const Eigen::Vector2d mid = 0.5 * (d.column_a + d.column_b);
    const Eigen::Vector2d normal = d.inward_normal;
    const double into = std::atan2(-normal.y(), -normal.x());
    // In the doorway, at a height below and above its top bar, facing through it.
    poses.push_back(LaserPose({mid.x(), mid.y(), rng.Uniform(0.1, d.top_height_m)},
                              into + rng.Uniform(-0.3, 0.3)));
    poses.push_back(LaserPose({mid.x(), mid.y(), d.top_height_m + rng.Uniform(0.01, 0.2)},
                              into + kPi + rng.Uniform(-0.3, 0.3), rng.Uniform(-0.02, 0.02)));
    // In the corridor, 1 to 3 m out and to one side, facing the doorway's middle.
    const Eigen::Vector2d tangent = (d.column_b - d.column_a).normalized();
    const Eigen::Vector2d from =
        mid + rng.Uniform(1.0, 3.0) * normal + rng.Uniform(-2.0, 2.0) * tangent;
    const Eigen::Vector2d to = mid - from;
    poses.push_back(LaserPose({from.x(), from.y(), rng.Uniform(0.1, 2.0)},
                              std::atan2(to.y(), to.x()), rng.Uniform(-0.01, 0.01)));
  }
  return poses;
}

TEST_CASE("from random poses, tilted and in doorways, every beam equals the brute-force cast",
          "[sim][laser]") {
  // A full turn at 1 deg, to the longest range the options allow.
  LaserOptions options;
  options.angle_min_deg = -180.0;
  options.angle_max_deg = 179.0;
  options.resolution_deg = 1.0;
  options.range_max_m = kMaxLaserRangeM;
  SECTION("the default world") {
    const worlds::World& world = test::GeneratedWorld(5);
    const Compared compared = CompareWithReference(world, RandomPoses(world, 5, 160), options);
    CHECK(compared.hits_by_class.count(SemanticClass::kDoorFrame) == 1);
    CHECK(compared.hits_by_class.count(SemanticClass::kRoom) == 1);
    CHECK(compared.hits_by_class.count(SemanticClass::kFloor) == 1);
    CHECK(compared.hits_by_class.count(SemanticClass::kCeiling) == 1);
    CHECK(compared.longest_m > 40.0);  // along the corridor
  }
  SECTION("a loop") {
    static const worlds::World loop = worlds::Generate(test::LayoutOptions()[3], 6);
    const Compared compared = CompareWithReference(loop, RandomPoses(loop, 6, 160), options);
    CHECK(compared.hits_by_class.count(SemanticClass::kDoorFrame) == 1);
    CHECK(compared.hits_by_class.count(SemanticClass::kWall) == 1);
  }
}

TEST_CASE("the ray grid finds the reference's hit at every cell size", "[sim][laser]") {
  // The cells only cull: from the random poses' beams, at four sides (the grid's default, 1 m,
  // above), RayGrid::Nearest meets the brute force's nearest surface.
  const worlds::World& world = test::GeneratedWorld(7);
  const ReferenceWorld reference = ReferenceOf(world);
  std::vector<Eigen::Vector3d> corners;
  std::vector<int> instance_of_triangle;
  for (const worlds::Mesh& mesh : world.meshes) {
    for (const std::uint32_t index : mesh.indices)
      corners.push_back(mesh.positions[index].cast<double>());
    instance_of_triangle.insert(instance_of_triangle.end(), mesh.triangle_count(),
                                mesh.instance_id);
  }
  constexpr double kRangeM = 60.0;
  for (const double cell_m : {0.25, 0.5, 2.0, 5.0}) {
    const RayGrid grid(corners, cell_m);
    CHECK(grid.cell_m() == cell_m);
    int mismatches = 0, hits = 0, rays = 0;
    for (const SE3& pose : RandomPoses(world, 7, 40)) {
      for (int i = 0; i < 72; ++i) {
        const double angle = i * kPi / 36;
        const Eigen::Vector3d direction =
            pose.rotation() * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
        const ReferenceHit expected =
            ReferenceCast(reference, pose.translation(), direction, kRangeM);
        const RayHit hit = grid.Nearest(pose.translation(), direction, kRangeM);
        ++rays;
        bool ok = false;
        if (expected.range_m > kRangeM) {
          ok = hit.triangle < 0;
        } else if (hit.triangle >= 0 && std::abs(hit.t - expected.range_m) <= kBeamAgreementM) {
          ++hits;
          for (const ReferenceHit::Candidate& c : expected.candidates) {
            ok =
                ok || c.instance_id == instance_of_triangle[static_cast<std::size_t>(hit.triangle)];
          }
        }
        mismatches += ok ? 0 : 1;
      }
    }
    INFO("cell " << cell_m << " m: " << rays << " rays, " << hits << " hits");
    CHECK(mismatches == 0);
    CHECK(hits > rays / 2);
  }
}

// ---- The corridor's geometry: a bare corridor 2.4 m wide (walls at y = +-1.2) ---------------

const worlds::World& BareCorridor() {
  static const worlds::World world = worlds::Generate(test::BareCorridorOptions(12.0), 3);
  return world;
}

TEST_CASE("a beam's range and incidence match the corridor's walls", "[sim][laser]") {
  LaserOptions options;
  options.noise = false;
  const LaserScanner scanner(BareCorridor(), options, 1);
  // On the centre line facing along the corridor: beam i at angle a hits a side wall 1.2 m away
  // at range 1.2 / |sin a|, incidence 90 deg - |a|, unless the end wall comes first.
  const SE3 pose = LaserPose({4.0, 0.0, 0.30}, 0.0);
  int side_hits = 0;
  for (int i = 0; i < scanner.beam_count(); ++i) {
    const double a = scanner.BeamAngleRad(i);
    const BeamTruth truth = scanner.Cast(i, pose);
    if (std::abs(std::sin(a)) < 0.2) continue;  // towards the ends
    INFO("beam " << i << " at " << a * 180 / kPi << " deg");
    CHECK(truth.range_m == Approx(1.2 / std::abs(std::sin(a))).margin(kBeamAgreementM));
    CHECK(truth.incidence_rad == Approx(kPi / 2 - std::abs(a)).margin(kIncidenceAgreementRad));
    CHECK(truth.semantic_class == SemanticClass::kWall);
    ++side_hits;
  }
  CHECK(side_hits > 250);
}

// ---- The sensing model, on made-up truths ---------------------------------------------------

// Beams at ranges 1 m to 5.9 m, square to their surfaces.
std::vector<BeamTruth> Truths(int count) {
  std::vector<BeamTruth> truths(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    truths[static_cast<std::size_t>(i)] = {1.0 + 0.1 * (i % 50), 7, SemanticClass::kWall, 0.0};
  }
  return truths;
}

TEST_CASE("the range noise has mean 0 and the configured standard deviation", "[sim][laser]") {
  LaserOptions options;
  options.range_sigma_m = 0.02;
  const LaserScanner scanner(BareCorridor(), options, 7);
  const std::vector<BeamTruth> truths = Truths(scanner.beam_count());
  double sum = 0.0, sum_sq = 0.0;
  std::size_t n = 0;
  for (std::uint64_t sweep = 0; sweep < 200; ++sweep) {
    const LaserScan scan = scanner.Measure(0, sweep, truths);
    for (std::size_t i = 0; i < truths.size(); ++i) {
      const double error = scan.ranges_m[i] - truths[i].range_m;
      sum += error;
      sum_sq += error * error;
      ++n;
    }
  }
  const double sigma = options.range_sigma_m, mean = sum / static_cast<double>(n);
  const double z = boost::math::quantile(boost::math::normal(), 0.5 + kStatConfidence / 2);
  CHECK(std::abs(mean) < z * sigma / std::sqrt(static_cast<double>(n)));
  // n s^2 / sigma^2 (about the known mean 0) is chi-squared with n degrees of freedom.
  const boost::math::chi_squared chi2(static_cast<double>(n));
  const double statistic = sum_sq / (sigma * sigma);
  CHECK(statistic > boost::math::quantile(chi2, 0.5 - kStatConfidence / 2));
  CHECK(statistic < boost::math::quantile(chi2, 0.5 + kStatConfidence / 2));
}

TEST_CASE("without noise a scan reports the exact ranges, the limits as REP 117 says",
          "[sim][laser]") {
  LaserOptions options;
  options.noise = false;
  options.range_min_m = 0.5;
  options.range_max_m = 8.0;
  options.max_incidence_deg = 80.0;
  const LaserScanner scanner(BareCorridor(), options, 1);
  std::vector<BeamTruth> truths = Truths(scanner.beam_count());
  truths[0].range_m = kInf;                      // nothing within range
  truths[1].range_m = 0.2;                       // too near
  truths[2].incidence_rad = 81.0 * kPi / 180.0;  // grazing
  truths[3].incidence_rad = 79.0 * kPi / 180.0;  // oblique, still seen
  truths[4].range_m = 0.2;                       // too near and grazing: lost
  truths[4].incidence_rad = 85.0 * kPi / 180.0;
  const LaserScan scan = scanner.Measure(123, 0, truths);
  CHECK(scan.ranges_m[0] == std::numeric_limits<float>::infinity());
  CHECK(scan.ranges_m[1] == -std::numeric_limits<float>::infinity());
  CHECK(std::isnan(scan.ranges_m[2]));
  CHECK(scan.ranges_m[3] == static_cast<float>(truths[3].range_m));
  CHECK(std::isnan(scan.ranges_m[4]));
  for (std::size_t i = 5; i < truths.size(); ++i) {
    CHECK(scan.ranges_m[i] == static_cast<float>(truths[i].range_m));
  }
}

TEST_CASE("noisy returns beyond range read +inf and nearer than range_min_m -inf", "[sim][laser]") {
  LaserOptions options;
  options.range_min_m = 0.5;
  options.range_max_m = 8.0;
  options.range_sigma_m = 0.01;
  const LaserScanner scanner(BareCorridor(), options, 3);
  std::vector<BeamTruth> truths = Truths(scanner.beam_count());
  for (std::size_t i = 0; i < truths.size(); ++i) {
    // 10 sigma inside or outside the limits: the noise cannot move them across.
    truths[i].range_m = i % 4 == 0 ? 0.4 : i % 4 == 1 ? 0.6 : i % 4 == 2 ? 7.9 : kInf;
  }
  const LaserScan scan = scanner.Measure(0, 5, truths);
  for (std::size_t i = 0; i < truths.size(); ++i) {
    INFO("beam " << i);
    if (i % 4 == 0) CHECK(scan.ranges_m[i] == -std::numeric_limits<float>::infinity());
    if (i % 4 == 1 || i % 4 == 2) CHECK(std::isfinite(scan.ranges_m[i]));
    if (i % 4 == 3) CHECK(scan.ranges_m[i] == std::numeric_limits<float>::infinity());
  }
}

TEST_CASE("beams meeting a wall beyond max_incidence_deg return NaN", "[sim][laser]") {
  LaserOptions options;
  options.noise = false;
  options.max_incidence_deg = 70.0;
  const LaserScanner scanner(BareCorridor(), options, 1);
  const SE3 pose = LaserPose({4.0, 0.3, 0.30}, 0.2);
  std::vector<BeamTruth> truths;
  for (int i = 0; i < scanner.beam_count(); ++i) truths.push_back(scanner.Cast(i, pose));
  const LaserScan scan = scanner.Measure(0, 0, truths);
  int lost = 0, kept = 0;
  for (std::size_t i = 0; i < truths.size(); ++i) {
    INFO("beam " << i << ", incidence " << truths[i].incidence_rad * 180 / kPi << " deg");
    if (truths[i].incidence_rad > 70.0 * kPi / 180.0) {
      CHECK(std::isnan(scan.ranges_m[i]));
      ++lost;
    } else {
      CHECK(scan.ranges_m[i] == static_cast<float>(truths[i].range_m));
      ++kept;
    }
  }
  CHECK(lost > 20);
  CHECK(kept > 20);
}

TEST_CASE("returns are lost at the dropout probability", "[sim][laser]") {
  LaserOptions options;
  options.dropout_probability = 0.05;
  const LaserScanner scanner(BareCorridor(), options, 11);
  const std::vector<BeamTruth> truths = Truths(scanner.beam_count());
  std::size_t lost = 0, n = 0;
  for (std::uint64_t sweep = 0; sweep < 100; ++sweep) {
    const LaserScan scan = scanner.Measure(0, sweep, truths);
    for (const float r : scan.ranges_m) lost += std::isnan(r) ? 1 : 0;
    n += scan.ranges_m.size();
  }
  const boost::math::binomial binomial(static_cast<double>(n), options.dropout_probability);
  CHECK(static_cast<double>(lost) >= boost::math::quantile(binomial, 0.5 - kStatConfidence / 2));
  CHECK(static_cast<double>(lost) <= boost::math::quantile(binomial, 0.5 + kStatConfidence / 2));
}

// ---- Determinism ----------------------------------------------------------------------------

bool SameBytes(const LaserScan& a, const LaserScan& b) {
  return a.ranges_m.size() == b.ranges_m.size() &&
         std::memcmp(a.ranges_m.data(), b.ranges_m.data(), a.ranges_m.size() * sizeof(float)) == 0;
}

TEST_CASE("scanners with the same seed give the same bytes, another id other noise",
          "[sim][laser]") {
  LaserOptions options;
  options.dropout_probability = 0.1;
  const LaserScanner a(BareCorridor(), options, 42), b(BareCorridor(), options, 42);
  options.id = "rear";
  const LaserScanner other(BareCorridor(), options, 42);
  const SE3 pose = LaserPose({4.0, 0.3, 0.30}, 0.5);
  std::vector<BeamTruth> truths;
  for (int i = 0; i < a.beam_count(); ++i) truths.push_back(a.Cast(i, pose));
  // Sweep 3 alone, and after other sweeps: a sweep's noise depends on its index only.
  const LaserScan first = a.Measure(1000, 3, truths);
  for (std::uint64_t s = 0; s < 3; ++s) b.Measure(0, s, truths);
  CHECK(SameBytes(first, b.Measure(1000, 3, truths)));
  CHECK_FALSE(SameBytes(first, other.Measure(1000, 3, truths)));
  CHECK_FALSE(SameBytes(first, a.Measure(1000, 4, truths)));
  CHECK(other.Measure(1000, 3, truths).sensor_id == "rear");
}

// ---- Options and timing ---------------------------------------------------------------------

TEST_CASE("laser options: every bound refused naming its key", "[sim][laser]") {
  LaserOptions options;
  test::CheckEveryBoundNamesKeyAndValue(LaserOptionsTable(), &options, "",
                                        [&] { return options.Check(); });
  using B = test::BrokenOption<LaserOptions>;
  test::CheckEachBrokenOption<LaserOptions>({
      B{[](LaserOptions& o) { o.rate_hz = 0.0; }, "rate_hz"},
      B{[](LaserOptions& o) { o.rate_hz = 150.0; }, "rate_hz"},
      B{[](LaserOptions& o) { o.phase_s = 1.0 / 37.5; }, "phase_s"},
      B{[](LaserOptions& o) { o.phase_s = -0.001; }, "phase_s"},
      // Below 1 / rate_hz, but the nanosecond it rounds to is the period's.
      B{[](LaserOptions& o) { o.phase_s = 0.0266666666; }, "phase_s"},
      B{[](LaserOptions& o) { o.phase_s = std::nan(""); }, "phase_s"},
      B{[](LaserOptions& o) { o.mount.z_m = 50.0; }, "mount.z_m"},
      B{[](LaserOptions& o) { o.mount.x_m = std::nan(""); }, "mount.x_m"},
      B{[](LaserOptions& o) { o.mount.yaw_deg = 400.0; }, "mount.yaw_deg"},
      B{[](LaserOptions& o) { o.angle_max_deg = o.angle_min_deg; }, "angle_max_deg"},
      B{[](LaserOptions& o) { o.angle_min_deg = -200.0; }, "angle_min_deg"},
      B{[](LaserOptions& o) { o.angle_min_deg = -180.0, o.angle_max_deg = 180.0; },
        "angle_max_deg"},
      B{[](LaserOptions& o) { o.resolution_deg = 0.0; }, "resolution_deg"},
      B{[](LaserOptions& o) { o.resolution_deg = 0.04; }, "resolution_deg"},  // 4501 beams
      B{[](LaserOptions& o) { o.range_max_m = 150.0; }, "range_max_m"},
      B{[](LaserOptions& o) { o.range_max_m = 0.0; }, "range_max_m"},
      B{[](LaserOptions& o) { o.range_min_m = 80.0; }, "range_min_m"},
      B{[](LaserOptions& o) { o.range_min_m = -1.0; }, "range_min_m"},
      B{[](LaserOptions& o) { o.range_sigma_m = -0.01; }, "range_sigma_m"},
      B{[](LaserOptions& o) { o.max_incidence_deg = 0.0; }, "max_incidence_deg"},
      B{[](LaserOptions& o) { o.max_incidence_deg = 95.0; }, "max_incidence_deg"},
      B{[](LaserOptions& o) { o.dropout_probability = 1.5; }, "dropout_probability"},
  });
  // The largest sweep passes: 4096 beams over 360 deg less one step.
  LaserOptions largest;
  largest.angle_min_deg = -180.0;
  largest.resolution_deg = 360.0 / 4096;
  largest.angle_max_deg = 180.0 - largest.resolution_deg;
  CHECK_FALSE(largest.Check());
  CHECK(largest.BeamCount() == 4096);
}

TEST_CASE("the default scanner's beams and timing fields", "[sim][laser]") {
  LaserOptions options;
  options.phase_s = 0.01;
  const LaserScanner scanner(BareCorridor(), options, 1);
  // A SICK LMS200 at 0.5 deg: 361 beams over 180 deg, a sweep every 1 / 37.5 s.
  CHECK(scanner.beam_count() == 361);
  CHECK(scanner.period_ns() == 26'666'667);
  CHECK(scanner.phase_ns() == 10'000'000);
  // The mirror turns once per period: 0.5 deg of it takes 26,666,667 ns / 720 = 37,037.04 ns.
  CHECK(scanner.time_increment_ns() == 37'037);
  CHECK(scanner.BeamAngleRad(0) == Approx(-kPi / 2).margin(1e-15));
  CHECK(scanner.BeamAngleRad(180) == Approx(0.0).margin(1e-15));
  CHECK(scanner.BeamAngleRad(360) == Approx(kPi / 2).margin(1e-15));
  const LaserScan scan =
      scanner.Measure(5'000'000'000, 0, std::vector<BeamTruth>(361, BeamTruth{}));
  CHECK(scan.stamp_ns == 5'000'000'000);
  CHECK(scan.sensor_id == "laser");
  CHECK(scan.angle_min_rad == Approx(-kPi / 2).margin(1e-15));
  CHECK(scan.angle_increment_rad == Approx(0.5 * kPi / 180).margin(1e-15));
  CHECK(scan.time_increment_ns == 37'037);
  CHECK(scan.scan_time_ns == 26'666'667);
  CHECK(scan.range_min_m == 0.1);
  CHECK(scan.range_max_m == 80.0);
  CHECK(scan.ranges_m.size() == 361);
  // The last beam fires within the sweep's period.
  CHECK(360 * scanner.time_increment_ns() < scanner.period_ns());
}

}  // namespace
}  // namespace corridorsim::sim
