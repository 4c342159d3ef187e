#include "slam/features/ceiling_lamps.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "common/random.h"
#include "slam/features/image_conversion.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> CeilingLampOptions::Check() const {
  if (auto p = CheckOptionBounds(CeilingLampOptionsTable(), *this)) return p;
  if (max_area_px < min_area_px) {
    return OptionsProblem{"max_area_px", "must be at least min_area_px"};
  }
  if (canny_high < canny_low) return OptionsProblem{"canny_high", "must be at least canny_low"};
  return std::nullopt;
}

std::optional<Eigen::Vector2d> ThreePointCentre(const Eigen::Vector2d& p1,
                                                const Eigen::Vector2d& p2,
                                                const Eigen::Vector2d& p3) {
  // P3 eq. 1 writes the bisectors as v = m u + n and eq. 2 intersects them; the same two lines
  // in the form a . c = b (no infinite slope for a vertical bisector):
  //   bisector of p1p2: (p2 - p1) . c = (|p2|^2 - |p1|^2) / 2, and likewise for p2p3.
  const Eigen::Vector2d a1 = p2 - p1, a2 = p3 - p2;
  const double b1 = 0.5 * (p2.squaredNorm() - p1.squaredNorm());
  const double b2 = 0.5 * (p3.squaredNorm() - p2.squaredNorm());
  const double det = a1.x() * a2.y() - a1.y() * a2.x();
  // |det| = |a1| |a2| sin(angle between the chords): nearly collinear points have no centre.
  if (!(std::abs(det) > 1e-6 * a1.norm() * a2.norm()) || !std::isfinite(det)) return std::nullopt;
  return Eigen::Vector2d((b1 * a2.y() - b2 * a1.y()) / det, (a1.x() * b2 - a2.x() * b1) / det);
}

namespace {

struct Region {
  int label = 0;
  cv::Rect box;
  int area = 0;
};

// The edge points of one region on the plane the circle test runs on.
struct EdgePoints {
  std::vector<Eigen::Vector2d> pixel;  // image pixels
  std::vector<Eigen::Vector2d> plane;  // the normalised plane scaled by the focal length (px)
  bool cut_by_border = false;
  double edge_contrast = 0.0;  // grey levels
};

EdgePoints RegionEdgePoints(const cv::Mat& grey, const cv::Mat& labels, const Region& region,
                            const CameraModel* model, const CeilingLampOptions& o) {
  EdgePoints out;
  const cv::Rect roi =
      (region.box + cv::Size(6, 6) - cv::Point(3, 3)) & cv::Rect(0, 0, grey.cols, grey.rows);
  cv::Mat edges;
  cv::Canny(grey(roi), edges, o.canny_low, o.canny_high, 3, true);
  // Edge pixels within 2 px of the region (a saturated lamp's edge lies on its outline).
  // Edge pixels on or next to the region's outline (a saturated lamp's edge lies on its outline;
  // the seams and fixtures that touch it do not).
  const cv::Mat inside = labels(roi) == region.label;
  cv::Mat eroded, near, ring;
  cv::erode(inside, eroded, cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3)));
  const cv::Mat outline = inside & ~eroded;
  cv::dilate(outline, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  // The step of grey level across the outline: the outline's mean against that of the pixels
  // 2 px outside it. A lamp is a sharp step from its light to the ceiling; the soft glare a lamp
  // throws on a wall crosses the threshold in a circle too, but with a small step.
  cv::Mat grown1, grown2;
  cv::dilate(inside, grown1, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  cv::dilate(inside, grown2, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
  ring = grown2 & ~grown1;
  out.edge_contrast = cv::mean(grey(roi), outline)[0] - cv::mean(grey(roi), ring)[0];
  const double f = model ? model->intrinsics().fx : 1.0;
  for (int y = 0; y < roi.height; ++y) {
    const std::uint8_t* e = edges.ptr<std::uint8_t>(y);
    const std::uint8_t* n = near.ptr<std::uint8_t>(y);
    for (int x = 0; x < roi.width; ++x) {
      if (!e[x] || !n[x]) continue;
      const int u = roi.x + x, v = roi.y + y;
      // P3 Fig. 3b: the border cuts the lamp here; its edge is not the lamp's.
      if (u < o.border_margin_px || v < o.border_margin_px || u >= grey.cols - o.border_margin_px ||
          v >= grey.rows - o.border_margin_px) {
        out.cut_by_border = true;
        continue;
      }
      const Eigen::Vector2d pixel(u, v);
      Eigen::Vector2d plane = pixel;
      if (model) {
        if (!model->IsInImage(pixel)) continue;
        const Eigen::Vector3d bearing = model->Unproject(pixel);
        // Beyond about 80 deg from the axis the normalised plane stretches without bound; such
        // points are the limit of the lens, as the border is.
        if (!(bearing.z() > 0.17)) {
          out.cut_by_border = true;
          continue;
        }
        plane = f * bearing.head<2>() / bearing.z();
      }
      out.pixel.push_back(pixel);
      out.plane.push_back(plane);
    }
  }
  return out;
}

CeilingLampRegion TestRegion(const cv::Mat& grey, const cv::Mat& labels, const Region& region,
                             const CameraModel* model, const CeilingLampOptions& o) {
  CeilingLampRegion r;
  r.area_px = region.area;
  const EdgePoints points = RegionEdgePoints(grey, labels, region, model, o);
  r.edge_points = static_cast<int>(points.plane.size());
  r.cut_by_border = points.cut_by_border;
  r.edge_contrast = points.edge_contrast;
  // Where the region lies, as a fallback centre for rejected regions: its bounding box centre.
  r.center_px = Eigen::Vector2d(region.box.x + 0.5 * (region.box.width - 1),
                                region.box.y + 0.5 * (region.box.height - 1));
  if (r.edge_contrast < o.min_edge_contrast) {
    r.rejection = "low_contrast";
    return r;
  }
  if (r.edge_points < o.min_edge_points) {
    r.rejection = "too_few_edge_points";
    return r;
  }
  const std::vector<Eigen::Vector2d>& q = points.plane;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : q) mean += p;
  mean /= double(q.size());
  double spread2 = 0.0;
  for (const Eigen::Vector2d& p : q) spread2 += (p - mean).squaredNorm();
  const double min_chord = o.min_chord_fraction * std::sqrt(spread2 / double(q.size()));
  const double min_chord2 = min_chord * min_chord;

  // P3 eqs. 1-2 repeated over random triples.
  RandomStream rng(o.seed,
                   (std::uint64_t(region.box.x) << 32) ^ (std::uint64_t(region.box.y) << 16) ^
                       std::uint64_t(region.box.width),
                   "slam.ceiling_lamps");
  const auto n = static_cast<std::int64_t>(q.size());
  std::vector<Eigen::Vector2d> centres;
  centres.reserve(std::size_t(o.triples));
  for (int attempt = 0; attempt < 20 * o.triples && int(centres.size()) < o.triples; ++attempt) {
    const auto i = std::size_t(rng.UniformInt(0, n - 1));
    const auto j = std::size_t(rng.UniformInt(0, n - 1));
    const auto k = std::size_t(rng.UniformInt(0, n - 1));
    if ((q[i] - q[j]).squaredNorm() < min_chord2 || (q[j] - q[k]).squaredNorm() < min_chord2 ||
        (q[i] - q[k]).squaredNorm() < min_chord2) {
      continue;
    }
    if (const std::optional<Eigen::Vector2d> c = ThreePointCentre(q[i], q[j], q[k])) {
      centres.push_back(*c);
    }
  }
  if (int(centres.size()) < std::max(3, o.triples / 2)) {
    r.rejection = "not_circular";
    r.sigma1_px = r.sigma2_px = std::numeric_limits<double>::infinity();
    return r;
  }
  // The centres back in the image (through the model: the image of the centre of a circle on a
  // plane parallel to the image plane is the centre of its image there), where K_conv applies:
  // the normalised plane stretches towards the edge of a wide lens, the pixels do not.
  if (model) {
    const double f = model->intrinsics().fx;
    std::vector<Eigen::Vector2d> in_image;
    in_image.reserve(centres.size());
    for (const Eigen::Vector2d& c : centres) {
      if (const std::optional<Eigen::Vector2d> pixel =
              model->Project(Eigen::Vector3d(c.x() / f, c.y() / f, 1.0))) {
        in_image.push_back(*pixel);
      }
    }
    centres.swap(in_image);
    if (int(centres.size()) < std::max(3, o.triples / 2)) {
      r.rejection = "not_circular";
      r.sigma1_px = r.sigma2_px = std::numeric_limits<double>::infinity();
      return r;
    }
  }
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : centres) c += p;
  c /= double(centres.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : centres) cov += (p - c) * (p - c).transpose();
  cov /= double(centres.size());
  const Eigen::Vector2d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues();
  r.sigma1_px = std::sqrt(std::max(eig(1), 0.0));
  r.sigma2_px = std::sqrt(std::max(eig(0), 0.0));
  r.circular = r.sigma1_px < o.k_conv_px && r.sigma2_px < o.k_conv_px;
  if (!r.circular) r.rejection = "not_circular";
  r.center_px = c;
  double radius = 0.0;
  for (const Eigen::Vector2d& p : points.pixel) radius += (p - r.center_px).norm();
  r.radius_px = radius / double(points.pixel.size());
  return r;
}

}  // namespace

CeilingLampDetection DetectCeilingLamps(const Image8& image, const CameraModel* model,
                                        const CeilingLampOptions& options) {
  CheckOrDie(!options.Check(), "slam::DetectCeilingLamps", "the options fail their Check()");
  CheckOrDie(!model || (model->width() == image.width && model->height() == image.height),
             "slam::DetectCeilingLamps", "the camera model's size is not the image's");
  CeilingLampDetection out;
  const cv::Mat grey = GreyMat(image);
  const cv::Mat bright = grey > options.brightness_threshold;
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(bright, labels, stats, centroids, 8, CV_32S);
  std::vector<Region> regions;
  for (int label = 1; label < count; ++label) {
    const int area = stats.at<int>(label, cv::CC_STAT_AREA);
    if (area < options.min_area_px || area > options.max_area_px) continue;
    regions.push_back(
        {label,
         cv::Rect(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                  stats.at<int>(label, cv::CC_STAT_WIDTH),
                  stats.at<int>(label, cv::CC_STAT_HEIGHT)),
         area});
  }
  // Largest first; ties in raster order of the bounding box (the labels' order is raster order).
  std::stable_sort(regions.begin(), regions.end(),
                   [](const Region& a, const Region& b) { return a.area > b.area; });
  out.regions = static_cast<int>(regions.size());
  if (regions.size() > std::size_t(options.max_regions)) {
    out.regions_skipped = out.regions - options.max_regions;
    regions.resize(std::size_t(options.max_regions));
  }
  for (const Region& region : regions) {
    CeilingLampRegion r = TestRegion(grey, labels, region, model, options);
    (r.circular ? out.lamps : out.rejected).push_back(r);
  }
  return out;
}

}  // namespace corridorsim::slam
