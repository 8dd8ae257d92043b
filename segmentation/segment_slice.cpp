// Segmentation of a slice into sections (see segment_slice.h). The mask is cleaned with OpenCV
// (threshold, field of view, morphology, small components); the section-contours are the iso-line
// of the smoothed image at the threshold, with the field nudged just across zero wherever cleaning
// changed a pixel, so the sub-pixel contours and the cleaned mask have the same topology.
#include "segmentation/segment_slice.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "geometry/polygon.h"
#include "segmentation/iso_contours.h"

namespace xsect {

namespace {

cv::Mat disk(int r) { return cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * r + 1, 2 * r + 1}); }

/// Removes 8-connected components of `mask` (0/255) smaller than minPixels.
void removeSmall(cv::Mat& mask, double minPixels) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  std::vector<unsigned char> keep(n, 1);
  for (int l = 1; l < n; ++l) keep[l] = stats.at<int>(l, cv::CC_STAT_AREA) >= minPixels;
  for (int j = 0; j < mask.rows; ++j)
    for (int i = 0; i < mask.cols; ++i) {
      const int l = labels.at<int>(j, i);
      if (l > 0 && !keep[l]) mask.at<unsigned char>(j, i) = 0;
    }
}

}  // namespace

SegmentedSlice segmentSlice(const cv::Mat& image, const cv::Mat& fov, const Vec2& spacing,
                            const SegmentationParams& p) {
  CV_Assert(image.channels() == 1 && !image.empty());
  CV_Assert(fov.empty() || (fov.size() == image.size() && fov.type() == CV_8U));
  SegmentedSlice out;

  // 1. Field whose zero level is the boundary: smoothed image minus threshold (labels: 0/1 - 0.5).
  cv::Mat f;
  if (p.method == "labels") {
    cv::Mat nz = image != 0;
    nz.convertTo(f, CV_32F, 1.0 / 255.0);
  } else {
    image.convertTo(f, CV_32F);
  }
  if (p.sigma_px > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), p.sigma_px, p.sigma_px,
                                       cv::BORDER_REPLICATE);
  double t = p.threshold;
  if (p.method == "labels") {
    t = 0.5;
  } else if (p.method == "otsu") {
    const double scale = image.depth() == CV_16U ? 1.0 / 256.0 : 1.0;
    cv::Mat f8;
    f.convertTo(f8, CV_8U, scale);
    t = cv::threshold(f8, f8, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU) / scale;
  }
  out.threshold_used = t;
  f -= t;

  // 2. Cleaned mask: threshold, field of view, morphology, small components (and small holes).
  cv::Mat mask = f > 0;
  if (!fov.empty()) mask &= (fov != 0);
  if (p.open_radius_px > 0) cv::morphologyEx(mask, mask, cv::MORPH_OPEN, disk(p.open_radius_px));
  if (p.close_radius_px > 0)
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, disk(p.close_radius_px));
  if (!fov.empty()) mask &= (fov != 0);
  if (p.min_area_mm2 > 0) {
    const double minPixels = p.min_area_mm2 / (spacing.x() * spacing.y());
    removeSmall(mask, minPixels);
    cv::Mat holes = ~mask;
    removeSmall(holes, minPixels);
    mask = ~holes;
  }

  // 3. Make the field agree with the mask: flip by a small margin where cleaning changed a pixel.
  const float nudge = 1e-3f * float(std::max(1.0, std::abs(t)));
  for (int j = 0; j < f.rows; ++j) {
    float* row = f.ptr<float>(j);
    const unsigned char* m = mask.ptr<unsigned char>(j);
    for (int i = 0; i < f.cols; ++i) {
      if (m[i] && row[i] <= 0) row[i] = nudge;
      if (!m[i] && row[i] > 0) row[i] = -nudge;
    }
  }

  // 4. Does a section reach the edge of what was observed?
  cv::Mat edge = cv::Mat::zeros(mask.size(), CV_8U);
  edge.row(0).setTo(255);
  edge.row(edge.rows - 1).setTo(255);
  edge.col(0).setTo(255);
  edge.col(edge.cols - 1).setTo(255);
  if (!fov.empty()) {
    cv::Mat outside = fov == 0, grown;
    cv::dilate(outside, grown, disk(1));
    edge |= grown;
  }
  out.touches_fov_edge = cv::countNonZero(edge & mask) > 0;

  // 5. Sub-pixel contours -> rings in mm; simplification; holes attached to their outer ring.
  std::vector<Ring> rings = isoContours(f);
  std::vector<Ring> outers, holes;
  for (auto& r : rings) {
    if (p.simplify_mm > 0) {
      std::vector<cv::Point2f> pts, simp;
      for (const auto& q : r) pts.emplace_back(float(q.x()), float(q.y()));
      cv::approxPolyDP(pts, simp, p.simplify_mm / std::min(spacing.x(), spacing.y()), true);
      if (simp.size() < 3) continue;
      r.clear();
      for (const auto& q : simp) r.emplace_back(q.x, q.y);
    }
    for (auto& q : r) q = Vec2(q.x() * spacing.x(), q.y() * spacing.y());
    const double a = signedArea(r);
    if (std::abs(a) < 1e-12) continue;
    (a > 0 ? outers : holes).push_back(std::move(r));
  }
  out.sections = sectionsFromRings(std::move(outers), std::move(holes));
  return out;
}

}  // namespace xsect
