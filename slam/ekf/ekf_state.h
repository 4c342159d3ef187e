#pragma once
// The one EKF core of the project (STYLE item 6; OpenVINS' StateHelper is the model): a state
// vector and covariance made of named blocks, the robot pose first, landmarks and pose clones
// added by augmentation. Landmark types supply only measurement models (residual, Jacobian over
// the blocks they touch, noise: slam/ekf/measurement_models.h); covariance bookkeeping, gating,
// augmentation and deletion live here.
//
// Storage: the covariance P keeps its lower triangle only (P(i, j) for i >= j); the upper one is
// never read. P is symmetric by construction, and the covariance update P -= K (H P) is one
// symmetric rank-m update of that triangle (half the flops and memory traffic of the full matrix).
// Costs, n = dim(), t = the touched dimensions, m = the measurement's rows: PredictRobot O(n),
// Update O(n t m + n m^2 + n^2 m / 2) (the last term, the rank-m update, dominates: bench_ekf),
// Nis O(t^2 m + m^3), Augment O(n s (t + s)), Remove O(n^2). Stacking a frame's measurements into
// one update (UpdateStacked) streams P once instead of once per measurement: 3x faster at
// N = 1000 point landmarks (bench/bench_ekf.cpp).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace corridorsim::slam::ekf {

/// Names one block of the state. Valid until that block is removed; ids are never reused, and
/// removing a block leaves the ids of the others valid.
struct BlockId {
  std::int64_t value = -1;
  friend bool operator==(BlockId, BlockId) = default;
  friend auto operator<=>(BlockId, BlockId) = default;
};

/// The largest state dimension: bounds the covariance to 8192^2 doubles (512 MiB). Callers bound
/// their landmark counts far below it; augmenting past it is a bug (it aborts).
inline constexpr int kMaxStateDim = 8192;
/// The largest measurement (rows of a single or stacked update).
inline constexpr int kMaxMeasurementDim = 1024;

/// One measurement over the blocks it touches (P1 eqs. 21-24 with the zero columns left out).
struct Measurement {
  std::vector<BlockId> blocks;  // touched blocks, distinct, in the column order of `jacobian`
  Eigen::VectorXd residual;     // r = z - h(x) (m); angle rows wrapped by the caller
  Eigen::MatrixXd jacobian;     // H = d h / d x over `blocks` (m x sum of their sizes)
  Eigen::MatrixXd noise;        // R (m x m), symmetric positive semi-definite
};

/// Why an update was or was not applied.
enum class UpdateReason {
  kAccepted,             // applied
  kGated,                // NIS above the chi-square threshold: state untouched
  kNonFinite,            // residual, Jacobian, noise, S or NIS not finite: state untouched
  kNotPositiveDefinite,  // S = H P H^T + R has no Cholesky factor: state untouched
};
/// "accepted", "gated", "non_finite", "not_positive_definite".
std::string UpdateReasonName(UpdateReason reason);

struct UpdateResult {
  double nis = 0.0;  // r^T S^-1 r (NaN when it could not be computed)
  int dof = 0;       // rows of the measurement (the chi-square's degrees of freedom)
  bool accepted = false;
  UpdateReason reason = UpdateReason::kNonFinite;
};

/// A new block from a function g of existing blocks and a measurement (P1 eqs. 26-27):
/// value g, A (A_r of P1) = d g / d (blocks), A_a = d g / d z, R = Cov(z). Its covariance is
/// A P_ff A^T + A_a R A_a^T and its cross-covariance A P_(f,:).
struct Augmentation {
  Eigen::VectorXd value;                  // g (s)
  std::vector<int> angle_components;      // components of the block that are angles (rad)
  std::vector<BlockId> blocks;            // existing blocks g depends on (distinct; may be empty)
  Eigen::MatrixXd d_value_d_blocks;       // A: s x sum of the sizes of `blocks` (0 x 0: none)
  Eigen::MatrixXd d_value_d_measurement;  // A_a: s x q (0 x 0: no measurement term)
  Eigen::MatrixXd measurement_noise;      // R: q x q (0 x 0: no measurement term)
};

class EkfState {
 public:
  /// Block 0: the robot pose (x m, y m, yaw rad) with its covariance (yaw wraps).
  EkfState(const Eigen::Vector3d& robot_pose, const Eigen::Matrix3d& robot_covariance);

  /// The robot pose block (always present; it cannot be removed).
  static constexpr BlockId robot() { return BlockId{0}; }

  int dim() const { return dim_; }
  int block_count() const { return static_cast<int>(blocks_.size()); }
  bool Contains(BlockId id) const { return Find(id) != nullptr; }
  /// The blocks in storage order (the robot first).
  std::vector<BlockId> Blocks() const;
  int BlockSize(BlockId id) const;
  /// Where the block starts in Mean() and FullCovariance() (changes when an earlier block goes).
  int BlockOffset(BlockId id) const;

  Eigen::VectorXd Value(BlockId id) const;
  Eigen::Vector3d RobotPose() const { return x_.head<3>(); }
  /// Cov(a, b): BlockSize(a) x BlockSize(b).
  Eigen::MatrixXd Covariance(BlockId a, BlockId b) const;
  Eigen::VectorXd Mean() const { return x_.head(dim_); }
  /// The whole symmetric n x n covariance (a copy: for outputs and tests).
  Eigen::MatrixXd FullCovariance() const;

  /// P1 eqs. 14-16: the robot block becomes `new_pose` (yaw wrapped), P_rr = F P_rr F^T + Q_pose
  /// and P_r,others = F P_r,others. O(n): the rest of P is untouched. Q_pose = G Q G^T (3x3).
  void PredictRobot(const Eigen::Vector3d& new_pose, const Eigen::Matrix3d& d_pose_d_pose,
                    const Eigen::Matrix3d& pose_noise);

  /// P1 eqs. 21-24 over the touched blocks: S = H P_tt H^T + R, NIS = r^T S^-1 r; rejected (state
  /// untouched) when NIS > `chi2_threshold` (+inf: no gate), when anything is non-finite, or when S
  /// has no Cholesky factor. Else K = P_(:,t) H^T S^-1, x += K r, P -= K (H P_(t,:)).
  UpdateResult Update(const Measurement& measurement, double chi2_threshold);
  /// Several measurements stacked into one update (one S, dof = total rows, gated as a whole
  /// against `chi2_threshold`). Gate each one first with Nis() when each needs its own gate.
  UpdateResult UpdateStacked(std::span<const Measurement> measurements, double chi2_threshold);
  /// The NIS the update would compute, without changing anything (Mahalanobis data
  /// association); nullopt when it cannot be computed (non-finite, S not positive definite).
  std::optional<double> Nis(const Measurement& measurement) const;

  /// P1 eqs. 26-27: appends a block; returns its id.
  BlockId Augment(const Augmentation& augmentation);
  /// A copy of block `id` (a pose clone: A = I, perfectly correlated with the original).
  BlockId Clone(BlockId id);
  /// Deletes a block (not the robot's); storage compacts, other ids stay valid.
  void Remove(BlockId id);

 private:
  struct Block {
    BlockId id;
    int offset = 0;
    int size = 0;
    std::vector<int> angle_components;
  };
  // A contiguous run of state indices [offset, offset + size) and where its columns sit in H.
  struct Segment {
    int offset = 0;
    int size = 0;
    int column = 0;
  };
  struct Prepared;  // the gathered quantities of one update (ekf_state.cpp)

  const Block* Find(BlockId id) const;
  const Block& Get(BlockId id) const;  // aborts on an unknown id
  // P(i, j) from the stored lower triangle.
  double P(int i, int j) const { return i >= j ? cov_(i, j) : cov_(j, i); }
  // out = P_(:, segments) (n x total size) from the lower triangle.
  void GatherColumns(const std::vector<Segment>& segments, int total, Eigen::MatrixXd* out) const;
  std::vector<Segment> SegmentsOf(std::span<const BlockId> blocks, int* total) const;
  // Checks shapes and finiteness, gathers P_(:,t) H^T, factors S; false when rejected.
  bool Prepare(const std::vector<Segment>& segments, int total, const Eigen::MatrixXd& jacobian,
               const Eigen::VectorXd& residual, const Eigen::MatrixXd& noise, bool with_gain,
               Prepared* prepared, UpdateResult* result) const;
  UpdateResult Apply(const std::vector<Segment>& segments, int total,
                     const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                     const Eigen::MatrixXd& noise, double chi2_threshold);
  void Reserve(int dim);
  void WrapAngles();
  void RebuildAngleIndices();

  int dim_ = 0;
  Eigen::VectorXd x_;    // capacity-sized; the first dim_ entries are the state
  Eigen::MatrixXd cov_;  // capacity-sized; the lower triangle of the top-left dim_ x dim_ is P
  std::vector<Block> blocks_;       // storage order = id order (appended, never reordered)
  std::vector<int> angle_indices_;  // state indices that are angles
  std::int64_t next_id_ = 0;
};

}  // namespace corridorsim::slam::ekf
