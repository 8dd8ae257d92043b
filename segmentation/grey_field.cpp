// The grey field a threshold is applied to (see grey_field.h).
#include "segmentation/grey_field.h"

#include <opencv2/imgproc.hpp>

#include <vector>

namespace xsect {

namespace {

/// `f` (CV_32F) with every pixel outside `fov` set to the grey of its nearest observed pixel
/// (OpenCV's distance transform with a label per observed pixel).
void fillUnobserved(cv::Mat& f, const cv::Mat& fov) {
  if (fov.empty()) return;
  const int observed = cv::countNonZero(fov);
  if (observed == 0 || observed == int(fov.total())) return;
  const cv::Mat unobserved = fov == 0;
  cv::Mat distance, nearest;
  cv::distanceTransform(unobserved, distance, nearest, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
  std::vector<float> grey(std::size_t(observed) + 1, 0.0f);
  for (int j = 0; j < f.rows; ++j) {
    const unsigned char* u = unobserved.ptr<unsigned char>(j);
    const int* l = nearest.ptr<int>(j);
    const float* g = f.ptr<float>(j);
    for (int i = 0; i < f.cols; ++i)
      if (!u[i] && l[i] >= 0 && std::size_t(l[i]) < grey.size()) grey[std::size_t(l[i])] = g[i];
  }
  for (int j = 0; j < f.rows; ++j) {
    const unsigned char* u = unobserved.ptr<unsigned char>(j);
    const int* l = nearest.ptr<int>(j);
    float* g = f.ptr<float>(j);
    for (int i = 0; i < f.cols; ++i)
      if (u[i] && l[i] >= 0 && std::size_t(l[i]) < grey.size()) g[i] = grey[std::size_t(l[i])];
  }
}

}  // namespace

cv::Mat greyField(const cv::Mat& image, const cv::Mat& fov, const SegmentationParams& p) {
  cv::Mat f;
  image.convertTo(f, CV_32F);
  if (p.speckle_filter_px >= 3 || p.sigma_px > 0) fillUnobserved(f, fov);
  if (p.speckle_filter_px >= 3) {
    cv::Mat grey8, filtered;
    f.convertTo(grey8, CV_8U, p.grey_to_8bit);
    cv::medianBlur(grey8, filtered, p.speckle_filter_px);
    filtered.convertTo(f, CV_32F, 1.0 / p.grey_to_8bit);
  }
  if (p.sigma_px > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), p.sigma_px, p.sigma_px, cv::BORDER_REPLICATE);
  return f;
}

}  // namespace xsect
