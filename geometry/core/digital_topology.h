// Topology of R, not of its sampling (issue: method 1, "Topology of R").
// In a cell C, every point of R lies on a segment [a, lift(a)] from a section point a (thesis ch. 1
// §1, characterisation of R_C), and every point of the complement lies on a segment from a point of
// ∂C outside the sections. So each connected component of R contains section points, and each
// bounded component of the complement contains points of a plane outside its sections (a section
// hole). A voxelisation adds specks and one-voxel cavities where R is thinner than a voxel, near the
// Voronoi skeleton and where planes cross. This repair keeps exactly the components that carry that
// evidence ("anchors": voxels next to a plane, clearly inside / clearly outside its sections),
// then removes the critical configurations (a 2x2 checkerboard, two voxels meeting at a vertex
// only) so that the set is well-composed: 6- and 26-connectivity agree and the iso-surface has one
// well-defined topology, that of the union of closed voxel cubes.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/block_grid.h"
#include "geometry/core/types.h"

namespace xsect {

struct TopologyRepair {
  int specks_removed = 0;        ///< components of R without an inside anchor
  int cavities_filled = 0;       ///< bounded complement components without an outside anchor
  int critical_voxels_added = 0; ///< voxels added to remove critical configurations
};

/// @param inside          1 = voxel in R (modified in place).
/// @param inside_anchor   1 = voxel certainly in R because of a section next to it.
/// @param outside_anchor  1 = voxel certainly outside R because of a plane next to it.
TopologyRepair repairSampledTopology(std::vector<std::uint8_t>& inside,
                                     const std::vector<std::uint8_t>& inside_anchor,
                                     const std::vector<std::uint8_t>& outside_anchor,
                                     const GridSpec& grid);

/// The same on a voxel set stored by blocks (block_grid.h: tiles of 0 or 1, leaves of bytes), on
/// the anchors' grid: rows whose blocks are all tiles of one value are never read voxel by voxel,
/// so the cost and memory follow the blocks the boundary passes through (issue 17). The result
/// is the dense version's, voxel for voxel.
TopologyRepair repairSampledTopology(BlockGrid<std::uint8_t>& inside, const BlockGrid<std::uint8_t>& inside_anchor,
                                     const BlockGrid<std::uint8_t>& outside_anchor);

/// Removes every critical configuration (a 2x2 checkerboard in an axis plane, two voxels or two
/// holes meeting at a vertex only) by adding voxels, until none is left: the set becomes
/// well-composed, so its 26-connected components, its 6-connected complement and the iso-surface
/// OpenVDB meshes between its voxel centres (volume_mesher.h) have one topology, that of the union
/// of its closed voxel cubes (voxelBetti). Voxels are only added, each next to the configuration
/// it removes. Returns the number of voxels added.
/// Terminates: every pass that finds a configuration adds a voxel (in practice 1-3 passes).
int makeWellComposed(std::vector<std::uint8_t>& inside, const GridSpec& grid);
int makeWellComposed(BlockGrid<std::uint8_t>& inside);

/// Gives a sampled field the solid `inside` (one byte per voxel): voxels of the set whose value is
/// >= 0 take -nudge_mm, voxels outside it whose value is < 0 take +nudge_mm (nudge > 0: a small
/// distance), so the zero set meshed bounds exactly that set. Returns the number of values changed.
std::int64_t imposeSolid(ScalarField& field, const std::vector<std::uint8_t>& inside, float nudge_mm);
/// The same on a field and a set stored by blocks (one grid); a tile of the field is expanded into
/// a leaf only where a voxel changes.
std::int64_t imposeSolid(BlockGrid<float>& field, const BlockGrid<std::uint8_t>& inside, float nudge_mm);

/// The 26-connected components of a voxel set, kept as its runs along x (no label per voxel):
/// at(i, j, k) is the component of a voxel of the set, -1 outside it. Components are numbered by
/// their first voxel in scan order.
struct SolidComponentIndex {
  GridSpec grid;
  int count = 0;
  std::vector<std::int32_t> x0, x1;      ///< runs: first and last voxel along x
  std::vector<std::int64_t> first;       ///< per row j + ny k: its first run; one more at the end
  std::vector<std::int32_t> component;   ///< per run
  int at(int i, int j, int k) const;
};
SolidComponentIndex solidComponentIndex(const std::vector<std::uint8_t>& inside, const GridSpec& grid);
SolidComponentIndex solidComponentIndex(const BlockGrid<std::uint8_t>& inside);

/// 26-connected components of the voxel set: label per voxel (-1 outside), count in *count.
std::vector<int> solidComponents(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                 int* count);

/// Betti numbers of the union of the closed voxel cubes of `inside` (26-connected components,
/// 6-connected bounded complement components, b1 from the Euler characteristic).
Betti voxelBetti(const std::vector<std::uint8_t>& inside, const GridSpec& grid);

/// The change of the Euler characteristic of the union of the closed voxel cubes of `inside` when
/// the voxels `voxels` (grid indices, sorted) take `value` (0 or 1): a sum over the lattice cells
/// next to them only, so its cost follows the change, not the grid. With b0 and b2 unchanged,
/// b1 changes by minus it (b1 = b0 + b2 - chi).
long long eulerCharacteristicChange(const std::vector<std::uint8_t>& inside, const GridSpec& grid,
                                    const std::vector<std::int64_t>& voxels, std::uint8_t value);
Betti voxelBetti(const BlockGrid<std::uint8_t>& inside);

}  // namespace xsect
