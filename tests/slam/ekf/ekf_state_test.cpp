// Tests slam/ekf/ekf_state.cpp: the block-sparse update, prediction and augmentation against the
// textbook dense EKF (P1 eqs. 14-16, 21-24, 26-27), removal, gating and rejection, angle
// wrapping, and the filter's consistency (NEES) on a simulated range-bearing SLAM run.

#include "slam/ekf/ekf_state.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <catch2/catch.hpp>

#include "common/pose.h"
#include "common/random.h"
#include "slam/ekf/measurement_models.h"
#include "tests/support/planar_motion.h"
#include "tests/support/tolerances.h"

namespace corridorsim::slam::ekf {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;
// The block-sparse EKF against the dense textbook formulas on the same numbers: both are exact,
// only rounding (a few hundred flops per entry) separates them.
constexpr double kDenseEkfTol = 1e-9;

MatrixXd RandomMatrix(RandomStream& rng, int rows, int cols) {
  MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) m(i, j) = rng.Uniform(-1.0, 1.0);
  }
  return m;
}

// A well-conditioned random covariance: B B^T / k + 0.1 I.
MatrixXd RandomCovariance(RandomStream& rng, int size) {
  const MatrixXd b = RandomMatrix(rng, size, size);
  return b * b.transpose() / size + 0.1 * MatrixXd::Identity(size, size);
}

// A state of the robot and five correlated blocks (sizes 2, 3, 2, 1, 2; the 3-block's last
// component an angle), each augmented from the robot and the block before it.
struct RandomState {
  EkfState state;
  std::vector<BlockId> landmarks;
};

RandomState MakeRandomState(RandomStream& rng) {
  const Eigen::Vector3d pose(rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-1, 1));
  RandomState s{EkfState(pose, RandomCovariance(rng, 3)), {}};
  const int sizes[] = {2, 3, 2, 1, 2};
  for (int size : sizes) {
    Augmentation a;
    a.value = RandomMatrix(rng, size, 1);
    if (size == 3) a.angle_components = {2};
    a.blocks = {EkfState::robot()};
    int cols = 3;
    if (!s.landmarks.empty()) {
      a.blocks.push_back(s.landmarks.back());
      cols += s.state.BlockSize(s.landmarks.back());
    }
    a.d_value_d_blocks = RandomMatrix(rng, size, cols);
    a.d_value_d_measurement = RandomMatrix(rng, size, size);
    a.measurement_noise = RandomCovariance(rng, size);
    s.landmarks.push_back(s.state.Augment(a));
  }
  return s;
}

// The dense H (m x n) of a measurement over some blocks.
MatrixXd DenseJacobian(const EkfState& state, const Measurement& z) {
  MatrixXd h = MatrixXd::Zero(z.jacobian.rows(), state.dim());
  int column = 0;
  for (BlockId id : z.blocks) {
    const int size = state.BlockSize(id);
    h.middleCols(state.BlockOffset(id), size) = z.jacobian.middleCols(column, size);
    column += size;
  }
  return h;
}

// Textbook EKF update (P1 eqs. 21-23): K = P H^T S^-1, x += K r, P = (I - K H) P.
void DenseUpdate(const MatrixXd& h, const VectorXd& r, const MatrixXd& noise, VectorXd* x,
                 MatrixXd* p) {
  const MatrixXd s = h * *p * h.transpose() + noise;
  const MatrixXd k = *p * h.transpose() * s.inverse();
  *x += k * r;
  *p = (MatrixXd::Identity(p->rows(), p->cols()) - k * h) * *p;
}

Measurement RandomMeasurement(RandomStream& rng, const EkfState& state, std::vector<BlockId> blocks,
                              int rows) {
  Measurement z;
  z.blocks = std::move(blocks);
  int cols = 0;
  for (BlockId id : z.blocks) cols += state.BlockSize(id);
  z.jacobian = RandomMatrix(rng, rows, cols);
  z.residual = 0.3 * RandomMatrix(rng, rows, 1);
  z.noise = RandomCovariance(rng, rows);
  return z;
}

bool SameBytes(const MatrixXd& a, const MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST_CASE("an update over the touched blocks equals the textbook dense EKF", "[ekf]") {
  RandomStream rng(11, 0, "tests.ekf.dense_update");
  for (int trial = 0; trial < 5; ++trial) {
    RandomState s = MakeRandomState(rng);
    // The robot and two non-adjacent landmarks, listed out of storage order.
    const Measurement z =
        RandomMeasurement(rng, s.state, {s.landmarks[3], EkfState::robot(), s.landmarks[1]}, 3);
    VectorXd x = s.state.Mean();
    MatrixXd p = s.state.FullCovariance();
    DenseUpdate(DenseJacobian(s.state, z), z.residual, z.noise, &x, &p);

    const UpdateResult result = s.state.Update(z, std::numeric_limits<double>::infinity());
    REQUIRE(result.accepted);
    CHECK(result.reason == UpdateReason::kAccepted);
    CHECK(result.dof == 3);
    CHECK((s.state.Mean() - x).cwiseAbs().maxCoeff() <= kDenseEkfTol);
    CHECK((s.state.FullCovariance() - p).cwiseAbs().maxCoeff() <= kDenseEkfTol);
  }
}

TEST_CASE("a stacked update equals the dense stacked update and the sequential ones", "[ekf]") {
  RandomStream rng(12, 0, "tests.ekf.stacked_update");
  RandomState s = MakeRandomState(rng);
  // Two measurements sharing the robot block.
  const std::vector<Measurement> zs = {
      RandomMeasurement(rng, s.state, {EkfState::robot(), s.landmarks[0]}, 2),
      RandomMeasurement(rng, s.state, {s.landmarks[4], EkfState::robot()}, 2)};
  EkfState sequential = s.state;

  MatrixXd h(4, s.state.dim());
  h << DenseJacobian(s.state, zs[0]), DenseJacobian(s.state, zs[1]);
  VectorXd r(4);
  r << zs[0].residual, zs[1].residual;
  MatrixXd noise = MatrixXd::Zero(4, 4);
  noise.topLeftCorner(2, 2) = zs[0].noise;
  noise.bottomRightCorner(2, 2) = zs[1].noise;
  VectorXd x = s.state.Mean();
  MatrixXd p = s.state.FullCovariance();
  DenseUpdate(h, r, noise, &x, &p);

  const UpdateResult stacked = s.state.UpdateStacked(zs, std::numeric_limits<double>::infinity());
  REQUIRE(stacked.accepted);
  CHECK(stacked.dof == 4);
  CHECK((s.state.Mean() - x).cwiseAbs().maxCoeff() <= kDenseEkfTol);
  CHECK((s.state.FullCovariance() - p).cwiseAbs().maxCoeff() <= kDenseEkfTol);

  // Linear measurements (fixed H, z): one after the other gives the same posterior, each residual
  // z - H x taken at the state the previous update left.
  const VectorXd x0 = sequential.Mean();
  for (const Measurement& z : zs) {
    Measurement linear = z;
    linear.residual -= DenseJacobian(sequential, z) * (sequential.Mean() - x0);
    REQUIRE(sequential.Update(linear, std::numeric_limits<double>::infinity()).accepted);
  }
  CHECK((sequential.Mean() - x).cwiseAbs().maxCoeff() <= kDenseEkfTol);
  CHECK((sequential.FullCovariance() - p).cwiseAbs().maxCoeff() <= kDenseEkfTol);
}

TEST_CASE("prediction leaves the landmark-landmark covariance untouched and equals F P F^T",
          "[ekf]") {
  RandomStream rng(13, 0, "tests.ekf.predict");
  RandomState s = MakeRandomState(rng);
  const MatrixXd before = s.state.FullCovariance();
  const Eigen::Matrix3d f = Eigen::Matrix3d::Identity() + 0.2 * RandomMatrix(rng, 3, 3);
  const Eigen::Matrix3d q = RandomCovariance(rng, 3);
  const Eigen::Vector3d new_pose(1.0, -2.0, 0.4);
  s.state.PredictRobot(new_pose, f, q);

  // P1 eqs. 14-16 densely: FF = blkdiag(F, I), GQG^T in the robot corner.
  const int n = s.state.dim();
  MatrixXd ff = MatrixXd::Identity(n, n);
  ff.topLeftCorner(3, 3) = f;
  MatrixXd expected = ff * before * ff.transpose();
  expected.topLeftCorner(3, 3) += q;
  const MatrixXd after = s.state.FullCovariance();
  CHECK((after - expected).cwiseAbs().maxCoeff() <= kDenseEkfTol);
  CHECK(SameBytes(after.bottomRightCorner(n - 3, n - 3), before.bottomRightCorner(n - 3, n - 3)));
  CHECK(s.state.RobotPose() == new_pose);
}

TEST_CASE("augmentation equals P1 eq. 27 computed densely", "[ekf]") {
  RandomStream rng(14, 0, "tests.ekf.augment");
  RandomState s = MakeRandomState(rng);
  const VectorXd x = s.state.Mean();
  const MatrixXd p = s.state.FullCovariance();
  const int n = s.state.dim();
  // A_r spans the robot and a landmark (as a plate's triangulation spans a clone and the pose).
  Augmentation a;
  a.value = Eigen::Vector2d(3.0, 4.0);
  a.blocks = {s.landmarks[2], EkfState::robot()};
  a.d_value_d_blocks = RandomMatrix(rng, 2, 2 + 3);
  a.d_value_d_measurement = RandomMatrix(rng, 2, 2);
  a.measurement_noise = RandomCovariance(rng, 2);
  const BlockId id = s.state.Augment(a);

  MatrixXd a_dense = MatrixXd::Zero(2, n);
  a_dense.middleCols(s.state.BlockOffset(s.landmarks[2]), 2) = a.d_value_d_blocks.leftCols(2);
  a_dense.leftCols(3) = a.d_value_d_blocks.rightCols(3);
  MatrixXd expected(n + 2, n + 2);
  expected.topLeftCorner(n, n) = p;
  expected.bottomLeftCorner(2, n) = a_dense * p;
  expected.topRightCorner(n, 2) = p * a_dense.transpose();
  expected.bottomRightCorner(2, 2) =
      a_dense * p * a_dense.transpose() +
      a.d_value_d_measurement * a.measurement_noise * a.d_value_d_measurement.transpose();
  REQUIRE(s.state.dim() == n + 2);
  CHECK((s.state.FullCovariance() - expected).cwiseAbs().maxCoeff() <= kDenseEkfTol);
  CHECK(s.state.Mean().head(n) == x);
  CHECK(s.state.Value(id) == a.value);
  CHECK(s.state.BlockOffset(id) == n);

  // A clone is the copied block, perfectly correlated with it.
  const BlockId clone = s.state.Clone(EkfState::robot());
  CHECK(s.state.Value(clone) == s.state.Value(EkfState::robot()));
  CHECK(s.state.Covariance(clone, clone) ==
        s.state.Covariance(EkfState::robot(), EkfState::robot()));
  CHECK(s.state.Covariance(clone, id) == s.state.Covariance(EkfState::robot(), id));
}

TEST_CASE("removal leaves the other blocks' values, covariance and ids intact", "[ekf]") {
  RandomStream rng(15, 0, "tests.ekf.remove");
  RandomState s = MakeRandomState(rng);
  const VectorXd x = s.state.Mean();
  const MatrixXd p = s.state.FullCovariance();
  const BlockId gone = s.landmarks[1];  // the 3-block in the middle
  const int offset = s.state.BlockOffset(gone);
  const int size = s.state.BlockSize(gone);
  s.state.Remove(gone);

  const int n = static_cast<int>(x.size());
  std::vector<int> kept;
  for (int i = 0; i < n; ++i) {
    if (i < offset || i >= offset + size) kept.push_back(i);
  }
  MatrixXd expected(kept.size(), kept.size());
  VectorXd expected_x(kept.size());
  for (std::size_t j = 0; j < kept.size(); ++j) {
    expected_x[j] = x[kept[j]];
    for (std::size_t i = 0; i < kept.size(); ++i) expected(i, j) = p(kept[i], kept[j]);
  }
  CHECK_FALSE(s.state.Contains(gone));
  CHECK(s.state.block_count() == 5);
  CHECK(s.state.dim() == n - size);
  CHECK(SameBytes(s.state.FullCovariance(), expected));
  CHECK(s.state.Mean() == expected_x);
  for (BlockId id : s.landmarks) {
    if (id != gone) CHECK(s.state.Contains(id));
  }
  // The angle of the removed block no longer wraps anything; the rest still works.
  const Measurement z = RandomMeasurement(rng, s.state, {s.landmarks[2], EkfState::robot()}, 2);
  CHECK(s.state.Update(z, std::numeric_limits<double>::infinity()).accepted);
}

TEST_CASE("a gated-out measurement leaves the state byte-identical", "[ekf]") {
  RandomStream rng(16, 0, "tests.ekf.gate");
  RandomState s = MakeRandomState(rng);
  Measurement z = RandomMeasurement(rng, s.state, {EkfState::robot(), s.landmarks[0]}, 2);
  z.residual = Eigen::Vector2d(40.0, -35.0);
  const VectorXd x = s.state.Mean();
  const MatrixXd p = s.state.FullCovariance();
  const double chi2_2dof_99 = 9.21;
  const std::optional<double> nis = s.state.Nis(z);
  REQUIRE(nis);
  const UpdateResult result = s.state.Update(z, chi2_2dof_99);
  CHECK_FALSE(result.accepted);
  CHECK(result.reason == UpdateReason::kGated);
  CHECK(result.nis == Approx(*nis).epsilon(1e-12));
  CHECK(result.nis > chi2_2dof_99);
  CHECK(SameBytes(s.state.Mean(), x));
  CHECK(SameBytes(s.state.FullCovariance(), p));
  CHECK(UpdateReasonName(result.reason) == "gated");
}

TEST_CASE("a non-finite measurement or a non-positive-definite S is rejected, never applied",
          "[ekf]") {
  RandomStream rng(17, 0, "tests.ekf.reject");
  RandomState s = MakeRandomState(rng);
  const VectorXd x = s.state.Mean();
  const MatrixXd p = s.state.FullCovariance();
  const double inf = std::numeric_limits<double>::infinity();
  const Measurement good = RandomMeasurement(rng, s.state, {EkfState::robot()}, 2);

  Measurement nan_residual = good;
  nan_residual.residual[1] = std::numeric_limits<double>::quiet_NaN();
  UpdateResult result = s.state.Update(nan_residual, inf);
  CHECK_FALSE(result.accepted);
  CHECK(result.reason == UpdateReason::kNonFinite);
  CHECK_FALSE(s.state.Nis(nan_residual));

  Measurement inf_jacobian = good;
  inf_jacobian.jacobian(0, 2) = inf;
  CHECK(s.state.Update(inf_jacobian, inf).reason == UpdateReason::kNonFinite);

  Measurement negative_noise = good;
  negative_noise.noise = -100.0 * MatrixXd::Identity(2, 2);
  result = s.state.Update(negative_noise, inf);
  CHECK_FALSE(result.accepted);
  CHECK(result.reason == UpdateReason::kNotPositiveDefinite);
  CHECK_FALSE(s.state.Nis(negative_noise));

  CHECK(SameBytes(s.state.Mean(), x));
  CHECK(SameBytes(s.state.FullCovariance(), p));
}

TEST_CASE("angle components wrap into (-pi, pi] after every change", "[ekf]") {
  EkfState state(Eigen::Vector3d(0.0, 0.0, 3.1), Eigen::Matrix3d::Identity());
  // An update that pushes the yaw past pi.
  Measurement yaw;
  yaw.blocks = {EkfState::robot()};
  yaw.jacobian = Eigen::RowVector3d(0.0, 0.0, 1.0);
  yaw.residual = VectorXd::Constant(1, 0.2);
  yaw.noise = MatrixXd::Constant(1, 1, 1e-6);
  REQUIRE(state.Update(yaw, std::numeric_limits<double>::infinity()).accepted);
  CHECK(state.RobotPose()[2] == Approx(3.3 - 2 * kPi).margin(1e-5));

  state.PredictRobot(Eigen::Vector3d(0.0, 0.0, -3.5), Eigen::Matrix3d::Identity(),
                     Eigen::Matrix3d::Zero());
  CHECK(state.RobotPose()[2] == Approx(2 * kPi - 3.5).margin(test::kPoseTol));

  Augmentation a;
  a.value = Eigen::Vector2d(1.0, 4.0);
  a.angle_components = {1};
  a.d_value_d_measurement = MatrixXd::Identity(2, 2);
  a.measurement_noise = MatrixXd::Identity(2, 2);
  const BlockId id = state.Augment(a);
  CHECK(state.Value(id)[0] == 1.0);
  CHECK(state.Value(id)[1] == Approx(4.0 - 2 * kPi).margin(test::kPoseTol));
  for (int k = 0; k < state.dim(); ++k) {
    const double v = state.Mean()[k];
    if (k == 2 || k == 4) CHECK((v > -kPi && v <= kPi));
  }
}

// A range-bearing SLAM simulation: the robot drives a circle, odometry and range-bearing noise as
// the standard workload (bench/bench_ekf.cpp), 40 landmarks in the state from the start
// with an independent 0.2 m prior (a surveyed map whose landmarks the filter refines). With weak
// priors the standard EKF-SLAM is known to turn overconfident (unobservable directions gain
// spurious information from Jacobians taken at changing estimates: Huang, Mourikis, Roumeliotis
// 2010); that is a property of the EKF, not of this core, and not what this test is for.
struct Simulation {
  static constexpr int kRuns = 12;
  static constexpr int kSteps = 300;  // two laps
  static constexpr int kLandmarks = 40;
  static constexpr int kObserved = 10;
  static constexpr double kRadiusM = 12.0;
  static constexpr double kStepM = 0.5;
  static constexpr double kOdometrySigma[3] = {0.03, 0.015, 1.0 * kPi / 180.0};
  static constexpr double kRangeSigmaM = 0.1;
  static constexpr double kBearingSigmaRad = 0.5 * kPi / 180.0;
  static constexpr double kLandmarkPriorSigmaM = 0.2;
};

// The robot-frame motion of one step along the circle (counter-clockwise).
Eigen::Vector3d CircleStep() {
  const double turn = Simulation::kStepM / Simulation::kRadiusM;
  return Eigen::Vector3d(Simulation::kRadiusM * std::sin(turn),
                         Simulation::kRadiusM * (1.0 - std::cos(turn)), turn);
}

using test::Compose;

struct NeesFigures {
  double mean_nees = 0.0;  // robot pose NEES over every run and step
  int rejected = 0;        // updates refused by the 99.9 % gate
};

// Runs the simulation; the filter believes the sensor's variances are `noise_scale` times the
// true ones (1: a correct model).
NeesFigures SimulateRangeBearingSlam(double noise_scale) {
  using S = Simulation;
  const double gate_2dof = boost::math::quantile(boost::math::chi_squared(2), 0.999);
  NeesFigures figures;
  double nees_sum = 0.0;
  for (int run = 0; run < S::kRuns; ++run) {
    RandomStream world_rng(21, run, "tests.ekf.nees.world");
    RandomStream odometry_rng(21, run, "tests.ekf.nees.odometry");
    RandomStream sensor_rng(21, run, "tests.ekf.nees.sensor");
    std::vector<Eigen::Vector2d> landmarks;
    for (int i = 0; i < S::kLandmarks; ++i) {
      landmarks.emplace_back(world_rng.Uniform(-20, 20), world_rng.Uniform(-20, 20));
    }
    SE2 truth(S::kRadiusM, 0.0, kPi / 2);
    EkfState state(Eigen::Vector3d(truth.x(), truth.y(), truth.yaw()),
                   Eigen::Matrix3d::Identity() * 1e-8);
    std::vector<BlockId> ids;
    for (const Eigen::Vector2d& l : landmarks) {
      Augmentation a;
      const double s = S::kLandmarkPriorSigmaM;
      a.value = l + Eigen::Vector2d(world_rng.Normal(0, s), world_rng.Normal(0, s));
      a.d_value_d_measurement = MatrixXd::Identity(2, 2);
      a.measurement_noise = MatrixXd::Identity(2, 2) * s * s;
      ids.push_back(state.Augment(a));
    }
    Eigen::Matrix3d odometry_cov = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) odometry_cov(k, k) = std::pow(S::kOdometrySigma[k], 2);
    const Eigen::Matrix2d sensor_cov =
        noise_scale *
        Eigen::Vector2d(std::pow(S::kRangeSigmaM, 2), std::pow(S::kBearingSigmaRad, 2))
            .asDiagonal();
    for (int step = 0; step < S::kSteps; ++step) {
      const Eigen::Vector3d delta = CircleStep();
      truth = Compose(truth, delta);
      Eigen::Vector3d measured = delta;
      for (int k = 0; k < 3; ++k) measured[k] += odometry_rng.Normal(0, S::kOdometrySigma[k]);
      const Eigen::Vector3d x = state.RobotPose();
      Eigen::Matrix3d f, g;
      const SE2 predicted = Compose(SE2(x[0], x[1], x[2]), measured, &f, &g);
      state.PredictRobot(Eigen::Vector3d(predicted.x(), predicted.y(), predicted.yaw()), f,
                         g * odometry_cov * g.transpose());
      // The kObserved nearest landmarks (ties by index), one update each.
      std::vector<int> order(landmarks.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return (landmarks[a] - truth.translation()).squaredNorm() <
               (landmarks[b] - truth.translation()).squaredNorm();
      });
      for (int o = 0; o < S::kObserved; ++o) {
        const int i = order[o];
        Eigen::Vector2d z = RangeBearing(truth, landmarks[i]);
        z[0] += sensor_rng.Normal(0, S::kRangeSigmaM);
        z[1] += sensor_rng.Normal(0, S::kBearingSigmaRad);
        const Eigen::Vector3d r = state.RobotPose();
        Eigen::Matrix<double, 2, 3> d_z_d_pose;
        Eigen::Matrix2d d_z_d_landmark;
        const Eigen::Vector2d h =
            RangeBearing(SE2(r[0], r[1], r[2]), state.Value(ids[i]), &d_z_d_pose, &d_z_d_landmark);
        Measurement m;
        m.blocks = {EkfState::robot(), ids[i]};
        m.jacobian.resize(2, 5);
        m.jacobian << d_z_d_pose, d_z_d_landmark;
        m.residual = Eigen::Vector2d(z[0] - h[0], NormalizeAngle(z[1] - h[1]));
        m.noise = sensor_cov;
        if (!state.Update(m, gate_2dof).accepted) ++figures.rejected;
      }
      Eigen::Vector3d error =
          state.RobotPose() - Eigen::Vector3d(truth.x(), truth.y(), truth.yaw());
      error[2] = NormalizeAngle(error[2]);
      const Eigen::Matrix3d cov = state.Covariance(EkfState::robot(), EkfState::robot());
      nees_sum += error.dot(cov.ldlt().solve(error));
    }
  }
  figures.mean_nees = nees_sum / (S::kRuns * S::kSteps);
  return figures;
}

TEST_CASE("a simulated range-bearing SLAM run keeps the robot's NEES inside the 95 % band",
          "[ekf][slow]") {
  using S = Simulation;
  // The mean over runs at one step is chi2(3 kRuns) / kRuns for a consistent filter; averaging it
  // over correlated steps only narrows its spread, so that band is conservative.
  const boost::math::chi_squared band(3 * S::kRuns);
  const double low = boost::math::quantile(band, 0.025) / S::kRuns;
  const double high = boost::math::quantile(band, 0.975) / S::kRuns;
  const NeesFigures correct = SimulateRangeBearingSlam(1.0);
  INFO("mean NEES " << correct.mean_nees << ", band [" << low << ", " << high << "], rejected "
                    << correct.rejected);
  CHECK(correct.mean_nees >= low);
  CHECK(correct.mean_nees <= high);
  CHECK(correct.rejected < S::kRuns * S::kSteps * S::kObserved / 200);
  // The test has teeth: a filter that believes its sensor 4x (variance) better than it is leaves
  // the band.
  const NeesFigures overconfident = SimulateRangeBearingSlam(0.25);
  INFO("overconfident mean NEES " << overconfident.mean_nees);
  CHECK(overconfident.mean_nees > high);
}

}  // namespace
}  // namespace corridorsim::slam::ekf
