#include "harness/evaluate/alignment.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/error.h"

namespace corridorsim::evaluate {
namespace {

// Singular values of the centred positions below this fraction of the largest count as zero.
constexpr double kDegenerateRatio = 1e-9;

// Rank of the spread of `points` (columns) about their mean.
int SpreadRank(const Eigen::MatrixXd& points) {
  const Eigen::MatrixXd centred = points.colwise() - points.rowwise().mean();
  const Eigen::VectorXd sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues();
  if (sigma.size() == 0 || sigma[0] <= 0.0) return 0;
  int rank = 0;
  for (Eigen::Index i = 0; i < sigma.size(); ++i) rank += sigma[i] > kDegenerateRatio * sigma[0];
  return rank;
}

}  // namespace

std::optional<Similarity> Align(Alignment alignment, const std::vector<Eigen::Vector3d>& estimate,
                                const std::vector<Eigen::Vector3d>& truth, std::string* why) {
  CheckOrDie(estimate.size() == truth.size(), "evaluate::Align", "unequal pair counts");
  if (alignment == Alignment::kNone) return Similarity{};
  const bool planar = alignment == Alignment::kSE2;
  const std::size_t needed = planar ? 2 : 3;
  const auto n = static_cast<Eigen::Index>(estimate.size());
  if (estimate.size() < needed) {
    *why = AlignmentName(alignment) + " alignment needs at least " + std::to_string(needed) +
           " poses with truth, got " + std::to_string(estimate.size());
    return std::nullopt;
  }
  const int dims = planar ? 2 : 3;
  Eigen::MatrixXd src(dims, n), dst(dims, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(i) = estimate[i].head(dims);
    dst.col(i) = truth[i].head(dims);
  }
  const int needed_rank = planar ? 1 : 2;
  if (SpreadRank(src) < needed_rank || SpreadRank(dst) < needed_rank) {
    *why = planar ? "se2 alignment needs two distinct x-y positions (the estimate or the truth "
                    "stands still)"
                  : AlignmentName(alignment) +
                        " alignment needs positions that do not all lie on one line (a rotation "
                        "about it would be free): use se2 for a straight planar drive";
    return std::nullopt;
  }
  // Umeyama eqs. 40-42: R = U S V^T, c = tr(D S) / sigma_x^2, t = mu_y - c R mu_x.
  const Eigen::MatrixXd m = Eigen::umeyama(src, dst, alignment == Alignment::kSim3);
  Similarity out;
  const Eigen::MatrixXd block = m.topLeftCorner(dims, dims);
  // Eigen returns c R as one block: its scale is the columns' common norm.
  out.scale = alignment == Alignment::kSim3 ? block.col(0).norm() : 1.0;
  out.rotation.topLeftCorner(dims, dims) = block / out.scale;
  out.translation.head(dims) = m.topRightCorner(dims, 1);
  return out;
}

}  // namespace corridorsim::evaluate
