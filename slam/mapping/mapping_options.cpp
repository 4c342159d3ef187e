// The scenario keys of the mapping stages (slam/mapping/): one table per options struct, with each
// key's unit, bounds and doc (common/options_table.h). The structs, their Check() and the stages
// that read them stay in their own files.

#include "common/options_table.h"
#include "slam/mapping/door_areas.h"
#include "slam/mapping/occupancy_mapper.h"
#include "slam/mapping/point_cloud.h"
#include "slam/mapping/voxel_filter.h"

namespace corridorsim::slam {

const OptionTable<DepthCloudOptions>& DepthCloudOptionsTable() {
  return StaticOptionTable<DepthCloudOptions>([](OptionTable<DepthCloudOptions>& t) {
    t.Add("pixel_stride", &DepthCloudOptions::pixel_stride, "px",
          "every stride-th pixel of every stride-th row of the depth image becomes a point")
        .Range(1, 64);
  });
}

const OptionTable<VoxelFilterOptions>& VoxelFilterOptionsTable() {
  return StaticOptionTable<VoxelFilterOptions>([](OptionTable<VoxelFilterOptions>& t) {
    t.Add("leaf_size_m", &VoxelFilterOptions::leaf_size_m, "m",
          "edge of the voxel grid's cubes: one point (the centroid) per occupied cube")
        .Range(0.001, 10);
  });
}

const OptionTable<OccupancyMapperOptions>& OccupancyMapperOptionsTable() {
  return StaticOptionTable<OccupancyMapperOptions>([](OptionTable<OccupancyMapperOptions>& t) {
    t.Add("resolution_m", &OccupancyMapperOptions::resolution_m, "m",
          "edge of the OctoMap's smallest voxel")
        .Range(0.01, 1.0);
    t.Add("max_range_m", &OccupancyMapperOptions::max_range_m, "m",
          "rays are cut at this length (the insertion's cost grows with it)")
        .Greater(0)
        .AtMost(20);
    t.Add("pixel_stride", &OccupancyMapperOptions::pixel_stride, "px",
          "every stride-th pixel of every stride-th depth row is inserted")
        .Range(1, 64);
    t.Add("voxel_leaf_m", &OccupancyMapperOptions::voxel_leaf_m, "m",
          "voxel-grid filter leaf before insertion (P1 Fig. 12b); 0 = off")
        .ZeroOr(0.005, 1.0);
    t.Add("keyframe_distance_m", &OccupancyMapperOptions::keyframe_distance_m, "m",
          "a frame is inserted when the camera has moved this far since the last keyframe")
        .Range(0, 100);
    t.Add("keyframe_angle_deg", &OccupancyMapperOptions::keyframe_angle_deg, "deg",
          "... or turned this much")
        .Range(0, 180);
  });
}

const OptionTable<DoorAreaOptions>& DoorAreaOptionsTable() {
  using O = DoorAreaOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("room_depth_m", &O::room_depth_m, "m",
          "how far behind a door's wall line its room reaches")
        .Range(0.1, 1000);
    t.Add("room_reach_m", &O::room_reach_m, "m",
          "how far beyond a door's columns its room reaches along the wall")
        .Range(0, 1000);
    t.Add("min_depth_m", &O::min_depth_m, "m",
          "landmarks nearer a door's wall line than this are the doorway's: the corridor's")
        .Range(0, 10);
    t.Add("manhattan", &O::manhattan, "",
          "square each door's wall line to the directions all doors agree on (modulo 90 deg)");
    t.Add("max_turn_deg", &O::max_turn_deg, "deg",
          "manhattan: a door line further than this from both directions keeps its own")
        .Range(0, 45);
  });
}

}  // namespace corridorsim::slam
