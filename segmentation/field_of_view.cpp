// Field-of-view mask -> rings (see field_of_view.h).
#include "segmentation/field_of_view.h"

#include <opencv2/imgproc.hpp>

#include "segmentation/iso_contours.h"

namespace xsect {

std::vector<Ring> fieldOfViewRings(const cv::Mat& fov, const Vec2& spacing) {
  if (fov.empty() || cv::countNonZero(fov) == int(fov.total())) return {};
  cv::Mat field;
  fov.convertTo(field, CV_32F, 1.0, 0.0);
  cv::threshold(field, field, 0.0, 1.0, cv::THRESH_BINARY);
  field -= 0.5f;
  std::vector<Ring> rings;
  for (const Ring& r : isoContours(field)) {
    std::vector<cv::Point2f> in, out;
    for (const Vec2& p : r) in.emplace_back(float(p.x()), float(p.y()));
    cv::approxPolyDP(in, out, 0.25, true);
    if (out.size() < 3) continue;
    Ring ring;
    for (const auto& p : out) ring.emplace_back(p.x * spacing.x(), p.y * spacing.y());
    rings.push_back(std::move(ring));
  }
  return rings;
}

}  // namespace xsect
