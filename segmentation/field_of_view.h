// The field of view of a slice as polygons (docs/methods.md stage 2): the region of a field-of-view mask
// (non-zero = observed), as rings in the plane's (u, v) mm frame, so that conformity (stage 3) can
// compare two slices' sections only where both were observed (thesis §3.1).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// @param fov      empty, or a CV_8U mask: non-zero where the image holds data.
/// @param spacing  mm per pixel along i (u) and j (v); pixel (i, j) is at (i sx, j sy).
/// @return the rings bounding the observed region (the 0.5 iso-line of the mask between pixel
///         centres, simplified to a quarter pixel), outer rings counter-clockwise, holes
///         clockwise; empty when there is no mask or the mask covers the whole image.
std::vector<Ring> fieldOfViewRings(const cv::Mat& fov, const Vec2& spacing);

}  // namespace xsect
