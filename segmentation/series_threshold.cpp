// Pooled Otsu threshold of a series (see series_threshold.h).
#include "segmentation/series_threshold.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace xsect {

// 16 bits onto 8 full range to full range (65535 / 257 = 255): the same picture stored at either
// depth (v16 = 257 v8) has the same histogram, hence the same threshold (issue 48).
double seriesGreyScale(int bits_per_sample) { return bits_per_sample > 8 ? 1.0 / 257.0 : 1.0; }

namespace {

/// visit(j, i, bin, border) for every observed pixel of `grey` (in `fov`, or all), its grey in
/// 8-bit bins (times `scale`), and whether a 4-neighbour is unobserved or off the image.
template <typename Visit>
void forEachObservedPixel(const cv::Mat& grey, const cv::Mat& fov, double scale, const Visit& visit) {
  cv::Mat f8;
  grey.convertTo(f8, CV_8U, scale);
  const auto seen = [&](int j, int i) {
    return i >= 0 && j >= 0 && i < f8.cols && j < f8.rows && (fov.empty() || fov.at<unsigned char>(j, i));
  };
  for (int j = 0; j < f8.rows; ++j) {
    const unsigned char* r = f8.ptr<unsigned char>(j);
    for (int i = 0; i < f8.cols; ++i)
      if (seen(j, i)) visit(j, i, r[i], !seen(j, i - 1) || !seen(j, i + 1) || !seen(j - 1, i) || !seen(j + 1, i));
  }
}

}  // namespace

ObservedHistograms observedHistograms(const cv::Mat& grey, const cv::Mat& fov, double scale) {
  ObservedHistograms h;
  forEachObservedPixel(grey, fov, scale, [&](int, int, unsigned char bin, bool border) {
    ++h.observed[bin];
    if (border) ++h.border[bin];
  });
  return h;
}

void ShadowedHistograms::add(const ShadowedHistograms& other) {
  for (std::size_t k = 0; k < observed.size(); ++k) observed[k] += other.observed[k], border[k] += other.border[k];
}

ShadowedHistograms shadowedHistograms(const cv::Mat& grey, const cv::Mat& fov, const cv::Mat& tail, double scale) {
  ShadowedHistograms h;
  forEachObservedPixel(grey, fov, scale, [&](int j, int i, unsigned char bin, bool border) {
    const float t = tail.at<float>(j, i);
    const int tailBin = std::isfinite(t) ? int(std::clamp(std::lround(double(t) * scale), 0L, 255L)) : 256;
    const std::size_t k = std::size_t(bin) * ShadowedHistograms::kTailBins + std::size_t(tailBin);
    ++h.observed[k];
    if (border) ++h.border[k];
  });
  return h;
}

ObservedHistograms outsideShadow(const ShadowedHistograms& h, double threshold_8bit) {
  ObservedHistograms out;
  for (int g = 0; g < 256; ++g)
    for (int t = 0; t < ShadowedHistograms::kTailBins; ++t) {
      if (t <= threshold_8bit) continue;  // in the shadow of this threshold
      const std::size_t k = std::size_t(g) * ShadowedHistograms::kTailBins + std::size_t(t);
      out.observed[std::size_t(g)] += h.observed[k];
      out.border[std::size_t(g)] += h.border[k];
    }
  return out;
}

double thresholdOutOfShadows(const ShadowedHistograms& h, const std::function<double(const GreyHistogram&)>& rule) {
  double previous = rule(outsideShadow(h, -1).observed);
  if (previous < 0) return previous;
  for (int t = 0; t < 255; ++t) {
    const double next = rule(outsideShadow(h, t + 1).observed);
    if (previous >= t && std::abs(next - previous) > std::max(1.0, previous - t)) return previous;
    if (previous >= t && next < t + 1) return std::max(double(t), std::min(previous, double(t + 1)));
    previous = next;
  }
  return rule(outsideShadow(h, -1).observed);
}

GreyHistogram observedHistogram(const cv::Mat& image, const cv::Mat& fov, double sigma_px, double scale) {
  cv::Mat f;
  image.convertTo(f, CV_32F);
  if (sigma_px > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), sigma_px, sigma_px, cv::BORDER_REPLICATE);
  return observedHistograms(f, fov, scale).observed;
}

InsideSide insideOfBorder(const GreyHistogram& border, double threshold_8bit) {
  std::int64_t dark = 0, bright = 0;
  for (int b = 0; b < 256; ++b) (b <= threshold_8bit ? dark : bright) += border[std::size_t(b)];
  return dark >= bright ? InsideSide::above : InsideSide::below;
}

double otsuThresholdOfHistogram(const GreyHistogram& h) {
  std::int64_t total = 0;
  double sum = 0;  // Σ i h_i
  for (int i = 0; i < 256; ++i) {
    total += h[std::size_t(i)];
    sum += i * double(h[std::size_t(i)]);
  }
  if (total == 0) return 0;
  const double scale = 1.0 / double(total), mean = sum * scale;
  // Class 1 = bins 0..t: weight w1 and mean m1 updated bin by bin; class 2 the rest.
  double w1 = 0, m1 = 0, best = 0, bestBin = 0;
  for (int t = 0; t < 256; ++t) {
    const double p = double(h[std::size_t(t)]) * scale;
    m1 *= w1;  // back to Σ i p_i over class 1
    w1 += p;
    const double w2 = 1.0 - w1;
    if (std::min(w1, w2) < FLT_EPSILON || std::max(w1, w2) > 1.0 - FLT_EPSILON) continue;
    m1 = (m1 + t * p) / w1;
    const double m2 = (mean - w1 * m1) / w2;
    const double between = w1 * w2 * (m1 - m2) * (m1 - m2);
    if (between > best) {
      best = between;
      bestBin = t;
    }
  }
  return bestBin;
}

namespace {

/// visit(t, m1, m2, J) for every split {<= t}, {> t} of `h` that Kittler and Illingworth's
/// criterion considers (classes of at least 0.1% of the pixels, variances of at least 1/12).
template <typename Visit>
void forEachMinimumErrorSplit(const GreyHistogram& h, const Visit& visit) {
  // Prefix sums of counts, first and second moments.
  std::array<double, 257> n{}, s1{}, s2{};
  for (int b = 0; b < 256; ++b) {
    const double c = double(h[std::size_t(b)]);
    n[std::size_t(b) + 1] = n[std::size_t(b)] + c;
    s1[std::size_t(b) + 1] = s1[std::size_t(b)] + c * b;
    s2[std::size_t(b) + 1] = s2[std::size_t(b)] + c * b * double(b);
  }
  const double total = n[256];
  if (total <= 0) return;
  for (int t = 0; t < 255; ++t) {
    const double n1 = n[std::size_t(t) + 1], n2 = total - n1;
    if (n1 < 1e-3 * total || n2 < 1e-3 * total) continue;
    const double m1 = s1[std::size_t(t) + 1] / n1, m2 = (s1[256] - s1[std::size_t(t) + 1]) / n2;
    const double v1 = s2[std::size_t(t) + 1] / n1 - m1 * m1, v2 = (s2[256] - s2[std::size_t(t) + 1]) / n2 - m2 * m2;
    if (v1 < 1.0 / 12 || v2 < 1.0 / 12) continue;
    const double p1 = n1 / total, p2 = n2 / total;
    visit(t, m1, m2, p1 * std::log(v1) + p2 * std::log(v2) - 2 * (p1 * std::log(p1) + p2 * std::log(p2)));
  }
}

}  // namespace

double minimumErrorThresholdOfHistogram(const GreyHistogram& h) {
  double best = INFINITY, level = -1;
  forEachMinimumErrorSplit(h, [&](int, double m1, double m2, double j) {
    if (j < best) best = j, level = 0.5 * (m1 + m2);
  });
  if (level < 0) return otsuThresholdOfHistogram(h);
  // The classes found, the boundary placed where a blurred step between them crosses: half-way
  // between their means (the minimum-error split itself leans into the narrower class).
  return std::floor(level);
}

GreyClasses minimumErrorClassesAt(const GreyHistogram& h, double threshold_8bit) {
  GreyClasses out;
  double bestGap = INFINITY, bestJ = INFINITY;
  forEachMinimumErrorSplit(h, [&](int, double m1, double m2, double j) {
    const double level = std::floor(0.5 * (m1 + m2));
    const double gap = std::abs(level - threshold_8bit);
    if (gap < bestGap || (gap == bestGap && j < bestJ)) {
      bestGap = gap, bestJ = j;
      out = {true, m1, m2};
    }
  });
  return out;
}

double coreThresholdOfClasses(const GreyClasses& c, InsideSide inside) {
  if (!c.found) return NAN;
  const double quarter = 0.25 * (c.bright_mean - c.dark_mean);
  return inside == InsideSide::below ? c.dark_mean + quarter : c.bright_mean - quarter;
}

double otsuThresholdOfPooled(const GreyHistogram& pooled, double scale) {
  std::int64_t total = 0;
  for (const std::int64_t c : pooled) total += c;
  if (total == 0) return 128.0 / scale;
  return otsuThresholdOfHistogram(pooled) / scale;
}

double otsuThresholdOfSeries(const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& fovs,
                             double sigma_px) {
  CV_Assert(!images.empty() && fovs.size() == images.size());
  const double scale = seriesGreyScale(images.front().depth() == CV_16U ? 16 : 8);
  GreyHistogram pooled{};
  for (std::size_t k = 0; k < images.size(); ++k) {
    const GreyHistogram h = observedHistogram(images[k], fovs[k], sigma_px, scale);
    for (std::size_t b = 0; b < pooled.size(); ++b) pooled[b] += h[b];
  }
  return otsuThresholdOfPooled(pooled, scale);
}

}  // namespace xsect
