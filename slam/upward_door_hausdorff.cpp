// The open-or-closed test of a door candidate whose columns are known (P3 section III-B, Fig. 7,
// eqs. 5-9, with the leaf depths of the wall's thickness; slam/upward_door_verifier.h says how):
// the edge points inside the opening, the prediction of the plane's points in a later view and
// the Hausdorff distance between prediction and observation.
#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "slam/upward_door_verifier.h"
#include "slam/upward_door_verifier_detail.h"

namespace corridorsim::slam {
namespace {

using door_detail::InFront;
using door_detail::kMaxColumnShift;
using door_detail::LeafDepths;

// Mean over `from` of the distance to the nearest point of `to` (P3 eq. 9's h_mod), by the
// distance transform of `to` drawn in the box `roi` of the image that holds both sets (the
// nearest point of `to` lies in it, so the distances are those of the whole image).
double ModifiedHausdorff(const std::vector<Eigen::Vector2d>& from,
                         const std::vector<Eigen::Vector2d>& to, const cv::Rect& roi) {
  if (from.empty()) return 0.0;
  cv::Mat image(roi.size(), CV_8UC1, cv::Scalar(255));
  const auto cell = [&](const Eigen::Vector2d& p) {
    return cv::Point(std::clamp(int(std::lround(p.x())) - roi.x, 0, roi.width - 1),
                     std::clamp(int(std::lround(p.y())) - roi.y, 0, roi.height - 1));
  };
  for (const Eigen::Vector2d& p : to) image.at<std::uint8_t>(cell(p)) = 0;
  cv::Mat distance;
  cv::distanceTransform(image, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  double sum = 0.0;
  for (const Eigen::Vector2d& p : from) sum += distance.at<float>(cell(p));
  return sum / double(from.size());
}

// H(A, B) = max(h_mod(A, B), h_mod(B, A)) (P3 eq. 9) of two sets of pixels of an image of `size`.
double Hausdorff(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                 const cv::Size& size) {
  double min_u = size.width, min_v = size.height, max_u = 0.0, max_v = 0.0;
  for (const auto* set : {&a, &b}) {
    for (const Eigen::Vector2d& p : *set) {
      min_u = std::min(min_u, p.x());
      min_v = std::min(min_v, p.y());
      max_u = std::max(max_u, p.x());
      max_v = std::max(max_v, p.y());
    }
  }
  const int u0 = std::clamp(int(std::floor(min_u)) - 1, 0, size.width - 1);
  const int v0 = std::clamp(int(std::floor(min_v)) - 1, 0, size.height - 1);
  const int u1 = std::clamp(int(std::ceil(max_u)) + 1, u0, size.width - 1);
  const int v1 = std::clamp(int(std::ceil(max_v)) + 1, v0, size.height - 1);
  const cv::Rect roi(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
  return std::max(ModifiedHausdorff(a, b, roi), ModifiedHausdorff(b, a, roi));
}

// The opening of a door hypothesis on the floor plan: column a at d1, column b at d1 + along,
// the tops at `height`; `normal` (unit) points from the columns' plane to the side the first
// view saw it from (the corridor). The plane `depth` behind it: normal . (x - d1) = -depth.
struct Opening {
  Eigen::Vector2d d1 = Eigen::Vector2d::Zero();
  Eigen::Vector2d along = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  double height = 0.0;
  double margin = 0.0;  // of the opening left out at each side and at the top

  // The ray c + t r meets the plane `depth` behind the columns at t (P3 eq. 8); NaN when
  // parallel to it.
  double Meet(const Eigen::Vector3d& c, const Eigen::Vector3d& r, double depth) const {
    const double denominator = normal.dot(r.head<2>());
    if (std::abs(denominator) < 1e-9) return std::numeric_limits<double>::quiet_NaN();
    return -(normal.dot(c.head<2>() - d1) + depth) / denominator;
  }
  // Whether a point lies inside the opening (less the margins) seen along the plane's normal.
  bool Inside(const Eigen::Vector3d& p) const {
    const double s = (p.head<2>() - d1).dot(along) / along.squaredNorm();
    return s >= margin && s <= 1.0 - margin && p.z() >= 0.0 && p.z() <= height * (1.0 - margin);
  }
  // Whether a camera at c sees the point p (behind the columns, or a little in front of them)
  // through the opening: the line from c to p crosses the columns' plane inside it.
  bool SeenThrough(const Eigen::Vector3d& c, const Eigen::Vector3d& p) const {
    const double t = Meet(c, p - c, 0.0);
    return t > 0.0 && Inside(c + t * (p - c));
  }
  // The angle between the normal and the line from the opening's middle to a camera at c, on
  // the floor plan (0: straight in front of the door, pi/2: along its wall).
  double ViewAngle(const Eigen::Vector3d& c) const {
    const Eigen::Vector2d to_camera = c.head<2>() - (d1 + 0.5 * along);
    const double side = std::abs(to_camera.dot(along)) / along.norm();
    return std::atan2(side, std::abs(normal.dot(to_camera)));
  }
};
}  // namespace

void UpwardDoorVerifier::EdgesInOpening(const cv::Mat& edges, const SE3& world_from_camera,
                                        const Eigen::Vector4d& columns, double height,
                                        std::vector<Eigen::Vector2d>* pixels,
                                        std::vector<Eigen::Vector3d>* points) const {
  pixels->clear();
  points->clear();
  const Eigen::Vector3d c = world_from_camera.translation();
  const Eigen::Vector2d d1 = columns.head<2>(), d2 = columns.tail<2>();
  const Eigen::Vector2d along = d2 - d1;
  const double width = along.norm();
  if (!(width > 1e-3) || !(height > 0.0)) return;
  // P3 eq. 5: the plane's normal, the columns' direction turned by 90 degrees.
  const Eigen::Vector2d normal(-along.y() / width, along.x() / width);
  const double m = options_.opening_margin;
  // The opening's image: the bounding box of its outline's points that project.
  const Eigen::Matrix3d camera_from_world = world_from_camera.rotation().transpose();
  double min_u = edges.cols, min_v = edges.rows, max_u = -1, max_v = -1;
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) {
      const double s = m + (1.0 - 2.0 * m) * i / 10.0, z = height * (1.0 - m) * j / 10.0;
      const Eigen::Vector2d xy = d1 + s * along;
      const std::optional<Eigen::Vector2d> px =
          model_.Project(camera_from_world * (Eigen::Vector3d(xy.x(), xy.y(), z) - c));
      if (!px) continue;
      min_u = std::min(min_u, px->x());
      min_v = std::min(min_v, px->y());
      max_u = std::max(max_u, px->x());
      max_v = std::max(max_v, px->y());
    }
  }
  const int u0 = std::max(0, int(std::floor(min_u))), v0 = std::max(0, int(std::floor(min_v)));
  const int u1 = std::min(edges.cols - 1, int(std::ceil(max_u)));
  const int v1 = std::min(edges.rows - 1, int(std::ceil(max_v)));
  const Eigen::Matrix3d world_from_camera_r = world_from_camera.rotation();
  for (int v = v0; v <= v1; ++v) {
    const std::uint8_t* row = edges.ptr<std::uint8_t>(v);
    for (int u = u0; u <= u1; ++u) {
      if (!row[u]) continue;
      const Eigen::Vector2d px(u, v);
      const Eigen::Vector3d ray = world_from_camera_r * model_.Unproject(px);
      // P3 eq. 8: t = -(n . (c - D1)) / (n . d).
      const double denominator = normal.x() * ray.x() + normal.y() * ray.y();
      if (std::abs(denominator) < 1e-9) continue;
      const double t =
          -(normal.x() * (c.x() - d1.x()) + normal.y() * (c.y() - d1.y())) / denominator;
      if (!(t > 0.0)) continue;
      const Eigen::Vector3d p = c + t * ray;
      const double s = (p.head<2>() - d1).dot(along) / (width * width);
      if (s < m || s > 1.0 - m || p.z() < 0.0 || p.z() > height * (1.0 - m)) continue;
      pixels->push_back(px);
      points->push_back(p);
    }
  }
}

bool UpwardDoorVerifier::Test(Track* track, const cv::Mat& edges,
                              const SE3& world_from_camera) const {
  const Eigen::Vector3d c = world_from_camera.translation();
  const Eigen::Vector3d c0 = track->plane_view.translation();
  if ((c.head<2>() - c0.head<2>()).norm() < options_.verify_baseline_m) return false;
  // Free space: a column where the robot has been is no door's.
  const Eigen::Vector4d columns = Report(*track).columns;
  for (const Eigen::Vector2d& xy : path_) {
    if ((columns.head<2>() - xy).norm() < options_.min_column_clearance_m ||
        (columns.tail<2>() - xy).norm() < options_.min_column_clearance_m) {
      track->state = DoorTrackState::kClosed;
      return true;
    }
  }
  // The columns tested are the ones the plane was taken for: a track whose samples have moved
  // off them (a wrong pairing continuing it; later sightings refine them by a few centimetres)
  // or spread again is estimated again; one no longer of a door's size is not a door.
  const DoorTrackReport now = Report(*track);
  if ((now.columns - track->plane_columns).cwiseAbs().maxCoeff() >
          kMaxColumnShift * options_.converged_sigma_m ||
      std::sqrt(now.covariance.diagonal().maxCoeff()) > 2.0 * options_.converged_sigma_m) {
    Restart(track);
    return false;
  }
  if (!DoorSized(*track, now.columns, TopHeight(*track))) {
    track->state = DoorTrackState::kClosed;
    return true;
  }
  // The opening the plane's rays were taken through, its normal toward the first view.
  Opening opening;
  opening.d1 = track->plane_columns.head<2>();
  opening.along = track->plane_columns.tail<2>() - opening.d1;
  if (!(opening.along.norm() > 1e-3)) return false;
  opening.normal = Eigen::Vector2d(-opening.along.y(), opening.along.x()).normalized();
  if (opening.normal.dot(c0.head<2>() - opening.d1) < 0.0) opening.normal = -opening.normal;
  opening.height = track->plane_height;
  opening.margin = options_.opening_margin;

  // The edge pixels now inside the opening, and their rays.
  std::vector<Eigen::Vector2d> observed;
  std::vector<Eigen::Vector3d> on_plane;
  EdgesInOpening(edges, world_from_camera, track->plane_columns, track->plane_height, &observed,
                 &on_plane);
  const Eigen::Matrix3d camera_from_world = world_from_camera.rotation().transpose();
  const Eigen::Matrix3d first_from_world = track->plane_view.rotation().transpose();
  const cv::Size size(edges.cols, edges.rows);
  const auto in_first_image = [&](const Eigen::Vector3d& p) {
    const std::optional<Eigen::Vector2d> px = model_.Project(first_from_world * (p - c0));
    return px && model_.IsInImage(*px);
  };

  // P3 eq. 9 between the prediction A and the observation B, at each leaf depth, over what both
  // views saw through the opening. A depth at which A and B agree makes the door closed; one
  // at which they do not is ruled out for the rest of the test.
  const std::size_t depths = LeafDepths(options_);
  if (track->ruled_out_px.size() != depths) {
    track->ruled_out_px.assign(depths, std::numeric_limits<double>::quiet_NaN());
  }
  const bool sparse_may_rule_out = opening.ViewAngle(c0) <= options_.sparse_max_view_angle_rad &&
                                   opening.ViewAngle(c) <= options_.sparse_max_view_angle_rad;
  std::vector<Eigen::Vector2d> predicted, seen;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_k = 0;
  for (std::size_t k = 0; k < depths; ++k) {
    const double depth = options_.min_leaf_depth_m + double(k) * options_.leaf_depth_step_m;
    predicted.clear();
    seen.clear();
    for (const Eigen::Vector3d& ray : track->plane_rays) {
      const double t = opening.Meet(c0, ray, depth);
      if (!(t > 0.0)) continue;
      const Eigen::Vector3d p = c0 + t * ray;
      if (!opening.Inside(p) || !opening.SeenThrough(c, p)) continue;
      const std::optional<Eigen::Vector2d> px = model_.Project(camera_from_world * (p - c));
      if (px && model_.IsInImage(*px)) predicted.push_back(*px);
    }
    for (std::size_t i = 0; i < observed.size(); ++i) {
      const Eigen::Vector3d ray = on_plane[i] - c;
      const double t = opening.Meet(c, ray, depth);
      if (!(t > 0.0)) continue;
      const Eigen::Vector3d p = c + t * ray;
      if (opening.Inside(p) && opening.SeenThrough(c0, p) && in_first_image(p)) {
        seen.push_back(observed[i]);
      }
    }
    // Too little seen by both views: this depth is neither confirmed nor ruled out now. H of
    // fewer points is noisier (closed doors seen with 37-54 points gave 5-7 px): with half
    // min_edge_points a depth can only be ruled out, at twice the threshold, and only from views
    // near the door's normal (from far off the jambs fill the opening). A depth in front of
    // the columns (a face flush with the edges paired) can close a candidate, never hold one
    // undecided: from the oblique view the plane was taken in, little of a plane in front falls
    // inside the opening, and the door would wait on it until it is out of view.
    const int shared = int(std::min(predicted.size(), seen.size()));
    if (2 * shared < options_.min_edge_points) continue;
    if (InFront(depth) && shared < options_.min_edge_points) continue;
    if (!sparse_may_rule_out && shared < options_.min_edge_points) continue;
    const double h = Hausdorff(predicted, seen, size);
    if (shared < options_.min_edge_points) {
      if (h > 2.0 * options_.mhd_threshold_px && !(h >= track->ruled_out_px[k])) {
        track->ruled_out_px[k] = h;
      }
      continue;
    }
    if (h < best) {
      best = h;
      best_k = k;
    }
    if (h > options_.mhd_threshold_px && !(h >= track->ruled_out_px[k])) {
      track->ruled_out_px[k] = h;
    }
  }
  if (best <= options_.mhd_threshold_px) {
    // A leaf at this depth explains what both views saw: closed.
    track->hausdorff_px = best;
    track->leaf_depth_m = options_.min_leaf_depth_m + double(best_k) * options_.leaf_depth_step_m;
    track->state = DoorTrackState::kClosed;
    return true;
  }
  // Open once every depth from the columns' plane back has been ruled out (in this frame or an
  // earlier one of the test): H is then the least of the distances that ruled them out.
  double least = std::numeric_limits<double>::infinity();
  std::size_t least_k = 0;
  for (std::size_t k = 0; k < depths; ++k) {
    if (InFront(options_.min_leaf_depth_m + double(k) * options_.leaf_depth_step_m)) continue;
    if (std::isnan(track->ruled_out_px[k])) return false;
    if (track->ruled_out_px[k] < least) {
      least = track->ruled_out_px[k];
      least_k = k;
    }
  }
  track->hausdorff_px = least;
  track->leaf_depth_m = options_.min_leaf_depth_m + double(least_k) * options_.leaf_depth_step_m;
  track->state = DoorTrackState::kOpen;
  return true;
}

}  // namespace corridorsim::slam
