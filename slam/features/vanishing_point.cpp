#include "slam/features/vanishing_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "common/enum_names.h"
#include "slam/features/image_conversion.h"

namespace corridorsim::slam {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

constexpr EnumName<VanishingPointStatus> kStatusNames[] = {
    {VanishingPointStatus::kFound, "found"},
    {VanishingPointStatus::kTooFewLines, "too_few_lines"},
    {VanishingPointStatus::kIllConditioned, "ill_conditioned"},
    {VanishingPointStatus::kNotConverging, "not_converging"},
    {VanishingPointStatus::kOutsideImage, "outside_image"}};

double Length(const ImageLineSegment& line) { return (line.b_px - line.a_px).norm(); }

// The segment of the infinite line x cos(theta) + y sin(theta) = rho inside the image rectangle
// [0, width - 1] x [0, height - 1] (pixel centres), or none when it misses the image.
std::optional<ImageLineSegment> ClipToImage(double rho, double theta, int width, int height) {
  const Eigen::Vector2d normal(std::cos(theta), std::sin(theta));
  const Eigen::Vector2d direction(-normal.y(), normal.x());
  const Eigen::Vector2d foot = rho * normal;
  // Liang-Barsky: the parameter range of foot + t direction inside the rectangle.
  double t0 = -1e300, t1 = 1e300;
  const double lo[2] = {0.0, 0.0};
  const double hi[2] = {width - 1.0, height - 1.0};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(direction[k]) < 1e-12) {
      if (foot[k] < lo[k] || foot[k] > hi[k]) return std::nullopt;
      continue;
    }
    double ta = (lo[k] - foot[k]) / direction[k];
    double tb = (hi[k] - foot[k]) / direction[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t1 > t0)) return std::nullopt;
  return ImageLineSegment{foot + t0 * direction, foot + t1 * direction};
}

// Candidate lines of the edge image, strongest first: HoughLinesP's segments by length
// (longest first), HoughLines' lines in its order (most votes first), clipped to the image.
std::vector<ImageLineSegment> HoughCandidates(const cv::Mat& edges,
                                              const VanishingPointOptions& o) {
  std::vector<ImageLineSegment> lines;
  const double theta_rad = o.hough_theta_deg * kDegToRad;
  if (o.hough == HoughMethod::kProbabilistic) {
    std::vector<cv::Vec4i> segments;
    cv::HoughLinesP(edges, segments, o.hough_rho_px, theta_rad, o.hough_votes, o.min_line_length_px,
                    o.max_line_gap_px);
    for (const cv::Vec4i& s : segments) {
      lines.push_back(ImageLineSegment{Eigen::Vector2d(s[0], s[1]), Eigen::Vector2d(s[2], s[3])});
    }
    // Longest first; ties by coordinates so that the order is total (deterministic).
    std::stable_sort(lines.begin(), lines.end(),
                     [](const ImageLineSegment& x, const ImageLineSegment& y) {
                       const double lx = Length(x), ly = Length(y);
                       if (lx != ly) return lx > ly;
                       return std::make_tuple(x.a_px.y(), x.a_px.x(), x.b_px.y(), x.b_px.x()) <
                              std::make_tuple(y.a_px.y(), y.a_px.x(), y.b_px.y(), y.b_px.x());
                     });
  } else {
    std::vector<cv::Vec2f> polar;
    cv::HoughLines(edges, polar, o.hough_rho_px, theta_rad, o.hough_votes);
    for (const cv::Vec2f& p : polar) {
      if (auto line = ClipToImage(p[0], p[1], edges.cols, edges.rows)) lines.push_back(*line);
    }
  }
  return lines;
}

// The segment re-fitted to the edge pixels within `band_px` of it (total least squares: the
// principal axis of their scatter), its ends projected onto the fit. HoughLinesP's endpoints are
// edge pixels (integers) and HoughLines' lines lie on the accumulator's grid; the fit over every
// edge pixel of a long line is good to a small fraction of a pixel. Unchanged when fewer than
// ten edge pixels lie near it.
ImageLineSegment RefineToEdges(const ImageLineSegment& line, const cv::Mat& edges, double band_px) {
  const Eigen::Vector2d d = line.b_px - line.a_px;
  const double length = d.norm();
  if (!(length > 0.0)) return line;
  const Eigen::Vector2d t = d / length, n(-t.y(), t.x());
  const int x0 =
      std::max(0, static_cast<int>(std::floor(std::min(line.a_px.x(), line.b_px.x()) - band_px)));
  const int x1 =
      std::min(edges.cols - 1,
               static_cast<int>(std::ceil(std::max(line.a_px.x(), line.b_px.x()) + band_px)));
  const int y0 =
      std::max(0, static_cast<int>(std::floor(std::min(line.a_px.y(), line.b_px.y()) - band_px)));
  const int y1 =
      std::min(edges.rows - 1,
               static_cast<int>(std::ceil(std::max(line.a_px.y(), line.b_px.y()) + band_px)));
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  Eigen::Matrix2d sum_sq = Eigen::Matrix2d::Zero();
  int count = 0;
  // Walk the band along the line's major axis: O(length * band) pixels, not the bounding box.
  const bool along_x = std::abs(t.x()) >= std::abs(t.y());
  const int lo = along_x ? x0 : y0, hi = along_x ? x1 : y1;
  for (int s = lo; s <= hi; ++s) {
    // The line's other coordinate at this column (or row).
    const double r = along_x ? line.a_px.y() + (s - line.a_px.x()) * t.y() / t.x()
                             : line.a_px.x() + (s - line.a_px.y()) * t.x() / t.y();
    const double reach = band_px / (along_x ? std::abs(t.x()) : std::abs(t.y()));
    const int r0 = static_cast<int>(std::floor(r - reach)),
              r1 = static_cast<int>(std::ceil(r + reach));
    for (int q = r0; q <= r1; ++q) {
      const int x = along_x ? s : q, y = along_x ? q : s;
      if (x < x0 || x > x1 || y < y0 || y > y1 || !edges.at<std::uint8_t>(y, x)) continue;
      const Eigen::Vector2d p(x, y);
      const double along = (p - line.a_px).dot(t);
      if (std::abs((p - line.a_px).dot(n)) > band_px || along < -band_px ||
          along > length + band_px) {
        continue;
      }
      sum += p;
      sum_sq += p * p.transpose();
      ++count;
    }
  }
  if (count < 10) return line;
  const Eigen::Vector2d mean = sum / count;
  const Eigen::Matrix2d scatter = sum_sq / count - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
  Eigen::Vector2d direction = eigen.eigenvectors().col(1);
  if (direction.dot(t) < 0) direction = -direction;
  return ImageLineSegment{mean + (line.a_px - mean).dot(direction) * direction,
                          mean + (line.b_px - mean).dot(direction) * direction, count};
}

// Merges the segments that lie on one image line (pieces of an edge broken by texture or
// occlusion, or the neighbouring accumulator cells of one edge): a segment within `angle_rad` of
// a kept one, both of its ends within `distance_px` of the kept one's line, extends the kept one
// (its ends projected onto it) instead of adding a line. `lines` come strongest first, so the
// longest piece stays. Without this, one long edge broken into pieces would count as several
// lines, and two such edges would meet in a "vanishing point" of their own.
std::vector<ImageLineSegment> MergeCollinear(const std::vector<ImageLineSegment>& lines,
                                             double angle_rad, double distance_px,
                                             int* merged_count) {
  std::vector<ImageLineSegment> merged;
  const double cos_tol = std::cos(angle_rad);
  for (const ImageLineSegment& line : lines) {
    const Eigen::Vector2d d = line.b_px - line.a_px;
    if (!(d.norm() > 0.0)) continue;
    const Eigen::Vector2d t = d.normalized();
    bool absorbed = false;
    for (ImageLineSegment& kept : merged) {
      const Eigen::Vector2d kt = (kept.b_px - kept.a_px).normalized();
      const Eigen::Vector2d kn(-kt.y(), kt.x());
      if (std::abs(t.dot(kt)) < cos_tol) continue;
      if (std::abs((line.a_px - kept.a_px).dot(kn)) > distance_px ||
          std::abs((line.b_px - kept.a_px).dot(kn)) > distance_px) {
        continue;
      }
      // Extend kept along its own direction over both segments' extents.
      double lo = 0.0, hi = (kept.b_px - kept.a_px).dot(kt);
      for (const Eigen::Vector2d& p : {line.a_px, line.b_px}) {
        const double s = (p - kept.a_px).dot(kt);
        lo = std::min(lo, s);
        hi = std::max(hi, s);
      }
      const Eigen::Vector2d origin = kept.a_px;
      kept.a_px = origin + lo * kt;
      kept.b_px = origin + hi * kt;
      absorbed = true;
      break;
    }
    if (absorbed) {
      ++*merged_count;
    } else {
      merged.push_back(line);
    }
  }
  return merged;
}

// True when the line lies within `reject_rad` of the image's u (horizontal) or v (vertical) axis.
bool NearlyAxisParallel(const ImageLineSegment& line, double reject_rad) {
  const Eigen::Vector2d d = line.b_px - line.a_px;
  // Angle to the u axis folded into [0, pi/2].
  const double angle = std::atan2(std::abs(d.y()), std::abs(d.x()));
  return angle < reject_rad || angle > std::numbers::pi / 2 - reject_rad;
}

// RMS angle (rad) of the lines' unit normals about their principal direction: asin of the root of
// the smaller eigenvalue of A^T A / M (P1 eq. 3's A). Two line families at +-phi give phi.
double DirectionSpreadRad(const std::vector<ImageLineSegment>& lines) {
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const ImageLineSegment& line : lines) {
    const Eigen::Vector2d d = (line.b_px - line.a_px).normalized();
    const Eigen::Vector2d n(-d.y(), d.x());
    scatter += n * n.transpose();
  }
  scatter /= static_cast<double>(lines.size());
  const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvalues()(0);
  return std::asin(std::sqrt(std::clamp(smallest, 0.0, 1.0)));
}

// True when the point falls inside the segment: its projection onto the segment's line lies
// more than `tol_px` from both ends. The image of a 3D line's part in front of the camera ends
// at the vanishing point of its direction, so a segment never passes through its own vanishing
// point; lines that cross there converge somewhere else (or nowhere).
bool Inside(const ImageLineSegment& line, const Eigen::Vector2d& point, double tol_px) {
  const Eigen::Vector2d d = line.b_px - line.a_px;
  const double length = d.norm();
  const double s = (point - line.a_px).dot(d) / length;
  return s > tol_px && s < length - tol_px;
}

// The lines that agree with the best-supported intersection of two of them: the pair whose
// intersection has the most lines within `tol_px` (and, for segments, not inside them), ties
// broken by the smaller summed distance, then by the first pair. Pairs within 1 degree of
// parallel meet too far away to be placed and are skipped. O(M^3) for M lines (max_lines bounds
// M). Deterministic: no sampling.
std::vector<std::size_t> ConsensusSupport(const std::vector<ImageLineSegment>& lines, double tol_px,
                                          bool segments) {
  const std::size_t m = lines.size();
  std::vector<Eigen::Vector2d> normals(m);
  std::vector<double> offsets(m);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector2d t = (lines[k].b_px - lines[k].a_px).normalized();
    normals[k] = Eigen::Vector2d(-t.y(), t.x());
    offsets[k] = normals[k].dot(lines[k].a_px);  // P1 eq. 1: a u + b v = c
  }
  const double min_sin = std::sin(1.0 * kDegToRad);
  std::size_t best_count = 0;
  double best_sum = 0.0;
  Eigen::Vector2d best_point = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 1; j < m; ++j) {
      const double det = normals[i].x() * normals[j].y() - normals[i].y() * normals[j].x();
      if (std::abs(det) < min_sin) continue;
      const Eigen::Vector2d p((offsets[i] * normals[j].y() - offsets[j] * normals[i].y()) / det,
                              (normals[i].x() * offsets[j] - normals[j].x() * offsets[i]) / det);
      std::size_t count = 0;
      double sum = 0.0;
      for (std::size_t k = 0; k < m; ++k) {
        const double distance = std::abs(normals[k].dot(p) - offsets[k]);
        if (distance > tol_px || (segments && Inside(lines[k], p, tol_px))) continue;
        ++count;
        sum += distance;
      }
      if (count > best_count || (count == best_count && count > 0 && sum < best_sum)) {
        best_count = count;
        best_sum = sum;
        best_point = p;
      }
    }
  }
  std::vector<std::size_t> support;
  if (best_count < 2) return support;
  for (std::size_t k = 0; k < m; ++k) {
    const double distance = std::abs(normals[k].dot(best_point) - offsets[k]);
    if (distance <= tol_px && !(segments && Inside(lines[k], best_point, tol_px))) {
      support.push_back(k);
    }
  }
  return support;
}

// The number of distinct directions among the lines: their angles (mod 180 degrees) sorted and
// split where neighbours differ by more than `tol_rad`. The two edges of one thin line, or pieces
// of one edge the merging missed, count once: they are no evidence of convergence.
int DistinctDirections(const std::vector<ImageLineSegment>& lines, double tol_rad) {
  std::vector<double> angles;
  for (const ImageLineSegment& line : lines) {
    const Eigen::Vector2d d = line.b_px - line.a_px;
    double a = std::atan2(d.y(), d.x());
    if (a < 0) a += std::numbers::pi;
    if (a >= std::numbers::pi) a -= std::numbers::pi;
    angles.push_back(a);
  }
  if (angles.empty()) return 0;
  std::sort(angles.begin(), angles.end());
  int clusters = 1;
  for (std::size_t k = 1; k < angles.size(); ++k) clusters += angles[k] - angles[k - 1] > tol_rad;
  // The first and last cluster are one when they meet across 0 = 180 degrees.
  if (clusters > 1 && angles.front() + std::numbers::pi - angles.back() <= tol_rad) --clusters;
  return clusters;
}

// P1 eq. 4 over `lines`, then (options.weighted) re-solved with each line weighted by the inverse
// of its offset variance at the point (LineOffsetVariance), three rounds from P1's unweighted
// point. `residuals` gets each line's signed distance to the final point (px) and `rms_px` their
// RMS, weighted alike.
std::optional<Eigen::Vector2d> SolvePoint(const std::vector<ImageLineSegment>& lines, bool weighted,
                                          std::vector<double>* residuals, double* rms_px) {
  std::optional<Eigen::Vector2d> point = IntersectLines(lines, residuals);
  std::vector<double> point_weights(lines.size(), 1.0);  // the weights `point` was solved with
  for (int round = 0; weighted && point && round < 3; ++round) {
    std::vector<double> weights(lines.size());
    for (std::size_t i = 0; i < lines.size(); ++i) {
      weights[i] = 1.0 / LineOffsetVariance(lines[i], *point);
    }
    std::vector<double> next_residuals;
    const std::optional<Eigen::Vector2d> next = IntersectLines(lines, &next_residuals, &weights);
    if (!next) break;  // a weight underflowed (a point absurdly far away): keep the last solution
    point = next;
    *residuals = std::move(next_residuals);
    point_weights = std::move(weights);
  }
  if (point) {
    double sum = 0.0, total = 0.0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      sum += point_weights[i] * (*residuals)[i] * (*residuals)[i];
      total += point_weights[i];
    }
    *rms_px = std::sqrt(sum / total);
  }
  return point;
}

}  // namespace

std::string HoughMethodName(HoughMethod method) { return NameOf(kHoughMethodNames, method); }

std::string VanishingPointStatusName(VanishingPointStatus status) {
  return NameOf(kStatusNames, status);
}

std::optional<OptionsProblem> VanishingPointOptions::Check() const {
  if (auto problem = CheckOptionBounds(VanishingPointOptionsTable(), *this)) return problem;
  if (canny_high < canny_low) {
    return OptionsProblem{"canny_high",
                          "must be at least canny_low (" + std::to_string(canny_low) + ")"};
  }
  if (min_directions > min_lines) {
    return OptionsProblem{"min_directions",
                          "must be at most min_lines (" + std::to_string(min_lines) + ")"};
  }
  if (min_lines > max_lines) {
    return OptionsProblem{"min_lines",
                          "must be at most max_lines (" + std::to_string(max_lines) + ")"};
  }
  return std::nullopt;
}

double LineOffsetVariance(const ImageLineSegment& line, const Eigen::Vector2d& point) {
  const Eigen::Vector2d d = line.b_px - line.a_px;
  const double length = std::max(d.norm(), 1.0);
  const double n = line.support_px > 0 ? line.support_px : std::max(length, 2.0);
  const double along = (point - 0.5 * (line.a_px + line.b_px)).dot(d) / length;
  return 1.0 / n + 12.0 * along * along / (n * length * length);
}

std::optional<Eigen::Vector2d> IntersectLines(const std::vector<ImageLineSegment>& lines,
                                              std::vector<double>* residuals_px,
                                              const std::vector<double>* weights) {
  if (residuals_px) residuals_px->clear();
  CheckOrDie(!weights || weights->size() == lines.size(), "slam::IntersectLines",
             "one weight per line");
  const Eigen::Index m = static_cast<Eigen::Index>(lines.size());
  if (m < 2) return std::nullopt;
  // P1 eqs. 1-3: row i of A is (a_i, b_i), the unit normal of line i, and c_i = (a_i, b_i) . p
  // for any point p on it, so a_i u + b_i v = c_i holds on the line.
  Eigen::MatrixX2d A(m, 2);
  Eigen::VectorXd c(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const ImageLineSegment& line = lines[static_cast<std::size_t>(i)];
    const Eigen::Vector2d d = line.b_px - line.a_px;
    if (!(d.norm() > 0.0)) return std::nullopt;  // a degenerate segment has no direction
    const Eigen::Vector2d normal = Eigen::Vector2d(-d.y(), d.x()) / d.norm();
    A.row(i) = normal.transpose();
    c(i) = normal.dot(line.a_px);
  }
  // P1 eq. 4: u = A^+ c, A^+ = (A^T A)^-1 A^T (the normal equations of the 2x2 system); with
  // weights, A^T W A and A^T W c.
  Eigen::VectorXd w = Eigen::VectorXd::Ones(m);
  if (weights) {
    for (Eigen::Index i = 0; i < m; ++i) {
      w(i) = (*weights)[static_cast<std::size_t>(i)];
      if (!(w(i) > 0.0) || !std::isfinite(w(i))) return std::nullopt;
    }
  }
  const Eigen::Matrix2d AtA = A.transpose() * w.asDiagonal() * A;
  const double det = AtA.determinant();
  if (!(std::abs(det) > 1e-12 * AtA.squaredNorm())) return std::nullopt;
  const Eigen::Vector2d u = AtA.inverse() * (A.transpose() * w.asDiagonal() * c);
  if (residuals_px) {
    const Eigen::VectorXd r = A * u - c;
    residuals_px->assign(r.data(), r.data() + r.size());
  }
  return u;
}

std::optional<VanishingPoint> DetectVanishingPoint(const Image8& image,
                                                   const VanishingPointOptions& options,
                                                   VanishingPointReport* report) {
  CheckOrDie(!options.Check(), "slam::DetectVanishingPoint", "the options fail their Check()");
  VanishingPointReport local;
  VanishingPointReport& out = report ? *report : local;
  out = VanishingPointReport{};
  if (image.width < 3 || image.height < 3) return std::nullopt;  // no edges in so small an image

  // P1 Fig. 3a-b: the binary edge image (Canny), after smoothing away sensor noise.
  cv::Mat grey = GreyMat(image);
  if (options.blur_sigma_px > 0) {
    cv::Mat blurred;
    cv::GaussianBlur(grey, blurred, cv::Size(0, 0), options.blur_sigma_px, options.blur_sigma_px,
                     cv::BORDER_REPLICATE);
    grey = blurred;
  }
  cv::Mat edges;
  cv::Canny(grey, edges, options.canny_low, options.canny_high, 3, /*L2gradient=*/true);

  // P1 Fig. 3c: candidate lines (Hough); P1 section 2: those nearly parallel to the u or v axis
  // do not converge to the vanishing point and are rejected.
  const std::vector<ImageLineSegment> candidates = HoughCandidates(edges, options);
  out.quality.candidate_count = static_cast<int>(candidates.size());
  const double reject_rad = options.axis_reject_deg * kDegToRad;
  std::vector<ImageLineSegment> kept;
  for (const ImageLineSegment& line : candidates) {
    if (NearlyAxisParallel(line, reject_rad)) {
      ++out.quality.rejected_axis_count;
    } else {
      kept.push_back(line);
    }
  }
  // One line per image line (pieces merged), re-fitted to its edge pixels, the strongest
  // max_lines of them.
  kept = MergeCollinear(kept, options.merge_angle_deg * kDegToRad, options.merge_distance_px,
                        &out.quality.merged_count);
  std::vector<ImageLineSegment>& lines = out.candidate_lines;
  for (const ImageLineSegment& line : kept) {
    if (static_cast<int>(lines.size()) >= options.max_lines) break;
    lines.push_back(options.refine_band_px > 0 ? RefineToEdges(line, edges, options.refine_band_px)
                                               : line);
  }
  if (static_cast<int>(lines.size()) < options.min_lines) {
    out.status = VanishingPointStatus::kTooFewLines;
    return std::nullopt;
  }
  if (DirectionSpreadRad(lines) < options.min_direction_spread_deg * kDegToRad) {
    out.status = VanishingPointStatus::kIllConditioned;
    return std::nullopt;
  }

  // Beyond P1 (P1 solves eq. 4 once over every line): a consensus seed, then P1 eq. 4 over the
  // lines that agree with it, then the outlier pass. Lines of other directions (the floor's
  // cross seams seen at an angle, texture edges) would otherwise pull the least-squares point.
  const bool segments = options.hough == HoughMethod::kProbabilistic;
  const double tol = options.outlier_distance_px;
  std::vector<std::size_t> support = ConsensusSupport(lines, tol, segments);
  std::vector<ImageLineSegment> used;
  for (std::size_t k : support) used.push_back(lines[k]);
  std::vector<double> residuals;
  double rms_px = 0.0;
  std::optional<Eigen::Vector2d> point;
  if (static_cast<int>(used.size()) >= options.min_lines) {
    point = SolvePoint(used, options.weighted, &residuals, &rms_px);
  }
  // The outlier pass: a line whose segment the point falls inside, else the line farthest from
  // the point beyond outlier_distance_px, is dropped and the point re-solved (P1 eq. 4); one line
  // per round, so at most max_lines rounds.
  while (point) {
    std::size_t worst = 0;
    double worst_badness = 0.0;
    for (std::size_t i = 0; i < used.size(); ++i) {
      const double badness = segments && Inside(used[i], *point, tol)
                                 ? std::numeric_limits<double>::infinity()
                                 : std::abs(residuals[i]);
      if (badness > worst_badness) {
        worst = i;
        worst_badness = badness;
      }
    }
    if (worst_badness <= tol) break;
    if (static_cast<int>(used.size()) <= options.min_lines) {
      point.reset();
      break;
    }
    used.erase(used.begin() + static_cast<std::ptrdiff_t>(worst));
    point = SolvePoint(used, options.weighted, &residuals, &rms_px);
  }
  out.quality.line_count = point ? static_cast<int>(used.size()) : 0;
  out.quality.rms_residual_px = point ? rms_px : 0.0;
  out.quality.rejected_outlier_count =
      static_cast<int>(lines.size()) - (point ? static_cast<int>(used.size()) : 0);
  out.quality.direction_count =
      point ? DistinctDirections(used, options.merge_angle_deg * kDegToRad) : 0;
  if (!point || out.quality.direction_count < options.min_directions) {
    out.status = VanishingPointStatus::kNotConverging;
    return std::nullopt;
  }
  if (DirectionSpreadRad(used) < options.min_direction_spread_deg * kDegToRad) {
    out.status = VanishingPointStatus::kIllConditioned;
    return std::nullopt;
  }
  if (out.quality.rms_residual_px > options.max_rms_residual_px) {
    out.status = VanishingPointStatus::kNotConverging;
    return std::nullopt;
  }
  const double margin = options.max_outside_image_px;
  if (point->x() < -0.5 - margin || point->x() > image.width - 0.5 + margin ||
      point->y() < -0.5 - margin || point->y() > image.height - 0.5 + margin) {
    out.status = VanishingPointStatus::kOutsideImage;
    return std::nullopt;
  }
  out.status = VanishingPointStatus::kFound;
  return VanishingPoint{*point, std::move(used), out.quality};
}

}  // namespace corridorsim::slam
