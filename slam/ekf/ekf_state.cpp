#include "slam/ekf/ekf_state.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "common/enum_names.h"
#include "common/error.h"
#include "common/pose.h"

namespace corridorsim::slam::ekf {
namespace {

constexpr EnumName<UpdateReason> kUpdateReasonNames[] = {
    {UpdateReason::kAccepted, "accepted"},
    {UpdateReason::kGated, "gated"},
    {UpdateReason::kNonFinite, "non_finite"},
    {UpdateReason::kNotPositiveDefinite, "not_positive_definite"},
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::string UpdateReasonName(UpdateReason reason) { return NameOf(kUpdateReasonNames, reason); }

struct EkfState::Prepared {
  Eigen::MatrixXd p_ht;             // P_(:,t) H^T (n x m); empty for Nis()
  Eigen::LLT<Eigen::MatrixXd> llt;  // of S = H P_tt H^T + R
  Eigen::VectorXd whitened;         // L^-1 r, so that NIS = |L^-1 r|^2
};

EkfState::EkfState(const Eigen::Vector3d& robot_pose, const Eigen::Matrix3d& robot_covariance) {
  CheckOrDie(robot_pose.allFinite() && robot_covariance.allFinite(), "EkfState",
             "non-finite initial robot pose or covariance");
  Reserve(3);
  dim_ = 3;
  x_.head<3>() = robot_pose;
  cov_.topLeftCorner<3, 3>() = 0.5 * (robot_covariance + robot_covariance.transpose());
  blocks_.push_back(Block{robot(), 0, 3, {2}});
  next_id_ = 1;
  RebuildAngleIndices();
  WrapAngles();
}

const EkfState::Block* EkfState::Find(BlockId id) const {
  // blocks_ is sorted by id: blocks are appended with increasing ids and erased in place.
  const auto it = std::lower_bound(blocks_.begin(), blocks_.end(), id,
                                   [](const Block& b, BlockId v) { return b.id < v; });
  return it != blocks_.end() && it->id == id ? &*it : nullptr;
}

const EkfState::Block& EkfState::Get(BlockId id) const {
  const Block* block = Find(id);
  CheckOrDie(block != nullptr, "EkfState", "unknown or removed block id");
  return *block;
}

std::vector<BlockId> EkfState::Blocks() const {
  std::vector<BlockId> ids;
  ids.reserve(blocks_.size());
  for (const Block& b : blocks_) ids.push_back(b.id);
  return ids;
}

int EkfState::BlockSize(BlockId id) const { return Get(id).size; }
int EkfState::BlockOffset(BlockId id) const { return Get(id).offset; }

Eigen::VectorXd EkfState::Value(BlockId id) const {
  const Block& b = Get(id);
  return x_.segment(b.offset, b.size);
}

Eigen::MatrixXd EkfState::Covariance(BlockId a, BlockId b) const {
  const Block& ba = Get(a);
  const Block& bb = Get(b);
  Eigen::MatrixXd out(ba.size, bb.size);
  for (int j = 0; j < bb.size; ++j) {
    for (int i = 0; i < ba.size; ++i) out(i, j) = P(ba.offset + i, bb.offset + j);
  }
  return out;
}

Eigen::MatrixXd EkfState::FullCovariance() const {
  Eigen::MatrixXd full = cov_.topLeftCorner(dim_, dim_).selfadjointView<Eigen::Lower>();
  return full;
}

void EkfState::Reserve(int dim) {
  CheckOrDie(dim <= kMaxStateDim, "EkfState", "state dimension above kMaxStateDim");
  const auto capacity = static_cast<int>(cov_.rows());
  if (dim <= capacity) return;
  const int new_capacity = std::min(kMaxStateDim, std::max({dim, 2 * capacity, 16}));
  // Amortised: doubling keeps the copies O(n^2) per doubling, not per augmentation.
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(new_capacity, new_capacity);
  cov.topLeftCorner(dim_, dim_) = cov_.topLeftCorner(dim_, dim_);
  cov_.swap(cov);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(new_capacity);
  x.head(dim_) = x_.head(dim_);
  x_.swap(x);
}

void EkfState::RebuildAngleIndices() {
  angle_indices_.clear();
  for (const Block& b : blocks_) {
    for (int c : b.angle_components) angle_indices_.push_back(b.offset + c);
  }
}

void EkfState::WrapAngles() {
  for (int i : angle_indices_) x_[i] = NormalizeAngle(x_[i]);
}

std::vector<EkfState::Segment> EkfState::SegmentsOf(std::span<const BlockId> blocks,
                                                    int* total) const {
  std::vector<Segment> segments;
  segments.reserve(blocks.size());
  int column = 0;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    for (std::size_t l = 0; l < k; ++l) {
      CheckOrDie(blocks[l] != blocks[k], "EkfState", "a block listed twice");
    }
    const Block& b = Get(blocks[k]);
    segments.push_back(Segment{b.offset, b.size, column});
    column += b.size;
  }
  *total = column;
  return segments;
}

void EkfState::GatherColumns(const std::vector<Segment>& segments, int total,
                             Eigen::MatrixXd* out) const {
  const int n = dim_;
  out->resize(n, total);
  for (const Segment& s : segments) {
    const int o = s.offset;
    // Rows above the block: P(i, j) = P(j, i) for i < j, from the block's rows of the triangle.
    out->block(0, s.column, o, s.size) = cov_.block(o, 0, s.size, o).transpose();
    out->block(o, s.column, s.size, s.size) =
        cov_.block(o, o, s.size, s.size).selfadjointView<Eigen::Lower>();
    out->block(o + s.size, s.column, n - o - s.size, s.size) =
        cov_.block(o + s.size, o, n - o - s.size, s.size);
  }
}

void EkfState::PredictRobot(const Eigen::Vector3d& new_pose, const Eigen::Matrix3d& d_pose_d_pose,
                            const Eigen::Matrix3d& pose_noise) {
  CheckOrDie(new_pose.allFinite() && d_pose_d_pose.allFinite() && pose_noise.allFinite(),
             "EkfState::PredictRobot", "non-finite pose, F or Q");
  const Eigen::Matrix3d& F = d_pose_d_pose;
  // P1 eq. 14 restricted to the robot rows: P_rr = F P_rr F^T + G Q G^T ...
  const Eigen::Matrix3d p_rr = cov_.topLeftCorner<3, 3>().selfadjointView<Eigen::Lower>();
  const Eigen::Matrix3d p_rr_new = F * p_rr * F.transpose() + pose_noise;
  cov_.topLeftCorner<3, 3>() = 0.5 * (p_rr_new + p_rr_new.transpose());
  // ... and P_others,r = P_others,r F^T (eq. 15's identity on the landmarks: O(n)).
  const int rest = dim_ - 3;
  if (rest > 0) {
    cov_.block(3, 0, rest, 3) = (cov_.block(3, 0, rest, 3) * F.transpose()).eval();
  }
  x_.head<3>() = new_pose;
  x_[2] = NormalizeAngle(x_[2]);
}

bool EkfState::Prepare(const std::vector<Segment>& segments, int total,
                       const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                       const Eigen::MatrixXd& noise, bool with_gain, Prepared* prepared,
                       UpdateResult* result) const {
  const auto m = static_cast<int>(residual.size());
  CheckOrDie(m >= 1 && m <= kMaxMeasurementDim, "EkfState::Update", "measurement size");
  CheckOrDie(
      jacobian.rows() == m && jacobian.cols() == total && noise.rows() == m && noise.cols() == m,
      "EkfState::Update", "H or R has the wrong shape");
  result->dof = m;
  result->nis = kNaN;
  result->accepted = false;
  if (!residual.allFinite() || !jacobian.allFinite() || !noise.allFinite()) {
    result->reason = UpdateReason::kNonFinite;
    return false;
  }
  // P_tt H^T (total x m): the touched rows of P_(:,t) H^T when the gain needs all of it.
  Eigen::MatrixXd p_tt_ht(total, m);
  if (with_gain) {
    Eigen::MatrixXd p_t;
    GatherColumns(segments, total, &p_t);
    prepared->p_ht.noalias() = p_t * jacobian.transpose();
    for (const Segment& s : segments) {
      p_tt_ht.middleRows(s.column, s.size) = prepared->p_ht.middleRows(s.offset, s.size);
    }
  } else {
    Eigen::MatrixXd p_tt(total, total);
    for (const Segment& a : segments) {
      for (const Segment& b : segments) {
        for (int j = 0; j < b.size; ++j) {
          for (int i = 0; i < a.size; ++i) {
            p_tt(a.column + i, b.column + j) = P(a.offset + i, b.offset + j);
          }
        }
      }
    }
    p_tt_ht.noalias() = p_tt * jacobian.transpose();
  }
  // P1 eq. 21's innovation covariance S = H P_tt H^T + R, symmetrised.
  Eigen::MatrixXd s = jacobian * p_tt_ht + noise;
  s = 0.5 * (s + s.transpose()).eval();
  if (!s.allFinite()) {
    result->reason = UpdateReason::kNonFinite;
    return false;
  }
  prepared->llt.compute(s);
  if (prepared->llt.info() != Eigen::Success) {
    result->reason = UpdateReason::kNotPositiveDefinite;
    return false;
  }
  prepared->whitened = prepared->llt.matrixL().solve(residual);
  result->nis = prepared->whitened.squaredNorm();
  if (!std::isfinite(result->nis)) {
    result->reason = UpdateReason::kNonFinite;
    return false;
  }
  return true;
}

UpdateResult EkfState::Apply(const std::vector<Segment>& segments, int total,
                             const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                             const Eigen::MatrixXd& noise, double chi2_threshold) {
  CheckOrDie(chi2_threshold >= 0.0, "EkfState::Update", "negative or NaN chi-square threshold");
  UpdateResult result;
  Prepared prepared;
  if (!Prepare(segments, total, jacobian, residual, noise, /*with_gain=*/true, &prepared,
               &result)) {
    return result;
  }
  if (result.nis > chi2_threshold) {
    result.reason = UpdateReason::kGated;
    return result;
  }
  // With S = L L^T and W = P_(:,t) H^T L^-T: K r = W L^-1 r (P1 eq. 22) and
  // K (H P_(t,:)) = W W^T, a symmetric rank-m update of the stored triangle (P1 eq. 23, STYLE 6).
  Eigen::MatrixXd& w = prepared.p_ht;
  prepared.llt.matrixU().solveInPlace<Eigen::OnTheRight>(w);
  x_.head(dim_).noalias() += w * prepared.whitened;
  cov_.topLeftCorner(dim_, dim_).selfadjointView<Eigen::Lower>().rankUpdate(w, -1.0);
  WrapAngles();
  result.accepted = true;
  result.reason = UpdateReason::kAccepted;
  return result;
}

UpdateResult EkfState::Update(const Measurement& measurement, double chi2_threshold) {
  int total = 0;
  const std::vector<Segment> segments = SegmentsOf(measurement.blocks, &total);
  return Apply(segments, total, measurement.jacobian, measurement.residual, measurement.noise,
               chi2_threshold);
}

UpdateResult EkfState::UpdateStacked(std::span<const Measurement> measurements,
                                     double chi2_threshold) {
  CheckOrDie(!measurements.empty(), "EkfState::UpdateStacked", "no measurement");
  // The union of the touched blocks, in order of first appearance, and the stacked rows.
  std::vector<BlockId> blocks;
  int rows = 0;
  for (const Measurement& z : measurements) {
    CheckOrDie(z.residual.size() <= kMaxMeasurementDim, "EkfState::UpdateStacked",
               "measurement size");
    rows += static_cast<int>(z.residual.size());
    CheckOrDie(rows <= kMaxMeasurementDim, "EkfState::UpdateStacked", "stacked size");
    for (BlockId id : z.blocks) {
      if (std::find(blocks.begin(), blocks.end(), id) == blocks.end()) blocks.push_back(id);
    }
  }
  int total = 0;
  const std::vector<Segment> segments = SegmentsOf(blocks, &total);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(rows, total);
  Eigen::VectorXd residual(rows);
  Eigen::MatrixXd noise = Eigen::MatrixXd::Zero(rows, rows);
  int row = 0;
  for (const Measurement& z : measurements) {
    const auto m = static_cast<int>(z.residual.size());
    int own_total = 0;
    SegmentsOf(z.blocks, &own_total);  // checks the ids and that none is listed twice
    CheckOrDie(z.jacobian.rows() == m && z.jacobian.cols() == own_total && z.noise.rows() == m &&
                   z.noise.cols() == m,
               "EkfState::UpdateStacked", "H or R has the wrong shape");
    int column = 0;
    for (BlockId id : z.blocks) {
      const auto k =
          static_cast<std::size_t>(std::find(blocks.begin(), blocks.end(), id) - blocks.begin());
      const Segment& s = segments[k];
      jacobian.block(row, s.column, m, s.size) = z.jacobian.middleCols(column, s.size);
      column += s.size;
    }
    residual.segment(row, m) = z.residual;
    noise.block(row, row, m, m) = z.noise;
    row += m;
  }
  return Apply(segments, total, jacobian, residual, noise, chi2_threshold);
}

std::optional<double> EkfState::Nis(const Measurement& measurement) const {
  int total = 0;
  const std::vector<Segment> segments = SegmentsOf(measurement.blocks, &total);
  UpdateResult result;
  Prepared prepared;
  if (!Prepare(segments, total, measurement.jacobian, measurement.residual, measurement.noise,
               /*with_gain=*/false, &prepared, &result)) {
    return std::nullopt;
  }
  return result.nis;
}

BlockId EkfState::Augment(const Augmentation& augmentation) {
  const auto s = static_cast<int>(augmentation.value.size());
  int total = 0;
  const std::vector<Segment> segments = SegmentsOf(augmentation.blocks, &total);
  const Eigen::MatrixXd& a = augmentation.d_value_d_blocks;
  const Eigen::MatrixXd& a_z = augmentation.d_value_d_measurement;
  const Eigen::MatrixXd& r = augmentation.measurement_noise;
  CheckOrDie(s >= 1, "EkfState::Augment", "empty block");
  // An empty A (no blocks) or an empty A_a and R (no measurement term) may be left 0 x 0.
  CheckOrDie((a.rows() == s && a.cols() == total) || (total == 0 && a.size() == 0),
             "EkfState::Augment", "A has the wrong shape");
  CheckOrDie((a_z.rows() == s && r.rows() == a_z.cols() && r.cols() == a_z.cols()) ||
                 (a_z.size() == 0 && r.size() == 0),
             "EkfState::Augment", "A_a or R has the wrong shape");
  CheckOrDie(augmentation.value.allFinite() && a.allFinite() && a_z.allFinite() && r.allFinite(),
             "EkfState::Augment", "non-finite value, A, A_a or R");
  for (int c : augmentation.angle_components) {
    CheckOrDie(c >= 0 && c < s, "EkfState::Augment", "angle component outside the block");
  }
  const int n = dim_;
  Reserve(n + s);
  // P1 eq. 27: the new rows A P_(f,:) and the new diagonal A P_ff A^T + A_a R A_a^T.
  Eigen::MatrixXd diagonal = Eigen::MatrixXd::Zero(s, s);
  if (a_z.size() != 0) diagonal.noalias() += a_z * r * a_z.transpose();
  if (total > 0) {
    Eigen::MatrixXd p_f;
    GatherColumns(segments, total, &p_f);
    cov_.block(n, 0, s, n).noalias() = a * p_f.transpose();
    Eigen::MatrixXd p_ff(total, total);
    for (const Segment& seg : segments) {
      p_ff.middleRows(seg.column, seg.size) = p_f.middleRows(seg.offset, seg.size);
    }
    diagonal.noalias() += a * p_ff * a.transpose();
  } else {
    cov_.block(n, 0, s, n).setZero();
  }
  cov_.block(n, n, s, s) = 0.5 * (diagonal + diagonal.transpose());
  x_.segment(n, s) = augmentation.value;
  const BlockId id{next_id_++};
  blocks_.push_back(Block{id, n, s, augmentation.angle_components});
  dim_ = n + s;
  RebuildAngleIndices();
  for (int c : augmentation.angle_components) x_[n + c] = NormalizeAngle(x_[n + c]);
  return id;
}

BlockId EkfState::Clone(BlockId id) {
  const Block& b = Get(id);
  Augmentation clone;
  clone.value = x_.segment(b.offset, b.size);
  clone.angle_components = b.angle_components;
  clone.blocks = {id};
  clone.d_value_d_blocks = Eigen::MatrixXd::Identity(b.size, b.size);
  clone.d_value_d_measurement = Eigen::MatrixXd::Zero(b.size, 0);
  clone.measurement_noise = Eigen::MatrixXd::Zero(0, 0);
  return Augment(clone);
}

void EkfState::Remove(BlockId id) {
  CheckOrDie(id != robot(), "EkfState::Remove", "the robot block cannot be removed");
  const Block* found = Find(id);
  CheckOrDie(found != nullptr, "EkfState::Remove", "unknown or removed block id");
  const int o = found->offset;
  const int s = found->size;
  const int n = dim_;
  const int kept = n - s;
  const auto stride = static_cast<std::ptrdiff_t>(cov_.rows());
  double* data = cov_.data();
  // Shift the later columns left by s, then in every kept column the later rows up by s
  // (forward copies of distinct or overlapping-left ranges are safe).
  for (int j = o; j < kept; ++j) {
    std::copy(data + (j + s) * stride, data + (j + s) * stride + n, data + j * stride);
  }
  for (int j = 0; j < kept; ++j) {
    double* column = data + j * stride;
    std::copy(column + o + s, column + n, column + o);
  }
  std::copy(x_.data() + o + s, x_.data() + n, x_.data() + o);
  const auto index = found - blocks_.data();
  blocks_.erase(blocks_.begin() + index);
  for (auto it = blocks_.begin() + index; it != blocks_.end(); ++it) it->offset -= s;
  dim_ = kept;
  RebuildAngleIndices();
}

}  // namespace corridorsim::slam::ekf
