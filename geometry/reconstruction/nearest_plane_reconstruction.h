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
//
// Observed pieces (issue 20, observed_piece.h): when a slice observed only a piece Ω_P of its
// plane, np(x) is the nearest point of the union of the pieces, d(x, Ω_P) = sqrt(s² + o²) with o
// the in-plane distance of proj_P(x) to Ω_P, and the value stored is f_P at that nearest point.
// The culling bounds o over a box by its value at the box's centre ± the projection's radius.
// With every piece whole this is the thesis' method 1, evaluated by the same code as before.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/scene/observed_piece.h"
#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct NearestPlaneField {
  ScalarField value;                ///< f_P(proj_P(x)) in mm, clamped to ±band; negative = in R
  std::vector<float> plane_distance;  ///< d(x, P) for the nearest plane P, mm
  std::vector<int> nearest_plane;     ///< index of P in the planes given
};

/// Method 1 on one block of 8³ voxels (block_grid.h), by BlockGrid's offset(); voxels of the
/// block beyond the grid repeat the block's first voxel, so that a block uniform within the grid
/// is uniform.
struct NearestPlaneBlock {
  static constexpr int kVoxels = BlockGrid<float>::kVoxels;
  std::array<float, kVoxels> value;           ///< f_P(proj_P(x)), mm, clamped to ±band
  std::array<float, kVoxels> plane_distance;  ///< d(x, P), mm
  std::array<int, kVoxels> nearest_plane;     ///< P
  /// Decided at once (forEachNearestPlaneBlock's whole_blocks): every value is +band and no voxel
  /// lies within half a voxel diagonal of a plane.
  bool far_outside = false;
};

/// Method 1 block by block: visit(b, values) for every block b of BlockGrid's numbering on `grid`,
/// from several threads at once (each block once), so that no per-voxel array of the whole grid is
/// needed (issue 17). Parameters and ties as nearestPlaneReconstruction's.
/// @param whole_blocks  decide a block at once where the bounds allow it: when every plane that
///                      may be nearest in it sees it only where its raster is +band and is farther
///                      than half a voxel diagonal from every voxel centre, the values are +band,
///                      and plane_distance / nearest_plane hold a lower bound of the distance and
///                      one of those planes instead of each voxel's own (no voxel is evaluated).
/// @param pieces        null (whole planes), or one observed piece per plane: distances are then to
///                      the pieces, and nearest_plane is -1 where no piece is observed at all.
void forEachNearestPlaneBlock(const std::vector<CuttingPlane>& planes,
                              const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                              const std::function<void(std::int64_t, const NearestPlaneBlock&)>& visit,
                              bool whole_blocks, const std::function<void(std::int64_t, std::int64_t)>& progress = {},
                              const std::vector<ObservedPiece>* pieces = nullptr);

/// The same on dense arrays (small grids, tests).
/// @param planes    cutting planes (real and virtual); planes[i] uses fields[i].
/// @param fields    section distance rasters, one per plane.
/// @param grid      voxel centres to evaluate (mm).
/// @param progress  optional, called with the blocks done and the blocks in all (from the calling thread).
/// Ties between equidistant planes go to the lower index (deterministic).
NearestPlaneField nearestPlaneReconstruction(const std::vector<CuttingPlane>& planes,
                                             const std::vector<SectionDistanceField>& fields,
                                             const GridSpec& grid,
                                             const std::function<void(std::int64_t, std::int64_t)>& progress = {},
                                             const std::vector<ObservedPiece>* pieces = nullptr);

}  // namespace xsect
