// Acoustic shadows of an ultrasound frame (see acoustic_shadows.h).
#include "segmentation/acoustic_shadows.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace xsect {

namespace {

/// Marks the shadow of every beam of `grey` / `seen`, one beam per row, the probe at column 0.
/// `shadow` (CV_8U, same size) receives 255 on the shadow's samples.
void shadowsAlongRows(const cv::Mat& grey, const cv::Mat& seen, double threshold, int min_length, cv::Mat& shadow) {
  shadow = cv::Mat::zeros(grey.size(), CV_8U);
  for (int r = 0; r < grey.rows; ++r) {
    const float* g = grey.ptr<float>(r);
    const unsigned char* s = seen.ptr<unsigned char>(r);
    int length = 0, start = grey.cols;
    for (int c = grey.cols - 1; c >= 0; --c) {
      if (!s[c]) {
        if (length > 0) break;  // the beam left the observed region: the run ends here
        continue;               // beyond the far end of the observed region
      }
      if (g[c] > threshold) break;
      ++length;
      start = c;
    }
    if (length >= min_length)
      for (int c = start; c < grey.cols; ++c)
        if (s[c]) shadow.at<unsigned char>(r, c) = 255;
  }
}

/// Per row (a beam, the probe at column 0): the running maximum of the observed samples from the
/// far end; +infinity on unobserved samples and on the samples nearer than where the beam left the
/// observed region (as shadowsAlongRows ends a run there).
void tailMaximumAlongRows(const cv::Mat& grey, const cv::Mat& seen, cv::Mat& tail) {
  tail = cv::Mat(grey.size(), CV_32F, cv::Scalar(INFINITY));
  for (int r = 0; r < grey.rows; ++r) {
    const float* g = grey.ptr<float>(r);
    const unsigned char* s = seen.ptr<unsigned char>(r);
    float* out = tail.ptr<float>(r);
    float running = -INFINITY;
    bool started = false;
    for (int c = grey.cols - 1; c >= 0; --c) {
      if (!s[c]) {
        if (started) break;
        continue;
      }
      started = true;
      running = std::max(running, g[c]);
      out[c] = running;
    }
  }
}

/// The polar frame of the beams from `apex`: one row per direction, at most a pixel apart at the
/// farthest image corner, and one column per pixel of radius. WARP_FILL_OUTLIERS: samples off the
/// image are 0 (unobserved); without it OpenCV leaves them as the buffer held them. Grey values are
/// sampled at the nearest pixel, as the observed mask is: a linear sample at the view's far edge
/// mixes in the grey beyond it and ended whole beams' shadows there (a test's fan lost a beam).
struct PolarBeams {
  cv::Point2f centre;
  double radius = 0;
  cv::Size size;
  PolarBeams(const cv::Size& image, const Vec2& apex) : centre(float(apex.x()), float(apex.y())) {
    for (const cv::Point2f corner : {cv::Point2f(0, 0), cv::Point2f(float(image.width), 0),
                                     cv::Point2f(0, float(image.height)),
                                     cv::Point2f(float(image.width), float(image.height))})
      radius = std::max(radius, double(cv::norm(corner - centre)));
    size = cv::Size(int(std::ceil(radius)) + 1, std::clamp(int(std::ceil(2 * M_PI * radius)), 64, 16384));
  }
  cv::Mat forward(const cv::Mat& m, int interpolation) const {
    cv::Mat out;
    cv::warpPolar(m, out, size, centre, radius, interpolation | cv::WARP_POLAR_LINEAR | cv::WARP_FILL_OUTLIERS);
    return out;
  }
  cv::Mat inverse(const cv::Mat& m, const cv::Size& image) const {
    cv::Mat out;
    cv::warpPolar(m, out, image, centre, radius,
                  cv::INTER_NEAREST | cv::WARP_POLAR_LINEAR | cv::WARP_INVERSE_MAP | cv::WARP_FILL_OUTLIERS);
    return out;
  }
};

}  // namespace

cv::Mat beamTailMaximum(const cv::Mat& grey, const cv::Mat& observed, const std::optional<Vec2>& apex_px) {
  CV_Assert(grey.type() == CV_32F);
  const cv::Mat seen = observed.empty() ? cv::Mat(grey.size(), CV_8U, cv::Scalar(255)) : cv::Mat(observed != 0);
  cv::Mat tail;
  if (!apex_px) {
    cv::Mat tailT;
    tailMaximumAlongRows(grey.t(), seen.t(), tailT);
    tail = tailT.t();
  } else {
    const PolarBeams beams(grey.size(), *apex_px);
    cv::Mat polarTail;
    tailMaximumAlongRows(beams.forward(grey, cv::INTER_NEAREST), beams.forward(seen, cv::INTER_NEAREST), polarTail);
    tail = beams.inverse(polarTail, grey.size());
  }
  tail.setTo(INFINITY, seen == 0);
  return tail;
}

cv::Mat acousticShadows(const cv::Mat& grey, const cv::Mat& observed, double threshold,
                        const std::optional<Vec2>& apex_px, int min_length_px) {
  CV_Assert(grey.type() == CV_32F);
  const cv::Mat seen = observed.empty() ? cv::Mat(grey.size(), CV_8U, cv::Scalar(255)) : cv::Mat(observed != 0);
  const int minLength = std::max(1, min_length_px);
  cv::Mat shadow;
  if (!apex_px) {
    // Beams are the columns: transposed, each is a row with the probe at column 0.
    cv::Mat shadowT;
    shadowsAlongRows(grey.t(), seen.t(), threshold, minLength, shadowT);
    shadow = shadowT.t();
  } else {
    // Rays from the apex: the polar image has one row per direction and one column per pixel of
    // radius, out to the farthest image corner (PolarBeams).
    const PolarBeams beams(grey.size(), *apex_px);
    cv::Mat polarShadow;
    shadowsAlongRows(beams.forward(grey, cv::INTER_NEAREST), beams.forward(seen, cv::INTER_NEAREST), threshold,
                     minLength, polarShadow);
    shadow = beams.inverse(polarShadow, grey.size());
  }
  shadow &= seen;
  return shadow;
}

}  // namespace xsect
