// Tests slam/mapping/voxel_filter.cpp: one centroid per occupied voxel, in voxel-key order.
#include "slam/mapping/voxel_filter.h"

#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include <catch2/catch.hpp>

#include "common/random.h"
#include "tests/support/tolerances.h"

namespace corridorsim::slam {
namespace {

TEST_CASE("the voxel filter keeps one centroid per voxel, ordered by voxel key",
          "[slam][mapping]") {
  // Voxels of 0.5 m: (1, 0, 0) gets two points, (0, 0, 0) one, (-1, 2, 0) two.
  const std::vector<Eigen::Vector3d> points = {
      {0.6, 0.1, 0.1}, {0.1, 0.2, 0.3}, {0.9, 0.3, 0.3}, {-0.1, 1.2, 0.2}, {-0.3, 1.4, 0.4},
  };
  const VoxelFilterResult result = VoxelFilter(points, VoxelFilterOptions{0.5});
  REQUIRE(result.points.size() == 3u);
  CHECK(result.dropped == 0u);
  CHECK((result.points[0] - Eigen::Vector3d(-0.2, 1.3, 0.3)).norm() < test::kGeomTolM);
  CHECK((result.points[1] - Eigen::Vector3d(0.1, 0.2, 0.3)).norm() < test::kGeomTolM);
  CHECK((result.points[2] - Eigen::Vector3d(0.75, 0.2, 0.2)).norm() < test::kGeomTolM);
}

TEST_CASE("the voxel filter's count is the number of distinct voxels of a dense cloud",
          "[slam][mapping]") {
  // 300k random points in a 4 x 3 x 2.5 m box, as a 640x480 cloud (P1 Fig. 12b).
  RandomStream rng(3, 0, "test.voxel_filter");
  std::vector<Eigen::Vector3d> points(300000);
  for (Eigen::Vector3d& p : points) {
    p = Eigen::Vector3d(4.0 * rng.Uniform01() - 2.0, 3.0 * rng.Uniform01(), 2.5 * rng.Uniform01());
  }
  const double leaf = 0.1;
  std::set<std::array<long, 3>> voxels;
  for (const Eigen::Vector3d& p : points) {
    voxels.insert({static_cast<long>(std::floor(p.x() / leaf)),
                   static_cast<long>(std::floor(p.y() / leaf)),
                   static_cast<long>(std::floor(p.z() / leaf))});
  }
  const VoxelFilterResult result = VoxelFilter(points, VoxelFilterOptions{leaf});
  CHECK(result.points.size() == voxels.size());
  CHECK(result.points.size() <= 40u * 30u * 25u);
  // Every centroid lies in its own voxel, the voxels in key order.
  std::array<long, 3> previous{std::numeric_limits<long>::min(), 0, 0};
  for (const Eigen::Vector3d& c : result.points) {
    const std::array<long, 3> key{static_cast<long>(std::floor(c.x() / leaf)),
                                  static_cast<long>(std::floor(c.y() / leaf)),
                                  static_cast<long>(std::floor(c.z() / leaf))};
    CHECK(voxels.count(key) == 1u);
    CHECK(previous < key);
    previous = key;
  }
  // The same input gives the same bytes.
  const VoxelFilterResult again = VoxelFilter(points, VoxelFilterOptions{leaf});
  CHECK(again.points == result.points);
}

TEST_CASE("the voxel filter drops non-finite and out-of-key-range points", "[slam][mapping]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const VoxelFilterResult result = VoxelFilter(
      {{nan, 0, 0}, {0, inf, 0}, {0, 0, 1e12}, {0.01, 0.01, 0.01}}, VoxelFilterOptions{0.05});
  CHECK(result.dropped == 3u);
  CHECK(result.points.size() == 1u);
  CHECK(VoxelFilter({}, VoxelFilterOptions{}).points.empty());
  CHECK(VoxelFilterOptions{0.0}.Check()->key == "leaf_size_m");
}

}  // namespace
}  // namespace corridorsim::slam
