// Method 1 (thesis ch. 1, Def. 15-17; Liu et al. 2008) evaluated on a voxel grid.
// A point x of a cell C is in R when its nearest point np(x) on ∂C lies in a section. Inside a
// convex cell that nearest point is the orthogonal projection of x on the nearest cutting plane
// (the segment [x, np(x)] crosses no other plane, or that plane would be nearer), so
//     R = { x : f_P(proj_P(x)) < 0,  P = the cutting plane nearest to x },
// with f_P the signed distance to P's section-contours (section_distance_field.h). The value
// stored per voxel is f_P(proj_P(x)): its zero crossing is ∂R inside each Voronoi cell of the
// planes, and its sign jumps exactly where ∂R follows the Voronoi skeleton VorSkel(C).
//
// Speed: distances to planes are linear, so over a box of voxels each plane's distance lies in an
// exact interval; a plane whose lower bound exceeds the smallest upper bound cannot be nearest
// anywhere in the box. Boxes of 32³ voxels cull against all planes, then an octree of sub-boxes
// (8³, 4³, 2³) culls each parent's survivors, and voxels scan the few left (about the planes
// within a voxel or two). Planes crossing a box shrink in number with its size, so the per-voxel
// cost hardly grows with the number of planes (bench: doubling 200 random planes to 400 at a fixed
// grid).
#pragma once

#include <functional>
#include <vector>

#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct NearestPlaneField {
  ScalarField value;                ///< f_P(proj_P(x)) in mm, clamped to ±band; negative = in R
  std::vector<float> plane_distance;  ///< d(x, P) for the nearest plane P, mm
  std::vector<int> nearest_plane;     ///< index of P in the planes given
};

/// @param planes    cutting planes (real and virtual); planes[i] uses fields[i].
/// @param fields    section distance rasters, one per plane.
/// @param grid      voxel centres to evaluate (mm).
/// @param progress  optional, called with the fraction done (from the calling thread).
/// Ties between equidistant planes go to the lower index (deterministic).
NearestPlaneField nearestPlaneReconstruction(const std::vector<CuttingPlane>& planes,
                                             const std::vector<SectionDistanceField>& fields,
                                             const GridSpec& grid,
                                             const std::function<void(double)>& progress = {});

}  // namespace xsect
