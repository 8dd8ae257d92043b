// Segmentation of a slice into sections (see segment_slice.h). The mask is cleaned with OpenCV
// (threshold, field of view, morphology, small components); the section-contours are the iso-line
// of the smoothed image at the threshold, with the field nudged just across zero wherever cleaning
// changed a pixel, so the sub-pixel contours and the cleaned mask have the same topology.
// Label images: the same per label, on the label's bounding box plus a margin wide enough that
// the result inside it equals the whole-image result; the labels' contours are then traced
// together (labelIsoContours) so that they tile the plane.
#include "segmentation/segment_slice.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <climits>
#include <cmath>

#include "geometry/core/disjoint_sets.h"
#include "geometry/core/polygon.h"
#include "geometry/core/ring_repair.h"
#include "segmentation/acoustic_shadows.h"
#include "segmentation/grey_field.h"
#include "segmentation/iso_contours.h"
#include "segmentation/series_threshold.h"

namespace xsect {

namespace {

cv::Mat disk(int r) { return cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * r + 1, 2 * r + 1}); }

/// Which sides of a (cropped) mask are sides of the whole image: left, top, right, bottom.
struct ImageSides {
  bool left = true, top = true, right = true, bottom = true;
};

/// Removes the components of `mask` (0/255) smaller than minPixels.
/// With `saddles` (one field traced by isoContours), connected as isoContours traces them: through
/// pixel edges, and diagonally through a saddle cell whose bilinear centre value is on their side
/// (f as it stands for the current mask: a pixel cleaning changed counts as just across zero, an
/// exact zero as just below it). 8-connected, a one-pixel hole touching the background at a corner
/// was part of the background while its contour closed around it: such holes at a vessel tree's
/// crotches stayed sections' holes whatever min_area_mm2 said. Without `saddles` (labels, which
/// labelIsoContours joins across saddles by the other corners' materials and the labels' maximum):
/// 8-connected.
/// @param inside  the mask of f > 0 that cleaning has made so far.
/// @param holes   `mask` holds the holes (the complement of `inside`), not the regions. Holes
///                touching a side of the crop that is not a side of the image are kept: they go
///                on outside the crop, so their size there says nothing.
void removeSmall(cv::Mat& mask, const cv::Mat& f, const cv::Mat& inside, float nudge, double minPixels,
                 const ImageSides& sides, bool holes, bool saddles) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, saddles ? 4 : 8, CV_32S);
  if (n <= 1) return;
  const auto value = [&](int j, int i) {
    const float v = f.at<float>(j, i);
    return inside.at<unsigned char>(j, i) ? (v > 0 ? v : nudge) : (v < 0 ? v : v == 0 ? -1e-6f : -nudge);
  };
  DisjointSets joined{std::size_t(n)};
  for (int j = 0; saddles && j + 1 < mask.rows; ++j) {
    const unsigned char *m0 = mask.ptr<unsigned char>(j), *m1 = mask.ptr<unsigned char>(j + 1);
    for (int i = 0; i + 1 < mask.cols; ++i) {
      if (m0[i] != m1[i + 1] || m0[i + 1] != m1[i] || m0[i] == m0[i + 1]) continue;  // not a saddle
      if (saddleJoinsInside(value(j, i), value(j, i + 1), value(j + 1, i + 1), value(j + 1, i)) == holes)
        continue;  // the saddle joins the other pair
      if (m0[i]) joined.unite(std::size_t(labels.at<int>(j, i)), std::size_t(labels.at<int>(j + 1, i + 1)));
      else joined.unite(std::size_t(labels.at<int>(j, i + 1)), std::size_t(labels.at<int>(j + 1, i)));
    }
  }
  std::vector<std::int64_t> area(std::size_t(n), 0);
  std::vector<unsigned char> open(std::size_t(n), 0);
  for (int l = 1; l < n; ++l) {
    const std::size_t r = joined.find(std::size_t(l));
    area[r] += stats.at<int>(l, cv::CC_STAT_AREA);
    const int x = stats.at<int>(l, cv::CC_STAT_LEFT), y = stats.at<int>(l, cv::CC_STAT_TOP);
    const int w = stats.at<int>(l, cv::CC_STAT_WIDTH), h = stats.at<int>(l, cv::CC_STAT_HEIGHT);
    if ((x == 0 && !sides.left) || (y == 0 && !sides.top) || (x + w == mask.cols && !sides.right) ||
        (y + h == mask.rows && !sides.bottom))
      open[r] = 1;
  }
  std::vector<unsigned char> keep(std::size_t(n), 1);
  for (int l = 1; l < n; ++l) {
    const std::size_t r = joined.find(std::size_t(l));
    keep[std::size_t(l)] = double(area[r]) >= minPixels || (holes && open[r]);
  }
  if (std::all_of(keep.begin(), keep.end(), [](unsigned char k) { return k != 0; })) return;
  for (int j = 0; j < mask.rows; ++j) {
    const int* l = labels.ptr<int>(j);
    unsigned char* m = mask.ptr<unsigned char>(j);
    for (int i = 0; i < mask.cols; ++i)
      if (l[i] > 0 && !keep[std::size_t(l[i])]) m[i] = 0;
  }
}

/// The object's mask `mask` cut to its core (SegmentationParams::core_threshold): the pixels where
/// f >= core_depth, opened by the opening's radius less the reach (a part of the object that the
/// opening keeps is at least that much wider than its core, so the core's opening does not lose
/// it), grown by the reach of a blurred step (it crosses the core's level, a quarter of the way
/// between the classes, 0.67 sigma from where it crosses the threshold: the normal quantile of
/// 1/4; sigma rounded up to a pixel holds that). The cut mask is then closed by the opening's
/// radius within the threshold's mask: notches the cut leaves where the object's own speckle is
/// lighter near its edge fill again; a closing fills only concavities narrower than its disk, so
/// what was cut off comes back at most in the corners where the cut meets the object's edge
/// (tests/test_ultrasound_segmentation.cpp bounds the edge by the reach plus a pixel beyond where
/// the step crosses the core's level). Unobserved pixels count as core, so that the
/// core's opening does not erode against the view's edge or a shadow, which are not the object's.
/// Measured on the B-mode family (bench/ultrasound_family.py, 36 runs at 0.4 mm voxels): truth
/// topology on 34 (32 without the core); before the closing, a reach of 2 sigma gave 15 of 18
/// runs where 1 sigma gave 18, and the denser plus-ultrasound sweeps got 2-voxel cavities where
/// the cut notched a section next to a shadow.
void cutToCore(cv::Mat& mask, const cv::Mat& f, const cv::Mat& fov, const SegmentationParams& p, float core_depth) {
  const int reach = std::max(1, int(std::ceil(p.sigma_px)));
  cv::Mat core = f >= core_depth;
  if (!fov.empty()) core |= (fov == 0);
  if (p.open_radius_px > reach) cv::morphologyEx(core, core, cv::MORPH_OPEN, disk(p.open_radius_px - reach));
  cv::dilate(core, core, disk(reach));
  const cv::Mat threshold = mask.clone();
  mask &= core;
  if (p.open_radius_px > 0) {
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, disk(p.open_radius_px));
    mask &= threshold;
  }
}

/// Steps 2-4 on a field f (zero level = boundary; whole image or a crop of it with the crop's
/// `sides` on the image border): cleaned mask (field of view, morphology, small components and
/// holes), f nudged to agree with it. Returns whether the mask reaches the edge of what was
/// observed (image border or field of view).
/// `saddles`: f alone is traced (isoContours), not with other labels (see removeSmall).
/// `core_depth`: > 0, the object's pixels are kept only near where f >= core_depth (the core,
/// SegmentationParams::core_threshold); 0, no core.
bool cleanField(cv::Mat& f, const cv::Mat& fov, const Vec2& spacing, const SegmentationParams& p,
                float nudge, const ImageSides& sides, bool saddles, float core_depth = 0) {
  // 2. Cleaned mask: threshold, field of view, core, morphology, small components (and holes).
  cv::Mat mask = f > 0;
  if (!fov.empty()) mask &= (fov != 0);
  if (core_depth > 0) cutToCore(mask, f, fov, p, core_depth);
  if (p.open_radius_px > 0) cv::morphologyEx(mask, mask, cv::MORPH_OPEN, disk(p.open_radius_px));
  if (p.close_radius_px > 0)
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, disk(p.close_radius_px));
  if (!fov.empty()) mask &= (fov != 0);
  if (p.min_area_mm2 > 0) {
    const double minPixels = p.min_area_mm2 / (spacing.x() * spacing.y());
    removeSmall(mask, f, mask, nudge, minPixels, sides, false, saddles);
    cv::Mat holes = ~mask;
    removeSmall(holes, f, mask, nudge, minPixels, sides, true, saddles);
    mask = ~holes;
  }

  // 3. Make the field agree with the mask: flip by a small margin where cleaning changed a pixel.
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
  if (sides.top) edge.row(0).setTo(255);
  if (sides.bottom) edge.row(edge.rows - 1).setTo(255);
  if (sides.left) edge.col(0).setTo(255);
  if (sides.right) edge.col(edge.cols - 1).setTo(255);
  if (!fov.empty()) {
    cv::Mat outside = fov == 0, grown;
    cv::dilate(outside, grown, disk(1));
    edge |= grown;
  }
  return cv::countNonZero(edge & mask) > 0;
}

/// Step 5: rings in pixel coordinates -> simplified rings in mm -> sections (holes attached).
/// Simplified rings that cross are made simple (with p.repair_contours); `repaired` says so.
std::vector<Section> sectionsOfRings(std::vector<Ring> rings, const Vec2& spacing,
                                     const SegmentationParams& p, bool* repaired) {
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
  if (p.simplify_mm > 0 && p.repair_contours) {
    RingRepair fixed = repairRings(outers, holes);
    if (fixed.changed) {
      *repaired = true;
      outers = std::move(fixed.outers);
      holes = std::move(fixed.holes);
    }
  }
  return sectionsFromRings(std::move(outers), std::move(holes));
}

/// Method `labels`: one field per distinct non-zero value, on its bounding box plus a margin.
SegmentedSlice segmentLabels(const cv::Mat& image, const cv::Mat& fov, const Vec2& spacing,
                             const SegmentationParams& p) {
  CV_Assert(image.depth() == CV_8U || image.depth() == CV_16U);
  cv::Mat lab;
  if (image.depth() == CV_16U) lab = image;
  else image.convertTo(lab, CV_16U);
  SegmentedSlice out;
  out.threshold_used = 0.5;

  // Bounding box of every label, one pass.
  double maxValue = 0;
  cv::minMaxLoc(lab, nullptr, &maxValue);
  const int maxLabel = int(maxValue);
  std::vector<int> x0(maxLabel + 1, INT_MAX), y0(maxLabel + 1, INT_MAX), x1(maxLabel + 1, -1),
      y1(maxLabel + 1, -1);
  for (int j = 0; j < lab.rows; ++j) {
    const std::uint16_t* row = lab.ptr<std::uint16_t>(j);
    for (int i = 0; i < lab.cols; ++i) {
      const int l = row[i];
      if (!l) continue;
      x0[l] = std::min(x0[l], i), x1[l] = std::max(x1[l], i);
      y0[l] = std::min(y0[l], j), y1[l] = std::max(y1[l], j);
    }
  }

  // Margin: the smoothing kernel's radius (OpenCV: 4 sigma for float images), twice the
  // morphology radius (a closing dilates, then erodes as far again), and 2 pixels so the crop's
  // edge is background; inside the crop the field and the cleaned mask are then exactly those of
  // the whole indicator image, so the crops cost what the labels' areas cost, not the image's.
  const int margin = (p.sigma_px > 0 ? int(std::ceil(4.0 * p.sigma_px)) + 1 : 0) +
                     2 * std::max(p.open_radius_px, p.close_radius_px) + 2;
  const cv::Rect whole(0, 0, lab.cols, lab.rows);
  const float nudge = 1e-3f;  // as the threshold path's, for t = 0.5
  std::vector<LabelField> fields;
  for (int l = 1; l <= maxLabel; ++l) {
    if (x1[l] < 0) continue;
    const cv::Rect box = cv::Rect(cv::Point(x0[l] - margin, y0[l] - margin),
                                  cv::Point(x1[l] + margin + 1, y1[l] + margin + 1)) & whole;
    ImageSides sides;
    sides.left = box.x == 0;
    sides.top = box.y == 0;
    sides.right = box.x + box.width == lab.cols;
    sides.bottom = box.y + box.height == lab.rows;
    cv::Mat f;
    cv::Mat(lab(box) == l).convertTo(f, CV_32F, 1.0 / 255.0);
    if (p.sigma_px > 0)
      cv::GaussianBlur(f, f, cv::Size(0, 0), p.sigma_px, p.sigma_px, cv::BORDER_REPLICATE);
    f -= 0.5;
    const cv::Mat fovBox = fov.empty() ? cv::Mat() : fov(box);
    out.touches_fov_edge |= cleanField(f, fovBox, spacing, p, nudge, sides, false);
    fields.push_back({l, box, std::move(f)});
  }

  // Contours of all labels at once: sorted by label, they tile the plane.
  std::vector<LabelRing> rings = labelIsoContours(lab.size(), fields, -0.5f);
  for (std::size_t g0 = 0; g0 < rings.size();) {
    std::size_t g1 = g0;
    std::vector<Ring> group;
    for (; g1 < rings.size() && rings[g1].label == rings[g0].label; ++g1)
      group.push_back(std::move(rings[g1].ring));
    for (auto& s : sectionsOfRings(std::move(group), spacing, p, &out.contours_repaired)) {
      s.label = rings[g0].label;
      out.sections.push_back(std::move(s));
    }
    g0 = g1;
  }
  return out;
}

}  // namespace

SegmentedSlice segmentSlice(const cv::Mat& image, const cv::Mat& fov, const Vec2& spacing,
                            const SegmentationParams& p) {
  CV_Assert(image.channels() == 1 && !image.empty());
  CV_Assert(fov.empty() || (fov.size() == image.size() && fov.type() == CV_8U));
  if (p.method == SegmentationMethod::labels) return segmentLabels(image, fov, spacing, p);
  SegmentedSlice out;

  // 1. Field whose zero level is the boundary: the grey field (speckle filter, smoothing) minus
  //    the threshold, negated when the object is the dark side.
  cv::Mat f = greyField(image, fov, p);
  double t = p.threshold, core = p.core_threshold;
  if (p.method == SegmentationMethod::otsu) {
    const double scale = seriesGreyScale(image.depth() == CV_16U ? 16 : 8);
    cv::Mat f8;
    f.convertTo(f8, CV_8U, scale);
    t = cv::threshold(f8, f8, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU) / scale;
  } else if (p.method == SegmentationMethod::min_error) {
    const double scale = seriesGreyScale(image.depth() == CV_16U ? 16 : 8);
    const GreyHistogram h = observedHistograms(f, fov, scale).observed;
    t = minimumErrorThresholdOfHistogram(h);
    core = coreThresholdOfClasses(minimumErrorClassesAt(h, t), p.inside) / scale;
    t /= scale;
  }
  out.threshold_used = t;
  // Acoustic shadows: what the beams did not reach leaves the field of view (acoustic_shadows.h).
  // Shorter than twice the speckle filter (or 4 pixels), a dark run at the beam's end is noise.
  cv::Mat observed = fov;
  if (p.shadows == ShadowRule::unobserved) {
    cv::Mat shadow = acousticShadows(f, fov, t, p.beam_apex_px, std::max(4, 2 * p.speckle_filter_px));
    if (cv::countNonZero(shadow) > 0) {
      // The filters spread a shadow's dark over the pixels within their reach (half the median,
      // two sigmas): those pixels are grown into it, or they stay as dark slivers along its sides.
      const int reach = p.speckle_filter_px / 2 + int(std::ceil(2 * p.sigma_px));
      if (reach > 0) cv::dilate(shadow, shadow, disk(reach));
      observed = fov.empty() ? cv::Mat(image.size(), CV_8U, cv::Scalar(255)) : fov.clone();
      observed.setTo(0, shadow);
      out.observed = observed;
    }
  }
  if (p.inside == InsideSide::below)
    // The dark class is g <= t, as the threshold rules' classes and the shadows have it: a pixel
    // at the threshold is inside (integer-valued fields, e.g. the median filter alone, hold ties).
    f = double(std::nextafter(float(t), INFINITY)) - f;
  else
    f -= t;
  CV_Assert(p.inside != InsideSide::automatic);  // resolved for the series before any frame

  // 2-4. Cleaning, nudging, edge test.
  const float nudge = 1e-3f * float(std::max(1.0, std::abs(t)));
  const float coreDepth = std::isnan(core) ? 0.0f : float(std::abs(t - core));
  out.touches_fov_edge = cleanField(f, observed, spacing, p, nudge, ImageSides(), true, coreDepth);

  // 5. Sub-pixel contours -> rings in mm; simplification; holes attached to their outer ring.
  //    Every section keeps Section::label = 1 (one material).
  out.sections = sectionsOfRings(isoContours(f), spacing, p, &out.contours_repaired);
  return out;
}

}  // namespace xsect
