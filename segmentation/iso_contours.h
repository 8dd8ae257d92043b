// Sub-pixel iso-contours of a sampled 2D field (marching squares on pixel centres). The contour of
// {f > 0} of the bilinear interpolant is traced with the inside on the left, so outer contours are
// counter-clockwise and holes clockwise in the (i, j) frame; saddle cells are decided by the
// bilinear value at the cell centre, so the curves are those of the interpolant itself.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/types.h"

namespace xsect {

/// @param field  CV_32F, row j, column i; positive = inside. Values outside the image count as
///               negative, so every contour is closed.
/// @return closed rings in pixel coordinates (x = i, y = j), no repeated end vertex.
std::vector<Ring> isoContours(const cv::Mat& field);

}  // namespace xsect
