// Method 3's solid R'' (delaunay_reconstruction.h: a union of tetrahedra) sampled on a voxel grid,
// for what reads voxels: labels.nrrd, the graph checks against the solid's components, the
// smoothing (stage 6) and the voxel Betti numbers. By the centre rule a voxel is in the solid when
// its centre lies in a closed tetrahedron: the centre's signed distance to each of the
// tetrahedron's four face planes (outward unit normals) is at most a tolerance of 1e-6 voxel, so
// that a centre on a face shared by two tetrahedra, or on a cutting plane where the solid lies
// flat, is not lost to rounding. Where R'' is thinner than a voxel that sampling may split it,
// open tunnels through its thin walls or enclose cavities (issue 49: a mug from 5 planes sampled
// as (4, 17, 3) while its boundary is (1, 0, 0)); by the cube rule a voxel is in the solid when its
// cube meets a tetrahedron, which keeps thin walls and necks (tetrahedraOnGridLike tries it when the
// centres do not have the boundary's Betti numbers).
//
// By rows of blocks of 8³ voxels (block_grid.h), layer of blocks by layer along z: each tetrahedron
// is listed in the rows its bounding box meets, and each row fills its blocks from its list, in
// the tetrahedra's order, along lines of voxel centres (the interval of a line inside a
// tetrahedron is the intersection of four half-lines): memory follows the blocks the boundary
// passes through and the tetrahedra of one layer, never the whole grid. Parallel over rows;
// deterministic (the same bytes whatever the thread count).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/delaunay/tetrahedron_set.h"
#include "geometry/reconstruction/sampled_reconstruction.h"

namespace xsect {

/// Which voxels hold the union of tetrahedra.
enum class VoxelRule {
  centre,  ///< the voxel's centre lies in a closed tetrahedron (within 1e-6 voxel of its faces)
  /// the voxel's closed cube meets a tetrahedron (separating axes, exact up to 1e-6 voxel): a
  /// part of R'' thinner than a voxel keeps its voxels, so a connected R'' stays connected
  cube,
};

/// @param tetrahedra  #T tetrahedra on their vertex table (world coordinates, mm); flat ones (volume below 1e-12 of
///                    their longest edge cubed) are skipped.
/// @param planes      the cutting planes; the first `realPlanes` are the real ones that hold the
///                    tetrahedra's vertices (section-vertices lie on them).
/// @param grid        the voxel grid (the scene's).
/// @param band_mm     the field's clamp, mm (> 0): as the other methods' fields, |value| <= band.
/// @param rule        centre (the default sampling) or cube (the conservative one).
/// @param progress    optional, called with (rows of blocks done, rows of blocks) from any thread.
/// @returns the sampled solid in the fields the other methods fill (sampled_reconstruction.h):
///  - `inside` (= `raw_inside`): 1 where a voxel centre lies in a tetrahedron;
///  - `field`: -band inside, +band outside, and ∓voxel/2 at voxels with a face neighbour of the
///    other side, so that the zero crossing lies half-way between voxel centres (a sign with a
///    clamped distance, as the level-set smoothing reads it);
///  - `section_plane`: for a voxel of the solid, of the real planes holding the vertices of the
///    first tetrahedron (in the given order) holding its centre, the nearest to the centre (ties:
///    lowest index; -1 when no vertex lies on a real plane): the plane voxel_labels.h reads
///    the voxel's label on;
///  - `max_lift_mm`: the largest distance of a voxel of the solid to that plane;
///  - `voxels_inside`, `voxel_betti`, `storage`, `evaluate_seconds`; no repair (zero counts).
SampledReconstruction tetrahedraOnGrid(const TetrahedronSet& tetrahedra,
                                       const std::vector<CuttingPlane>& planes, std::size_t realPlanes,
                                       const GridSpec& grid, float band_mm, VoxelRule rule = VoxelRule::centre,
                                       const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// How tetrahedraOnGridLike sampled R''.
struct VoxelLikeness {
  VoxelRule rule = VoxelRule::centre;
  int refinement = 0;    ///< the grid's voxel halved this many times
  bool matched = false;  ///< the voxels have the target's Betti numbers
};

/// The most voxels a refined grid may have: each refinement samples R'' twice more, on 8 times the
/// voxels (random-200 with method 3 spent 8.8 s instead of 2.5 s voxelising at 4e8; refinement
/// rarely finds the boundary's topology where the grid's own rules do not).
inline constexpr double kMaxRefinedVoxels = 3e7;

/// R'' on the grid as its boundary mesh is, where a grid can hold it: the centre rule, then the cube
/// rule, on `grid`, then on the same box with the voxel halved, up to `refinements` times (at most
/// kMaxRefinedVoxels voxels): the first whose voxels have the Betti numbers `target` (the
/// boundary's). When none has, the one whose Betti numbers are nearest the target's (the sum of
/// the differences; ties: the coarser grid, the centre rule), matched = false.
/// A refined grid's centres include the coarse grid's (origin kept, dims (n - 1) 2^k + 1).
SampledReconstruction tetrahedraOnGridLike(const TetrahedronSet& tetrahedra, const std::vector<CuttingPlane>& planes,
                                           std::size_t realPlanes, const GridSpec& grid, float band_mm,
                                           const Betti& target, int refinements, VoxelLikeness* how);

}  // namespace xsect
