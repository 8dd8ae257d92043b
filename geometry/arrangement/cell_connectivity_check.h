// Connectivity cell by cell (thesis ch. 1 §2 and ch. 2 §5.2: in each cell C of the arrangement,
// the components of R_C are the classes of sections of S_C that the lifts join, which is what the
// graph's edges of cell C record). Compares, per cell, the sections each component of a voxel
// solid (the method's, or a smooth surface's) joins inside that cell with the classes of the
// graph's edges of that cell. A stronger check than the global one (connectivity_graph.h
// compareWithVoxels): two sections can be joined through another cell in one and not the other.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/arrangement/connectivity_graph.h"
#include "geometry/core/block_grid.h"
#include "geometry/arrangement/section_arrangement.h"
#include "geometry/scene/section_scene.h"
#include "geometry/core/types.h"

namespace xsect {

struct CellConnectivityCheck {
  int cells_compared = 0;    ///< cells bounded by two or more sections, each with a voxel seed
  /// Cells bounded by two or more sections where some sub-section has no voxel of the solid in
  /// the cell beside it (a cell thinner than a voxel there, or a solid that misses the section).
  int cells_unresolved = 0;
  int cells_differing = 0;   ///< compared cells whose two partitions differ
  int pairs_joined_by_graph_only = 0;   ///< summed over the compared cells
  int pairs_joined_by_voxels_only = 0;
  std::vector<int> differing_cells;     ///< their ids (arrangement cell ids), at most 20
  /// Per cell id: the section pairs the two groupings disagree on; -1 where not compared.
  std::vector<int> pairs_by_cell;
};

/// @param edges        the graph (GraphEdge::cell says in which cell two lifts meet).
/// @param scene        all planes the arrangement was built on (real and virtual), same order, and
///                     per plane its sections' distance raster (to choose deep seed points).
/// @param arrangement  arrangeSections(scene.planes, ...).
/// @param inside       the solid, one byte per voxel of `grid`.
/// A voxel belongs to the cell whose sign vector its centre has. Components are 6-connected
/// inside one cell. Seeds: beside every sample point of a sub-section at least a voxel deep in
/// it (into the section and away from the traces bounding it), or beside its deepest point
/// (the voxel whose centre is nearest to the point moved 0.6 or else 1 voxel into the cell); a
/// section joins every component it touches. A cell is unresolved when a seed point has no
/// voxel of the solid within a voxel beside it. Deterministic; parallel over cells.
/// @param only_cells   optional, sorted cell ids: compare these cells only (the others are not
///                     compared, pairs_by_cell -1), e.g. on a small grid around them.
/// @param seed_mm      optional (> 0), in place of grid.voxel for the seeds: how deep a sample
///                     point must be to seed, and how far off the section its voxel is looked
///                     for. On a finer lattice, the coarse grid's voxel keeps the same seeds (what
///                     "a section touches a component" means) while the solid between them is
///                     resolved finer.
CellConnectivityCheck compareCellsWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                             const SectionArrangement& arrangement,
                                             const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                             const std::vector<int>& only_cells = {},
                                             double seed_mm = 0);
/// The same for a solid stored by blocks (block_grid.h), on its grid.
CellConnectivityCheck compareCellsWithVoxels(const std::vector<GraphEdge>& edges, const SectionScene& scene,
                                             const SectionArrangement& arrangement,
                                             const BlockGrid<std::uint8_t>& inside, const std::vector<int>& only_cells = {},
                                             double seed_mm = 0);

/// Whether `solid` differs from the graph, in every cell both compared, in no more section pairs
/// than `reference` (the method's own solid) does.
bool keepsCellConnectivity(const CellConnectivityCheck& solid, const CellConnectivityCheck& reference);

/// The cells, in increasing id, where keepsCellConnectivity fails: compared by both, and `solid`
/// differs from the graph in more section pairs than `reference` does.
std::vector<int> cellsDifferingMore(const CellConnectivityCheck& solid, const CellConnectivityCheck& reference);

}  // namespace xsect
