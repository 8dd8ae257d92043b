// A lighter copy of a mesh for display (report.html's 3D view, issue 21): vertex clustering
// (Rossignac-Borrel) on a regular grid whose cell is sized for a triangle budget. Linear in the
// mesh's size: the whole page of a 1.1 M-triangle run is built in 0.21 s, where CGAL's edge collapse
// alone took 6 s (cheapest policies) to 15 s (Garland-Heckbert) on 710 k triangles, too slow for a
// page written at the end of every run. The
// result is for looking at only: its topology is not checked and no output file holds it.
#pragma once

#include <cstddef>

#include "geometry/core/types.h"

namespace xsect {

/// `mesh` with at most `max_triangles` triangles (unchanged when it has no more): every vertex
/// moved to the mean of the vertices in its grid cell, triangles whose corners share a cell dropped.
/// Deterministic. @param max_triangles  the budget, >= 4.
TriangleMesh decimatedMesh(const TriangleMesh& mesh, std::size_t max_triangles);

}  // namespace xsect
