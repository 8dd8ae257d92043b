// The handles and cavities of a voxel solid, each with a size and a place (issue 51 item 3): the
// persistence pairs of the sublevel-set filtration of the solid's signed distance on its voxels
// (GUDHI's cubical complex, H. Wagner, C. Chen, E. Vuçini, "Efficient computation of persistent
// homology for cubical data", 2012), restricted to those alive at 0 — the solid itself, the union
// of its closed voxel cubes, so that there is one per tunnel (b1) and per cavity (b2) that
// voxelBetti counts. A feature is born at birth <= 0 (a handle closes once the solid is eroded to
// -birth: its thickness is about -2 birth) and dies at death > 0 (a tunnel's hole is filled once
// the solid is grown by death: its width is about 2 death); its size is the smaller of the two,
// the least growth or erosion that removes it: thin spurious tunnels (a voxel or a lift wide)
// have sizes near the voxel, a mug's handle its own thickness.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct TopologyFeature {
  int dimension = 1;          ///< 1: a tunnel or handle, 2: a cavity
  double birth_mm = 0;        ///< <= 0: minus the erosion that removes it
  double death_mm = 0;        ///< > 0: the growth that removes it (+infinity: never, on the grid)
  double size_mm = 0;         ///< min(-birth, death)
  Vec3 born_at = Vec3::Zero(); ///< the centre of the cell at which it is born (the thinnest place of a handle), mm
  Vec3 dies_at = Vec3::Zero(); ///< the centre of the cell at which it dies (the middle of a tunnel's hole), mm
  /// The cells of the arrangement holding born_at and dies_at (-1: not computed, or no section
  /// point bounds the cell): filled by topology control.
  int born_in_cell = -1, dies_in_cell = -1;
};

/// Grids larger than this are not analysed: the cubical complex holds 8 cells a voxel and its
/// persistent cohomology took 9 µs and 250-480 bytes a voxel on this machine (the mug's box,
/// 443 k voxels: 4 s, 140 MB; a frustum's, 987 k voxels: 9 s, 470 MB), so 5 s and 250 MB at most.
inline constexpr std::int64_t kMaxFeatureVoxels = std::int64_t(1) << 19;

/// @param inside  1 = in the solid, per voxel of `grid`, with at least one voxel of empty margin.
/// @return        the features alive at 0, sorted by (dimension, size, place): deterministic.
/// Throws std::invalid_argument when `inside` does not hold one value per voxel or the grid holds
/// more than kMaxFeatureVoxels voxels.
std::vector<TopologyFeature> topologyFeatures(const std::vector<std::uint8_t>& inside, const GridSpec& grid);

}  // namespace xsect
