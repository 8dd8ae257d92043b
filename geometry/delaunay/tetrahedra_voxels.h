// Method 3's solid R'' (delaunay_reconstruction.h: a union of tetrahedra) sampled on a voxel grid,
// for what reads voxels: labels.nrrd, the graph checks against the solid's components, the
// smoothing (stage 6) and the voxel Betti numbers. A voxel is in the solid when its centre lies in
// a closed tetrahedron: the centre's signed distance to each of the tetrahedron's four face planes
// (outward unit normals) is at most a tolerance of 1e-6 voxel, so that a centre on a face shared
// by two tetrahedra, or on a cutting plane where the solid lies flat, is not lost to rounding.
// No topology repair: where R'' is thinner than a voxel its sampling may split or vanish, which the
// voxel Betti numbers show against the mesh's (the mesh, not the voxels, is the reconstruction).
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

/// @param tetrahedra  #T tetrahedra on their vertex table (world coordinates, mm); flat ones (volume below 1e-12 of
///                    their longest edge cubed) are skipped.
/// @param planes      the cutting planes; the first `realPlanes` are the real ones that hold the
///                    tetrahedra's vertices (section-vertices lie on them).
/// @param grid        the voxel grid (the scene's).
/// @param band_mm     the field's clamp, mm (> 0): as the other methods' fields, |value| <= band.
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
                                       const GridSpec& grid, float band_mm,
                                       const std::function<void(std::int64_t, std::int64_t)>& progress = {});

}  // namespace xsect
