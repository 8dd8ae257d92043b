// The automatic voxel size (see automatic_voxel_size.h).
#include "geometry/reconstruction/automatic_voxel_size.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/scene/end_planes.h"
#include "geometry/core/median.h"

namespace xsect {

const char* voxelSizeLimitName(VoxelSizeLimit limit) {
  switch (limit) {
    case VoxelSizeLimit::bounds: return "bounds";
    case VoxelSizeLimit::section_width: return "section_width";
    case VoxelSizeLimit::pixel: return "pixel";
    case VoxelSizeLimit::voxel_budget: return "voxel_budget";
  }
  return "bounds";
}

double twoSignificantDigits(double v, bool up) {
  if (!(v > 0) || !std::isfinite(v)) return v;
  // v = q 10^k with q in [10, 100): q rounded, then scaled by an exact power of ten (dividing by
  // 10^-k when k < 0, so that 41 / 100 is the double nearest 0.41, not 41 * 0.01 = 0.41000000000000003).
  const int k = int(std::floor(std::log10(v))) - 1;
  const double scale = std::pow(10.0, std::abs(k));
  const double q = k < 0 ? v * scale : v / scale;
  // A relative slack of 1e-9 keeps exact two-digit values (0.35) from rounding up to the next.
  const double r = up ? std::ceil(q - 1e-9) : std::round(q);
  return k < 0 ? r / scale : r * scale;
}

VoxelSizeChoice automaticVoxelSize(const std::vector<CuttingPlane>& planes, const std::vector<double>& widths,
                                   ReconstructionParams params, std::int64_t voxel_budget) {
  if (voxel_budget < 1000) throw std::invalid_argument("voxel budget must be at least 1000 voxels");
  Vec3 lo, hi;
  if (!sectionBounds(planes, &lo, &hi)) throw std::invalid_argument("no section in any slice: nothing to reconstruct");
  VoxelSizeChoice c;
  c.voxel_budget = voxel_budget;
  c.bounds_diagonal_mm = (hi - lo).norm();
  c.median_section_width_mm = upperMedian(widths);
  std::vector<double> pixels;
  for (const auto& p : planes)
    if (!p.is_virtual && !p.sections.empty() && p.pixel_mm > 0) pixels.push_back(p.pixel_mm);
  c.median_pixel_mm = upperMedian(pixels);

  double h = c.bounds_diagonal_mm / 100.0;
  if (c.median_section_width_mm > 0 && c.median_section_width_mm / 4.0 < h) {
    h = c.median_section_width_mm / 4.0;
    c.limited_by = VoxelSizeLimit::section_width;
  }
  if (c.median_pixel_mm / 2.0 > h) {
    h = c.median_pixel_mm / 2.0;
    c.limited_by = VoxelSizeLimit::pixel;
  }
  if (!(h > 0)) throw std::invalid_argument("the sections have no extent: no voxel size fits them");
  h = twoSignificantDigits(h);
  // The budget: the grid shrinks as h^-3; a few steps reach it. It cannot shrink below the
  // margins' layers (about 9^3 voxels for method 1, 11^3 for method 2, more with a fixed end
  // margin larger than the object): a budget below that is refused with the smallest grid.
  // Past a thousand times the larger of the rule's size and the bounds, the grid is its margins'
  // layers alone.
  const double last = 1000 * std::max(h, c.bounds_diagonal_mm);
  for (;;) {
    params.voxel_mm = h;
    try {
      c.voxels = reconstructionLayout(planes, params).grid.count();
    } catch (const std::invalid_argument&) {  // past 2^40 voxels
      c.voxels = std::int64_t(1) << 40;
    }
    if (c.voxels <= voxel_budget) break;
    if (h > last)
      throw std::invalid_argument("no voxel size fits a grid of " + std::to_string(voxel_budget) +
                                  " voxels (the smallest grid has " + std::to_string(c.voxels) +
                                  "): raise reconstruction.voxel_budget");
    h = twoSignificantDigits(h * std::max(1.01, std::cbrt(double(c.voxels) / double(voxel_budget))), true);
    c.limited_by = VoxelSizeLimit::voxel_budget;
  }
  c.voxel_mm = h;
  return c;
}

}  // namespace xsect
