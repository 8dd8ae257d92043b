// Inscribed-disk diameter of a section on a raster (see section_width.h).
#include "geometry/reconstruction/section_width.h"

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/core/polygon.h"

namespace xsect {

double sectionWidth(const Section& section, double cells_per_width) {
  if (!(cells_per_width >= 4)) throw std::invalid_argument("section width raster must have at least 4 cells per width");
  const double area = sectionArea(section);
  if (section.outer.size() < 3 || !(area > 0)) return 0.0;
  double perimeter = ringLength(section.outer);
  for (const Ring& h : section.holes) perimeter += ringLength(h);
  const Eigen::AlignedBox2d box = ringBounds(section.outer);
  const Vec2 size = box.sizes();
  const double step = std::max(2.0 * area / perimeter / cells_per_width, std::max(size.x(), size.y()) / 4096.0);
  if (!(step > 0) || !std::isfinite(step)) return 0.0;
  // One empty cell around the box, so the distance transform sees the outside on every side.
  const int cols = int(std::ceil(size.x() / step)) + 3, rows = int(std::ceil(size.y() / step)) + 3;
  const Vec2 origin = box.min() - Vec2::Constant(step);
  const auto pixels = [&](const Ring& r) {
    std::vector<cv::Point> p;
    p.reserve(r.size());
    // Cell centres at integer coordinates; 8 fractional bits so that OpenCV rounds each vertex to
    // its nearest cell rather than truncating.
    for (const Vec2& q : r)
      p.emplace_back(int(std::lround((q.x() - origin.x()) / step * 256.0 - 128.0)),
                     int(std::lround((q.y() - origin.y()) / step * 256.0 - 128.0)));
    return p;
  };
  cv::Mat mask = cv::Mat::zeros(rows, cols, CV_8U);
  const std::vector<std::vector<cv::Point>> outer{pixels(section.outer)};
  cv::fillPoly(mask, outer, cv::Scalar(255), cv::LINE_8, 8);
  if (!section.holes.empty()) {
    std::vector<std::vector<cv::Point>> holes;
    for (const Ring& h : section.holes) holes.push_back(pixels(h));
    cv::fillPoly(mask, holes, cv::Scalar(0), cv::LINE_8, 8);
  }
  cv::Mat distance;
  cv::distanceTransform(mask, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  double largest = 0;
  cv::minMaxLoc(distance, nullptr, &largest);
  // A cell centre at distance d (cells) from the nearest outside cell centre is about d - 1/2
  // from the boundary; a filled section has at least one cell at d = 1.
  return 2.0 * std::max(0.5, largest - 0.5) * step;
}

std::vector<double> sectionWidths(const std::vector<CuttingPlane>& planes, double cells_per_width) {
  std::vector<const Section*> all;
  for (const auto& p : planes)
    if (!p.is_virtual)
      for (const auto& s : p.sections) all.push_back(&s);
  std::vector<double> out(all.size());
  tbb::parallel_for(std::size_t(0), all.size(), [&](std::size_t q) { out[q] = sectionWidth(*all[q], cells_per_width); });
  return out;
}

}  // namespace xsect
