// The scenario keys of the shipped pipelines (a pipeline's `options:` map, docs/scenarios.md), with
// the door verifier's and the mapping stages' (slam/mapping/) they hold as sections: one table per
// options struct, with each key's unit, bounds and doc (common/options_table.h). The structs,
// their Check() and the code that reads them stay in their own files; the detectors' tables are
// in slam/features/feature_options.cpp.

#include "common/options_table.h"
#include "slam/imu_odometry_pipeline.h"
#include "slam/laser_slam_pipeline.h"
#include "slam/mapping/door_areas.h"
#include "slam/mapping/occupancy_mapper.h"
#include "slam/mapping/point_cloud.h"
#include "slam/mapping/voxel_filter.h"
#include "slam/odometry_pipeline.h"
#include "slam/p1_harris_pipeline.h"
#include "slam/p1_vp_doorplate_pipeline.h"
#include "slam/p3_upward_pipeline.h"
#include "slam/upward_door_verifier.h"

namespace corridorsim::slam {

const OptionTable<OdometryPipelineOptions>& OdometryPipelineOptionsTable() {
  return StaticOptionTable<OdometryPipelineOptions>([](OptionTable<OdometryPipelineOptions>& t) {
    t.Add("k_m", &OdometryPipelineOptions::k_m, "m",
          "k of P1 eq. 17: Q = diag(k |s_l|, k |s_r|); set it to robot.odometry.random_k_m for a "
          "consistent filter")
        .Range(0, 0.1);
  });
}

const OptionTable<ImuOdometryOptions>& ImuOdometryOptionsTable() {
  return StaticOptionTable<ImuOdometryOptions>([](OptionTable<ImuOdometryOptions>& t) {
    using O = ImuOdometryOptions;
    t.Add("k_m", &O::k_m, "m",
          "k of P1 eq. 17: Q = diag(k |s_l|, k |s_r|); set it to robot.odometry.random_k_m")
        .Range(0, 0.1);
    t.Add("imu", &O::imu, "", "the IMU it reads (its name under sensors:); empty: the first one");
    t.Add("initial_bias_sigma_rad_s", &O::initial_bias_sigma_rad_s, "rad/s",
          "prior standard deviation of the gyroscope's z bias")
        .Range(0, 1);
    t.Add("wheel_yaw_inflation", &O::wheel_yaw_inflation, "",
          "factor on P1 eq. 17's wheel-turn variance in the bias update (systematic E_d, E_b)")
        .Range(1, 1e6);
    t.Add("max_update_turn_rate_rad_s", &O::max_update_turn_rate_rad_s, "rad/s",
          "the bias update runs only while the gyro says the robot turns at most this fast")
        .Range(0, 10);
    t.Add("gate_chi2", &O::gate_chi2, "",
          "NIS gate of the bias update (chi-square at 1 dof; 10.83 = 99.9 %): slips are refused")
        .Range(1, 1000);
    t.Add("compensate_slips", &O::compensate_slips, "",
          "a gated interval's excess turn names the slipped wheel; its extra distance is dropped");
    t.Add("max_imu_gap_s", &O::max_imu_gap_s, "s",
          "an odometry interval with no IMU sample this recent turns by the wheels (P1 eq. 13)")
        .Range(0.001, 10);
  });
}

const OptionTable<LaserSlamOptions>& LaserSlamOptionsTable() {
  return StaticOptionTable<LaserSlamOptions>([](OptionTable<LaserSlamOptions>& t) {
    using O = LaserSlamOptions;
    t.Add("k_m", &O::k_m, "m",
          "k of P1 eq. 17: Q = diag(k |s_l|, k |s_r|); set it to robot.odometry.random_k_m")
        .Range(0, 0.1);
    t.Add("laser", &O::laser, "", "the scanner used (a sensors: name; empty: the first scanner)");
    t.Add("max_range_m", &O::max_range_m, "m", "beams beyond this range are not used")
        .Greater(0)
        .Range(0, 100);
    t.Add("match_interval_s", &O::match_interval_s, "s",
          "a sweep closer than this to the last matched one is skipped (0: match every sweep)")
        .Range(0, 60);
    t.Add("min_points", &O::min_points, "",
          "a sweep with fewer usable beams is not matched (odometry alone)")
        .Range(1, 100000);
    t.Add("point_spacing_m", &O::point_spacing_m, "m",
          "the matched points keep this far apart in beam order (0: every beam; all are inserted)")
        .Range(0, 10);
    t.Add("resolution_m", &O::resolution_m, "m", "the probability grid's cell side").Range(0.01, 1);
    t.Add("hit_probability", &O::hit_probability, "",
          "p_hit of a beam's endpoint cell (Cartographer: 0.55)")
        .RangeOpenLow(0.5, 0.9);
    t.Add("miss_probability", &O::miss_probability, "",
          "p_miss of a cell a beam crosses (Cartographer: 0.49)")
        .Range(0.1, 0.5)
        .Note("< hit_probability");
    t.Add("max_map_extent_m", &O::max_map_extent_m, "m",
          "the grid reaches at most this far from the first sweep's origin, each way")
        .Range(1, 5000)
        .Note("(2 max_map_extent_m / resolution_m)^2 < 2^28 cells");
    t.Add("insert_distance_m", &O::insert_distance_m, "m",
          "a matched sweep is inserted after this much travel since the last insertion ...")
        .Range(0, 100);
    t.Add("insert_angle_deg", &O::insert_angle_deg, "deg", "... or this much turn").Range(0, 360);
    t.Add("search_window_m", &O::search_window_m, "m",
          "correlative search before the Ceres match: +- this in x and y (0: no search)")
        .Range(0, 0.5);
    t.Add("search_window_deg", &O::search_window_deg, "deg", "... and +- this in heading")
        .Range(0, 10);
    t.Add("occupied_space_weight", &O::occupied_space_weight, "",
          "w_occ of the Ceres cost's 1 - p residuals (scaled by 1 / sqrt(beams))")
        .Greater(0)
        .Range(0, 1e6);
    t.Add("translation_weight", &O::translation_weight, "1/m",
          "w_t of the prior towards the odometry's predicted position")
        .Range(0, 1e6);
    t.Add("rotation_weight", &O::rotation_weight, "1/rad",
          "w_r of the prior towards the odometry's predicted heading")
        .Range(0, 1e6);
    t.Add("max_iterations", &O::max_iterations, "", "Ceres iterations per match").Range(1, 1000);
    t.Add("match_sigma_m", &O::match_sigma_m, "m",
          "covariance model: sigma of a scan point across the straight piece it lies on")
        .Greater(0)
        .Range(0, 10);
    t.Add("map_sigma_m", &O::map_sigma_m, "m",
          "the reported covariance adds this sigma (squared) in x and y: the grid's own error")
        .Range(0, 10);
    t.Add("map_sigma_deg", &O::map_sigma_deg, "deg", "... and this sigma in heading").Range(0, 90);
    t.Add("normal_half_window", &O::normal_half_window, "",
          "a point's normal is fitted to this many neighbouring beams on each side")
        .Range(1, 100);
    t.Add("normal_neighbourhood_m", &O::normal_neighbourhood_m, "m",
          "... those within this distance of it")
        .Greater(0)
        .Range(0, 10);
    t.Add("write_map", &O::write_map, "", "write the grid as maps/<name>.pgm");
  });
}

const OptionTable<P1HarrisOptions>& P1HarrisOptionsTable() {
  return StaticOptionTable<P1HarrisOptions>([](OptionTable<P1HarrisOptions>& t) {
    using O = P1HarrisOptions;
    t.Add("k_m", &O::k_m, "m",
          "k of P1 eq. 17: Q = diag(k |s_l|, k |s_r|); set it to robot.odometry.random_k_m")
        .Range(0, 0.1);
    t.Add("gate_chi2", &O::gate_chi2, "",
          "Mahalanobis gate of an association (chi-square at 3 dof; 11.34 = 99 %)")
        .Range(1, 1000);
    t.Add("pixel_sigma_px", &O::pixel_sigma_px, "px", "sigma of a corner's u and v")
        .Greater(0)
        .Range(0, 100);
    t.Add("depth_sigma_a_m", &O::depth_sigma_a_m, "m", "depth sigma at zero range")
        .Greater(0)
        .Range(0, 10);
    t.Add("depth_sigma_b", &O::depth_sigma_b, "1/m", "growth of the depth sigma with z^2")
        .Range(0, 10);
    t.Add("max_depth_m", &O::max_depth_m, "m", "corners farther than this are not used")
        .Greater(0)
        .Range(0, 100);
    t.Add("search_radius_px", &O::search_radius_px, "px",
          "landmarks predicted within this of a corner are association candidates")
        .Greater(0)
        .Range(0, 1000);
    t.Add("max_corners_per_frame", &O::max_corners_per_frame, "",
          "corners used per frame, strongest first")
        .Range(1, 1000);
    t.Add("max_landmarks", &O::max_landmarks, "",
          "the state stops growing at this many point landmarks")
        .Range(1, 2500);
    t.AddSection("corners", &O::corners, HarrisCornerOptionsTable(), "the Harris detector",
                 &HarrisCornerOptions::Check);
  });
}

const OptionTable<P1VpDoorplateOptions>& P1VpDoorplateOptionsTable() {
  return StaticOptionTable<P1VpDoorplateOptions>([](OptionTable<P1VpDoorplateOptions>& t) {
    using O = P1VpDoorplateOptions;
    t.Add("k_m", &O::k_m, "m",
          "k of P1 eq. 17: Q = diag(k |s_l|, k |s_r|); set it to robot.odometry.random_k_m")
        .Range(0, 0.1);
    t.Add("gate_chi2", &O::gate_chi2, "",
          "NIS gate of every update (chi-square at 1 dof; 10.83 = 99.9 %)")
        .Range(1, 1000);
    t.Add("use_vanishing_point", &O::use_vanishing_point, "",
          "observe the front camera's vanishing point (P1 eq. 19)");
    t.Add("vp_sigma_px", &O::vp_sigma_px, "px", "sigma of the vanishing point's u (eq. 19's R)")
        .Greater(0)
        .Range(0, 100);
    t.Add("vp_virtual_distance_m", &O::vp_virtual_distance_m, "m",
          "distance of the virtual plane the VP landmark lies on (P1 Fig. 10)")
        .Range(10, 1e6);
    t.AddSection("vanishing_point", &O::vanishing_point, VanishingPointOptionsTable(),
                 "the vanishing-point detector (P1 section 2)", &VanishingPointOptions::Check);
    t.Add("use_door_plates", &O::use_door_plates, "",
          "observe the lateral camera's door plates (P1 eq. 20)");
    t.Add("plate_sigma_px", &O::plate_sigma_px, "px", "sigma_u of P1 eq. 25")
        .Greater(0)
        .Range(0, 100);
    t.Add("plate_height_m", &O::plate_height_m, "m",
          "nominal height of the plates' numbers (the plate state is planar, P1 eq. 11)")
        .Range(0, 10);
    t.Add("plate_height_tolerance_m", &O::plate_height_tolerance_m, "m",
          "a plate is initialised only when seen within this of plate_height_m (row and depth)")
        .Greater(0)
        .Range(0, 10);
    t.Add("min_readings", &O::min_readings, "",
          "accepted readings of a number before it may become a landmark")
        .Range(1, 100);
    t.Add("min_parallax_deg", &O::min_parallax_deg, "deg",
          "parallax of the two sightings a plate is triangulated from (delayed initialisation)")
        .Range(0.5, 90);
    t.Add("max_plate_range_m", &O::max_plate_range_m, "m",
          "a triangulated plate farther than this from the camera is refused")
        .Greater(0)
        .Range(0, 100);
    t.Add("pending_timeout_s", &O::pending_timeout_s, "s",
          "a number read but not initialised within this is forgotten (its clone removed)")
        .Greater(0)
        .Range(0, 3600);
    t.Add("models_dir", &O::models_dir, "",
          "folder of the trained detector models (docs/detectors.md); empty: the source tree's "
          "models/");
    t.AddSection("door_plates", &O::door_plates, DoorPlateOptionsTable(),
                 "door-plate detector and room-number reader (P1 section 3)",
                 &DoorPlateOptions::Check);
    t.Add("octomap", &O::octomap, "", "build the OctoMap from the front depth (P1 section 5)");
    t.AddSection("octomap_map", &O::octomap_map, OccupancyMapperOptionsTable(),
                 "the OctoMap's resolution, range and keyframes", &OccupancyMapperOptions::Check);
  });
}

const OptionTable<P3UpwardOptions>& P3UpwardOptionsTable() {
  return StaticOptionTable<P3UpwardOptions>([](OptionTable<P3UpwardOptions>& t) {
    using O = P3UpwardOptions;
    t.Add("k_m", &O::k_m, "m",
          "k of the wheel noise Q = diag(k |s_l|, k |s_r|); set it to robot.odometry.random_k_m")
        .Range(0, 0.1);
    t.Add("use_corners", &O::use_corners, "", "corner landmarks (P3: FAST; P2: Harris)");
    t.Add("use_lamps", &O::use_lamps, "", "circular lamp landmarks (P3 section II)");
    t.Add("use_doors", &O::use_doors, "",
          "open doors as landmarks of two column bearings (P3 section III, eq. 17)");
    t.Add("door_sigma_rad", &O::door_sigma_rad, "rad", "sigma of a door column's bearing")
        .Greater(0)
        .Range(0, 1);
    t.Add("min_height_m", &O::min_height_m, "m", "lowest landmark height of the prior (P3: 0)")
        .Range(-10, 100);
    t.Add("max_height_m", &O::max_height_m, "m", "highest landmark height of the prior (P3: 5)")
        .Range(-10, 100)
        .Note("> min_height_m");
    t.Add("min_above_camera_m", &O::min_above_camera_m, "m",
          "landmarks are at least this far above the camera (the prior's near end)")
        .Greater(0)
        .Range(0, 100);
    t.Add("corner_sigma_px", &O::corner_sigma_px, "px", "sigma of a corner's image position")
        .Greater(0)
        .Range(0, 100);
    t.Add("lamp_sigma_px", &O::lamp_sigma_px, "px", "sigma of a lamp centre's image position")
        .Greater(0)
        .Range(0, 100);
    t.Add("gate_chi2", &O::gate_chi2, "",
          "NIS gate of an association (chi-square at 2 dof; 9.21 = 99 %)")
        .Range(1, 1000);
    t.Add("search_radius_px", &O::search_radius_px, "px",
          "landmarks predicted within this of a detection are association candidates")
        .Greater(0)
        .Range(0, 1000);
    t.Add("min_correlation", &O::min_correlation, "",
          "corners: patch normalised cross-correlation needed to match")
        .Range(-1, 1);
    t.Add("min_polar_radius_px", &O::min_polar_radius_px, "px",
          "detections closer to the principal point are not used (theta ill-defined)")
        .Range(0, 1000);
    t.Add("min_ray_z", &O::min_ray_z, "",
          "a new landmark's ray must point within acos(this) of the vertical")
        .RangeOpenLow(0, 1);
    t.Add("new_landmark_clearance_px", &O::new_landmark_clearance_px, "px",
          "a new landmark starts only this far from every predicted landmark")
        .Range(0, 1000);
    t.Add("max_new_corners_per_frame", &O::max_new_corners_per_frame, "",
          "corner landmarks started per frame at most")
        .Range(0, 1000);
    t.Add("first_frame_corners", &O::first_frame_corners, "",
          "a frame that finds the map empty (the first) starts at least this many corners (0: "
          "as many as any frame)")
        .Range(0, 1000);
    t.Add("max_tracked_corners", &O::max_tracked_corners, "",
          "new corners start only while fewer corners than this were matched in the frame")
        .Range(0, 1000);
    t.Add("max_landmarks", &O::max_landmarks, "", "point landmarks in the state at most")
        .Range(1, 1500);
    t.Add("retire_after_s", &O::retire_after_s, "s",
          "with the state full, a new landmark replaces the corner matched longest ago if it is "
          "out of view and unmatched this long (never: a large value)")
        .Range(0, 1e6);
    t.Add("delete_after", &O::delete_after, "",
          "predictions in the image before a rarely matched landmark is deleted (P3 Fig. 16c)")
        .Range(1, 100000);
    t.Add("min_match_fraction", &O::min_match_fraction, "",
          "landmarks matched in fewer of their predictions are deleted")
        .Range(0, 1);
    t.AddSection("corners", &O::corners, CornerPatchOptionsTable(), "the corner detector",
                 &CornerPatchOptions::Check);
    t.AddSection("lamps", &O::lamps, CeilingLampOptionsTable(), "the lamp detector",
                 &CeilingLampOptions::Check);
    t.AddSection("doors", &O::doors, UpwardDoorOptionsTable(), "the door candidates",
                 &UpwardDoorOptions::Check);
    t.AddSection("door_verifier", &O::door_verifier, DoorVerifierOptionsTable(),
                 "the door candidates' particle filter and open-door test",
                 &DoorVerifierOptions::Check);
    t.AddSection("areas", &O::areas, DoorAreaOptionsTable(),
                 "the map divided into areas at the doors (P2 Fig. 12)", &DoorAreaOptions::Check);
  });
}

const OptionTable<DoorVerifierOptions>& DoorVerifierOptionsTable() {
  using O = DoorVerifierOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("particles", &O::particles, "", "samples per door candidate (P3: 200)").Range(10, 10000);
    t.AddEnum(
        "sensor_model", &O::sensor_model,
        {{"gaussian", DoorSensorModel::kGaussian}, {"triangular", DoorSensorModel::kTriangular}},
        "the particle filter's sensor model: gaussian (P3) or triangular (P2)");
    t.Add("bearing_error_rad", &O::bearing_error_rad, "rad",
          "theta error of a column's bearing: sigma, or the triangle's half-width")
        .Greater(0)
        .Range(0, 1);
    t.Add("elevation_error_rad", &O::elevation_error_rad, "rad",
          "alpha, beta errors of a column top's elevation")
        .Greater(0)
        .Range(0, 1);
    t.Add("min_top_height_m", &O::min_top_height_m, "m", "lowest column top of the prior")
        .Range(0, 100);
    t.Add("max_top_height_m", &O::max_top_height_m, "m", "highest column top of the prior")
        .Range(0, 100)
        .Note("> min_top_height_m");
    t.Add("min_door_top_m", &O::min_door_top_m, "m",
          "a converged candidate whose tops are lower is not a door")
        .Range(0, 100);
    t.Add("max_door_top_m", &O::max_door_top_m, "m", "nor one whose tops are higher")
        .Range(0, 100)
        .Note(">= min_door_top_m");
    t.Add("min_door_width_m", &O::min_door_width_m, "m",
          "a converged candidate whose columns are closer is not a door")
        .Range(0, 100);
    t.Add("max_door_width_m", &O::max_door_width_m, "m", "nor one whose columns are farther apart")
        .Range(0, 100)
        .Note(">= min_door_width_m");
    t.Add("min_median_bar_coverage", &O::min_median_bar_coverage, "",
          "a converged candidate whose bar covered less of the span between its columns in the "
          "median of its sightings is not a door")
        .Range(0, 1);
    t.Add("min_column_clearance_m", &O::min_column_clearance_m, "m",
          "a track with a column this close to where the robot has been is not a door")
        .Range(0, 100)
        .Note("< min_door_width_m / 2");
    t.Add("max_range_m", &O::max_range_m, "m", "columns drawn at most this far from the camera")
        .Greater(0)
        .Range(0, 1000);
    t.Add("roughening_m", &O::roughening_m, "m", "jitter of the samples after resampling")
        .Range(0, 10);
    t.Add("associate_rad", &O::associate_rad, "rad",
          "a candidate continues a track when each column lies within this of the interval of "
          "the track's samples' bearings (their central 95 %)")
        .Greater(0)
        .Range(0, 3.2);
    t.Add("converged_sigma_m", &O::converged_sigma_m, "m",
          "columns known to this (samples' standard deviation) are verified")
        .Greater(0)
        .Range(0, 100);
    t.Add("verify_baseline_m", &O::verify_baseline_m, "m",
          "camera travel between the plane's edge points and their comparison")
        .Greater(0)
        .Range(0, 100);
    t.Add("mhd_threshold_px", &O::mhd_threshold_px, "px",
          "Hausdorff distance of the prediction above which a candidate is open (P3 eq. 9)")
        .Greater(0)
        .Range(0, 10000);
    t.Add("min_leaf_depth_m", &O::min_leaf_depth_m, "m",
          "shallowest depth behind the columns' plane at which a closed surface is tried "
          "(negative: in front of it, a face flush with the edges paired; those depths can only "
          "close a candidate)")
        .Range(-1, 1);
    t.Add("max_leaf_depth_m", &O::max_leaf_depth_m, "m",
          "deepest depth behind the columns' plane at which a closed surface is tried (a leaf in "
          "the wall's thickness)")
        .Range(0, 1)
        .Note(">= min_leaf_depth_m");
    t.Add("leaf_depth_step_m", &O::leaf_depth_step_m, "m", "step between the leaf depths tried")
        .Greater(0)
        .Range(0, 1)
        .Note("at most 100 depths, one at or behind the columns");
    t.Add("opening_margin", &O::opening_margin, "",
          "fraction of the opening left out at each side (the frame's own edges)")
        .Range(0, 0.45);
    t.Add("min_edge_points", &O::min_edge_points, "", "fewer edge points: no decision yet")
        .Range(1, 100000);
    t.Add("sparse_max_view_angle_rad", &O::sparse_max_view_angle_rad, "rad",
          "a depth shared by fewer than min_edge_points (at least half) is ruled out, at twice "
          "the threshold, only when both views lie within this angle of the door's normal")
        .Range(0, 1.5708);
    t.Add("max_edge_points", &O::max_edge_points, "", "edge points kept on the plane at most")
        .Range(1, 1000000);
    t.Add("canny_low", &O::canny_low, "grey levels/px", "Canny's lower threshold").Range(0, 5000);
    t.Add("canny_high", &O::canny_high, "grey levels/px", "Canny's upper threshold")
        .Range(0, 5000)
        .Note(">= canny_low");
    t.Add("forget_after_frames", &O::forget_after_frames, "",
          "a track not seen for this many frames is dropped")
        .Range(1, 100000);
    t.Add("max_tracks", &O::max_tracks, "", "candidates followed at once at most").Range(1, 1000);
    t.Add("seed", &O::seed, "", "seed of the samples");
  });
}

// The mapping stages the pipelines hold as sections (slam/mapping/).

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
