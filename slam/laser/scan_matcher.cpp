#include "slam/laser/scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <ceres/ceres.h>
#include <ceres/cubic_interpolation.h>
#include <Eigen/Eigenvalues>

namespace corridorsim::slam::laser {
namespace {

// The grid as ceres::BiCubicInterpolator reads it: the correspondence cost 1 - p of each cell,
// the highest cost outside (Cartographer's GridArrayAdapter).
class GridAdapter {
 public:
  enum { DATA_DIMENSION = 1 };
  explicit GridAdapter(const ProbabilityGrid& grid) : grid_(grid) {}
  void GetValue(int row, int col, double* value) const {
    *value = grid_.CorrespondenceCost(row, col);
  }

 private:
  const ProbabilityGrid& grid_;
};

// One residual per scan point: w_occ / sqrt(K) * (1 - M_smooth(T_xi h_k)).
class OccupiedSpaceCost {
 public:
  OccupiedSpaceCost(const ProbabilityGrid& grid, const std::vector<Eigen::Vector2d>& points,
                    double weight)
      : grid_(grid),
        adapter_(grid),
        interpolator_(adapter_),
        points_(points),
        scale_(weight / std::sqrt(static_cast<double>(points.size()))) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    using std::cos;
    using std::sin;
    const T c = cos(pose[2]), s = sin(pose[2]);
    const double inverse_resolution = 1.0 / grid_.resolution_m();
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const Eigen::Vector2d& h = points_[k];
      const T x = c * h.x() - s * h.y() + pose[0];
      const T y = s * h.x() + c * h.y() + pose[1];
      // Cell centres at integer grid coordinates (ProbabilityGrid::GridCoordinates).
      const T col = (x - grid_.origin().x()) * inverse_resolution - 0.5;
      const T row = (y - grid_.origin().y()) * inverse_resolution - 0.5;
      interpolator_.Evaluate(row, col, &residual[k]);
      residual[k] = scale_ * residual[k];
    }
    return true;
  }

 private:
  const ProbabilityGrid& grid_;
  GridAdapter adapter_;
  ceres::BiCubicInterpolator<GridAdapter> interpolator_;
  const std::vector<Eigen::Vector2d>& points_;
  double scale_;
};

// The priors towards the prediction: w_t (t - t_pred), w_r (theta - theta_pred), the angle
// difference wrapped into (-pi, pi].
class PriorCost {
 public:
  PriorCost(const SE2& prediction, double translation_weight, double rotation_weight)
      : prediction_(prediction), wt_(translation_weight), wr_(rotation_weight) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    residual[0] = wt_ * (pose[0] - prediction_.x());
    residual[1] = wt_ * (pose[1] - prediction_.y());
    const T d = pose[2] - prediction_.yaw();
    residual[2] = wr_ * atan2(sin(d), cos(d));
    return true;
  }

 private:
  SE2 prediction_;
  double wt_, wr_;
};

}  // namespace

SE2 CorrelativeSearch(const ProbabilityGrid& grid, const std::vector<Eigen::Vector2d>& points,
                      const SE2& prediction, const CorrelativeSearchOptions& options) {
  if (points.empty() || grid.empty() || options.linear_window_m <= 0) return prediction;
  const double res = grid.resolution_m();
  double max_range = 0.0;
  for (const Eigen::Vector2d& p : points) max_range = std::max(max_range, p.norm());
  // The angle that moves the farthest point by one cell (Cartographer's angular step).
  const double step =
      max_range > res ? std::acos(1.0 - res * res / (2.0 * max_range * max_range)) : 0.1;
  const int angles = static_cast<int>(std::ceil(options.angular_window_rad / step));
  const int cells = static_cast<int>(std::ceil(options.linear_window_m / res));
  const double n = static_cast<double>(points.size());
  double best_score = -1.0;
  SE2 best = prediction;
  std::vector<Eigen::Vector2d> rotated(points.size());
  for (int a = -angles; a <= angles; ++a) {
    const double dtheta = a * step;
    const SE2 turned(prediction.translation(), prediction.yaw() + dtheta);
    for (std::size_t k = 0; k < points.size(); ++k) rotated[k] = turned * points[k];
    const double angular_penalty = std::pow(options.rotation_weight * dtheta, 2);
    for (int i = -cells; i <= cells; ++i) {
      for (int j = -cells; j <= cells; ++j) {
        const Eigen::Vector2d shift(i * res, j * res);
        double sum = 0.0;
        for (const Eigen::Vector2d& p : rotated) sum += grid.ProbabilityAt(p + shift);
        const double score =
            sum / n *
            std::exp(-std::pow(options.translation_weight * shift.norm(), 2) - angular_penalty);
        if (score > best_score) {  // strictly: ties keep the earlier (deterministic) pose
          best_score = score;
          best = SE2(prediction.translation() + shift, turned.yaw());
        }
      }
    }
  }
  return best;
}

ScanMatchResult MatchScan(const ProbabilityGrid& grid, const std::vector<Eigen::Vector2d>& points,
                          const SE2& start, const SE2& prediction,
                          const ScanMatcherOptions& options) {
  ScanMatchResult result;
  result.world_from_robot = start;
  if (points.empty() || grid.empty()) return result;
  double pose[3] = {start.x(), start.y(), start.yaw()};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<OccupiedSpaceCost, ceres::DYNAMIC, 3>(
                               new OccupiedSpaceCost(grid, points, options.occupied_space_weight),
                               static_cast<int>(points.size())),
                           nullptr, pose);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorCost, 3, 3>(new PriorCost(
                               prediction, options.translation_weight, options.rotation_weight)),
                           nullptr, pose);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;  // determinism (and the run's one core)
  solver.minimizer_progress_to_stdout = false;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.usable = summary.IsSolutionUsable() && std::isfinite(pose[0]) && std::isfinite(pose[1]) &&
                  std::isfinite(pose[2]);
  if (result.usable) result.world_from_robot = SE2(pose[0], pose[1], pose[2]);
  return result;
}

std::vector<Eigen::Vector2d> ScanNormals(const std::vector<Eigen::Vector2d>& points,
                                         int half_window, double neighbourhood_m) {
  const int n = static_cast<int>(points.size());
  std::vector<Eigen::Vector2d> normals(points.size(), Eigen::Vector2d::Zero());
  const double r2 = neighbourhood_m * neighbourhood_m;
  for (int k = 0; k < n; ++k) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d outer = Eigen::Matrix2d::Zero();
    int count = 0;
    for (int j = std::max(0, k - half_window); j <= std::min(n - 1, k + half_window); ++j) {
      if ((points[j] - points[k]).squaredNorm() > r2) continue;
      sum += points[j];
      outer += points[j] * points[j].transpose();
      ++count;
    }
    if (count < 3) continue;
    const Eigen::Vector2d mean = sum / count;
    const Eigen::Matrix2d scatter = outer / count - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
    const Eigen::Vector2d values = eigen.eigenvalues();  // ascending
    if (!(values[1] > 0.0) || values[0] > 0.01 * values[1]) continue;
    normals[k] = eigen.eigenvectors().col(0).normalized();
  }
  return normals;
}

Eigen::Matrix3d ScanInformation(const std::vector<Eigen::Vector2d>& points,
                                const std::vector<Eigen::Vector2d>& normals,
                                const SE2& world_from_robot, double sigma_m) {
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  const Eigen::Matrix2d rotation = world_from_robot.rotation();
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (normals[k].isZero()) continue;
    const Eigen::Vector2d n = rotation * normals[k];
    const Eigen::Vector2d h = rotation * points[k];
    // d(R h)/d theta = (-h_y, h_x) for the rotated point h.
    const Eigen::Vector3d J(n.x(), n.y(), n.x() * -h.y() + n.y() * h.x());
    information += J * J.transpose();
  }
  return information / (sigma_m * sigma_m);
}

}  // namespace corridorsim::slam::laser
