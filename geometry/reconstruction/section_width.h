// The width of a section: the diameter of the largest disk inside it (its inscribed disk), mm.
// A grid resolves a section when the section is at least two voxels wide (issue 14: a grid too
// coarse for most sections is refused or warned about, and the automatic voxel size is a fraction
// of the sections' typical width).
#pragma once

#include <vector>

#include "geometry/core/types.h"

namespace xsect {

/// Diameter (mm) of the largest disk inside the section (outer ring minus holes). Computed on a
/// raster (OpenCV fillPoly and the exact Euclidean distance transform) whose step is the
/// section's mean width 2 A / P (A its area, P the length of its rings: the width of a strip,
/// the radius of a disk) divided by `cells_per_width`, and never finer than a 4096th of its
/// bounding box; exact to within about three raster steps (the disk's centre and rim are read at
/// cell centres). Why the mean width and not the bounding box: a freehand sweep has thousands of
/// sections, and a raster of 32 cells across the mean width costs about 4,000 cells for a
/// round section (measured with a 256-cell bounding-box raster instead: 0.3 s more per 400-frame
/// run). 0 for a section without area. Throws std::invalid_argument when cells_per_width < 4.
double sectionWidth(const Section& section, double cells_per_width = 32);

/// sectionWidth of every section of every plane (real planes only), in plane order.
std::vector<double> sectionWidths(const std::vector<CuttingPlane>& planes, double cells_per_width = 32);

}  // namespace xsect
