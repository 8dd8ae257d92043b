// Pooled Otsu threshold of a series (see series_threshold.h).
#include "segmentation/series_threshold.h"

#include <algorithm>
#include <cfloat>
#include <opencv2/imgproc.hpp>

namespace xsect {

// 16 bits onto 8 full range to full range (65535 / 257 = 255): the same picture stored at either
// depth (v16 = 257 v8) has the same histogram, hence the same threshold (issue 48).
double seriesGreyScale(int bits_per_sample) { return bits_per_sample > 8 ? 1.0 / 257.0 : 1.0; }

GreyHistogram observedHistogram(const cv::Mat& image, const cv::Mat& fov, double sigma_px, double scale) {
  GreyHistogram h{};
  cv::Mat f, f8;
  image.convertTo(f, CV_32F);
  if (sigma_px > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), sigma_px, sigma_px, cv::BORDER_REPLICATE);
  f.convertTo(f8, CV_8U, scale);
  for (int j = 0; j < f8.rows; ++j) {
    const unsigned char* r = f8.ptr<unsigned char>(j);
    const unsigned char* m = fov.empty() ? nullptr : fov.ptr<unsigned char>(j);
    for (int i = 0; i < f8.cols; ++i)
      if (!m || m[i]) ++h[r[i]];
  }
  return h;
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
