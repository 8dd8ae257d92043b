// Otsu's threshold of a whole slice series: the pooled histogram of all images (smoothed as they
// will be segmented, inside their fields of view). A per-slice Otsu invents an object in every
// slice that misses it (pure noise still splits in two); slices that hold the object make the
// pooled histogram bimodal, and one threshold then serves the series consistently.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace xsect {

/// @param images    8- or 16-bit single-channel images.
/// @param fovs      per image: empty, or a CV_8U mask of the same size (non-zero = observed).
/// @param sigma_px  Gaussian smoothing applied before the histogram, pixels (0 = none).
/// @return the threshold in the images' grey units.
double otsuThresholdOfSeries(const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& fovs,
                             double sigma_px);

}  // namespace xsect
