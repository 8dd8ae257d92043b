// Re-deciding, on finer lattices, the cells in which a smooth surface's voxel solid joins the
// sections differently from the method's own voxel solid (thesis ch. 1 §1.1: for large p the
// zero set of Shepard's interpolant induces method 1's connectivity; cell_connectivity_check.h
// compares a solid with the graph cell by cell, on voxel centres).
//
// Why: a cell a few voxels thick holds few voxel centres, and a passage of the continuous surface
// narrower than a voxel can miss every centre of one lattice and hold some of another. Such a
// difference belongs to the lattice, not to the surface: on random-200 (the genus-2 solid cut by
// 200 random planes, 0.35 mm voxels) the 4 cells where Shepard's voxel solid joined the sections
// differently from method 1's are at most 2.4 voxels deep, and on lattices of h/2 or h/4 Shepard
// joins them exactly as the graph does in all 4.
//
// The algorithm, per cell: the box of the grid's voxel centres in the cell (found from the cell's
// section points, 26-connected within the cell), widened by two voxels on every side; on lattices
// of spacing h/2, h/4, ..., h/max_factor over that box, the surface's field is evaluated again
// (`evaluate`) and the cell compared with the graph again (compareCellsWithVoxels restricted to
// it). The first lattice on which the cell resolves (every sub-section has a voxel of the solid
// beside it) decides: the cell is accepted when the surface there differs from the graph in no
// more section pairs than the reference (the method's own solid on the grid) does. A cell that
// resolves on none of them, whose box exceeds max_voxels at the next factor, or in which the
// solid reaches the box's outer layer (it might join sections through a part of the cell beyond
// the box), is not accepted.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/arrangement/cell_connectivity_check.h"

namespace xsect {

struct CellRefinement {
  int cell = -1;             ///< arrangement cell id
  int pairs = 0;             ///< section pairs the solid on the grid disagrees with the graph on
  int reference_pairs = 0;   ///< the same for the reference solid
  int factor = 0;            ///< the lattice that decided, spacing grid.voxel / factor; 0: none
  int refined_pairs = -1;    ///< section pairs the surface disagrees on there (-1: not resolved)
  std::array<int, 3> dims{0, 0, 0};  ///< that lattice's size (the last one tried)
  bool leaves_box = false;   ///< the solid in the cell reached the box's outer layer (rejected)
  bool accepted = false;     ///< refined_pairs in 0..reference_pairs
};

/// @param cells       the cells to re-decide, e.g. cellsDifferingMore(solid, reference).
/// @param solid       the smooth surface's solid compared on `grid`.
/// @param reference   the method's own solid compared on the same grid's lattice.
/// @param edges, scene, arrangement  as for compareCellsWithVoxels.
/// @param grid        the grid `solid` was compared on (its lattice and spacing).
/// @param evaluate    the surface's solid on a given grid (one byte per voxel, 1 = inside).
/// @param max_factor  the finest lattice tried is grid.voxel / max_factor (a power of 2, >= 2).
/// @param max_voxels  no lattice larger than this is evaluated.
/// Deterministic when `evaluate` is.
std::vector<CellRefinement> refineCellComparison(
    const std::vector<int>& cells, const CellConnectivityCheck& solid,
    const CellConnectivityCheck& reference, const std::vector<GraphEdge>& edges,
    const SectionScene& scene, const SectionArrangement& arrangement, const GridSpec& grid,
    const std::function<std::vector<std::uint8_t>(const GridSpec&)>& evaluate, int max_factor = 8,
    std::int64_t max_voxels = std::int64_t(1) << 23);

}  // namespace xsect
