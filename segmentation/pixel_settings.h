// Segmentation settings given in mm (sigma_mm, open_radius_mm, close_radius_mm, speckle_filter_mm)
// resolved into pixels for one frame's pixel size (issue 49: settings that transfer between probes
// and zooms, where pixel counts do not).
#pragma once

#include "geometry/core/types.h"
#include "segmentation/segment_slice.h"

namespace xsect {

/// `params` with every mm setting given (> 0) converted to pixels at `spacing` (mm per pixel
/// along i and j; their mean is the pixel size): sigma_px = sigma_mm / pixel; radii rounded to
/// whole pixels, at least 1; the median filter's diameter rounded to an odd number of pixels, at
/// least 3. Settings given in pixels are kept.
SegmentationParams inPixels(const SegmentationParams& params, const Vec2& spacing);

}  // namespace xsect
