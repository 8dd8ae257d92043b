// Segmentation settings in mm resolved into pixels (see pixel_settings.h).
#include "segmentation/pixel_settings.h"

#include <algorithm>
#include <cmath>

namespace xsect {

SegmentationParams inPixels(const SegmentationParams& params, const Vec2& spacing) {
  SegmentationParams p = params;
  const double pixel = 0.5 * (spacing.x() + spacing.y());
  if (!(pixel > 0)) return p;
  // Ratios far beyond any image are clamped before the integer conversion; the image's own limits
  // (setting_limits.h) then refuse them by name.
  const auto pixels = [&](double mm) { return std::min(mm / pixel, 1e7); };
  if (p.sigma_mm > 0) p.sigma_px = pixels(p.sigma_mm);
  if (p.open_radius_mm > 0) p.open_radius_px = std::max(1, int(std::lround(pixels(p.open_radius_mm))));
  if (p.close_radius_mm > 0) p.close_radius_px = std::max(1, int(std::lround(pixels(p.close_radius_mm))));
  if (p.speckle_filter_mm > 0) {
    const int d = std::max(3, int(std::lround(pixels(p.speckle_filter_mm))));
    p.speckle_filter_px = d % 2 ? d : d + 1;
  }
  return p;
}

}  // namespace xsect
