// Pooled Otsu threshold of a series (see series_threshold.h): the observed pixels of every image,
// smoothed and brought to 8 bits, side by side in one row that cv::threshold(THRESH_OTSU) reads.
#include "segmentation/series_threshold.h"

#include <opencv2/imgproc.hpp>

namespace xsect {

double otsuThresholdOfSeries(const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& fovs,
                             double sigma_px) {
  CV_Assert(!images.empty() && fovs.size() == images.size());
  const double scale = images.front().depth() == CV_16U ? 1.0 / 256.0 : 1.0;
  std::vector<unsigned char> pooled;
  for (std::size_t k = 0; k < images.size(); ++k) {
    cv::Mat f, f8;
    images[k].convertTo(f, CV_32F);
    if (sigma_px > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), sigma_px, sigma_px, cv::BORDER_REPLICATE);
    f.convertTo(f8, CV_8U, scale);
    for (int j = 0; j < f8.rows; ++j) {
      const unsigned char* r = f8.ptr<unsigned char>(j);
      const unsigned char* m = fovs[k].empty() ? nullptr : fovs[k].ptr<unsigned char>(j);
      for (int i = 0; i < f8.cols; ++i)
        if (!m || m[i]) pooled.push_back(r[i]);
    }
  }
  if (pooled.empty()) return 128.0 / scale;
  cv::Mat row(1, int(pooled.size()), CV_8U, pooled.data()), out;
  return cv::threshold(row, out, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU) / scale;
}

}  // namespace xsect
