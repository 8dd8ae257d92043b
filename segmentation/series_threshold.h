// Otsu's threshold of a whole slice series: the pooled histogram of all images (smoothed as they
// will be segmented, inside their fields of view). A per-slice Otsu invents an object in every
// slice that misses it (pure noise still splits in two); slices that hold the object make the
// pooled histogram bimodal, and one threshold then serves the series consistently.
// The histogram is pooled frame by frame (observedHistogram), so that a series is read as a
// stream: its frames need not be held together (issue 17).
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace xsect {

/// 256 bins of 8-bit grey values, pixel counts.
using GreyHistogram = std::array<std::int64_t, 256>;

/// One image's observed pixels, smoothed and brought to 8 bits as the series threshold reads them.
/// @param image     8- or 16-bit single-channel image.
/// @param fov       empty, or a CV_8U mask of the same size (non-zero = observed).
/// @param sigma_px  Gaussian smoothing applied before the histogram, pixels (0 = none).
/// @param scale     grey value -> 8 bits: 1 for an 8-bit series, 1/257 for a 16-bit one.
GreyHistogram observedHistogram(const cv::Mat& image, const cv::Mat& fov, double sigma_px, double scale);

/// The scale of a series of `bits_per_sample` (up to 8 bits: 1; 16: 1/257, full range to full range).
double seriesGreyScale(int bits_per_sample);

/// Otsu's threshold of a histogram in its 8-bit units: the bin t maximising the between-class
/// variance of {<= t} and {> t}, the first of equal maxima, classes holding less than FLT_EPSILON
/// of the pixels not considered; 0 when no split qualifies. The value cv::threshold(THRESH_OTSU)
/// returns for an 8-bit image of that histogram (tests/test_segmentation.cpp checks it).
double otsuThresholdOfHistogram(const GreyHistogram& histogram);

/// @param images    8- or 16-bit single-channel images.
/// @param fovs      per image: empty, or a CV_8U mask of the same size (non-zero = observed).
/// @param sigma_px  Gaussian smoothing applied before the histogram, pixels (0 = none).
/// @return the threshold in the images' grey units (128 in 8-bit units when no pixel is observed).
double otsuThresholdOfSeries(const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& fovs,
                             double sigma_px);

/// The same from the series' pooled histogram and scale.
double otsuThresholdOfPooled(const GreyHistogram& pooled, double scale);

}  // namespace xsect
