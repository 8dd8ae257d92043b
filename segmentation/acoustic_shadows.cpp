// Acoustic shadows of an ultrasound frame (see acoustic_shadows.h).
#include "segmentation/acoustic_shadows.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
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
/// farthest image corner, one column per pixel of radius, over the directions and radii that meet
/// the image only: all directions when the apex lies inside it, otherwise the angle the image
/// subtends (under half a turn), and radii from the image's nearest point to its farthest corner.
/// So the polar image is at most 2π times the image's diagonal squared wherever the apex lies (a
/// full circle out to the farthest corner, as OpenCV's warpPolar samples, grows with the apex's
/// distance: 0.7 GB per frame 5000 px away). Maps are built in double precision (an apex may lie
/// far away) and stored as the image positions they reach. Samples are read at the nearest pixel,
/// the grey as the observed mask: a linear sample at the view's far edge mixes in the grey beyond
/// it and ended whole beams' shadows there (a test's fan lost a beam). Off the image: 0.
struct PolarBeams {
  cv::Mat forward_x, forward_y;  ///< per polar sample, its image position (CV_32F)
  cv::Mat inverse_x, inverse_y;  ///< per image pixel, its polar position (CV_32F)
  PolarBeams(const cv::Size& image, const Vec2& apex) {
    CV_Assert(std::isfinite(apex.x()) && std::isfinite(apex.y()) && apex.cwiseAbs().maxCoeff() < 1e9);
    const double cx = apex.x(), cy = apex.y();
    const double x0 = -0.5, y0 = -0.5, x1 = image.width - 0.5, y1 = image.height - 0.5;
    const std::array<Vec2, 4> corners{Vec2(x0, y0), Vec2(x1, y0), Vec2(x0, y1), Vec2(x1, y1)};
    double rmax = 0;
    for (const Vec2& c : corners) rmax = std::max(rmax, (c - apex).norm());
    const double rmin = std::floor(std::hypot(std::max({x0 - cx, 0.0, cx - x1}), std::max({y0 - cy, 0.0, cy - y1})));
    // Directions relative to the one towards the image's centre, in (-pi, pi].
    const double towards = std::atan2(0.5 * (y0 + y1) - cy, 0.5 * (x0 + x1) - cx);
    const auto relative = [&](double dy, double dx) {
      double a = std::atan2(dy, dx) - towards;
      if (a > M_PI) a -= 2 * M_PI;
      if (a <= -M_PI) a += 2 * M_PI;
      return a;
    };
    double lo = -M_PI, hi = M_PI;
    if (rmin > 0) {
      lo = hi = 0;
      for (const Vec2& c : corners) {
        const double r = relative(c.y() - cy, c.x() - cx);
        lo = std::min(lo, r), hi = std::max(hi, r);
      }
    }
    const int cols = int(std::ceil(rmax - rmin)) + 1;
    const int rows = int(std::ceil((hi - lo) * rmax)) + 2;
    const double dAngle = (hi - lo) / (rows - 1);
    forward_x.create(rows, cols, CV_32F);
    forward_y.create(rows, cols, CV_32F);
    for (int r = 0; r < rows; ++r) {
      const double angle = towards + lo + r * dAngle, c = std::cos(angle), sn = std::sin(angle);
      float* fx = forward_x.ptr<float>(r);
      float* fy = forward_y.ptr<float>(r);
      for (int k = 0; k < cols; ++k) fx[k] = float(cx + (rmin + k) * c), fy[k] = float(cy + (rmin + k) * sn);
    }
    inverse_x.create(image, CV_32F);
    inverse_y.create(image, CV_32F);
    for (int j = 0; j < image.height; ++j) {
      float* ix = inverse_x.ptr<float>(j);
      float* iy = inverse_y.ptr<float>(j);
      const double dy = j - cy;
      for (int i = 0; i < image.width; ++i) {
        const double dx = i - cx;
        ix[i] = float(std::sqrt(dx * dx + dy * dy) - rmin);
        iy[i] = float(std::clamp((relative(dy, dx) - lo) / dAngle, 0.0, double(rows - 1)));
      }
    }
  }
  cv::Mat forward(const cv::Mat& m) const {
    cv::Mat out;
    cv::remap(m, out, forward_x, forward_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
    return out;
  }
  cv::Mat inverse(const cv::Mat& m) const {
    cv::Mat out;
    cv::remap(m, out, inverse_x, inverse_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
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
    tailMaximumAlongRows(beams.forward(grey), beams.forward(seen), polarTail);
    tail = beams.inverse(polarTail);
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
    shadowsAlongRows(beams.forward(grey), beams.forward(seen), threshold, minLength, polarShadow);
    shadow = beams.inverse(polarShadow);
  }
  shadow &= seen;
  return shadow;
}

}  // namespace xsect
