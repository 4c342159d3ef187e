// Tests slam/mapping/occupancy_mapper.cpp: an OctoMap built from the depth image of a wall.
#include "slam/mapping/occupancy_mapper.h"

#include <cstdlib>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "tests/support/broken_options.h"

namespace corridorsim::slam {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// A depth camera (80 x 60 px, 58 deg) at robot height 0.5 m facing world +x.
CameraCalibration FrontCamera() {
  return CameraCalibration{"front", PinholeRadTan::FromFov(80, 60, 58 * kDeg), SE3(),
                           DepthRange{0.2, 8.0}};
}
SE3 CameraAt(double x, double y, double yaw_rad) {
  Eigen::Matrix3d robot_from_optical;  // optical z forward (+x), x right (-y), y down (-z)
  robot_from_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return SE3::FromSE2(SE2(x, y, yaw_rad), 0.5) * SE3(robot_from_optical, Eigen::Vector3d::Zero());
}
// What a camera facing a wall `distance_m` ahead sees: the same depth everywhere.
ImageF WallDepth(double distance_m) { return ImageF(80, 60, static_cast<float>(distance_m)); }

OccupancyMapperOptions Options(double max_range_m) {
  OccupancyMapperOptions options;
  options.resolution_m = 0.1;
  options.max_range_m = max_range_m;
  options.pixel_stride = 1;
  return options;
}

bool Occupied(const octomap::OcTree& tree, double x, double y, double z) {
  const octomap::OcTreeNode* node = tree.search(x, y, z);
  return node != nullptr && tree.isNodeOccupied(node);
}
bool Free(const octomap::OcTree& tree, double x, double y, double z) {
  const octomap::OcTreeNode* node = tree.search(x, y, z);
  return node != nullptr && !tree.isNodeOccupied(node);
}
bool Unknown(const octomap::OcTree& tree, double x, double y, double z) {
  return tree.search(x, y, z) == nullptr;
}

TEST_CASE(
    "a wall's depth image gives an octree with the wall occupied and the space in front "
    "free",
    "[slam][mapping]") {
  OccupancyMapper mapper(Options(5.0), FrontCamera());
  // The wall at x = 3.04: inside the voxel layer [3.0, 3.1).
  mapper.Insert(WallDepth(3.04), CameraAt(0, 0, 0));
  const octomap::OcTree& tree = mapper.octree();
  CHECK(tree.getResolution() == 0.1);
  // Along the optical axis and off it, within the field of view (+-29 deg: +-1.6 m at 3 m).
  for (double y : {-1.0, -0.25, 0.05, 0.65, 1.2}) {
    for (double z : {-0.35, 0.55, 1.25}) {
      INFO("y " << y << " z " << z);
      CHECK(Occupied(tree, 3.05, y, z));
      CHECK(Free(tree, 2.85, y * 2.85 / 3.04, 0.5 + (z - 0.5) * 2.85 / 3.04));
      CHECK(Free(tree, 1.55, y * 1.55 / 3.04, 0.5 + (z - 0.5) * 1.55 / 3.04));
      CHECK(Unknown(tree, 3.35, y, z));  // behind the wall
    }
  }
  CHECK(Unknown(tree, 1.0, 2.0, 0.5));  // outside the field of view
  const OccupancyMapperStats& stats = mapper.stats();
  CHECK(stats.keyframes == 1);
  CHECK(stats.points_inserted == 80 * 60);
}

TEST_CASE("the maximum range cuts the rays: nothing beyond it is occupied or free",
          "[slam][mapping]") {
  OccupancyMapper mapper(Options(2.0), FrontCamera());
  mapper.Insert(WallDepth(3.04), CameraAt(0, 0, 0));
  const octomap::OcTree& tree = mapper.octree();
  CHECK(Free(tree, 1.55, 0.05, 0.55));
  CHECK(Unknown(tree, 2.55, 0.05, 0.55));
  CHECK(Unknown(tree, 3.05, 0.05, 0.55));
  int occupied = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    occupied += tree.isNodeOccupied(*it);
    // Every known voxel lies within the range (and one voxel's diagonal) of the sensor.
    const double distance = (it.getCoordinate() - octomap::point3d(0, 0, 0.5)).norm();
    CHECK(distance <= 2.0 + it.getSize() * std::sqrt(3.0));
  }
  CHECK(occupied == 0);
}

TEST_CASE("frames become keyframes after the camera moved or turned enough", "[slam][mapping]") {
  OccupancyMapperOptions options = Options(5.0);
  options.keyframe_distance_m = 0.5;
  options.keyframe_angle_deg = 15.0;
  options.pixel_stride = 8;
  OccupancyMapper mapper(options, FrontCamera());
  CHECK(mapper.OnDepth(WallDepth(3.04), CameraAt(0, 0, 0)));  // the first frame always is
  CHECK_FALSE(mapper.OnDepth(WallDepth(3.04), CameraAt(0.3, 0, 0)));
  CHECK_FALSE(mapper.OnDepth(WallDepth(3.04), CameraAt(0.3, 0, 10 * kDeg)));
  CHECK(mapper.OnDepth(WallDepth(2.54), CameraAt(0.5, 0, 0)));
  CHECK(mapper.OnDepth(WallDepth(2.54), CameraAt(0.5, 0, 16 * kDeg)));
  const OccupancyMapperStats& stats = mapper.stats();
  CHECK(stats.frames == 5);
  CHECK(stats.keyframes == 3);
  CHECK(stats.points_inserted == 3 * 10 * 8);
  REQUIRE(mapper.keyframe_origins_in_world().size() == 3u);
  CHECK((mapper.keyframe_origins_in_world()[1] - Eigen::Vector3d(0.5, 0, 0.5)).norm() < 1e-12);
  CHECK(stats.ms_per_keyframe() >= 0.0);
}

TEST_CASE("the .bt bytes read back into the same tree, and the same input gives the same bytes",
          "[slam][mapping]") {
  OccupancyMapper mapper(Options(5.0), FrontCamera());
  mapper.Insert(WallDepth(3.04), CameraAt(0, 0, 0));
  mapper.Insert(WallDepth(2.0), CameraAt(0.7, 0.4, 20 * kDeg));
  const std::string bytes = mapper.BinaryBytes();
  CHECK(bytes.rfind("# Octomap OcTree binary file", 0) == 0);

  const std::unique_ptr<octomap::OcTree> read = OcTreeFromBinaryBytes(bytes);
  REQUIRE(read);
  const octomap::OcTree& tree = mapper.octree();
  CHECK(read->getResolution() == tree.getResolution());
  CHECK(read->getNumLeafNodes() == tree.getNumLeafNodes());
  std::size_t leaves = 0, occupied = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const octomap::OcTreeNode* other = read->search(it.getKey(), it.getDepth());
    REQUIRE(other != nullptr);
    CHECK(read->isNodeOccupied(other) == tree.isNodeOccupied(*it));
    ++leaves;
    occupied += tree.isNodeOccupied(*it);
  }
  CHECK(leaves > 1000u);
  CHECK(occupied > 100u);
  // Written again: the same bytes.
  std::ostringstream again;
  REQUIRE(read->writeBinaryConst(again));
  CHECK(again.str() == bytes);

  OccupancyMapper twin(Options(5.0), FrontCamera());
  twin.Insert(WallDepth(3.04), CameraAt(0, 0, 0));
  twin.Insert(WallDepth(2.0), CameraAt(0.7, 0.4, 20 * kDeg));
  CHECK(twin.BinaryBytes() == bytes);

  CHECK(OcTreeFromBinaryBytes("not an octree") == nullptr);
  CHECK(OcTreeFromBinaryBytes("") == nullptr);
}

TEST_CASE("the mapper's options are checked", "[slam][mapping]") {
  test::CheckEachBrokenOption<OccupancyMapperOptions>({
      {[](OccupancyMapperOptions& o) { o.resolution_m = 0.0; }, "resolution_m"},
      {[](OccupancyMapperOptions& o) { o.max_range_m = 50.0; }, "max_range_m"},
      {[](OccupancyMapperOptions& o) { o.voxel_leaf_m = 0.001; }, "voxel_leaf_m"},
  });
}

// Writes a .bt file for tests/slam/mapping/octomap_tools_test.cmake, which reads it with
// octomap-tools: CORRIDORSIM_BT_OUT names the file (hidden: run only by that test).
TEST_CASE("write a .bt file for octomap-tools", "[.write_bt]") {
  const char* path = std::getenv("CORRIDORSIM_BT_OUT");
  REQUIRE(path != nullptr);
  OccupancyMapper mapper(Options(5.0), FrontCamera());
  mapper.Insert(WallDepth(3.04), CameraAt(0, 0, 0));
  std::ofstream out(path, std::ios::binary);
  out << mapper.BinaryBytes();
  REQUIRE(out.good());
}

}  // namespace
}  // namespace corridorsim::slam
