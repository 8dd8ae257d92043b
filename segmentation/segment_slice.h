// Segmentation of one slice image into sections (GUIDE.md stage 2): Gaussian smoothing, fixed or
// Otsu threshold (or given label masks), field-of-view masking, morphological open/close,
// removal of small components, then sub-pixel section-contours (the iso-line of the smoothed image
// at the threshold) turned into polygons with holes in the plane's (u, v) mm frame.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "geometry/types.h"

namespace xsect {

struct SegmentationParams {
  std::string method = "threshold";  ///< threshold | otsu (this image's own) | labels
  double threshold = 128.0;          ///< grey level (threshold method); inside = above
  double sigma_px = 0.0;             ///< Gaussian smoothing, pixels (0 = none)
  int open_radius_px = 0;            ///< morphological opening radius, pixels
  int close_radius_px = 0;           ///< morphological closing radius, pixels
  double min_area_mm2 = 0.0;         ///< components smaller than this are removed
  double simplify_mm = 0.0;          ///< Douglas-Peucker tolerance on contours, mm (0 = none)
};

struct SegmentedSlice {
  std::vector<Section> sections;   ///< one per connected region, holes and islands resolved
  double threshold_used = 0.0;     ///< the threshold applied (Otsu's when method = otsu)
  bool touches_fov_edge = false;   ///< a section reaches the edge of the image / field of view
};

/// @param image    8- or 16-bit single-channel image (row j, column i).
/// @param fov      empty, or an 8-bit mask of the same size: non-zero where the image holds data.
/// @param spacing  mm per pixel along i (u) and j (v).
/// Pixel (i, j) has plane coordinates (i * spacing.x, j * spacing.y).
SegmentedSlice segmentSlice(const cv::Mat& image, const cv::Mat& fov, const Vec2& spacing,
                            const SegmentationParams& params);

}  // namespace xsect
