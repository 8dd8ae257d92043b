// Mends of a cell for topology control (issue 51; see topology_control.h): the gaps a ball
// closing fills and the necks a ball opening cuts, inside one cell of the arrangement (thesis
// ch. 1 §1.2), changing no voxel against what a plane next to it says (planesAllow), so that the
// cut of the solid by every plane stays its sections. They reach what joins cut and added
// cannot: a ring-shaped gap between the lifts of two sections of one cell that the sections on
// the cell's other faces hold together (a tunnel of a thin wall between parallel planes: the mug
// of the contour literature has eight), and the one-voxel pinholes and necks a voxelisation
// leaves where lifts barely meet (OReX's Elephant has eleven).
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/arrangement/section_arrangement.h"
#include "geometry/core/types.h"
#include "geometry/scene/section_distance_field.h"

namespace xsect {

/// Whether the planes let the voxel centred at x take `value` (1 = in the solid): the voxels within
/// one voxel of a real plane decide the cut of the solid (and of its mesh) by that plane, so each
/// such plane must say the same at x's projection: inside its sections for 1, outside them for 0,
/// either where the projection lies within half a voxel of a section's contour (the contour
/// crosses the voxel: the grid cannot tell). A plane that saw only part of itself (an image) says nothing
/// beyond its extent or where a field of view narrows it, and then allows no change near it.
/// @param planes       every plane of the arrangement, the real ones first.
/// @param real_planes  how many of `planes` are real.
/// @param fields       per plane, its sections' signed distance (negative inside), mm.
/// @param voxel        the voxel size, mm.
bool planesAllow(const Vec3& x, bool value, const std::vector<CuttingPlane>& planes, std::size_t real_planes,
                 const std::vector<SectionDistanceField>& fields, double voxel);

/// One mend: voxels of one cell added (a gap filled) or removed (a neck cut), one 26-connected
/// group of the voxels a closing or an opening changes in that cell.
struct CellMend {
  bool fill = false;                  ///< a gap filled (else a neck cut)
  double radius = 0;                  ///< the ball's radius, voxels
  CellKey key{0, 0};
  std::vector<std::int64_t> voxels;   ///< grid indices, sorted
  /// 1 + the flat ids (section_ids.h) of the sections whose lifts the mend touches (fill: the
  /// voxels of the solid next to it in its cell; cut: its own voxels), sorted: a gap filled
  /// between two or more of them joins them in the cell.
  std::vector<int> sections;
};

/// The mends of the solid `inside` by balls of radius 1, 2, ... max_radius voxels: per radius, the
/// voxels its closing adds (resp. its opening removes) that the planes allow, grouped
/// into 26-connected sets of one cell. A neck holds at most 4 (2r + 1)³ voxels (larger sets are
/// walls, not necks). A set found at a smaller radius is not repeated.
/// @param inside       1 = in the solid, per voxel of `grid`, with max_radius + 1 voxels of empty
///                     margin (ball_morphology.h).
/// @param source       per voxel, 1 + the flat id of the section its lift comes from (0: none).
/// The gaps first, then the necks; each by radius, then by first voxel: deterministic.
std::vector<CellMend> cellMends(const std::vector<std::uint8_t>& inside, const std::vector<std::uint16_t>& source,
                                const GridSpec& grid,
                                const std::vector<CuttingPlane>& planes, std::size_t real_planes,
                                const std::vector<SectionDistanceField>& fields,
                                const SectionArrangement& arrangement, int max_radius);

}  // namespace xsect
