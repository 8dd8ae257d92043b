// A lighter copy of a mesh for display (report.html's 3D view, issue 21): CGAL's edge-collapse
// simplification (Garland-Heckbert quadric costs and placements) down to a triangle budget. The
// result is for looking at only: its topology is not checked and no output file holds it.
#pragma once

#include <cstddef>

#include "geometry/core/types.h"

namespace xsect {

/// `mesh` with at most about `max_triangles` triangles (unchanged when it has no more). Edge
/// collapse needs a manifold mesh; a mesh that is not one is thinned by clustering its vertices on
/// a regular grid instead. @param max_triangles  the budget, >= 4.
TriangleMesh decimatedMesh(const TriangleMesh& mesh, std::size_t max_triangles);

}  // namespace xsect
