// Segmentation settings an image can take (see setting_limits.h).
#include "segmentation/setting_limits.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

namespace xsect {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

}  // namespace

std::optional<SettingProblem> segmentationSettingProblem(const SegmentationParams& p, cv::Size size,
                                                         const Vec2& spacing, double observed_pixels) {
  const int larger = std::max(size.width, size.height), smaller = std::min(size.width, size.height);
  const std::string image = std::to_string(size.width) + " x " + std::to_string(size.height) + " pixels";
  // A length given in mm (pixel_settings.h) is named as given, its value in this image's pixels.
  const double pixel = 0.5 * (spacing.x() + spacing.y());
  const auto keyOf = [](const char* stem, double mm) { return std::string(stem) + (mm > 0 ? "_mm" : "_px"); };
  if (p.speckle_filter_px > smaller) {
    const int widest = smaller % 2 ? smaller : smaller - 1;  // the filter's width is odd
    return SettingProblem{keyOf("speckle_filter", p.speckle_filter_mm),
                          "a median filter " + std::to_string(p.speckle_filter_px) +
                              " pixels wide does not fit in the image (" + image + "); use at most " +
                              (p.speckle_filter_mm > 0 ? number(widest * pixel) + " mm" : std::to_string(widest)) +
                              " (about 1 mm is typical against speckle)"};
  }
  if (4 * p.sigma_px > larger)
    return SettingProblem{keyOf("sigma", p.sigma_mm), "a Gaussian of " + number(p.sigma_px) + " pixels reaches " +
                                          number(4 * p.sigma_px) + " pixels on each side, beyond the image (" + image +
                                          "): it would blur every section away; use at most " +
                                          (p.sigma_mm > 0 ? number(std::floor(larger / 4.0) * pixel) + " mm"
                                                          : number(std::floor(larger / 4.0))) +
                                          " (a few pixels is typical)"};
  const int largestRadius = (smaller - 1) / 2;
  for (const auto& [stem, r, mm] : {std::tuple{"open_radius", p.open_radius_px, p.open_radius_mm},
                                     std::tuple{"close_radius", p.close_radius_px, p.close_radius_mm}})
    if (r > largestRadius)
      return SettingProblem{keyOf(stem, mm), "a disk of radius " + std::to_string(r) + " pixels does not fit in the image (" +
                                     image + "): " +
                                     (std::string(stem) == "open_radius" ? "the opening would remove every section"
                                                                           : "the closing would fill the image") +
                                     "; use at most " + (mm > 0 ? number(largestRadius * pixel) + " mm" : std::to_string(largestRadius)) +
                                     " (a few pixels is typical)"};
  const double observed_mm2 = observed_pixels * spacing.x() * spacing.y();
  if (p.min_area_mm2 > 0 && observed_pixels > 0 && p.min_area_mm2 >= observed_mm2)  // (a frame observed nowhere holds nothing to remove)
    return SettingProblem{"min_area_mm2", "a minimum area of " + number(p.min_area_mm2) +
                                              " mm² is at or above the image's observed area (" + number(observed_mm2) +
                                              " mm²): every section would be removed and the background filled as a "
                                              "hole; use a value below the smallest part to keep, e.g. " +
                                              number(observed_mm2 / 1000)};
  return std::nullopt;
}

}  // namespace xsect
