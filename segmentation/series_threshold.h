// Otsu's threshold of a whole slice series: the pooled histogram of all images (smoothed as they
// will be segmented, inside their fields of view). A per-slice Otsu invents an object in every
// slice that misses it (pure noise still splits in two); slices that hold the object make the
// pooled histogram bimodal, and one threshold then serves the series consistently.
// The histogram is pooled frame by frame (observedHistogram), so that a series is read as a
// stream: its frames need not be held together (issue 17).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "segmentation/segment_slice.h"

namespace xsect {

/// 256 bins of 8-bit grey values, pixel counts.
using GreyHistogram = std::array<std::int64_t, 256>;

/// One image's observed pixels, smoothed and brought to 8 bits as the series threshold reads them.
/// @param image     8- or 16-bit single-channel image.
/// @param fov       empty, or a CV_8U mask of the same size (non-zero = observed).
/// @param sigma_px  Gaussian smoothing applied before the histogram, pixels (0 = none).
/// @param scale     grey value -> 8 bits: 1 for an 8-bit series, 1/257 for a 16-bit one.
GreyHistogram observedHistogram(const cv::Mat& image, const cv::Mat& fov, double sigma_px, double scale);

/// A grey field's histograms (8-bit units, `scale` applied): of its observed pixels, and of the
/// border of the observed region (observed pixels with a 4-neighbour unobserved or off the image),
/// which decides segmentation.inside: auto (insideOfBorder).
struct ObservedHistograms {
  GreyHistogram observed{};
  GreyHistogram border{};
};
/// @param grey  CV_32F grey field (grey_field.h), the images' grey units.
ObservedHistograms observedHistograms(const cv::Mat& grey, const cv::Mat& fov, double scale);

/// The same with each pixel's beam-tail maximum (acoustic_shadows.h beamTailMaximum), so that the
/// pixels a threshold t puts in shadow (tail maximum <= t) can be left out after t is known:
/// counts by (grey bin, tail bin), the tail's bin 256 for +infinity. Sums of integer counts: the
/// same in any order of frames.
struct ShadowedHistograms {
  static constexpr int kTailBins = 257;
  std::vector<std::int64_t> observed = std::vector<std::int64_t>(256 * kTailBins, 0);
  std::vector<std::int64_t> border = std::vector<std::int64_t>(256 * kTailBins, 0);
  void add(const ShadowedHistograms& other);
};
/// @param tail  CV_32F beam-tail maximum of `grey`, same size.
ShadowedHistograms shadowedHistograms(const cv::Mat& grey, const cv::Mat& fov, const cv::Mat& tail, double scale);
/// The histograms of the pixels out of the shadow of threshold `threshold_8bit`.
ObservedHistograms outsideShadow(const ShadowedHistograms& h, double threshold_8bit);

/// The threshold (8-bit units) that `rule` (a two-class threshold of a histogram, in bins) gives
/// on the pixels out of its own shadows: the first t from 0 up where rule(pixels out of the shadow
/// of t) >= t and the same at t + 1 is below t + 1 (a fixed point, crossed downwards). Below the
/// darkest class nothing is in shadow and the rule's threshold is above t; once t passes the
/// shadows they leave the histogram, and the rule splits the classes that remain (object and
/// tissue), which a two-class rule on all pixels would not do when shadows make three. The rule on
/// all pixels when no t qualifies.
/// The threshold is followed as t rises: where it jumps by more than it lay above t (or by more
/// than a bin), the two classes it separates changed (a small object, once the shadows around it
/// have left the histogram, is no longer a class: the rule splits the tissue's speckle instead; a
/// cyst with two reflectors' shadows went from 58 to 146 at t = 44), and the threshold before the
/// jump is kept.
double thresholdOutOfShadows(const ShadowedHistograms& h, const std::function<double(const GreyHistogram&)>& rule);

/// segmentation.inside: auto: the object is the side of `threshold_8bit` (a bin of `border`) that
/// covers less of the observed region's border over the series: the background surrounds an
/// object more than the object reaches the edge of the view (a vessel, a cyst, a bone in tissue).
/// Ties and an empty border: above.
InsideSide insideOfBorder(const GreyHistogram& border, double threshold_8bit);

/// The scale of a series of `bits_per_sample` (up to 8 bits: 1; 16: 1/257, full range to full range).
double seriesGreyScale(int bits_per_sample);

/// Otsu's threshold of a histogram in its 8-bit units: the bin t maximising the between-class
/// variance of {<= t} and {> t}, the first of equal maxima, classes holding less than FLT_EPSILON
/// of the pixels not considered; 0 when no split qualifies. The value cv::threshold(THRESH_OTSU)
/// returns for an 8-bit image of that histogram (tests/test_segmentation.cpp checks it).
double otsuThresholdOfHistogram(const GreyHistogram& histogram);

/// Kittler and Illingworth's minimum-error threshold of a histogram ("Minimum error thresholding",
/// Pattern Recognition 19, 1986), in its 8-bit units: the bin t minimising
/// J(t) = P1 ln(var1) + P2 ln(var2) - 2 (P1 ln P1 + P2 ln P2) for the classes {<= t} and {> t}
/// fitted as two normal distributions with their own weights P and variances; classes under 0.1%
/// of the pixels or with a variance under 1/12 of a bin (one grey level) are not considered.
/// Unlike Otsu's (equal spreads implied), it does not split a large, wide class around a small
/// one. The threshold returned is then half-way between the two classes' means (rounded down to a
/// bin): the level at which a blurred step from one class to the other crosses its edge, where
/// the split itself leans into the narrower class. Otsu's threshold when no split qualifies.
double minimumErrorThresholdOfHistogram(const GreyHistogram& histogram);

/// The two classes of a minimum-error split whose threshold (as above, half-way between their
/// means) is `threshold_8bit`, by their means in 8-bit units: among the splits whose half-way level
/// rounds down to the threshold, or else lies nearest to it, the one of least J. The classes behind
/// a series' threshold, found again on the histogram it was applied to (out of its shadows).
/// `found` is false when no split qualifies.
struct GreyClasses {
  bool found = false;
  double dark_mean = 0, bright_mean = 0;
};
GreyClasses minimumErrorClassesAt(const GreyHistogram& histogram, double threshold_8bit);

/// The grey level (8-bit units) past which a pixel is the object's core: a quarter of the way from
/// the object's class mean to the other class's, the object being the dark class when `inside` is
/// below. NaN when the classes were not found. See SegmentationParams::core_threshold.
double coreThresholdOfClasses(const GreyClasses& classes, InsideSide inside);

/// @param images    8- or 16-bit single-channel images.
/// @param fovs      per image: empty, or a CV_8U mask of the same size (non-zero = observed).
/// @param sigma_px  Gaussian smoothing applied before the histogram, pixels (0 = none).
/// @return the threshold in the images' grey units (128 in 8-bit units when no pixel is observed).
double otsuThresholdOfSeries(const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& fovs,
                             double sigma_px);

/// The same from the series' pooled histogram and scale.
double otsuThresholdOfPooled(const GreyHistogram& pooled, double scale);

}  // namespace xsect
