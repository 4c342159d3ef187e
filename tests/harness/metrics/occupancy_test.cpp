// Tests harness/metrics/occupancy.cpp: an OctoMap scored against a hand-built world, with counts
// worked out by hand.
#include "harness/metrics/occupancy.h"

#include <vector>

#include <catch2/catch.hpp>

#include "common/random.h"

namespace corridorsim::metrics {
namespace {

// A world of one axis-aligned quad (two triangles) in the plane x = x_m, over [y0, y1] x [z0, z1].
worlds::World QuadWorld(float x_m, float y0, float y1, float z0, float z1) {
  worlds::World world;
  worlds::Mesh mesh;
  mesh.name = "wall";
  mesh.semantic_class = worlds::SemanticClass::kWall;
  mesh.positions = {{x_m, y0, z0}, {x_m, y1, z0}, {x_m, y1, z1}, {x_m, y0, z1}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  world.meshes.push_back(mesh);
  return world;
}

TEST_CASE("occupancy precision and recall of a hand-filled octree against a quad wall",
          "[harness][metrics]") {
  // The wall x = 1.05 (the middle of the voxel layer [1.0, 1.1) at 0.1 m), y in [0.01, 0.59],
  // z in [0.01, 0.19]: truth voxels x 1.05, y 0.05 .. 0.55 (6), z 0.05, 0.15 (2) = 12.
  const worlds::World world = QuadWorld(1.05f, 0.01f, 0.59f, 0.01f, 0.19f);
  octomap::OcTree octree(0.1);
  // Occupied: A, B on the wall, C one voxel in front of it, D five voxels in front.
  for (const octomap::point3d& p :
       {octomap::point3d(1.05f, 0.05f, 0.05f), octomap::point3d(1.05f, 0.15f, 0.05f),
        octomap::point3d(1.15f, 0.25f, 0.15f), octomap::point3d(1.55f, 0.05f, 0.05f)}) {
    octree.updateNode(p, true);
  }
  // Free (observed) wall voxels: two beside A/C, one far from every occupied voxel.
  for (const octomap::point3d& p :
       {octomap::point3d(1.05f, 0.25f, 0.15f), octomap::point3d(1.05f, 0.05f, 0.15f),
        octomap::point3d(1.05f, 0.55f, 0.05f)}) {
    octree.updateNode(p, false);
  }

  const OccupancyQuality one = ComputeOccupancyQuality(world, octree, OccupancyQualityOptions{});
  CHECK(one.occupied_voxels == 4);
  CHECK(one.occupied_near_truth == 3);  // A, B, C
  CHECK(one.precision == 0.75);
  CHECK(one.truth_voxels == 12);
  CHECK(one.truth_observed == 5);           // A, B and the three free ones
  CHECK(one.truth_observed_recalled == 4);  // all but (1.05, 0.55, 0.05)
  CHECK(one.recall == 0.8);

  OccupancyQualityOptions exact;
  exact.tolerance_voxels = 0;
  const OccupancyQuality zero = ComputeOccupancyQuality(world, octree, exact);
  CHECK(zero.occupied_near_truth == 2);  // A, B
  CHECK(zero.precision == 0.5);
  CHECK(zero.truth_observed == 5);
  CHECK(zero.truth_observed_recalled == 2);
  CHECK(zero.recall == 0.4);
}

TEST_CASE("a pruned occupied leaf counts as the voxels it covers", "[harness][metrics]") {
  const worlds::World world = QuadWorld(1.05f, 0.01f, 0.59f, 0.01f, 0.19f);
  octomap::OcTree octree(0.1);
  // The 8 voxels x 1.05, 1.15; y 0.05, 0.15; z 0.05, 0.15 share one parent: pruned into it.
  for (float x : {1.05f, 1.15f}) {
    for (float y : {0.05f, 0.15f}) {
      for (float z : {0.05f, 0.15f}) octree.updateNode(octomap::point3d(x, y, z), true);
    }
  }
  octree.prune();
  REQUIRE(octree.getNumLeafNodes() == 1u);
  const OccupancyQuality q = ComputeOccupancyQuality(world, octree, OccupancyQualityOptions{});
  CHECK(q.occupied_voxels == 8);
  CHECK(q.occupied_near_truth == 8);  // x 1.15 is one voxel from the wall
  CHECK(q.precision == 1.0);
  CHECK(q.truth_observed == 4);  // the wall voxels inside the leaf
  CHECK(q.recall == 1.0);
  // Within the known box grown by one voxel: y 0.05 .. 0.25 (3) x z 0.05, 0.15 (2).
  CHECK(q.truth_voxels == 6);
}

TEST_CASE("an empty octree or world scores zero with zero counts", "[harness][metrics]") {
  const worlds::World world = QuadWorld(1.05f, 0.01f, 0.59f, 0.01f, 0.19f);
  const OccupancyQuality none =
      ComputeOccupancyQuality(world, octomap::OcTree(0.1), OccupancyQualityOptions{});
  CHECK(none.occupied_voxels == 0);
  CHECK(none.truth_voxels == 0);
  CHECK(none.precision == 0.0);
  octomap::OcTree octree(0.1);
  octree.updateNode(octomap::point3d(1.05f, 0.05f, 0.05f), true);
  const OccupancyQuality empty_world =
      ComputeOccupancyQuality(worlds::World{}, octree, OccupancyQualityOptions{});
  CHECK(empty_world.occupied_voxels == 1);
  CHECK(empty_world.precision == 0.0);
  CHECK(empty_world.truth_observed == 0);
  CHECK(OccupancyQualityOptions{.tolerance_voxels = -1}.Check()->key == "tolerance_voxels");
}

TEST_CASE("the triangle-box test agrees with dense sampling of the triangle",
          "[harness][metrics]") {
  RandomStream rng(5, 0, "test.triangle_box");
  const Eigen::Vector3d half(0.05, 0.05, 0.05);
  int touching = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Vector3d v[3];
    for (Eigen::Vector3d& p : v) {
      p = Eigen::Vector3d(rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3));
    }
    // Any sample of the triangle inside the box proves contact; a box grown by the sampling's
    // spacing that holds no sample proves none.
    bool sample_inside = false, sample_near = false;
    constexpr int kSteps = 120;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const Eigen::Vector3d p =
            v[0] + (v[1] - v[0]) * (double(i) / kSteps) + (v[2] - v[0]) * (double(j) / kSteps);
        sample_inside = sample_inside || (p.cwiseAbs().array() <= half.array()).all();
        sample_near = sample_near || (p.cwiseAbs().array() <= half.array() + 0.01).all();
      }
    }
    const bool touches = TriangleTouchesBox(Eigen::Vector3d::Zero(), half, v[0], v[1], v[2]);
    INFO("trial " << trial);
    if (sample_inside) CHECK(touches);
    if (!sample_near) CHECK_FALSE(touches);
    touching += touches;
  }
  CHECK(touching > 30);
  CHECK(touching < 270);
  // A triangle in a box's face plane touches it; one a hair outside does not.
  const Eigen::Vector3d a(0.05, -1, -1), b(0.05, 1, -1), c(0.05, 0, 1);
  CHECK(TriangleTouchesBox(Eigen::Vector3d::Zero(), half, a, b, c));
  const Eigen::Vector3d out(1e-9, 0, 0);
  CHECK_FALSE(TriangleTouchesBox(Eigen::Vector3d::Zero(), half, a + out, b + out, c + out));
}

}  // namespace
}  // namespace corridorsim::metrics
