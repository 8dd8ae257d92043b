// The width of a section: the diameter of the largest disk inside it (its inscribed disk), mm.
// A grid resolves a section when the section is at least two voxels wide (issue 14: a grid too
// coarse for most sections is refused or warned about, and the automatic voxel size is a fraction
// of the sections' typical width).
#pragma once

#include <vector>

#include "geometry/types.h"

namespace xsect {

/// Diameter (mm) of the largest disk inside the section (outer ring minus holes). Computed on a
/// raster of the section's bounding box with `raster_px` cells along its longer side (OpenCV
/// fillPoly and the exact Euclidean distance transform), so it is exact to within about three
/// raster steps (bounding box / raster_px: the disk's centre and rim are read at cell centres); a
/// section thinner than that reports about one step.
/// 0 for a section without area. Throws std::invalid_argument when raster_px < 8.
double sectionWidth(const Section& section, int raster_px = 256);

/// sectionWidth of every section of every plane (real planes only), in plane order.
std::vector<double> sectionWidths(const std::vector<CuttingPlane>& planes, int raster_px = 256);

}  // namespace xsect
