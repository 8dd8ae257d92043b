// Conformity of the mesh with the sections (thesis Introduction §3.1: R ∩ P = S_P for every
// cutting plane P). In a cell, near a face on P, R is the prism over S_P: a point at distance t
// from P projects onto P and is in R exactly when the projection is in S_P (Def. 15-16), except
// near the Voronoi skeleton of the cell, where another plane is nearer. Meshing a sampled field
// blurs this prism where planes cross (the field jumps between two sections' values there), so
// the mesh's cut by P drifts from ∂S_P by a fraction of a voxel. This step restores the prism:
// each mesh vertex within `reach` of its nearest cutting plane P whose projection lies within
// `max_move` of ∂S_P is moved parallel to P onto the prism over ∂S_P (Newton steps on f_P). The
// mesh's connectivity is unchanged, so its topology is too.
#pragma once

#include <vector>

#include "geometry/section_distance_field.h"
#include "geometry/types.h"

namespace xsect {

struct SnapStats {
  int moved = 0;            ///< vertices moved
  double max_move_mm = 0;   ///< largest displacement
};

/// @param planes    cutting planes (virtual ones, holding no section, are skipped).
/// @param fields    f_P rasters, fields[i] for planes[i].
/// @param reach     vertices farther than this from every plane stay (mm; one voxel is right).
/// @param max_move  vertices farther than this from ∂S_P (in the plane) stay (mm).
SnapStats snapToSectionContours(TriangleMesh& mesh, const std::vector<CuttingPlane>& planes,
                                const std::vector<SectionDistanceField>& fields, double reach,
                                double max_move);

}  // namespace xsect
