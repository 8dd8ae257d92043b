// The voxel size chosen from the data when the configuration says `auto` (the default; issue 14):
// data come in any unit (OReX contours are about one unit across, ultrasound in mm), so no fixed
// length can be the default. The rule, in the sections' own length scale:
//   h = min(D / 100, w / 4), then at least p / 2, then at least the size that fits the budget,
// D the diagonal of the sections' bounding box (a grid about 60 voxels along each side of a
// cube-like object), w the median section width (inscribed-disk diameter, section_width.h: the
// typical section is at least 4 voxels wide, so thin objects get a finer grid), p the median pixel
// size of the images (finer voxels than half a pixel add no detail in the planes; unknown for
// .csl contours), and the budget the largest grid allowed for the method (voxels, end margins
// included).
// Rounded to two significant digits.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/scene/section_scene.h"
#include "geometry/core/types.h"

namespace xsect {

/// Which term of the rule decided the voxel size.
enum class VoxelSizeLimit { bounds, section_width, pixel, voxel_budget };
const char* voxelSizeLimitName(VoxelSizeLimit limit);

struct VoxelSizeChoice {
  double voxel_mm = 0;                  ///< the voxel size, mm
  VoxelSizeLimit limited_by = VoxelSizeLimit::bounds;
  double bounds_diagonal_mm = 0;        ///< D
  double median_section_width_mm = 0;   ///< w
  double median_pixel_mm = 0;           ///< p; 0 when no plane has a pixel size
  std::int64_t voxel_budget = 0;
  std::int64_t voxels = 0;              ///< grid voxels at voxel_mm (reconstructionLayout)
};

/// @param planes  the real cutting planes with their sections (at least one section).
/// @param widths  sectionWidths(planes) (section_width.h), mm.
/// @param params  the reconstruction's method and end margin (voxel_mm is ignored).
/// @param voxel_budget  largest grid of the method, voxels (>= 1000; the smoothing's grid, which
///                      reaches the end planes, is larger).
/// Throws std::invalid_argument when there is no section, the budget is below 1000, or no voxel
/// size fits the budget (the margins' layers alone exceed it).
VoxelSizeChoice automaticVoxelSize(const std::vector<CuttingPlane>& planes, const std::vector<double>& widths,
                                   ReconstructionParams params, std::int64_t voxel_budget);

/// v rounded to two significant digits (to nearest, or up), for readable lengths.
double twoSignificantDigits(double v, bool up = false);

}  // namespace xsect
