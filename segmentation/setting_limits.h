// The segmentation settings an image can take (issue 48): a setting beyond these removes every
// section, fills the whole image, or makes OpenCV refuse (or take minutes over) a kernel larger
// than the image. Checked per image where its size and field of view are known, before it is
// segmented, so that a refusal names the setting (exit 2) instead of OpenCV's text or a cube.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "geometry/core/types.h"
#include "segmentation/segment_slice.h"

namespace xsect {

/// A setting that cannot work on an image: its key under `segmentation.` and why, with a value
/// that would.
struct SettingProblem {
  std::string key;   ///< e.g. "min_area_mm2"
  std::string what;  ///< what happens at this value, and a value to use
};

/// The first problem of `params` on an image of `size` pixels at `spacing` mm per pixel whose
/// observed part (field of view) holds `observed_pixels`:
/// - sigma_px: the Gaussian kernel (4 sigma on each side, as OpenCV sizes it) wider than the
///   image's larger side;
/// - open_radius_px, close_radius_px: a disk (diameter 2r + 1) that does not fit in the image;
/// - min_area_mm2 at or above the observed area: every section and every hole would be removed
///   (the background, a hole of the image, filled: a slab of solid).
/// Labels are cleaned per label with the same settings, so the same limits hold.
std::optional<SettingProblem> segmentationSettingProblem(const SegmentationParams& params, cv::Size size,
                                                         const Vec2& spacing, double observed_pixels);

}  // namespace xsect
