// Sub-pixel iso-contours of a sampled 2D field (marching squares on pixel centres). The contour of
// {f > 0} of the bilinear interpolant is traced with the inside on the left, so outer contours are
// counter-clockwise and holes clockwise in the (i, j) frame; saddle cells are decided by the
// bilinear value at the cell centre, so the curves are those of the interpolant itself.
//
// labelIsoContours: the same for several materials at once (label images, thesis remark after
// Def. 17). Each label L has its own field f_L (positive inside); a pixel belongs to the label with
// the largest positive field (background when none is positive). Crossings: label|background at the
// zero of f_L, label L|label M at the zero of f_L - f_M (the same point as f_L's zero when
// f_L + f_M = const, e.g. indicator images). Each cell is partitioned among the materials of its
// corners, so the labels' regions tile the plane: shared boundaries are the same vertices, no
// overlap, no gap. Background saddles are decided on F = max_L f_L as isoContours decides them,
// so for a label image without smoothing the union of all labels is exactly isoContours' region
// of "image != 0".
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// The saddle rule: in a cell whose diagonal corners agree and differ from the other two, the
/// inside corners are joined through the cell when the bilinear value at its centre is positive
/// (corners (i, j), (i+1, j), (i+1, j+1), (i, j+1); the sum of four floats is exact in double).
inline bool saddleJoinsInside(float f00, float f10, float f11, float f01) {
  return double(f00) + f10 + f11 + f01 > 0.0;
}

/// @param field  CV_32F, row j, column i; positive = inside. Values outside the image count as
///               negative, so every contour is closed.
/// @return closed rings in pixel coordinates (x = i, y = j), no repeated end vertex.
std::vector<Ring> isoContours(const cv::Mat& field);

/// One label's field, stored on the label's bounding box (plus whatever margin the caller needs).
struct LabelField {
  int label = 0;   ///< 1..65535
  cv::Rect box;    ///< where `field` lies in the image, pixels
  cv::Mat field;   ///< CV_32F, box.size(); positive = inside this label
};

/// A closed ring of one label's region, inside on the left (outer CCW, holes CW in (i, j)).
struct LabelRing {
  int label = 0;
  Ring ring;  ///< pixel coordinates (x = i, y = j), no repeated end vertex
};

/// @param size        image size, pixels.
/// @param fields      one per label, labels distinct (any order); boxes inside the image.
/// @param background  every field's value outside its box (must be <= 0), e.g. -0.5 for an
///                    indicator image minus 0.5. Outside the image every field counts as -1.
/// @return rings sorted by label, then in the order they are met scanning the image.
std::vector<LabelRing> labelIsoContours(cv::Size size, const std::vector<LabelField>& fields,
                                        float background);

}  // namespace xsect
