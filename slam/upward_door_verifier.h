#pragma once
// P3 section III-B (P2 section 4): door candidates of the upward camera followed over frames,
// their column positions estimated by a particle filter, and each verified as open or closed.
//
// Particle filter (P3 Fig. 8-9). A candidate is stationary: no motion model, only the sensor
// model's weights. Each of `particles` samples (P3: 200) is a door hypothesis
// (x_D1, y_D1, x_D2, y_D2, h): the columns on the floor plan and the height h of their tops.
// At the first sighting the samples are drawn along the rays to the two column tops over the
// height prior (top heights from min_top_height_m to max_top_height_m, ranges below
// max_range_m), with a common h. Each later sighting weighs them by the errors of the columns'
// bearings (theta error, P3 Fig. 8a) and of the tops' elevations (alpha, beta errors, Fig. 8c):
// Gaussian (P3) or triangular (P2, zero beyond the maximal error). They are resampled
// (systematic) when the effective sample size falls below half, then roughened.
//
// Verification (P3 Fig. 7, eqs. 5-9). Once the columns are known to converged_sigma_m, the
// candidate is assumed closed: a vertical plane through the two columns (eqs. 5-6) holds
// everything seen inside it. The Canny edge points inside the opening are projected onto that
// plane along their rays (eqs. 7-8, through the calibrated lens instead of the pinhole's
// (u, v, f)). After the camera has moved verify_baseline_m, the points are projected into the
// new image (the prediction A) and compared with the edge points now seen inside the opening
// (B) by the Hausdorff distance built of modified Hausdorff distances (eq. 9),
//   H(A, B) = max(h_mod(A, B), h_mod(B, A)),  h_mod(A, B) = mean over a of min over b |a - b|.
// A closed door (a leaf, a cabinet, a bookshelf, a wall) matches its prediction; through an open
// door the room beyond moves with parallax: H above mhd_threshold_px is an open door.
// Beyond P3, a closed door's leaf stands in the wall's thickness, behind the columns' faces that
// the filter finds (in the shipped worlds 0.085 m behind), and the wall's jambs hide a strip of
// it at one side or the other as the camera passes: seen from either side of the door the leaf
// moves against the plane through the columns as the room behind an open door does (tens of
// pixels), and the jamb seen from one side is not there from the other. A face flush with the
// edges the detector pairs (a bookshelf's or a cabinet's front) stands in front of the columns
// the filter finds, by as much. So the plane is tried at the depths from min_leaf_depth_m (in
// front of the columns) to max_leaf_depth_m behind them (every leaf_depth_step_m), and at each
// only what both views saw of it through the opening is
// compared: a point of A or B counts when the line from each camera to it crosses the columns'
// plane inside the opening. H is the least over the depths; the room behind an open door is
// metres behind its columns, and no depth of the wall's thickness explains it. A depth is ruled
// out by a frame in which both sets have min_edge_points and H is above the threshold; the door
// is open once every depth from the columns' plane back is ruled out (over one or more frames),
// closed as soon as one depth explains both views, undecided while a depth behind the plane has
// not been seen well enough by both (a depth in front can close a door, never hold it: seen from
// the oblique view the plane was taken in, little of it falls inside the opening).
// Ruling a depth out takes min_edge_points in both sets, or half of them at twice the threshold
// (H of fewer points is noisier) from views both within sparse_max_view_angle_rad of the door's
// normal. Once the columns are known, a sighting no sample explains is
// an outlier (ignored); at each test the samples must still put the columns within
// 4 converged_sigma_m of where they were when the plane was taken, spread below 2, or the track
// is estimated again; and the door's size and bar coverage are checked again.
//
// Deterministic: the samples come from a RandomStream seeded by `seed`.

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "common/random.h"
#include "slam/features/upward_doors.h"

namespace corridorsim::slam {

enum class DoorSensorModel { kGaussian, kTriangular };

struct DoorVerifierOptions {
  int particles = 200;  // P3
  DoorSensorModel sensor_model = DoorSensorModel::kGaussian;
  double bearing_error_rad = 0.03;    // theta error: sigma (Gaussian) or half-width (triangular)
  double elevation_error_rad = 0.06;  // alpha, beta errors of the tops' elevation
  double min_top_height_m = 1.0;      // height prior of the columns' tops
  double max_top_height_m = 5.0;
  // What a door is (beyond P3, against furniture and mixed pairs of columns): standard single
  // doors are 2.0-2.1 m high and 0.7-1.0 m wide in the clear, their column lines a frame's
  // width (about 0.1 m) farther apart; a converged candidate outside these bounds is rejected as
  // not a door. The widest bound leaves room for the estimate's spread (0.89-1.05 m for the
  // shipped worlds' 0.98 m) and rejects a door's column paired with the wall of the room seen
  // through it (1.18-1.39 m; docs/p3.md). Worlds with wider doors (world.doors.width_m) need it
  // raised.
  double min_door_top_m = 1.9;
  double max_door_top_m = 2.4;
  double min_door_width_m = 0.7;
  double max_door_width_m = 1.15;
  // A door's top bar spans it from column to column. A pair of two different things (a door's
  // column and a poster's or a bookshelf's side) has a "bar" only where one of them has, which
  // the candidates' min_bar_coverage lets through in single frames: a converged candidate whose
  // bar covered less than this of the span in the median of its sightings is not a door.
  double min_median_bar_coverage = 0.9;
  // Free space: a door's columns stand beside the robot's path, never on it. A track with a
  // column within this of a position the robot has been at (the last kPathPositions frames) is
  // not a door (a pairing of lines across the corridor). Below half the narrowest door
  // (min_door_width_m), so a robot driving through a doorway's middle keeps it.
  double min_column_clearance_m = 0.3;
  double max_range_m = 8.0;    // columns farther from the camera are not drawn
  double roughening_m = 0.01;  // jitter after resampling
  // A candidate continues a track when each column lies within this of the interval holding the
  // central 95 % of the track's samples' bearings of that column.
  double associate_rad = 0.08;
  double converged_sigma_m = 0.05;  // column positions known to this: verify
  double verify_baseline_m = 0.3;   // camera travel between the plane's points and the test
  double mhd_threshold_px = 5.0;    // H(A, B) above it: open (P3 eq. 9's threshold)
  // Depths behind the columns' plane at which a closed surface may stand (ours; negative: in
  // front): the filter's columns are 0.04-0.09 m behind the face whose edges the detector pairs
  // (docs/p3.md), and the shipped worlds' leaves, 0.085 m behind the frame's face, up to 0.05 m
  // behind. In front, a piece of furniture against the wall: the edges paired may be its back
  // ones, at the wall, with its front a furniture's depth in front of them (the shipped
  // cabinets are 0.45 m deep, bookshelves 0.35 m; p3_doors seed 9's cabinet was paired 0.12 and
  // 0.32 m behind its front), so the depths in front reach 0.5 m. Every depth behind costs
  // recall: each is a chance for an open door's frame and jambs to explain both views, and the
  // deeper the plane, the less of it two oblique views share. A depth in front can only close a
  // candidate (an open door has nothing in front of its columns for both views to agree on).
  double min_leaf_depth_m = -0.5;
  double max_leaf_depth_m = 0.1;
  double leaf_depth_step_m = 0.025;
  double opening_margin = 0.15;  // of the opening left out at each side (the frame's edges)
  int min_edge_points = 80;      // fewer in A or B: no decision in this frame
  // A depth seen by fewer than min_edge_points (at least half) is ruled out at twice the
  // threshold only when both views lie within this angle of the door's normal (ours): from
  // farther off, the jambs fill the opening, and a closed door's few points disagree at every
  // depth (p3_lamps.yaml seed 11: 57-71 points from views 53-57 deg off, H 16-20 px).
  double sparse_max_view_angle_rad = 0.785;
  int max_edge_points = 3000;  // points kept on the plane at most
  double canny_low = 50.0;
  double canny_high = 150.0;
  int forget_after_frames = 15;  // a track not seen for this many frames is dropped
  int max_tracks = 12;
  std::uint64_t seed = 0;
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<DoorVerifierOptions>& DoorVerifierOptionsTable();

enum class DoorTrackState { kEstimating, kVerifying, kOpen, kClosed };

/// A door hypothesis of the particle filter: (x_D1, y_D1, x_D2, y_D2, h).
using DoorParticle = Eigen::Matrix<double, 5, 1>;

/// One candidate of a frame as its track stands after the frame.
struct DoorTrackReport {
  int track_id = 0;
  DoorTrackState state = DoorTrackState::kEstimating;
  bool decided_now = false;                           // open or closed was decided in this frame
  Eigen::Vector4d columns = Eigen::Vector4d::Zero();  // the particles' weighted mean
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Identity();
  Eigen::Vector2d range_sigma_m = Eigen::Vector2d::Zero();      // of each column from the camera
  Eigen::Vector2d bearing_sigma_rad = Eigen::Vector2d::Zero();  // of each column's bearing
  double hausdorff_px = 0.0;            // H(A, B) of the decision (NaN before)
  double leaf_depth_m = 0.0;            // the depth behind the columns of that least H (NaN before)
  std::vector<DoorParticle> particles;  // the cloud at the decision (decided_now only)
};

/// The robot-frame bearing (from the camera centre) of a pixel's ray and its elevation above
/// the camera's horizontal plane; nullopt for a ray pointing down.
struct ColumnSighting {
  double bearing_rad = 0.0;
  double elevation_rad = 0.0;
};
std::optional<ColumnSighting> SightColumnTop(const Eigen::Vector2d& pixel, const CameraModel& model,
                                             const SE3& robot_from_camera);

class UpwardDoorVerifier {
 public:
  UpwardDoorVerifier(const DoorVerifierOptions& options, const CameraModel& model,
                     const SE3& robot_from_camera);

  /// One frame: the detector's candidates still unexplained (not matched to a registered door),
  /// the grey image, the robot pose estimate. A report per candidate, or nullopt for one not
  /// tracked (no sighting, or max_tracks reached). A track reports kOpen once, decided_now, and
  /// is then dropped (the SLAM holds it as a landmark from there).
  std::vector<std::optional<DoorTrackReport>> Process(
      const std::vector<UpwardDoorCandidate>& candidates, const cv::Mat& grey, const SE2& pose);

  /// The tracks that Process decided open in its last frame without a candidate of theirs in it
  /// (kOpen, decided_now, with their particles). A track whose columns are known (kVerifying) is
  /// tested in every frame once the camera has moved verify_baseline_m, whether or not the
  /// detector paired its columns again: a door passed abeam often gives no candidate in the last
  /// frames it is seen, and the test needs only the opening's edges, not the pairing.
  const std::vector<DoorTrackReport>& opened_without_candidate() const {
    return opened_without_candidate_;
  }

  int tracks() const { return int(tracks_.size()); }

 private:
  struct Track {
    int id = 0;
    DoorTrackState state = DoorTrackState::kEstimating;
    std::vector<DoorParticle> particles;
    std::vector<double> weights;
    int last_frame = 0;
    // The rays (world) of the edge pixels in the opening and the view they were seen from.
    std::vector<Eigen::Vector3d> plane_rays;
    SE3 plane_view;
    Eigen::Vector4d plane_columns = Eigen::Vector4d::Zero();
    double plane_height = 0.0;
    double hausdorff_px = 0.0;
    double leaf_depth_m = 0.0;
    // Per leaf depth: the least H that ruled it out so far in the test (NaN: not yet).
    std::vector<double> ruled_out_px;
    // The bar coverage of the track's candidates, the last kMaxSightings of them.
    std::vector<double> bar_coverages;
  };
  struct Sighting;
  static constexpr std::size_t kMaxSightings = 200;

  bool Initialise(Track* track, const Sighting& s, const SE3& world_from_camera);
  void Weigh(Track* track, const Sighting& s, const SE3& world_from_camera);
  DoorTrackReport Report(const Track& track) const;
  // The weighted mean height of the samples' tops.
  static double TopHeight(const Track& track);
  // Whether converged columns and tops are a door's (the size bounds, the bar's median
  // coverage).
  bool DoorSized(const Track& track, const Eigen::Vector4d& columns, double height) const;
  // Back to kEstimating, the plane and the test's results dropped.
  static void Restart(Track* track);
  // Each column's range and bearing from the camera centre c: their spread over the samples,
  // about report->columns (Report's mean, set before).
  void Spread(const Track& track, const Eigen::Vector3d& c, DoorTrackReport* report) const;
  // P3 eq. 9 on a kVerifying track once the camera has moved verify_baseline_m from where the
  // plane's points were seen, at each leaf depth: the track becomes kOpen or kClosed; false
  // while undecided.
  bool Test(Track* track, const cv::Mat& edges, const SE3& world_from_camera) const;
  // Edge pixels whose rays meet the plane of (columns, height) inside the opening; with their
  // points on the plane.
  void EdgesInOpening(const cv::Mat& edges, const SE3& world_from_camera,
                      const Eigen::Vector4d& columns, double height,
                      std::vector<Eigen::Vector2d>* pixels,
                      std::vector<Eigen::Vector3d>* points) const;

  DoorVerifierOptions options_;
  CameraModel model_;
  SE3 robot_from_camera_;
  RandomStream random_;
  std::vector<Track> tracks_;
  // The robot's positions of the last kPathPositions frames (free space for the columns' test).
  static constexpr std::size_t kPathPositions = 1000;
  std::deque<Eigen::Vector2d> path_;
  std::vector<DoorTrackReport> opened_without_candidate_;
  int next_id_ = 0;
  int frame_ = 0;
};

}  // namespace corridorsim::slam
