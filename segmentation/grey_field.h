// The grey field a threshold is applied to (docs/methods.md stage 2): the image with its speckle reduced
// by a median filter (ultrasound: the grain of coherent imaging, which a Gaussian only blurs into
// blobs that a threshold still splits), then Gaussian-smoothed. Shared by the segmentation of a
// frame and the series' histograms (Otsu's threshold, the inside side), so that both read the
// same grey values.
#pragma once

#include <opencv2/core.hpp>

#include "segmentation/segment_slice.h"

namespace xsect {

/// Pixels outside the field of view are first given the grey of their nearest observed pixel, so
/// that the filters do not darken the view's edge with the blank (zero) pixels around it: a dark
/// rim would otherwise be segmented as the object where it is the dark side (inside: below), and
/// would pull the border's histogram (inside: auto) to the dark side.
/// @param image   8- or 16-bit (or floating-point, in the series' grey units) single-channel image.
/// @param fov     empty (the whole image is observed) or CV_8U of the image's size, non-zero where
///                observed.
/// @param params  in pixels (pixel_settings.h): speckle_filter_px (odd, or 0 = none), sigma_px,
///                grey_to_8bit.
/// @return CV_32F, the image's grey units. The median is exact on 8-bit images; others are
///         brought to 8 bits by grey_to_8bit for the median (OpenCV's median of larger kernels
///         takes 8-bit images only) and back, which rounds their greys to 1/256 of the range.
cv::Mat greyField(const cv::Mat& image, const cv::Mat& fov, const SegmentationParams& params);

}  // namespace xsect
