// Conformity by construction (thesis Introduction §3.1: R ∩ P = S_P for every cutting plane P).
// The mesh is split along every cutting plane that holds sections (each triangle crossing P is
// cut into two or three, consistently oriented, so the mesh stays closed and keeps its topology),
// and every vertex created on P is moved within P onto the section contour ∂S_P (Newton steps on
// f_P); a vertex on two planes moves along their common line, where both contours meet it. The
// cut of the mesh by P is then a polygon inscribed in ∂S_P: conformity up to chord error. A move
// that would fold the surface (turn an incident triangle over) is shortened or dropped: the mesh
// stays free of folds, and the report counts the vertices left short of their contour.
#pragma once

#include <vector>

#include "geometry/scene/section_distance_field.h"
#include "geometry/core/types.h"

namespace xsect {

struct ConformalCutStats {
  int planes_cut = 0;           ///< planes that crossed the mesh
  int vertices_added = 0;       ///< vertices created on planes
  int vertices_snapped = 0;     ///< plane vertices moved onto their contour
  int vertices_shortened = 0;   ///< moved part of the way: the full move would fold the surface
  int vertices_unsnapped = 0;   ///< plane vertices left: no contour within a voxel, or any move folds
  double max_move_mm = 0;
};

/// @param planes    cutting planes; those without sections (virtual or empty) are not cut.
/// @param fields    f_P rasters, fields[i] for planes[i].
/// @param voxel     grid spacing, mm: vertices within 2% of it from a plane are put on the plane
///                  instead of splitting next to them; moves are limited to one voxel.
ConformalCutStats cutAlongSections(TriangleMesh& mesh, const std::vector<CuttingPlane>& planes,
                                   const std::vector<SectionDistanceField>& fields, double voxel);

}  // namespace xsect
